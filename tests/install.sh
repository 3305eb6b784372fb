#!/bin/sh
# install.sh — `make install` honours PREFIX and DESTDIR, and the installed
# libraries are usable through `pkg-config --cflags --libs brdfkit` alone:
#   - shared (the default link): a C program prints GGX D at a = 1, which is
#     1/π; a C program that includes only the installed <brdfkit/search.h>
#     plants 0.45*LoH^2 + 0.2, runs bk_search_drive with progress and stop
#     callbacks, and finds the planted form (rmse of its best form against the
#     planted values tiny); against a wrong plant (0.5*LoH^2 + 0.2) the same
#     form is far off (the check's negative control); a C++17 program calls
#     bk_D_ggx, the fitter (bk_fit_defaults, bk_fit_run_cb and its progress)
#     and a function of every other installed header, and recovers a planted
#     fit. They run from the non-system PREFIX through the rpath in Libs;
#   - every installed header compiles alone as C11 and as C++17 with
#     -Wall -Wextra -Werror, and declares C linkage (the C++ object refers to
#     no mangled bk_ name);
#   - static (pkg-config --static, from the DESTDIR stage with the shared
#     libraries removed, so the archives are what links): the C program and
#     the C++ one (the fitter: Ceres, glog, libstdc++ from Libs.private) link
#     and run.
# Negative controls, each showing a check above can fail: the static-only
# libraries linked without --static (the bug of issue 24: -lm, Ceres only in
# Libs.private) fail with undefined symbols; a C++ program against brdf.h
# without its extern "C" guard fails to link; the shared program without the
# rpath cannot find libbrdf at run time.
# The catalog (issue 40): a C and a C++ program through pkg-config name a
# published form, bk_catalog_form("vf_talk_r"), and evaluate it; the value is
# the talk's printed f0/(4 LoH^2 (r + 0.5)) computed here by hand (0.05 at
# LoH 0.5, r 0.3, f0 0.04); an unknown name fails with its message (control).
# Exports: `nm -D --defined-only` of the two installed libraries lists exactly
# the bk_ functions the installed headers declare (read from the preprocessed
# headers, not from the Makefile's version script), each once, and no
# internal symbol (the search's modules, the benchmark switches); negative
# control: libbrdf's objects linked without the version script export more.
# Stripped: the installed .so has no .debug_info, its split debug file under
# lib/debug/.build-id/ has it, and gdb finds bk_catalog_form's source line
# through it (set debug-file-directory); negative control: without that
# directory gdb finds no line.
# The manual pages: a page per command under share/man/man1 of the stage, and
# from PREFIX `MANPATH=PREFIX/share/man man -w` finds brdfkit(1) and
# brdfkit-search(1), which render without a warning (man --warnings); its
# brdfkit_catalog(3) (section 3: the library's pages); its
# negative control: a page that was not installed is not found.
set -u
T=$(mktemp -d /tmp/bk_install_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
V=$(sed -n 's/^#define BK_VERSION "\(.*\)"/\1/p' brdf/brdf.h)
CSVGET=build/csvget
. tests/lib.sh # api_names
SO=${V%%.*}

# ---- the layout under DESTDIR/PREFIX ----------------------------------------
S="$T/stage/opt/bk"
${MAKE:-make} -s install PREFIX=/opt/bk DESTDIR="$T/stage" >/dev/null || bad "make install"
for f in lib/libbrdf.a lib/libbrdfkit-fit.a lib/libbrdf.so.$V lib/libbrdfkit-fit.so.$V include/brdf.h \
	include/brdfkit/search.h include/brdfkit/fit.h include/brdfkit/expr.h include/brdfkit/target.h \
	include/brdfkit/solver.h include/brdfkit/brdf.h include/brdfkit/brdf_ops.h include/brdfkit/ir_ops.h \
	include/brdfkit/catalog.h lib/pkgconfig/brdfkit.pc bin/brdfkit bin/brdfkit-mpi share/man/man3/brdfkit_catalog.3; do
	[ -f "$S/$f" ] && ok || bad "missing $f under DESTDIR/PREFIX"
done
for l in libbrdf libbrdfkit-fit; do # the soname and the name -l finds, links to the file
	[ "$(readlink "$S/lib/$l.so.$SO")" = "$l.so.$V" ] && [ "$(readlink "$S/lib/$l.so")" = "$l.so.$SO" ] && ok ||
		bad "$l symlinks"
	readelf -d "$S/lib/$l.so.$V" | grep -q "SONAME.*\[$l\.so\.$SO\]" && ok || bad "$l soname"
done
grep -q '^prefix=/opt/bk$' "$S/lib/pkgconfig/brdfkit.pc" && ok || bad "pc prefix"
for c in $(build/brdfkit --help | awk '/^commands:/ { on = 1; next } on && /^  [a-z]/ { print $1 }') mpi; do
	[ -f "$S/share/man/man1/brdfkit-$c.1" ] || bad "no manual page share/man/man1/brdfkit-$c.1 under DESTDIR/PREFIX"
done
[ -f "$S/share/man/man1/brdfkit.1" ] && ok || bad "no manual page share/man/man1/brdfkit.1 under DESTDIR/PREFIX"

# ---- exports: exactly the installed headers' functions ------------------------
# exported LIB...: the symbols the libraries define for others, one a line (a
# name twice if two define it)
exported() { for l in "$@"; do nm -D --defined-only "$l" | awk 'NF == 3 { print $3 }'; done | LC_ALL=C sort; }
# exports_exact LIB...: exported == declared, or the difference printed
exports_exact() {
	exported "$@" >"$T/exp.txt"
	diff "$T/decl.txt" "$T/exp.txt" >"$T/exp.diff" || { head -8 "$T/exp.diff"; return 1; }
}
api_names "$S/include" >"$T/decl.txt" && [ "$(wc -l <"$T/decl.txt")" -ge 150 ] && ok ||
	bad "the installed headers' declarations: $(wc -l <"$T/decl.txt") names read"
exports_exact "$S/lib/libbrdf.so.$V" "$S/lib/libbrdfkit-fit.so.$V" && ok || bad "exports are not the headers' functions"
# internal: the benchmark switches, an IR helper, a fitter module; each defined
# in the objects the libraries are linked from (so the check is not vacuous)
nm -g --defined-only build/pic/brdf/*.o build/pic/fit/*.o | awk 'NF == 3 { print $3 }' >"$T/objsyms"
for sym in bk_tiny_fixed bk_fit_ctx_bind bk_ir_const bk_albfit_new; do
	grep -qx "$sym" "$T/objsyms" && ! exported "$S/lib/libbrdf.so.$V" "$S/lib/libbrdfkit-fit.so.$V" | grep -qx "$sym" &&
		ok || bad "internal $sym exported, or not in the objects"
done
exported "$S/lib/libbrdfkit-fit.so.$V" | grep -qx bk_catalog_form && ok || bad "bk_catalog_form not exported"
# negative control: libbrdf's own objects, linked without the version script
gcc -shared build/pic/brdf/*.o -lm -o "$T/libopen.so" &&
	! exports_exact "$T/libopen.so" "$S/lib/libbrdfkit-fit.so.$V" >/dev/null && ok ||
	bad "a library exporting everything passed the exports check"

# ---- stripped, the debug info split off ---------------------------------------
for l in libbrdf libbrdfkit-fit; do
	so="$S/lib/$l.so.$V"
	id=$(readelf -n "$so" | sed -n 's/.*Build ID: *\([0-9a-f]*\).*/\1/p')
	dbg="$S/lib/debug/.build-id/$(echo "$id" | cut -c1-2)/$(echo "$id" | cut -c3-).debug"
	! readelf -S "$so" | grep -q '\.debug_info' && readelf -S "$so" | grep -q '\.gnu_debuglink' && ok ||
		bad "$l.so.$V: not stripped, or no debug link"
	[ -n "$id" ] && [ -f "$dbg" ] && readelf -S "$dbg" | grep -q '\.debug_info' && ok || bad "$l: no debug file $dbg"
	echo "install: $l.so.$V $(wc -c <"$so") bytes, debug $(wc -c <"$dbg" 2>/dev/null) bytes (the -g build: $(wc -c <build/$l.so.$V))"
done
gdbline() { gdb -nx -batch -ex "set debug-file-directory $1" -ex "file $S/lib/libbrdfkit-fit.so.$V" -ex 'info line bk_catalog_form' 2>&1; }
gdbline "$S/lib/debug" | grep -q 'Line [0-9]* of "fit/catalog.c"' && ok || bad "gdb through lib/debug: $(gdbline "$S/lib/debug" | tail -1)"
! gdbline "$T/nowhere" | grep -q 'Line [0-9]* of' && ok || bad "gdb found a line without the debug files: the check proves nothing"

# ---- the catalog's program ------------------------------------------------------
# the catalog by name, C and C++: vf_talk_r at LoH 0.5, r 0.3, f0 0.04, and an
# unknown name
cat >"$T/cat.c" <<'C'
#include <brdfkit/catalog.h>
#include <stdio.h>
int main(void)
{
	bk_form_error fe;
	double p[BK_MAX_PARAMS];
	bk_form *f = bk_catalog_form("vf_talk_r", p, &fe);
	if (!f)
		return fprintf(stderr, "%s\n", fe.message), 1;
	double loh = 0.5, r = 0.3, f0 = 0.04, v = -1;
	const double *in[BK_IN_COUNT] = {0};
	in[BK_IN_LOH] = &loh, in[BK_IN_R] = &r, in[BK_IN_F0] = &f0;
	int rc = bk_form_eval(f, BK_F64, 1, in, p, &v);
	bk_form_free(f);
	bk_form *g = bk_catalog_form("zz_no_such_form", p, &fe);
	printf("%d %.17g %s\n", rc, v, g ? "found" : fe.message);
	return 0;
}
C
cp "$T/cat.c" "$T/cat.cc"
# the talk's printed V*F with brdfkit's 1/4 (catalog.c's note): f0/(4 LoH^2 (r + 0.5))
cat_expect() {
	awk '{ want = 0.04 / (4 * 0.5 * 0.5 * (0.3 + 0.5)); d = $2 - want; if (d < 0) d = -d
		exit !($1 == 0 && d <= 1e-15 * want && $0 ~ /unknown catalog form .zz_no_such_form./) }' "$1"
}

# ---- the programs -------------------------------------------------------------
cat >"$T/use.c" <<'C'
#include <brdf.h>
#include <stdio.h>
int main(void) { printf("%.15f\n", bk_D_ggx(0.3, 1.0) * BK_PI); return 0; }
C
cat >"$T/plant.c" <<'C'
/* a program of the search's installed API alone */
#include <brdfkit/brdf_ops.h>
#include <brdfkit/search.h>
_Static_assert(BK_OP_PARAM < BK_OP_COUNT, "the opcodes a tree is made of, from the installed table");
#include <math.h> /* NAN */
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

/* mean square error of candidate c's values against samples sm (no sqrt:
 * the program needs no libm of its own, only what pkg-config gives) */
static double mse(const bk_cand *c, const bk_samples *sm)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(c->text, &fe);
	double v[4096], se = 0;
	if (!f || sm->n > 4096 || bk_form_eval(f, BK_F64, sm->n, (const double *const *)sm->in, c->p, v))
		return NAN;
	bk_form_free(f);
	for (size_t i = 0; i < sm->n; i++)
		se += (v[i] - sm->y[i]) * (v[i] - sm->y[i]);
	return se / (double)sm->n;
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
	       asked, best->text, mse(best, &sm), mse(best, &wrong));
	bk_search_free(s);
	bk_samples_free(&sm);
	bk_samples_free(&wrong);
	return 0;
}
C
# C++: bk_D_ggx and the fitter, and one function of each other installed
# header (so that a header without C linkage fails the link)
cat >"$T/use.cc" <<'CC'
#include <brdf.h>
#include <brdfkit/brdf_ops.h>
#include <brdfkit/expr.h>
#include <brdfkit/fit.h>
#include <brdfkit/search.h>
#include <brdfkit/solver.h>
#include <brdfkit/target.h>
#include <cmath>
#include <cstdio>

static int heard;
static int progress(void *, int, int, const bk_fit_summary *) { return heard++, 0; }

int main()
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_FORM, &to);                          // target.h
	to.form_text = "0.45*LoH*LoH + 0.2";
	to.ndomain = 1;
	to.dom_in[0] = BK_IN_LOH, to.dom_lo[0] = 0, to.dom_hi[0] = 1;
	to.nx = 32;
	char err[256];
	bk_samples sm;
	if (bk_target_build(&to, &sm, nullptr, nullptr, err, sizeof err))
		return std::fprintf(stderr, "%s\n", err), 1;
	bk_form_error fe;
	bk_form *f = bk_form_parse("p0*LoH*LoH + p1", &fe);               // brdf.h
	bk_fit_spec sp;
	bk_fit_defaults(&sp);                                              // fit.h
	sp.s = &sm, sp.form[0] = f, sp.np = bk_form_nparams(f), sp.starts = 2;
	bk_fit_callbacks cb = BK_FIT_CALLBACKS_INIT;
	cb.progress = progress;
	bk_fit_result res;
	int rc = bk_fit_run_cb(&sp, &cb, &res);
	char why[128];
	int valid = bk_fit_options_valid(&sp.opt, why, sizeof why);        // solver.h
	bk_search_options so;
	bk_search_defaults(&so);                                           // search.h
	std::printf("D %.15f fit %d p0 %.12f p1 %.12f progress %d valid %d ops %s %llx evals %ld\n",
	            bk_D_ggx(0.3, 1.0) * BK_PI, rc, res.p[0], res.p[1], heard, valid,
	            bk_op_name(BK_OP_SQRT),                                // brdf_ops.h
	            (unsigned long long)bk_grammar_default_ops(), so.evals); // expr.h
	bk_form_free(f);
	bk_samples_free(&sm);
	return 0;
}
CC
cxx_expect() { # the C++ program's line: 1/π, converged, the planted constants, 2 starts heard
	awk '{ exit !($2 == "1.000000000000000" && $4 == 0 && $6 == "0.450000000000" && $8 == "0.200000000000" &&
		$10 == 2 && $12 == 1 && $14 == "sqrt") }' "$1"
}

# ---- shared, from PREFIX, pkg-config alone --------------------------------------
U="$T/usr"
${MAKE:-make} -s install PREFIX="$U" >/dev/null || bad "make install PREFIX"
flags=$(PKG_CONFIG_PATH="$U/lib/pkgconfig" pkg-config --cflags --libs brdfkit) || bad "pkg-config"
cc -std=c11 "$T/use.c" $flags -o "$T/use" && [ "$("$T/use")" = "1.000000000000000" ] && ok ||
	bad "a C program through pkg-config --cflags --libs"
readelf -d "$T/use" | grep -q "NEEDED.*\[libbrdf\.so\.$SO\]" && readelf -d "$T/use" | grep -q "R.*PATH.*\[$U/lib\]" &&
	ok || bad "the C program links libbrdf.so.$SO with the rpath $U/lib"
cc -std=c11 "$T/plant.c" $flags -o "$T/plant" 2>"$T/plant.err" && "$T/plant" >"$T/plant.out" && ok ||
	bad "the search through the installed headers: $(cat "$T/plant.err" "$T/plant.out" 2>/dev/null | head -5)"
num() { tr ' ' '\n' <"$T/plant.out" | awk -v k="$1" 'p { print; exit } $0 == k { p = 1 }'; }
# the planted form found: its rmse a rounding error (below 1e-9 of its values' 0.2 to 0.65; mse 1e-18)
awk -v e="$(num planted)" 'BEGIN { exit !(e != "" && e + 0 < 1e-18) }' && ok || bad "planted form not recovered: $(cat "$T/plant.out")"
# negative control: the same form against a plant of another constant is far off
awk -v e="$(num wrong)" 'BEGIN { exit !(e != "" && e + 0 > 1e-6) }' && ok || bad "a wrong plant reads as recovered: $(cat "$T/plant.out")"
# the callbacks were called: stop after each step, progress at least once
awk -v p="$(num progress)" -v q="$(num stop)" 'BEGIN { exit !(p >= 1 && q >= 1) }' && ok || bad "callbacks not called: $(cat "$T/plant.out")"
g++ -std=c++17 -Wall -Wextra -Werror -c "$T/use.cc" $(PKG_CONFIG_PATH="$U/lib/pkgconfig" pkg-config --cflags brdfkit) \
	-o "$T/use_cc.o" && g++ "$T/use_cc.o" $flags -o "$T/use_cc" && "$T/use_cc" >"$T/use_cc.out" && cxx_expect "$T/use_cc.out" &&
	ok || bad "a C++ program through pkg-config: $(cat "$T/use_cc.out" 2>/dev/null)"
cc -std=c11 -Wall -Wextra -Werror "$T/cat.c" $flags -o "$T/cat" && "$T/cat" >"$T/cat.out" && cat_expect "$T/cat.out" && ok ||
	bad "the catalog by name from C: $(cat "$T/cat.out" 2>/dev/null)"
g++ -std=c++17 -Wall -Wextra -Werror "$T/cat.cc" $flags -o "$T/cat_cc" && "$T/cat_cc" >"$T/cat_cc.out" &&
	cat_expect "$T/cat_cc.out" && ok || bad "the catalog by name from C++: $(cat "$T/cat_cc.out" 2>/dev/null)"
# negative control: the expectation rejects a value off by one part in 1e12
sed 's/^0 [^ ]*/0 0.05000000000005/' "$T/cat.out" >"$T/cat.off" && ! cat_expect "$T/cat.off" && ok ||
	bad "a wrong catalog value passed the check"
# C linkage: the C++ object refers to our functions by their C names only
nm -u "$T/use_cc.o" | grep -q ' bk_D_ggx$' && ! nm -u "$T/use_cc.o" | grep -q '_Z.*bk_' && ok ||
	bad "mangled brdfkit names in the C++ object: $(nm -u "$T/use_cc.o" | grep '_Z.*bk_' | head -3)"
# each installed header alone, C11 and C++17 (ir_ops.h is the opcode table
# brdf_ops.h expands, no header of its own)
for h in brdf.h brdfkit/brdf.h brdfkit/brdf_ops.h brdfkit/solver.h brdfkit/target.h brdfkit/fit.h brdfkit/expr.h \
	brdfkit/search.h brdfkit/catalog.h; do
	echo "#include <$h>" >"$T/h.c"
	cp "$T/h.c" "$T/h.cc"
	gcc -std=c11 -Wall -Wextra -Werror -I"$U/include" -c "$T/h.c" -o /dev/null &&
		g++ -std=c++17 -Wall -Wextra -Werror -I"$U/include" -c "$T/h.cc" -o /dev/null && ok || bad "$h alone as C11 and C++17"
done
grep -q 'extern "C"' "$U/include/brdfkit/fit.h" && ok || bad "fit.h guard"
# negative control: without the rpath the program does not find libbrdf
cc -std=c11 "$T/use.c" $(echo "$flags" | sed 's/-Wl,-rpath,[^ ]*//') -o "$T/use_norpath" && ! "$T/use_norpath" >/dev/null 2>&1 &&
	ok || bad "a program without the rpath ran: the rpath check proves nothing"
# negative control: brdf.h without its guard, C++ links a mangled bk_D_ggx and fails
mkdir -p "$T/noguard"
awk '/^#ifdef __cplusplus/ { skip = 2; next } skip && /^(extern "C"|}|#endif)/ { skip--; next } { skip = 0; print }' \
	"$U/include/brdf.h" >"$T/noguard/brdf.h"
printf '#include <brdf.h>\n#include <cstdio>\nint main() { std::printf("%%g\\n", bk_D_ggx(0.3, 1.0)); }\n' >"$T/ng.cc"
! grep -q 'extern "C"' "$T/noguard/brdf.h" && ! g++ -std=c++17 -I"$T/noguard" "$T/ng.cc" $flags -o "$T/ng" 2>/dev/null &&
	g++ -std=c++17 -I"$U/include" "$T/ng.cc" $flags -o "$T/ng" && ok || bad "the guard's negative control"

# ---- static, from the stage without the shared libraries ------------------------
rm -f "$S"/lib/*.so*
sflags=$(PKG_CONFIG_PATH="$S/lib/pkgconfig" pkg-config --define-prefix --static --cflags --libs brdfkit) || bad "pkg-config --static"
cc -std=c11 "$T/use.c" $sflags -o "$T/use_s" && [ "$("$T/use_s")" = "1.000000000000000" ] &&
	! readelf -d "$T/use_s" | grep -q 'NEEDED.*libbrdf' && ok || bad "static C link"
g++ "$T/use_cc.o" $sflags -o "$T/use_cc_s" && "$T/use_cc_s" >"$T/use_cc_s.out" && cxx_expect "$T/use_cc_s.out" && ok ||
	bad "static C++ link: $(cat "$T/use_cc_s.out" 2>/dev/null)"
# negative control: the archives without Libs.private (issue 24's .pc): libm undefined
# (bk_D_ggx's object calls sqrt)
nflags=$(PKG_CONFIG_PATH="$S/lib/pkgconfig" pkg-config --define-prefix --cflags --libs brdfkit)
! cc -std=c11 "$T/use.c" $nflags -o "$T/use_n" 2>"$T/use_n.err" && grep -q 'undefined reference to .sqrt' "$T/use_n.err" &&
	ok || bad "the archives linked without Libs.private: the static check proves nothing"

"$U/bin/brdfkit" --version | grep -q '^brdfkit ' && ok || bad "installed tool"

# ---- the manual pages, from PREFIX ------------------------------------------------
for p in brdfkit brdfkit-search; do
	f=$(MANPATH="$U/share/man" man -w "$p" 2>/dev/null)
	[ "$f" = "$U/share/man/man1/$p.1" ] && ok || bad "man -w $p: '$f', not the installed page"
	MANPATH="$U/share/man" MANWIDTH=80 LC_ALL=C.UTF-8 man --warnings "$p" >"$T/man.out" 2>"$T/man.err" &&
		[ ! -s "$T/man.err" ] && grep -q "^NAME" "$T/man.out" && ok || bad "man $p: $(head -3 "$T/man.err")"
done
# section 3: the catalog's page, from PREFIX
f=$(MANPATH="$U/share/man" man -w 3 brdfkit_catalog 2>/dev/null)
[ "$f" = "$U/share/man/man3/brdfkit_catalog.3" ] && ok || bad "man -w 3 brdfkit_catalog: '$f'"
# negative control: a page that was not installed is not found
! MANPATH="$U/share/man" man -w brdfkit-zzfake >/dev/null 2>&1 && ok || bad "man -w found a page never installed"

echo "install: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
