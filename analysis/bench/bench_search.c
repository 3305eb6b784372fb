/*
 * bench_search.c — make bench: the search's speed, side by side in one run.
 *
 *   1. screening fits per second: a search on vf2d at 32x32 (1,024 samples,
 *      the screening grid of brdfkit search), the default grammar, at most 4
 *      parameters, a fixed budget of fits, on 1 and on 2 threads (median of
 *      REPS runs each; the same candidates each time: the search is
 *      deterministic; 20,000 fits: the enumeration and 15,000 evolved children,
 *      whose trees are larger). Target (issue 10): >= 2,000 fits/s on 2 threads.
 *   2. the same candidates fitted one by one by SciPy's least_squares
 *      (analysis/bench/bench_search_scipy.py: method 'lm', the Jacobian by
 *      finite differences as a SciPy user fitting a formula string would, the
 *      same residuals sqrt(w)(f - y), the same start of all ones, at most as
 *      many iterations), for the ratio. SciPy's time per fit is taken over
 *      NSCIPY candidates with parameters spread over the run; brdfkit's figure
 *      is the whole search (generation, cost, up to two starts, scoring).
 *   3. IR node evaluations per second in f32: every candidate of the run
 *      evaluated by bk_form_eval on the 1,024 samples (nodes: the tree's size),
 *      single thread. Target: >= 1 G nodes/s per core (PySR publishes ~0.5 G
 *      per thread).
 */
#include "brdf.h"
#include "catalog.h"
#include "clock.h"
#include "bench_vf2d.h"
#include "search.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REPS 3
#define EVALS 20000
#define NSCIPY 300

static double run_search(const bk_search_options *o, bk_search **keep)
{
	char err[256];
	bk_search *s = bk_search_new(o, err, sizeof err);
	if (!s) {
		fprintf(stderr, "bench_search: %s\n", err);
		exit(1);
	}
	double t0 = bk_clock_now();
	int rc = bk_search_run(s, NULL, NULL, err, sizeof err);
	double dt = bk_clock_now() - t0;
	if (rc < 0) {
		fprintf(stderr, "bench_search: %s\n", err);
		exit(1);
	}
	if (keep && !*keep)
		*keep = s;
	else
		bk_search_free(s);
	return dt;
}

/* The samples and the candidates for the SciPy side, as text. */
static void write_problem(const bk_samples *sm, const bk_search *s, const char *path)
{
	FILE *f = fopen(path, "w");
	if (!f) {
		fprintf(stderr, "bench_search: cannot write %s\n", path);
		exit(1);
	}
	fprintf(f, "%zu\n", sm->n);
	for (size_t i = 0; i < sm->n; i++)
		fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g\n", sm->in[BK_IN_LOH][i], sm->in[BK_IN_R][i],
		        sm->in[BK_IN_A][i], sm->in[BK_IN_F0][i], sm->y[i], sm->w[i]);
	/* NSCIPY candidates spread over the whole run (the enumeration's small
	 * trees first, the evolved larger ones after), as brdfkit's figure is */
	size_t n = bk_search_count(s), stride = n / NSCIPY ? n / NSCIPY : 1;
	int k = 0;
	for (size_t i = 0; i < n && k < NSCIPY; i += stride) {
		const bk_cand *c = bk_search_at(s, i);
		if (c->np == 0 || c->seed_name)
			continue;
		fprintf(f, "%d %s\n", c->np, c->text);
		k++;
	}
	fclose(f);
}

int main(void)
{
	bk_samples sm;
	bk_search_options o;
	bench_vf2d_case("bench_search", EVALS, &sm, &o);

	printf("bench_search: vf2d 32x32 (%zu samples), default grammar, <= 4 parameters, %d fits per run, median of %d\n",
	       sm.n, EVALS, REPS);
	bk_search *keep = NULL;
	double t[2][REPS];
	for (int r = 0; r < REPS; r++) /* interleaved: machine noise hits both alike */
		for (int th = 1; th <= 2; th++) {
			o.threads = th;
			t[th - 1][r] = run_search(&o, &keep);
		}
	double fps[2];
	for (int th = 0; th < 2; th++) {
		fps[th] = EVALS / bk_clock_median(t[th], REPS);
		printf("  screening fits/s, %d thread%s: %8.0f%s\n", th + 1, th ? "s" : " ", fps[th],
		       th ? (fps[th] >= 2000 ? "   (target >= 2000: met)" : "   (target >= 2000: NOT met)") : "");
	}

	/* IR node evaluations in f32 over every candidate of the run */
	double *v = malloc(sizeof(double) * sm.n);
	double nodes = 0, secs = 0;
	for (int rep = 0; rep < REPS; rep++) {
		double n = 0, t0 = bk_clock_now();
		for (size_t i = 0; i < bk_search_count(keep); i++) {
			const bk_cand *c = bk_search_at(keep, i);
			bk_form_error fe;
			bk_form *f = bk_form_parse(c->text, &fe);
			if (!f)
				continue;
			double p[BK_MAX_PARAMS];
			memcpy(p, c->p, sizeof p);
			for (int k = 0; k < 8; k++)
				bk_form_eval(f, BK_F32, sm.n, (const double *const *)sm.in, p, v);
			n += 8.0 * (double)sm.n * (double)(c->ntree[0] + (c->text_b ? c->ntree[1] : 0) + 2);
			bk_form_free(f);
		}
		double dt = bk_clock_now() - t0;
		if (rep == 0 || n / dt > nodes / secs)
			nodes = n, secs = dt;
	}
	free(v);
	printf("  IR node evaluations/s in f32, 1 thread (parse included): %.3g%s\n", nodes / secs,
	       nodes / secs >= 1e9 ? "   (target >= 1e9: met)" : "   (target >= 1e9: NOT met)");

	/* SciPy on the same candidates */
	const char *path = "build/bench_search_problem.txt";
	write_problem(&sm, keep, path);
	FILE *p = popen("/usr/bin/python3 analysis/bench/bench_search_scipy.py build/bench_search_problem.txt", "r");
	double spf = NAN;
	char line[256];
	while (p && fgets(line, sizeof line, p))
		if (sscanf(line, "seconds_per_fit %lf", &spf) == 1)
			break;
	if (p)
		pclose(p);
	if (isfinite(spf) && spf > 0)
		printf("  SciPy least_squares, one by one: %8.0f fits/s; brdfkit 1 thread / SciPy: %.1fx, 2 threads: %.1fx\n",
		       1 / spf, fps[0] * spf, fps[1] * spf);
	else
		printf("  SciPy least_squares: not run (python3-scipy missing?)\n");
	bk_search_free(keep);
	bk_samples_free(&sm);
	return 0;
}
