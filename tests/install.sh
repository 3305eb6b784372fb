#!/bin/sh
# install.sh — `make install` honours PREFIX and DESTDIR, and an installed
# libbrdf is usable through its pkg-config file: a program built with
# `pkg-config --cflags --libs brdfkit` prints GGX D at a = 1, which is 1/π.
# The search is usable the same way: a program that includes only the
# installed <brdfkit/search.h> plants 0.45*LoH^2 + 0.2, runs bk_search_drive
# with progress and stop callbacks, and finds the planted form (rmse of its
# best form against the planted values tiny); against a wrong plant
# (0.5*LoH^2 + 0.2) the same form is far off (the check's negative control).
set -u
T=$(mktemp -d /tmp/bk_install_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

${MAKE:-make} -s install PREFIX=/opt/bk DESTDIR="$T/stage" >/dev/null || bad "make install"
for f in lib/libbrdf.a lib/libbrdfkit-fit.a include/brdf.h include/brdfkit/search.h include/brdfkit/fit.h \
	include/brdfkit/expr.h include/brdfkit/target.h include/brdfkit/solver.h include/brdfkit/brdf.h include/brdfkit/brdf_ops.h \
	lib/pkgconfig/brdfkit.pc bin/brdfkit bin/brdfkit-mpi; do
	[ -f "$T/stage/opt/bk/$f" ] && ok || bad "missing $f under DESTDIR/PREFIX"
done
grep -q '^prefix=/opt/bk$' "$T/stage/opt/bk/lib/pkgconfig/brdfkit.pc" && ok || bad "pc prefix"

${MAKE:-make} -s install PREFIX="$T/usr" >/dev/null || bad "make install PREFIX"
cat >"$T/use.c" <<'C'
#include <brdf.h>
#include <stdio.h>
int main(void) { printf("%.15f\n", bk_D_ggx(0.3, 1.0) * BK_PI); return 0; }
C
flags=$(PKG_CONFIG_PATH="$T/usr/lib/pkgconfig" pkg-config --static --cflags --libs brdfkit) || bad "pkg-config"
cc -std=c11 "$T/use.c" $flags -o "$T/use" && [ "$("$T/use")" = "1.000000000000000" ] && ok || bad "linking the installed library"
cat >"$T/plant.c" <<'C'
/* a program of the search's installed API alone */
#include <brdfkit/brdf_ops.h>
#include <brdfkit/search.h>
_Static_assert(BK_OP_PARAM < BK_OP_COUNT, "the opcodes a tree is made of, from the installed table");
#include <math.h>
#include <stdio.h>
#include <string.h>

static int heard, asked;
static void progress(void *ctx, const bk_search *s) { (void)ctx, (void)s, heard++; }
static int stop(void *ctx, const bk_search *s) { (void)ctx, (void)s, asked++; return 0; }

/* samples of form text on LoH in [0, 1] */
static int plant(const char *text, bk_samples *sm)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_FORM, &to);
	to.form_text = text;
	to.ndomain = 1;
	to.dom_in[0] = BK_IN_LOH, to.dom_lo[0] = 0, to.dom_hi[0] = 1;
	to.nx = 32;
	char err[256];
	if (bk_target_build(&to, sm, NULL, NULL, err, sizeof err)) {
		fprintf(stderr, "plant: %s\n", err);
		return -1;
	}
	return 0;
}

/* rmse of candidate c's values against samples sm */
static double rmse(const bk_cand *c, const bk_samples *sm)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(c->text, &fe);
	double v[4096], se = 0;
	if (!f || sm->n > 4096 || bk_form_eval(f, BK_F64, sm->n, (const double *const *)sm->in, c->p, v))
		return NAN;
	bk_form_free(f);
	for (size_t i = 0; i < sm->n; i++)
		se += (v[i] - sm->y[i]) * (v[i] - sm->y[i]);
	return sqrt(se / (double)sm->n);
}

int main(void)
{
	bk_samples sm, wrong;
	if (plant("0.45*LoH*LoH + 0.2", &sm) || plant("0.5*LoH*LoH + 0.2", &wrong))
		return 1;
	bk_search_options o;
	bk_search_defaults(&o);
	o.screen = &sm;
	o.shape = BK_SHAPE_PLAIN;
	memset(&o.grammar, 0, sizeof o.grammar);
	o.grammar.ops = bk_grammar_default_ops();
	o.grammar.inputs = 1u << BK_IN_LOH;
	o.grammar.max_params = 2;
	o.grammar.max_size = 9;
	o.evals = 600;
	o.threads = 2;
	char err[256];
	bk_search *s = bk_search_new(&o, err, sizeof err);
	bk_search_callbacks cb = BK_SEARCH_CALLBACKS_INIT;
	cb.progress = progress;
	cb.stop = stop;
	cb.progress_every = 100;
	if (!s || bk_search_drive(s, &cb, err, sizeof err) != 0) {
		fprintf(stderr, "search: %s\n", err);
		return 1;
	}
	size_t idx[64], n = bk_search_front(s, idx, 64);
	const bk_cand *best = n ? bk_search_at(s, idx[n - 1]) : NULL; /* the front's last: the least error */
	if (!best)
		return 1;
	printf("fits %ld front %zu progress %d stop %d best %s\nplanted %.3g wrong %.3g\n", bk_search_evals(s), n, heard,
	       asked, best->text, rmse(best, &sm), rmse(best, &wrong));
	bk_search_free(s);
	bk_samples_free(&sm);
	bk_samples_free(&wrong);
	return 0;
}
C
cc -std=c11 "$T/plant.c" $flags -o "$T/plant" 2>"$T/plant.err" && "$T/plant" >"$T/plant.out" && ok ||
	bad "the search through the installed headers: $(cat "$T/plant.err" "$T/plant.out" 2>/dev/null | head -5)"
num() { tr ' ' '\n' <"$T/plant.out" | awk -v k="$1" 'p { print; exit } $0 == k { p = 1 }'; }
# the planted form found: its rmse a rounding error (below 1e-9 of its values' 0.2 to 0.65)
awk -v e="$(num planted)" 'BEGIN { exit !(e != "" && e + 0 < 1e-9) }' && ok || bad "planted form not recovered: $(cat "$T/plant.out")"
# negative control: the same form against a plant of another constant is far off
awk -v e="$(num wrong)" 'BEGIN { exit !(e != "" && e + 0 > 1e-3) }' && ok || bad "a wrong plant reads as recovered: $(cat "$T/plant.out")"
# the callbacks were called: stop after each step, progress at least once
awk -v p="$(num progress)" -v q="$(num stop)" 'BEGIN { exit !(p >= 1 && q >= 1) }' && ok || bad "callbacks not called: $(cat "$T/plant.out")"
"$T/usr/bin/brdfkit" --version | grep -q '^brdfkit ' && ok || bad "installed tool"

echo "install: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
