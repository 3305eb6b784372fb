/*
 * cmd_albedo.c — brdfkit albedo: directional albedo ∫ D·V·F·NoL dω of any
 * registered D, V and F, at one point or over a grid ("all", comma lists).
 */
#include "brdf.h"
#include "prov.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"

#include <math.h>
#include <string.h>

/* Resolves "all" or one name (with or without the role prefix) into list. */
static int pick_terms(bk_role role, const char *name, const bk_term **list, int *n)
{
	*n = 0;
	for (size_t i = 0; i < bk_term_count(); i++) {
		const bk_term *t = bk_term_at(i);
		if (t->role == role && strcmp(name, "all") == 0)
			list[(*n)++] = t;
	}
	if (*n)
		return 0;
	const bk_term *t = bk_term_find_role(role, name);
	if (!t) {
		fprintf(stderr, "brdfkit albedo: --%s: unknown %s term '%s' (see brdfkit terms --role %s)\n",
		        role == BK_ROLE_D ? "d" : role == BK_ROLE_V ? "v" : "f", bk_role_name(role),
		        name, bk_role_name(role));
		return 2;
	}
	list[(*n)++] = t;
	return 0;
}

typedef struct grid {
	const bk_term *d[32], *v[32], *f[32];
	int nd, nv, nf;
	cli_list nov, rough, f0;
	double f90, eta, k, tol;
	int from_ior;
} grid;

static void material_at(const grid *g, double f0, double r, bk_sample *s)
{
	memset(s, 0, sizeof *s);
	bk_sample_roughness(s, r);
	s->f90 = g->f90;
	if (g->from_ior) {
		s->eta = g->eta;
		s->k = g->k;
		s->f0 = f0;
	} else {
		s->f0 = f0;
		s->eta = f0 < 1.0 ? bk_ior_from_f0(f0) : INFINITY;
		s->k = 0.0;
	}
}

static int run_grid(const grid *g, FILE *out)
{
	fputs("D,V,F,nov,roughness,f0,f90,eta,k,albedo\n", out);
	long total = (long)g->nd * g->nv * g->nf, done = 0;
	for (int a = 0; a < g->nd; a++)
		for (int b = 0; b < g->nv; b++)
			for (int c = 0; c < g->nf; c++, done++) {
				for (int q = 0; q < g->f0.n; q++)
					for (int j = 0; j < g->rough.n; j++)
						for (int i = 0; i < g->nov.n; i++) {
							bk_sample s;
							double alb, NoV = g->nov.v[i];
							bk_quad_stats st = {0};
							material_at(g, g->f0.v[q], g->rough.v[j], &s);
							bk_albedo(g->d[a], g->v[b], g->f[c], &s, NoV, g->tol, &alb, &st);
							if (!isfinite(alb))
								return cli_fail("albedo", "non-finite albedo for %s·%s·%s at nov %g, roughness %g, f0 %g",
								                g->d[a]->name, g->v[b]->name, g->f[c]->name, NoV, s.r, s.f0);
							if (!st.converged)
								fprintf(stderr, "brdfkit albedo: warning: tolerance %g not reached for %s·%s·%s at nov %g, roughness %g (estimate %.2g)\n",
								        g->tol, g->d[a]->name, g->v[b]->name, g->f[c]->name, NoV, s.r, st.err);
							fprintf(out, "%s,%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", g->d[a]->name,
							        g->v[b]->name, g->f[c]->name, NoV, s.r, s.f0, s.f90, s.eta, s.k, alb);
						}
				cli_progress("albedo combinations", (int)(done + 1), (int)total);
			}
	return 0;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

enum { DIM_INDEX, DIM_F90 };
static const cli_dim dims[] = {
	{"index", {"f0", "ior"}, {" with --f0", " with --ior"}},
	{"f90", {"unread", "read"}, {" on the F terms chosen (none reads f90: only F_schlick and F_schlick_sg do)", NULL}},
};
static const cli_rule rules[] = {
	{"--k", NULL, DIM_INDEX, 1u << 1, "it is the extinction coefficient of the index --ior", "3"},
	{"--f90", NULL, DIM_F90, 1u << 1, "it sets Schlick's grazing reflectance", "0.5"},
	{"--d", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--v", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--f", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--nov", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--roughness", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--f0", NULL, CLI_EVERYWHERE, 0, NULL, NULL},  /* one of --f0, --ior: every setup gives it */
	{"--ior", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--tol", NULL, CLI_EVERYWHERE, 0, NULL, "1e-6"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, "o.csv"},
};
static const char *const setups[] = {
	"--d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --f0 0.04",
	"--d ggx --v implicit --f schlick --nov 0.5 --roughness 0.5 --ior 1.5",
	"--d ggx --v implicit --f dielectric --nov 0.5 --roughness 0.5 --f0 0.04",
	NULL};
static const cli_table table = {dims, 2, rules, sizeof rules / sizeof rules[0], setups};

/* 1 if one of the F terms chosen reads f90 (its argument list names it). */
static int reads_f90(const grid *g)
{
	for (int c = 0; c < g->nf; c++)
		if (strstr(g->f[c]->args, "f90"))
			return 1;
	return 0;
}

int cmd_albedo(int argc, char **argv)
{
	grid g = {.f90 = 1.0, .tol = 1e-7};
	const char *dn = NULL, *vn = NULL, *fn = NULL, *out = NULL;
	double ior = 0.0;
	cli_opt opts[] = {
		{.name = "--d", .kind = CLI_STR, .metavar = "NAME|all", .help = "distribution, e.g. ggx or D_ggx", .dest = &dn, .required = 1},
		{.name = "--v", .kind = CLI_STR, .metavar = "NAME|all", .help = "visibility, e.g. smith_ggx_correlated", .dest = &vn, .required = 1},
		{.name = "--f", .kind = CLI_STR, .metavar = "NAME|all", .help = "Fresnel, e.g. schlick", .dest = &fn, .required = 1},
		{.name = "--nov", .kind = CLI_LIST, .metavar = "X[,X...]", .help = "cosine of the view angle", .dest = &g.nov, .lo = 0, .hi = 1, .lo_open = 1, .required = 1},
		{.name = "--roughness", .kind = CLI_LIST, .metavar = "R[,R...]", .help = "perceptual roughness (alpha = r^2)", .dest = &g.rough, .lo = 0, .hi = 1, .required = 1},
		{.name = "--f0", .kind = CLI_LIST, .metavar = "F[,F...]", .help = "normal-incidence reflectance; exact Fresnel uses n = (1+sqrt f0)/(1-sqrt f0), k = 0", .dest = &g.f0, .lo = 0, .hi = 1},
		{.name = "--f90", .kind = CLI_NUM, .metavar = "F", .help = "Schlick grazing reflectance (default 1)", .dest = &g.f90, .lo = 0, .hi = 1},
		{.name = "--ior", .kind = CLI_NUM, .metavar = "N", .help = "real part of the index instead of --f0 (f0 derived)", .dest = &ior, .lo = 0, .hi = 1e6, .lo_open = 1},
		{.name = "--k", .kind = CLI_NUM, .metavar = "K", .help = "extinction coefficient with --ior (default 0)", .dest = &g.k, .lo = 0, .hi = 1e6},
		{.name = "--tol", .kind = CLI_NUM, .metavar = "T", .help = "absolute tolerance (default 1e-7)", .dest = &g.tol, .lo = 1e-13, .hi = 0.1},
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE.csv", .help = "write there (atomically) instead of stdout", .dest = &out},
	};
	cli_cmd cmd = {"albedo", "Directional albedo ∫ D·V·F·NoL dω_l of a D·V·F combination, as CSV with header\n"
	               "D,V,F,nov,roughness,f0,f90,eta,k,albedo. 'all' and comma lists make a grid.",
	               "--d NAME --v NAME --f NAME --nov X --roughness R (--f0 F | --ior N [--k K])",
	               NULL, opts, 11, 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	if (opts[5].seen == opts[7].seen) {
		return cli_bad("give exactly one of --f0 and --ior");
	}
	if ((rc = pick_terms(BK_ROLE_D, dn, g.d, &g.nd)) || (rc = pick_terms(BK_ROLE_V, vn, g.v, &g.nv)) ||
	    (rc = pick_terms(BK_ROLE_F, fn, g.f, &g.nf)))
		return rc;
	if ((rc = cli_applicable(&cmd, (int[]){opts[7].seen ? 1 : 0, reads_f90(&g)})))
		return rc;
	if (opts[7].seen) {
		g.from_ior = 1;
		g.eta = ior;
		g.f0.n = 1;
		g.f0.v[0] = bk_f0_from_ior(ior, g.k);
	}
	if (!out)
		return run_grid(&g, stdout);
	if ((rc = cli_out_file("albedo", out))) /* before the integrals, not after */
		return rc;
	bk_out co;
	char err[512];
	if (bk_out_open_file(&co, out, err, sizeof err))
		return cli_fail("albedo", "%s", err);
	bk_prov_title(co.f, "directional albedo: integral of D*V*F*NoL over the light hemisphere");
	bk_prov_command(co.f, bk_out_command());
	fprintf(co.f, "# roughness perceptual (alpha = r^2); V includes 1/(4 NoL NoV); exact Fresnel uses eta + ik; tol %g\n", g.tol);
	if ((rc = run_grid(&g, co.f))) {
		bk_out_abort(&co);
		return rc;
	}
	return bk_out_commit(&co, err, sizeof err) ? cli_fail("albedo", "%s", err) : 0;
}
