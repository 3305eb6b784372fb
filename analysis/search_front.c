/*
 * search_front.c — the search's front refitted and scored on the full
 * samples, beside the catalog and LUT rows (search_front.h).
 */
#include "search_front.h"

#include "albfit.h"
#include "catalog.h"
#include "lutrows.h"
#include "out.h"
#include "pool.h"
#include "search/constraint.h"
#include "search/pair.h"
#include "search/pareto.h"
#include "search/prune.h"
#include "search/refit.h"
#include "stability.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef bk_sfront_member member;


const char *bk_sfront_objective_name(const bk_search_options *so)
{
	static const char *const n[] = {"rmse", "max_abs", "albedo_max_abs"};
	if (so->relative && so->objective != BK_OBJ_ALBEDO)
		return so->objective == BK_OBJ_MAX ? "max_rel" : "rmse_rel";
	return n[so->objective];
}

int bk_sfront_beats(const member *m, const member *q)
{
	return !q->c && !q->status && m->cost <= q->cost && m->err <= q->err && (m->cost < q->cost || m->err < q->err);
}

/* A published seed (one of the first exempt_seeds the search was given),
 * kept whatever the constraints say, as the search keeps it (search.c names
 * a seed without a name "start K"). */
static int seed_exempt(const bk_search_options *so, const bk_cand *c)
{
	for (int k = 0; c && c->seed_name && k < so->nseeds && k < so->exempt_seeds; k++) {
		char name[32];
		snprintf(name, sizeof name, "start %d", k + 1);
		if (!strcmp(c->seed_name, so->seed_names && so->seed_names[k] ? so->seed_names[k] : name))
			return 1;
	}
	return 0;
}

/* --objective albedo: the least-squares point of fit's fitter minimises the
 * values' error, not the albedo's; from it, Lawson's minimax on the cells'
 * albedo errors (fit/albfit.h). The constants are rounded to 7 significant
 * digits (a float literal, and no last-bit difference of libm survives it)
 * and kept where they lower the albedo's max error; the standard errors stay
 * those of the least-squares point, and the message says so. */
static void albedo_minimax(const bk_sfront *F, member *m)
{
	bk_albfit *af = bk_albfit_new(F->s, m->f[0], m->spec.np);
	if (!af)
		return;
	double p[BK_MAX_PARAMS], before = bk_albfit_max(af, m->res.p), after;
	memcpy(p, m->res.p, sizeof p);
	bk_fit_options o = bk_refit_albedo_options();
	if (bk_albfit_run(af, p, 1, &o, &after) == 0 && after < before) {
		for (int j = 0; j < m->spec.np; j++) {
			char lit[32];
			snprintf(lit, sizeof lit, "%.7g", p[j]);
			p[j] = strtod(lit, NULL);
		}
		if (bk_albfit_max(af, p) < before) {
			memcpy(m->res.p, p, sizeof p);
			size_t k = strlen(m->res.message);
			snprintf(m->res.message + k, sizeof m->res.message - k, "%sconstants moved from the least-squares point "
			         "by the albedo minimax (standard errors: of that point)", k ? "; " : "");
		}
	}
	bk_albfit_free(af);
}

int bk_sfront_half_safe(const member *m)
{
	return !strcmp(m->verdict, "as is") || !strcmp(m->verdict, "with guards");
}

/* Stability in half, each half of a pair on its own: the worse verdict. */
static void stability(member *m, int finite)
{
	static const char *const verdict[3] = {"as is", "with guards", "no"};
	int worst = 0, analysed = 1;
	for (int q = 0; finite && q < (m->text_b ? 2 : 1); q++) {
		bk_stability st;
		char e2[256];
		if (bk_stability_run_form(m->name, m->f[q], m->spec.np ? m->res.p : NULL, BK_STAB_TOL, &st, e2,
		                          sizeof e2)) {
			analysed = 0;
			continue;
		}
		int w = st.safe_as_is ? 0 : st.guarded_ok ? 1 : 2; /* stability.h: a pole is never "as is" */
		if (w > worst) /* the worse of A and B */
			worst = w;
		bk_stability_free(&st);
	}
	snprintf(m->verdict, sizeof m->verdict, "%s", !finite ? "not finite" : analysed ? verdict[worst] : "not analysed");
}

/* Half precision reads every constant rounded to half (bk_form_eval BK_F16,
 * and the float16_t shader's literals), so the least-squares point in double
 * is not the best point a half shader can hold: a constant that cancels
 * against an input (p + LoH) loses its last bits. A pattern search on the
 * half grid itself — each constant moved by 1, 2, 4 ... 64 half ulps, the
 * best move of each kept while the error in half falls — finds the
 * representable point. Ceres stays the solver of the least-squares problem;
 * this is a discrete search over what the rounding allows, after it.
 * Returns the number of moves taken (0: the double point stands). */
static double half_step(double x, int k)
{
	double ax = fabs(x), ulp = ax < 0x1p-14 ? 0x1p-24 : ldexp(1.0, ilogb(ax) - 10);
	return bk_half_round(x + k * ulp);
}

static double half_err(const bk_sfront *F, const member *m, const double *p, double *v)
{
	const bk_samples *s = F->s;
	if (bk_refit_values(&m->spec, p, BK_F16, v))
		return HUGE_VAL;
	bk_fit_metrics h;
	bk_samples_metrics(s, v, NULL, &h);
	if (h.nonfinite || (!seed_exempt(F->so, m->c) && !bk_search_admissible(F->so, s, v)))
		return HUGE_VAL;
	double e = bk_search_error(F->so, s, v, &h);
	return isfinite(e) ? e : HUGE_VAL;
}

static int half_polish(const bk_sfront *F, member *m)
{
	double *v = malloc(sizeof(double) * F->s->n);
	if (!v)
		return 0;
	double p[BK_MAX_PARAMS], best;
	memcpy(p, m->res.p, sizeof p);
	for (int j = 0; j < m->spec.np; j++)
		p[j] = bk_half_round(p[j]); /* what half reads: the same error */
	best = half_err(F, m, p, v);
	int moves = 0;
	for (int pass = 0; pass < 16 && isfinite(best); pass++) {
		int moved = 0;
		for (int j = 0; j < m->spec.np; j++) {
			if (m->spec.hold[j] || m->res.held[j])
				continue;
			double keep = p[j], bj = keep, ej = best;
			for (int k = 1; k <= 64; k *= 2)
				for (int sgn = -1; sgn <= 1; sgn += 2) {
					p[j] = half_step(keep, sgn * k);
					if (!isfinite(p[j]) || p[j] == keep || p[j] < m->spec.lower[j] || p[j] > m->spec.upper[j])
						continue;
					double e = half_err(F, m, p, v);
					if (e < ej) {
						ej = e;
						bj = p[j];
					}
				}
			p[j] = bj;
			if (ej < best) {
				best = ej;
				moved = 1;
				moves++;
			}
		}
		if (!moved)
			break;
	}
	free(v);
	if (moves) {
		memcpy(m->res.p, p, sizeof p);
		size_t k = strlen(m->res.message);
		snprintf(m->res.message + k, sizeof m->res.message - k, "%sconstants moved on the half grid to the least error "
		         "in half (%d moves; standard errors: of the least-squares point)", k ? "; " : "", moves);
	}
	return moves;
}

/* The member on the full samples: fitted with fit's full fitter (the refit
 * preset: several starts, minimax for the max objective, optimality check,
 * constants rounded to what their standard errors justify) unless it is a
 * catalog row at its published constants; then its error in the search
 * precision, constraints on the denser grid, half-precision error and
 * stability. */
static int score_member(const bk_sfront *F, member *m, const double *start, int fit)
{
	const bk_search_options *so = F->so;
	bk_form_error fe;
	/* the search's own forms where it kept them (a candidate of this run on
	 * the front, as it was made: fit/search.h, parsed once); else the text
	 * is parsed here, where it comes in (a start, a merged front's member, a
	 * pruned form, a candidate read back from a checkpoint) */
	const bk_cand *c = m->c && m->c->form && m->text == m->c->text && m->text_b == m->c->text_b ? m->c : NULL;
	m->f[0] = c ? bk_form_dup(c->form) : bk_form_parse(m->text, &fe);
	m->f[1] = !m->text_b ? NULL : c ? bk_form_dup(c->form_b) : bk_form_parse(m->text_b, &fe);
	if (!m->f[0] || (m->text_b && !m->f[1]))
		return -1;
	/* the pair as the shader computes it, f0*(A) + (B): a form of its own
	 * (its sharing counted once); one tree: the member's form */
	bk_form *w = NULL;
	if (m->text_b && c) {
		w = bk_form_dup(c->form_pair);
	} else if (m->text_b) {
		char *whole = bk_pair_dup(m->text, m->text_b);
		w = whole ? bk_form_parse(whole, &fe) : NULL;
		free(whole);
	}
	if (m->text_b && !w)
		return -1;
	bk_form_count(w ? w : m->f[0], &m->ops);
	m->cost = bk_ops_cost(&m->ops, so->simple_cost, so->complex_cost);
	bk_form_free(w);
	bk_fit_spec *sp = &m->spec;
	bk_refit_spec(sp, F->s, m->f[0], m->f[1], start);
	sp->relative = so->relative;
	sp->minimax = so->objective == BK_OBJ_MAX;
	if (fit && sp->np > 0) {
		if (bk_fit_run(sp, &m->res) < 0) {
			/* a member the full fitter cannot fit from any start (not finite
			 * on the denser grid: a pole between the screening samples; a
			 * --start or catalog form whose every start fails) is a row not
			 * analysed, not the search's failure */
			memset(&m->res, 0, sizeof m->res);
			memcpy(m->res.p, start, sizeof m->res.p);
			m->status = 1;
			m->err = HUGE_VAL;
			snprintf(m->verdict, sizeof m->verdict, "not analysed");
			return 0;
		}
		if (so->objective == BK_OBJ_ALBEDO && !m->f[1])
			albedo_minimax(F, m);
		if (so->precision == BK_F16)
			half_polish(F, m);
	} else {
		memset(&m->res, 0, sizeof m->res);
		memcpy(m->res.p, start, sizeof m->res.p);
		m->res.optimal = -1;
	}
	bk_fit_evaluate(sp, m->res.p, &m->res.fitted);
	const bk_samples *s = F->s;
	double *v = malloc(sizeof(double) * s->n);
	if (!v)
		return -1;
	int rc = bk_refit_values(sp, m->res.p, so->precision, v);
	m->status = 0;
	int finite = 1;
	if (rc == 0) {
		bk_samples_metrics(s, v, NULL, &m->prec);
		finite = m->prec.nonfinite == 0;
		for (size_t i = 0; i < s->n; i++)
			if (!isfinite(v[i]) && isfinite(s->y[i]))
				m->status = 1;
		if (!seed_exempt(so, m->c) && !bk_search_admissible(so, s, v))
			m->status = 1;
		m->err = bk_search_round_err(bk_search_error(so, s, v, &m->prec));
		if (!isfinite(m->err))
			m->status = 1;
		bk_fit_metrics h;
		rc = bk_refit_values(sp, m->res.p, BK_F16, v);
		bk_samples_metrics(s, v, NULL, &h);
		m->f16_max = h.nonfinite ? HUGE_VAL : h.max_abs;
	}
	free(v);
	if (!finite) { /* the metrics skip what is not finite: over none they would read 0, a perfect fit */
		m->prec.rmse = m->prec.max_abs = m->prec.max_rel = HUGE_VAL;
		m->err = m->f16_max = HUGE_VAL;
	}
	stability(m, finite);
	return rc;
}

/* A refitted search member's dead branches (search/prune.h): the form (or
 * split pair) without them is refitted from the member's constants and
 * replaces the member where it is scored (finite, admissible) with an error
 * no worse than the member's, both as the front reports them
 * (bk_search_round_err): at the member's constants it has the same values on
 * every sample in double (a mix at t = 1 up to its rounding), so the refit
 * starts from the member's error, at fewer ops. Returns 0, or -1 as score_member (out of memory). */
static int prune_member(const bk_sfront *F, member *m)
{
	if (!m->c || m->status)
		return 0;
	char text[2][4096];
	double p[BK_MAX_PARAMS];
	int n = m->f[0] && (!m->text_b || m->f[1]) ? /* the member's forms, as it was scored */
	            bk_prune_dead_forms(m->f[0], m->text_b ? m->f[1] : NULL, m->res.p, F->s, text[0], text[1],
	                                sizeof text[0], p) :
	            -1;
	if (n <= 0)
		return 0; /* nothing dead, or a tree bk_expr cannot hold: the member as it is */
	member t = *m;
	t.f[0] = t.f[1] = NULL;
	size_t la = strlen(text[0]) + 1, lb = m->text_b ? strlen(text[1]) + 1 : 0;
	if (!(t.pruned = malloc(la + lb)))
		return -1;
	memcpy(t.pruned, text[0], la);
	if (lb)
		memcpy(t.pruned + la, text[1], lb);
	t.text = t.pruned;
	t.text_b = lb ? t.pruned + la : NULL; /* one block: bk_sfront_free frees it once */
	t.npruned = n;
	int rc = score_member(F, &t, p, 1);
	if (rc || t.status || !(t.err <= m->err)) {
		bk_form_free(t.f[0]);
		bk_form_free(t.f[1]);
		free(t.pruned);
		return rc;
	}
	bk_form_free(m->f[0]);
	bk_form_free(m->f[1]);
	*m = t;
	return 0;
}

/* env --fetch-cost K: the DFG LUTs of compare (lutrows.h, the generic
 * layout) as rows of cost K (the fetch) + 1 (the mad of f0·A + B), scored
 * on the same samples. */
static int add_luts(bk_sfront *F)
{
	bk_lut_layout L[BK_LUTROWS_MAX_LAYOUTS];
	bk_lutrow *rows = malloc(BK_LUTROWS_MAX * sizeof *rows);
	if (!rows)
		return -1;
	int nl = bk_lutrows_layouts(0, 0, 1, NAN, L);
	int n = bk_lutrows_build(L, nl, F->smith, 0, BK_F64, F->s, F->progress, "LUT rows", rows);
	for (int k = 0; k < n; k++) {
		if (!rows[k].scored)
			continue;
		member *m = &F->m[F->nm++];
		memset(m, 0, sizeof *m);
		snprintf(m->name, sizeof m->name, "%s", rows[k].name);
		m->prec = rows[k].m;
		m->lut = 1;
		m->text = "";
		m->ops.n[BK_K_MAD] = m->ops.simple = 1;
		m->cost = 1 + F->fetch_cost;
		/* NaN for a relative rmse: no values */
		m->err = bk_search_round_err(bk_search_error(F->so, F->s, NULL, &m->prec));
		m->f16_max = NAN;
		snprintf(m->verdict, sizeof m->verdict, "-");
	}
	free(rows);
	return 0;
}

/* A member of a --start-front is refitted like any start; it is also scored
 * at the constants its file gave, and kept so where that is better: a merge
 * of fronts (make results') is never worse than a front it merged at that
 * member, whatever the refit finds (a half polish, a minimax or a local
 * optimum from another start may land a little off). */
static int keep_as_is(const bk_sfront *F, member *m, const double *p)
{
	/* a half front holds binary16 constants (the half code's): a double
	 * front's member is kept only as refitted there */
	for (int i = 0; F->so->precision == BK_F16 && i < m->c->np; i++)
		if (bk_half_round((float)p[i]) != p[i])
			return 0;
	member t = *m;
	t.f[0] = t.f[1] = NULL;
	t.pruned = NULL;
	t.npruned = 0;
	t.text = m->c->text;
	t.text_b = m->c->text_b;
	t.status = 0;
	int rc = score_member(F, &t, p, 0);
	if (rc || t.status || !(t.err < m->err) || (m->status == 0 && t.cost > m->cost)) {
		bk_form_free(t.f[0]);
		bk_form_free(t.f[1]);
		return rc;
	}
	bk_form_free(m->f[0]);
	bk_form_free(m->f[1]);
	free(m->pruned);
	*m = t;
	return 0;
}

/* The members are scored by the search's threads (pool.h: each member
 * whole by one thread; score_member reads the samples and writes its member
 * alone, so the rows are the same bits for any count), taken in order;
 * progress per phase as members end. */
typedef struct score_job {
	int m;           /* member index */
	int fit;         /* refit (0: a catalog row at its published constants) */
	const double *start;
	int front;       /* counted in "refit of the front", else in "catalog" */
	const double *as_is; /* a --start-front member's own constants, or NULL */
} score_job;

typedef struct score_run {
	const bk_sfront *F;
	score_job *job;
	int done[2], total[2]; /* under the pool's lock (score_after) */
} score_run;

static int score_one(void *ctx, int k)
{
	score_run *R = ctx;
	score_job *j = &R->job[k];
	int rc = score_member(R->F, &R->F->m[j->m], j->start, j->fit);
	if (!rc && j->front)
		rc = prune_member(R->F, &R->F->m[j->m]);
	if (!rc && j->as_is)
		rc = keep_as_is(R->F, &R->F->m[j->m], j->as_is);
	return rc;
}

static void score_after(void *ctx, int k, int rc)
{
	static const char *const label[2] = {"catalog", "refit of the front"};
	score_run *R = ctx;
	int front = R->job[k].front, d = ++R->done[front];
	(void)rc;
	if (R->F->progress)
		R->F->progress((void *)label[front], d, R->total[front]);
}

static int score_all(const bk_sfront *F, score_job *job, int njobs, int nfront)
{
	score_run R = {F, job, {0, 0}, {njobs - nfront, nfront}};
	return bk_pool_run(njobs, F->so->threads, score_one, score_after, &R);
}

/* qsort's order of search members: cost, then error, then name (unique),
 * so the order is total and the same for any thread count; a member that
 * was dropped (NaN error) after every one with an error. */
static int by_cost(const void *a, const void *b)
{
	const member *p = a, *q = b;
	if (p->cost != q->cost)
		return p->cost < q->cost ? -1 : 1;
	if (isnan(p->err) != isnan(q->err))
		return isnan(p->err) ? 1 : -1;
	if (p->err != q->err && !isnan(p->err))
		return p->err < q->err ? -1 : 1;
	return strcmp(p->name, q->name);
}

/* Catalog rows (published and refitted), then the screening front refitted;
 * the final front: the refitted members no other beats at no greater cost. */
int bk_sfront_build(bk_sfront *F, const bk_seeds *sd)
{
	/* the screening front, and every seed that fitted: the published forms
	 * compete for the final front on the full samples, refitted, even where
	 * a generated form beat them on the screening grid */
	size_t idx[BK_SFRONT_MAX + BK_SEEDS_MAX];
	size_t nf = bk_search_front(F->S, idx, BK_SFRONT_MAX);
	for (size_t i = 0, n = bk_search_count(F->S); i < n && nf < BK_SFRONT_MAX + BK_SEEDS_MAX; i++) {
		const bk_cand *c = bk_search_at(F->S, i);
		int on = 0;
		for (size_t k = 0; k < nf && !on; k++)
			on = idx[k] == i;
		if (c->seed_name && c->status == BK_CAND_OK && !on)
			idx[nf++] = i;
	}
	F->nm = 0;
	F->m = calloc((size_t)(2 * sd->n) + nf + BK_LUTROWS_MAX + 1, sizeof *F->m);
	score_job *job = calloc((size_t)(2 * sd->n) + nf + 1, sizeof *job);
	int njobs = 0;
	if (!F->m || !job) {
		free(job);
		return -1;
	}
	for (int k = 0; k < sd->n; k++) { /* catalog names, and typed --start forms as "start K" */
		if (sd->from_front[k]) /* a start of the search (--start-front), not a published form */
			continue;
		const bk_catalog_entry *e = sd->name[k] ? bk_catalog_find(sd->name[k]) : NULL;
		for (int r = 0; r < 2; r++) {
			member *m = &F->m[F->nm++];
			m->entry = e;
			m->refit = r;
			if (e)
				snprintf(m->name, sizeof m->name, "%s%s%s", e->name, !strcmp(e->target, "V") ? " x F_schlick" : "",
				         r ? " (refit)" : "");
			else if (sd->name[k])
				snprintf(m->name, sizeof m->name, "%s%s", sd->name[k], r ? " (refit)" : "");
			else
				snprintf(m->name, sizeof m->name, "start %d%s", k + 1, r ? " (refit)" : "");
			m->text = sd->text[k];
			m->text_b = sd->text_b[k];
			job[njobs++] = (score_job){F->nm - 1, r, sd->p[k], 0, NULL};
		}
	}
	if (F->luts && add_luts(F)) { /* the textures the formulas compete with, on compare's axis */
		free(job);
		return -1;
	}
	for (size_t i = 0; i < nf; i++) {
		const bk_cand *c = bk_search_at(F->S, idx[i]);
		member *m = &F->m[F->nm++];
		m->c = c;
		int k = bk_search_seed_index(F->S, c);
		/* a published seed on the front is named after it; a member of a
		 * --start-front is a start like any generated one, and named as the
		 * run's own (its name was its old front's: two fronts merged may
		 * both have a search_T_3, and seed_ would pile up at each merge) */
		if (c->seed_name && !(k >= 0 && k < sd->n && sd->from_front[k])) {
			char slug[80];
			bk_slug(c->seed_name, slug, sizeof slug);
			snprintf(m->name, sizeof m->name, "seed_%s", slug);
		} else {
			snprintf(m->name, sizeof m->name, "search_%s_%zu", bk_target_name(F->kind), i + 1);
		}
		m->text = c->text;
		m->text_b = c->text_b;
		job[njobs++] = (score_job){F->nm - 1, 1, c->p, 1,
		                           k >= 0 && k < sd->n && sd->from_front[k] ? sd->p[k] : NULL};
	}
	int rc = score_all(F, job, njobs, (int)nf);
	free(job);
	if (rc)
		return -1;
	/* the final front over the refitted search members, ties on the text;
	 * a half search's front holds only members safe in half: one that is
	 * not is left off as an inadmissible one (the rows are the same for any
	 * thread count, so is this choice) */
	bk_pareto_pt *pt = calloc((size_t)F->nm + 1, sizeof *pt);
	if (!pt)
		return -1;
	size_t n = 0;
	F->unsafe = 0;
	for (int i = 0; i < F->nm; i++) {
		if (!F->m[i].c || F->m[i].status)
			continue;
		if (F->so->precision == BK_F16 && !bk_sfront_half_safe(&F->m[i])) {
			F->unsafe++;
			continue;
		}
		pt[n++] = (bk_pareto_pt){F->m[i].cost, F->m[i].err, F->m[i].text, (size_t)i};
	}
	size_t k = bk_pareto_scan(pt, n);
	for (size_t i = 0; i < k; i++)
		F->m[pt[i].id].front = 1;
	free(pt);
	/* the search members in cost order, the one order of every file written
	 * from them (front.csv, the plot's staircase, the page, the report): a
	 * reader taking "the last row at cost <= C" gets the best there. They
	 * are the tail of m (catalog and LUT rows first); the names stay those
	 * given above, so a member keeps its name. */
	int first = F->nm;
	while (first > 0 && F->m[first - 1].c)
		first--;
	qsort(F->m + first, (size_t)(F->nm - first), sizeof *F->m, by_cost);
	return 0;
}

void bk_sfront_free(bk_sfront *F)
{
	for (int i = 0; F->m && i < F->nm; i++) {
		bk_form_free(F->m[i].f[0]);
		bk_form_free(F->m[i].f[1]);
		free(F->m[i].pruned);
	}
	free(F->m);
	F->m = NULL;
	F->nm = 0;
}

int bk_sfront_gpu(bk_sfront *F, const char *const *chip, int nchips, char *driver, size_t dlen, char *err,
                  size_t errlen)
{
	int n = F->nm, nc = nchips, rc = 0;
	const char **a = calloc((size_t)n + 1, sizeof *a), **b = calloc((size_t)n + 1, sizeof *b);
	const double **p = calloc((size_t)n + 1, sizeof *p);
	double *insn = calloc(2 * (size_t)n * (size_t)nc + 1, sizeof *insn), *transc = insn + n * nc;
	if (!a || !b || !p || !insn) {
		snprintf(err, errlen, "out of memory");
		rc = -1;
	}
	for (int i = 0; !rc && i < n; i++) {
		const member *m = &F->m[i];
		int want = !m->lut && !m->status && (m->front || !m->c);
		a[i] = want ? m->text : NULL;
		b[i] = want ? m->text_b : NULL;
		p[i] = m->res.p;
	}
	if (!rc && bk_gpucost_texts(a, b, p, n, chip, nc, insn, transc, NULL, driver, dlen, err, errlen))
		rc = -1;
	for (int i = 0; !rc && i < n; i++)
		for (int c = 0; c < nc; c++) {
			F->m[i].gpu_insn[c] = insn[i * nc + c];
			F->m[i].gpu_transc[c] = transc[i * nc + c];
		}
	free(a);
	free(b);
	free(p);
	free(insn);
	return rc;
}
