/*
 * bench_enum.c — the unique-form enumeration's counts and rate (issue 38),
 * as ESR's tables give them: for each target's default grammar and each
 * size, the raw trees of the grammar (bk_grammar_trees), the canonical
 * trees the enumeration draws (a pair's tree once for each of its three
 * kinds), the twins left out (fit/search/unique.h), the unique forms
 * fitted, and the CPU seconds and wall seconds until the size was complete
 * (the certificate's size reached). Then the rate (unique forms fitted per
 * CPU-second and per wall-second), the fingerprints' share of the CPU time,
 * and, from the growth of the last two sizes, the size a 64-core MPI run
 * would certify in 10 minutes.
 *
 * With --audit, each twin is checked against the form it was taken for, at
 * every screening sample (not the fingerprint's 64) and at the fingerprint's
 * parameter vectors and eight more drawn uniformly in (-3, 3): a twin whose values
 * differ anywhere by more than rounding is a false twin, a unique form the
 * certificate says was fitted and was not. The audit is the bound on the
 * fingerprint's misses on the samples the fits see.
 *
 * usage: bench_enum [--targets vf2d,f,env] [--max N] [--threads T] [--audit]
 *   --max N       the last size enumerated (default: 7 for vf2d and env, 8 for f)
 *   --audit       check every twin as above (slower: each twin evaluated at
 *                 every screening sample)
 * The screening grid and the grammar are brdfkit search's (fit/search/seeds.h).
 * Times vary with the machine; the counts do not.
 */
#include "clock.h"
#include "search.h"
#include "search/seeds.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct watch {
	int done;                         /* the certificate's size so far */
	int want;                         /* the size to stop at */
	double cpu0, wall0;
	double cpu[BK_EXPR_MAX + 1], wall[BK_EXPR_MAX + 1];
} watch;

static void progress(void *ctx, const bk_search *S)
{
	watch *w = ctx;
	bk_search_cert c;
	bk_search_certificate(S, &c);
	for (; w->done < c.complete_size; w->done++) {
		w->cpu[w->done + 1] = bk_clock_cpu() - w->cpu0;
		w->wall[w->done + 1] = bk_clock_now() - w->wall0;
	}
}

static int whole(void *ctx, const bk_search *S)
{
	(void)S;
	return ((const watch *)ctx)->done >= ((const watch *)ctx)->want;
}

/* The vectors the audit evaluates at beside the fingerprint's, and at most
 * how many of the fingerprint's it takes. */
#define AUDIT_EXTRA 8
#define AUDIT_VECTORS (16 + AUDIT_EXTRA)

/* The audit (--audit): the fitted spelling of each fingerprint, and the
 * twins whose values differ from it. */
typedef struct audit {
	const bk_samples *sm;
	double theta[AUDIT_VECTORS][BK_MAX_PARAMS]; /* the fingerprint's, then the audit's own */
	int nv;
	uint64_t *fp; /* open-addressed by fingerprint, 0 free */
	char **a, **b;
	size_t cap, n;
	long twins, false_twins, shown;
	double *va, *vb; /* the vectors x the samples, of the twin and of its spelling */
	int oom;
} audit;

static size_t audit_slot(const audit *au, uint64_t fp)
{
	size_t j = fp & (au->cap - 1);
	while (au->fp[j] && au->fp[j] != fp)
		j = (j + 1) & (au->cap - 1);
	return j;
}

static int audit_grow(audit *au)
{
	size_t cap = au->cap ? 2 * au->cap : 4096;
	uint64_t *fp = calloc(cap, sizeof *fp);
	char **a = calloc(cap, sizeof *a), **b = calloc(cap, sizeof *b);
	if (!fp || !a || !b) { /* au as it was */
		free(fp), free(a), free(b);
		return -1;
	}
	audit old = *au;
	au->cap = cap, au->fp = fp, au->a = a, au->b = b;
	for (size_t i = 0; i < old.cap; i++)
		if (old.fp[i]) {
			size_t j = audit_slot(au, old.fp[i]);
			au->fp[j] = old.fp[i], au->a[j] = old.a[i], au->b[j] = old.b[i];
		}
	free(old.fp), free(old.a), free(old.b);
	return 0;
}

/* The values of the forms of texts a and b (b NULL but for a pair) at every
 * screening sample at the vectors, one after the other into v (a
 * pair's A then B): the number of values, or -1 when one does not parse or
 * evaluate. */
static long audit_values(const audit *au, const char *a, const char *b, double *v)
{
	const char *text[2] = {a, b};
	long n = 0;
	for (int h = 0; h < 2 && text[h]; h++) {
		bk_form_error fe;
		bk_form *f = bk_form_parse(text[h], &fe);
		if (!f)
			return -1;
		for (int t = 0; t < au->nv; t++) {
			if (bk_form_eval(f, BK_F64, au->sm->n, (const double *const *)au->sm->in, au->theta[t], v + n)) {
				bk_form_free(f);
				return -1;
			}
			n += (long)au->sm->n;
		}
		bk_form_free(f);
	}
	return n;
}

/* Whether x and y are one value up to rounding (the fingerprint's classes:
 * NaN, each infinity, zero of either sign). */
static int same_value(double x, double y)
{
	if (isnan(x) || isnan(y))
		return isnan(x) && isnan(y);
	if (isinf(x) || isinf(y))
		return x == y;
	return fabs(x - y) <= 1e-9 * fmax(1.0, fmax(fabs(x), fabs(y)));
}

static void audit_one(void *ctx, const char *a, const char *b, uint64_t fp, int twin)
{
	audit *au = ctx;
	if (au->oom || !fp)
		return;
	if (2 * (au->n + 1) > au->cap && audit_grow(au)) {
		au->oom = 1;
		return;
	}
	size_t j = audit_slot(au, fp);
	if (!twin) {
		if (!au->fp[j]) { /* the model's first spelling (a cheaper one of a model is not met later) */
			au->fp[j] = fp, au->n++;
			au->a[j] = strdup(a), au->b[j] = b ? strdup(b) : NULL;
			au->oom = !au->a[j] || (b && !au->b[j]);
		}
		return;
	}
	au->twins++;
	if (!au->fp[j])
		return; /* its spelling came from a checkpoint: not here */
	long n = audit_values(au, a, b, au->va), m = audit_values(au, au->a[j], au->b[j], au->vb);
	int differ = n != m;
	for (long i = 0; !differ && i < n; i++)
		differ = !same_value(au->va[i], au->vb[i]);
	if (differ && au->shown++ < 3)
		fprintf(stderr, "bench_enum: audit: false twin %s%s%s taken for %s%s%s\n", a, b ? " ; " : "", b ? b : "",
		        au->a[j], au->b[j] ? " ; " : "", au->b[j] ? au->b[j] : "");
	au->false_twins += differ;
}

static void audit_free(audit *au)
{
	for (size_t i = 0; i < au->cap; i++)
		if (au->fp && au->fp[i])
			free(au->a[i]), free(au->b[i]);
	free(au->fp), free(au->a), free(au->b), free(au->va), free(au->vb);
}

static int run(bk_target_kind kind, const char *name, int max, int threads, int check)
{
	bk_target_options to;
	bk_target_defaults(kind, &to);
	bk_seeds_screening_grid(&to);
	bk_samples sm;
	char err[512];
	if (bk_target_build(&to, &sm, NULL, NULL, err, sizeof err)) {
		fprintf(stderr, "bench_enum: %s: %s\n", name, err);
		return 1;
	}
	bk_search_options o;
	bk_search_defaults(&o);
	o.screen = &sm;
	o.shape = kind == BK_TARGET_VF2D ? BK_SHAPE_F0 : kind == BK_TARGET_ENV ? BK_SHAPE_PAIR : BK_SHAPE_PLAIN;
	bk_seeds_grammar(&o.grammar, kind);
	o.grammar.inputs = sm.provides; /* as brdfkit search gives them (analysis/cli/search_setup.c) */
	if (o.shape == BK_SHAPE_F0)
		o.grammar.inputs &= ~(1u << BK_IN_F0);
	o.enum_size = max;
	o.enum_max = 1000000000L;
	o.evals = 1000000000L; /* the run ends with the enumeration (stop below): no evolution */
	o.generation = 4096;
	o.threads = threads;
	o.nonneg = 1;
	o.env_bound = kind == BK_TARGET_ENV;
	bk_search *S = bk_search_new(&o, err, sizeof err);
	if (!S) {
		fprintf(stderr, "bench_enum: %s: %s\n", name, err);
		bk_samples_free(&sm);
		return 1;
	}
	audit au = {.sm = &sm};
	size_t probes, stride;
	int nfp = bk_search_twin_probes(S, au.theta, AUDIT_VECTORS - AUDIT_EXTRA, &probes, &stride);
	au.nv = (nfp < AUDIT_VECTORS - AUDIT_EXTRA ? nfp : AUDIT_VECTORS - AUDIT_EXTRA) + AUDIT_EXTRA;
	uint64_t rng = 0x2545f4914f6cdd1dull; /* the audit's own vectors: uniform in (-3, 3) */
	for (int t = au.nv - AUDIT_EXTRA; t < au.nv; t++)
		for (int j = 0; j < BK_MAX_PARAMS; j++) {
			rng = rng * 6364136223846793005ull + 1442695040888963407ull;
			au.theta[t][j] = 6.0 * ((double)(rng >> 11) * 0x1p-53) - 3.0;
		}
	if (check) {
		au.va = malloc(2 * (size_t)au.nv * sm.n * sizeof *au.va);
		au.vb = malloc(2 * (size_t)au.nv * sm.n * sizeof *au.vb);
		if (!au.va || !au.vb) {
			fprintf(stderr, "bench_enum: %s: out of memory\n", name);
			audit_free(&au);
			bk_search_free(S);
			bk_samples_free(&sm);
			return 1;
		}
		bk_search_on_twin(S, audit_one, &au);
	}
	watch w = {0, max, bk_clock_cpu(), bk_clock_now(), {0}, {0}};
	bk_search_callbacks cb = {progress, whole, &w, 0};
	if (bk_search_drive(S, &cb, err, sizeof err) < 0 || au.oom) {
		fprintf(stderr, "bench_enum: %s: %s\n", name, au.oom ? "out of memory" : err);
		audit_free(&au);
		bk_search_free(S);
		bk_samples_free(&sm);
		return 1;
	}
	bk_search_cert c;
	bk_search_certificate(S, &c);
	char g[1024];
	bk_grammar_describe(&o.grammar, g, sizeof g);
	printf("%s (%zu screening samples, %s; %d thread%s): complete to %d nodes\n  grammar: %s\n", name, sm.n,
	       o.shape == BK_SHAPE_PAIR ? "pairs: each tree as A, as B and as a shared feature" : "one tree each",
	       threads, threads == 1 ? "" : "s", c.complete_size, g);
	printf("  %4s %14s %11s %11s %10s %10s %9s %8s\n", "size", "raw trees", "canonical", "twins", "fitted",
	       "cumulative", "CPU s", "wall s");
	long cum = 0, all_drawn = 0;
	for (int k = 1; k <= c.complete_size; k++) {
		cum += c.fitted[k];
		all_drawn += c.drawn[k];
		printf("  %4d %14.4g %11ld %11ld %10ld %10ld %9.2f %8.2f\n", k, bk_grammar_trees(&o.grammar, k), c.drawn[k],
		       c.twins[k], c.fitted[k], cum, w.cpu[k], w.wall[k]);
	}
	int n = c.complete_size;
	double cpu = w.cpu[n], wall = w.wall[n];
	printf("  rate: %.0f unique forms fitted per CPU-s, %.0f per wall-s; fingerprints %.2f CPU-s (%.1f us a "
	       "fingerprinted candidate, %.1f %% of the CPU time)\n",
	       cpu > 0 ? (double)cum / cpu : 0.0, wall > 0 ? (double)cum / wall : 0.0, c.dedup_seconds,
	       all_drawn > 0 ? 1e6 * c.dedup_seconds / (double)all_drawn : 0.0, cpu > 0 ? 100 * c.dedup_seconds / cpu : 0.0);
	printf("  probes: screening sample i %zu mod %zu for i < %zu, at %d parameter vectors\n", stride, sm.n, probes, nfp);
	if (check)
		printf("  audit: %ld of %ld twins differ from the form they were taken for (at every screening sample, "
		       "%d parameter vectors)\n", au.false_twins, au.twins, au.nv);
	audit_free(&au);
	/* how often a start after the first changed the answer (screen.c: the
	 * next start runs only where the one before did not converge, or
	 * converged no better than a constant) */
	long ok = 0, more = 0, won = 0;
	for (size_t i = 0; i < bk_search_count(S); i++) {
		const bk_cand *q = bk_search_at(S, i);
		if (q->status != BK_CAND_OK)
			continue;
		ok++;
		more += q->starts_run > 1;
		won += q->start_won > 0;
	}
	printf("  starts: of %ld forms fitted within the limits, %ld ran a second start (%.1f %%) and %ld kept a later "
	       "start's constants (%.1f %%)\n", ok, more, ok ? 100.0 * (double)more / (double)ok : 0.0, won,
	       ok ? 100.0 * (double)won / (double)ok : 0.0);
	/* The drawing alone (expr.h's enumerator, one thread): every island of an
	 * MPI run draws every tree and keeps its share, so the drawing is not
	 * shared out; the fits are. */
	bk_grammar eg = o.grammar; /* the enumerated tree's grammar (search/driver.c) */
	if (o.shape == BK_SHAPE_PAIR && eg.max_params > 1)
		eg.max_params /= 2;
	if (o.scale && eg.max_params > 0)
		eg.max_params--;
	double t0 = bk_clock_now();
	bk_expr_enum *E = bk_expr_enum_new(&eg, n, BK_SEARCH_ENUM_TREES);
	long trees[BK_EXPR_MAX + 1] = {0}, all = 0;
	bk_expr e;
	for (int r; E && (r = bk_expr_enum_next(E, &e)) > 0;)
		trees[r]++, all++;
	bk_expr_enum_free(E);
	double rate = all / fmax(bk_clock_now() - t0, 1e-9);
	printf("  drawing alone: %.2g trees/s (one thread, the canonical rules and the nesting limit applied)\n", rate);
	if (n >= 3 && c.fitted[n - 1] > 0 && trees[n - 1] > 0) {
		/* the next sizes grow as the last did */
		double gf = (double)c.fitted[n] / (double)c.fitted[n - 1], gt = (double)trees[n] / (double)trees[n - 1];
		double per = cpu / (double)cum, f = (double)c.fitted[n], t = (double)trees[n];
		double fits = (double)cum, drawn = (double)all, kept = (double)(all - trees[n]);
		int k = n;
		double wall = 0, next = 0, keep_gb = 0;
		for (;;) {
			f *= gf, t *= gt;
			double w = (drawn + t) / rate + (fits + f) * per / 64;
			if (k >= BK_EXPR_MAX || w > 600) {
				next = (fits + f) * per / 3600;
				break;
			}
			kept = drawn, drawn += t, fits += f, wall = w, k++;
		}
		keep_gb = kept * 160 / 1e9;
		printf("  growth a node: fitted %.1fx, trees %.1fx at size %d; a 64-core MPI run of 10 minutes, each rank "
		       "drawing every tree and fitting its share, would certify %d nodes (a rank: %.0f s, keeping %.2g "
		       "GB of trees); the next node: %.2g core-hours of fits, its drawing alone %.0f s a rank\n",
		       gf, gt, n, k, wall, keep_gb, next, (drawn + t) / rate);
	}
	bk_search_free(S);
	bk_samples_free(&sm);
	return 0;
}

int main(int argc, char **argv)
{
	const char *targets = "vf2d,f,env";
	int max = 0, threads = 2, check = 0;
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--targets") && i + 1 < argc)
			targets = argv[++i];
		else if (!strcmp(argv[i], "--max") && i + 1 < argc)
			max = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
			threads = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--audit"))
			check = 1;
		else {
			fprintf(stderr, "usage: bench_enum [--targets vf2d,f,env] [--max N] [--threads T] [--audit]\n");
			return 2;
		}
	}
	if (max < 0 || max > 9 || threads < 1 || threads > 64) {
		fprintf(stderr, "bench_enum: --max 1 to 9, --threads 1 to 64\n");
		return 2;
	}
	static const struct {
		const char *name;
		bk_target_kind kind;
		int max;
	} all[] = {{"vf2d", BK_TARGET_VF2D, 7}, {"f", BK_TARGET_F, 8}, {"env", BK_TARGET_ENV, 7}};
	int rc = 0;
	for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
		size_t n = strlen(all[i].name);
		for (const char *p = targets; p; p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL)
			if (!strncmp(p, all[i].name, n) && (p[n] == ',' || p[n] == '\0')) {
				rc |= run(all[i].kind, all[i].name, max ? max : all[i].max, threads, check);
				break;
			}
	}
	return rc;
}
