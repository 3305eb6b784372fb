/*
 * halves.c — the halves S = A + B and B, and their compositions
 * mix(B, S, f0) as seeds (halves.h).
 */
#include "search/halves.h"

#include "search/pareto.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct half_step {
	const bk_halves_report *rep;
	const char *what;
} half_step;

static int after_step(void *ctx, const bk_search *s)
{
	const half_step *h = ctx;
	if (h->rep && h->rep->step)
		h->rep->step(h->rep->ctx, h->what, s);
	return 0;
}

/* One half's search on the screening grid at that f0; its front out. */
static int half_search(const bk_search_options *so, const bk_target_options *screen, double f0,
                       const bk_halves_report *rep, bk_half *out, size_t *nout, long *evals, char *err, size_t errlen)
{
	bk_target_options t = *screen;
	t.nf0 = 1;
	t.f0[0] = f0;
	bk_samples sm;
	if (bk_target_build(&t, &sm, NULL, NULL, err, errlen))
		return -1;
	bk_search_options o = *so;
	o.screen = &sm;
	o.seeds = o.seeds_b = o.seed_names = NULL;
	o.seed_forms = o.seed_forms_b = NULL;
	o.seed_p = NULL;
	o.nseeds = 0;
	o.exempt_seeds = INT_MAX;
	o.evals = so->evals / 8 * 3;
	o.max_cost = so->max_cost - 2; /* mix(B, S, f0) adds a subtract and a multiply-add */
	o.grammar.inputs &= ~(1u << BK_IN_F0); /* f0 is the composition's */
	half_step hs = {rep, f0 == 1 ? "S = A + B" : "B"};
	int rc = -1;
	bk_search *S = bk_search_new(&o, err, errlen);
	if (S) {
		rc = bk_search_run(S, after_step, &hs, err, errlen);
		if (rc >= 0) {
			size_t idx[BK_HALVES_FRONT];
			size_t n = bk_search_front(S, idx, BK_HALVES_FRONT);
			*nout = 0;
			for (size_t i = 0; i < n; i++) {
				const bk_cand *c = bk_search_at(S, idx[i]);
				bk_half *h = &out[(*nout)++];
				bk_expr t[2];
				bk_cand_trees(c, t);
				h->tree = t[0];
				h->np = bk_expr_nparams(&t[0]);
				memcpy(h->p, c->p, sizeof h->p);
				h->err = c->err; /* rounded (search.h): no choice below hinges on a last bit */
			}
			*evals = bk_search_evals(S);
			if (rep && rep->done)
				rep->done(rep->ctx, hs.what, *evals, *nout);
			rc = 0;
		}
		bk_search_free(S);
	}
	bk_samples_free(&sm);
	return rc;
}

typedef struct composed {
	char *text;
	double p[BK_MAX_PARAMS];
} composed;

int bk_halves_compose(const bk_half *s, size_t ns, const bk_half *b, size_t nb, int max_params, double max_cost,
                      double simple, double complex, bk_halves *hv)
{
	for (int k = 0; k < hv->n; k++)
		free(hv->text[k]);
	hv->n = 0;
	composed *c = calloc(ns * nb + 1, sizeof *c);
	bk_pareto_pt *pt = calloc(ns * nb + 1, sizeof *pt);
	size_t nc = 0;
	int rc = c && pt ? 0 : -1;
	for (size_t i = 0; i < ns && !rc; i++)
		for (size_t j = 0; j < nb && !rc; j++) {
			if (s[i].np + b[j].np > max_params)
				continue;
			bk_expr bt = b[j].tree;
			bk_expr_shift_params(&bt, s[i].np);
			char ts[4200], tb[4200], text[8600];
			if (bk_expr_print(&s[i].tree, ts, sizeof ts) < 0 || bk_expr_print(&bt, tb, sizeof tb) < 0)
				continue;
			snprintf(text, sizeof text, "mix(%s, %s, f0)", tb, ts);
			bk_form_error fe;
			bk_form *f = bk_form_parse(text, &fe);
			if (!f)
				continue;
			bk_ops ops;
			bk_form_count(f, &ops);
			bk_form_free(f);
			double cost = bk_ops_cost(&ops, simple, complex);
			if (cost > max_cost)
				continue;
			if (!(c[nc].text = strdup(text))) {
				rc = -1;
				break;
			}
			/* the rmse of f0 A + B over the f0 list if the halves' errors were
			 * independent and equal across f0: a ranking, not a promise */
			double est = bk_search_round_err(sqrt((s[i].err * s[i].err + b[j].err * b[j].err) / 2));
			memcpy(c[nc].p, s[i].p, sizeof(double) * (size_t)s[i].np);
			memcpy(c[nc].p + s[i].np, b[j].p, sizeof(double) * (size_t)b[j].np);
			pt[nc] = (bk_pareto_pt){cost, est, c[nc].text, nc};
			nc++;
		}
	if (!rc) {
		size_t nf = bk_pareto_scan(pt, nc);
		for (size_t k = 0; k < nf && hv->n < BK_HALVES_MAX; k++) {
			composed *m = &c[pt[k].id];
			hv->text[hv->n] = m->text;
			m->text = NULL;
			memcpy(hv->p[hv->n], m->p, sizeof hv->p[0]);
			snprintf(hv->name[hv->n], sizeof hv->name[0], "halves %d", hv->n + 1);
			hv->n++;
		}
	}
	for (size_t k = 0; c && k < nc; k++)
		free(c[k].text);
	free(c);
	free(pt);
	return rc;
}

int bk_halves_run(const bk_search_options *o, const bk_target_options *screen, const bk_halves_report *rep,
                  bk_halves *hv, char *err, size_t errlen)
{
	bk_half *hs = calloc(2 * BK_HALVES_FRONT, sizeof *hs), *hb = hs + BK_HALVES_FRONT;
	size_t ns = 0, nb = 0;
	long es = 0, eb = 0;
	int rc = -1;
	if (!hs)
		snprintf(err, errlen, "out of memory");
	else if (!half_search(o, screen, 1.0, rep, hs, &ns, &es, err, errlen) &&
	         !half_search(o, screen, 0.0, rep, hb, &nb, &eb, err, errlen)) {
		hv->evals = es + eb;
		rc = bk_halves_compose(hs, ns, hb, nb, o->grammar.max_params, o->max_cost, o->simple_cost, o->complex_cost,
		                       hv);
		if (rc)
			snprintf(err, errlen, "out of memory");
	}
	free(hs);
	return rc;
}

void bk_halves_seed(bk_halves *hv, const bk_seeds *sd, bk_search_options *o)
{
	int n = 0;
	for (int k = 0; k < sd->n; k++, n++) {
		hv->seed_text[n] = sd->text[k];
		hv->seed_text_b[n] = sd->text_b[k];
		hv->seed_form[n] = sd->form[k];
		hv->seed_form_b[n] = sd->form_b[k];
		hv->seed_name[n] = sd->name[k];
		memcpy(hv->seed_p[n], sd->p[k], sizeof hv->seed_p[0]);
	}
	for (int k = 0; k < hv->n; k++, n++) {
		hv->seed_text[n] = hv->text[k];
		hv->seed_text_b[n] = NULL;
		hv->seed_form[n] = hv->seed_form_b[n] = NULL;
		hv->seed_name[n] = hv->name[k];
		memcpy(hv->seed_p[n], hv->p[k], sizeof hv->seed_p[0]);
	}
	o->seeds = hv->seed_text;
	o->seeds_b = hv->seed_text_b;
	o->seed_forms = hv->seed_form;
	o->seed_forms_b = hv->seed_form_b;
	o->seed_names = hv->seed_name;
	o->seed_p = (const double(*)[BK_MAX_PARAMS])hv->seed_p;
	o->nseeds = n;
	o->exempt_seeds = sd->n;
	o->evals -= hv->evals;
}

void bk_halves_free(bk_halves *hv)
{
	for (int k = 0; k < hv->n; k++)
		free(hv->text[k]);
	hv->n = 0;
}
