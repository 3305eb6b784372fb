/*
 * cmd_dfg.c — brdfkit dfg (A, B at points) and brdfkit lut (the engine LUT as
 * OpenEXR with its conventions in the header, and the same values as CSV).
 */
#include "brdf.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"
#include "lut.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


static int parse_smith(const char *cmd, const char *s, bk_smith *m)
{
	if (bk_smith_parse(s, m) == 0)
		return 0;
	static const char *const models[] = {"correlated", "separable", "schlick"};
	(void)cmd; /* cli_set_name has it */
	return cli_unknown_value("--smith", s, models, 3);
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* dfg and lut integrate deterministically, or bake with --samples N. */
enum { BY_QUADRATURE, BY_BAKE };
static const cli_dim dims[] = {
	{"integrator", {"quadrature", "bake"}, {" without --samples", " with --samples"}},
};
#define TOL_RULE {"--tol", NULL, 0, 1u << BY_QUADRATURE, "the Monte Carlo bake has no tolerance", "1e-6"}

static const cli_rule dfg_rules[] = {
	TOL_RULE,
	{"--nov", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--roughness", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--smith", NULL, CLI_EVERYWHERE, 0, NULL, "schlick"},
	{"--samples", NULL, CLI_EVERYWHERE, 0, NULL, "64"},
};
static const char *const dfg_setups[] = {"--nov 0.5 --roughness 0.5", "--nov 0.5 --roughness 0.5 --samples 16", NULL};
static const cli_table dfg_table = {dims, 1, dfg_rules, sizeof dfg_rules / sizeof dfg_rules[0], dfg_setups};

static const cli_rule lut_rules[] = {
	TOL_RULE,
	{"--size", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--f0", NULL, CLI_EVERYWHERE, 0, NULL, "0.04"},
	{"--r-range", NULL, CLI_EVERYWHERE, 0, NULL, "0.2:1"},
	{"--warp", NULL, CLI_EVERYWHERE, 0, NULL, "sqrt"},
	{"--smith", NULL, CLI_EVERYWHERE, 0, NULL, "schlick"},
	{"--samples", NULL, CLI_EVERYWHERE, 0, NULL, "64"},
	{"--precision", NULL, CLI_EVERYWHERE, 0, NULL, "half"},
	{"--origin", NULL, CLI_EVERYWHERE, 0, NULL, "bottom"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--channels", NULL, 0, 1u << BY_QUADRATURE, "the cloth and E_avg channels are integrated, not baked", "filament"},
};
static const char *const lut_setups[] = {"--size 2 --out o", "--size 2 --samples 16 --out o", NULL};
static const cli_table lut_table = {dims, 1, lut_rules, sizeof lut_rules / sizeof lut_rules[0], lut_setups};

int cmd_dfg(int argc, char **argv)
{
	cli_list nov = {0}, rough = {0};
	const char *smith = "correlated";
	double tol = BK_DFG_TOL;
	long samples = 0;
	cli_opt opts[] = {
		{.name = "--nov", .kind = CLI_LIST, .metavar = "X[,X...]", .help = "cosine of the view angle", .dest = &nov, .lo = 0, .hi = 1, .lo_open = 1, .required = 1},
		{.name = "--roughness", .kind = CLI_LIST, .metavar = "R[,R...]", .help = "perceptual roughness r (alpha = r^2)", .dest = &rough, .lo = 0, .hi = 1, .required = 1},
		{.name = "--smith", .kind = CLI_STR, .metavar = "MODEL", .help = "correlated (default), separable or schlick", .dest = &smith},
		{.name = "--tol", .kind = CLI_NUM, .metavar = "T", .help = "absolute tolerance of the deterministic integrator (default 1e-8)", .dest = &tol, .lo = 1e-13, .hi = 0.1},
		{.name = "--samples", .kind = CLI_INT, .metavar = "N", .help = "use the Hammersley Monte Carlo bake with N samples instead", .dest = &samples, .lo = 1, .hi = 1 << 30},
	};
	cli_cmd cmd = {"dfg", "Prints the split-sum environment BRDF, f0·A + B = ∫ D·V·F·NoL dω for GGX D\n"
	               "and Schlick F (f90 = 1), as CSV: nov,roughness,A,B. Lists give every pair.",
	               "--nov X[,X...] --roughness R[,R...] [--smith MODEL] [--tol T | --samples N]",
	               "The deterministic integrator (default) is accurate to 1e-6 absolute for\n"
	               "r in [0.02, 1], NoV in [0.01, 1]; r = 0 is the exact smooth limit.",
	               opts, 5, 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &dfg_table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, (int[]){samples ? BY_BAKE : BY_QUADRATURE})))
		return rc == 1 ? 0 : rc;
	bk_smith m;
	if (parse_smith("dfg", smith, &m))
		return 2;
	puts("nov,roughness,A,B");
	for (int i = 0; i < nov.n; i++)
		for (int j = 0; j < rough.n; j++) {
			double A, B;
			bk_quad_stats st = {0};
			int bad = samples ? bk_dfg_hammersley(nov.v[i], rough.v[j], m, (unsigned)samples, &A, &B)
			                  : bk_dfg(nov.v[i], rough.v[j], m, tol, &A, &B, &st);
			if (bad || !isfinite(A) || !isfinite(B))
				return cli_fail("dfg", "integration failed at nov %g, roughness %g", nov.v[i], rough.v[j]);
			if (!samples && !st.converged)
				fprintf(stderr, "brdfkit dfg: warning: tolerance %g not reached at nov %g, roughness %g (estimate %.2g)\n",
				        tol, nov.v[i], rough.v[j], st.err);
			printf("%.9g,%.9g,%.9g,%.9g\n", nov.v[i], rough.v[j], A, B);
		}
	return 0;
}

int cmd_lut(int argc, char **argv)
{
	for (int i = 0; i < argc && strcmp(argv[i], "--"); i++) /* the specular LUT: options of its own */
		if (!strcmp(argv[i], "--specular"))
			return cmd_lut_specular(argc, argv);
	long size = 0, samples = 0;
	const char *smith = "correlated", *origin = "top", *out = NULL;
	const char *precision = "single";
	double tol = 1e-6, f0 = NAN;
	const char *r_range = NULL, *warp = "none", *channels = "split";
	cli_opt opts[] = {
		{.name = "--size", .kind = CLI_INT, .metavar = "N", .help = "texels per side", .dest = &size, .lo = 1, .hi = 4096, .required = 1},
		{.name = "--f0", .kind = CLI_NUM, .metavar = "F", .help = "one channel f0*A + B at this f0 (a scene's one dielectric)", .dest = &f0, .lo = 0, .hi = 1},
		{.name = "--r-range", .kind = CLI_STR, .metavar = "LO:HI", .help = "rows over roughness LO..HI only (default 0:1)", .dest = &r_range},
		{.name = "--warp", .kind = CLI_STR, .metavar = "none|sqrt", .help = "x = NoV (default) or sqrt(NoV): texels crowd at grazing angles", .dest = &warp},
		{.name = "--smith", .kind = CLI_STR, .metavar = "MODEL", .help = "correlated (default), separable or schlick", .dest = &smith},
		{.name = "--samples", .kind = CLI_INT, .metavar = "N", .help = "Hammersley Monte Carlo bake with N samples (default: deterministic)", .dest = &samples, .lo = 1, .hi = 1 << 30},
		{.name = "--tol", .kind = CLI_NUM, .metavar = "T", .help = "tolerance of the deterministic integrator (default 1e-6)", .dest = &tol, .lo = 1e-13, .hi = 0.1},
		{.name = "--precision", .kind = CLI_STR, .metavar = "single|half", .help = "texels stored as float32 (default) or half floats", .dest = &precision},
		{.name = "--origin", .kind = CLI_STR, .metavar = "top|bottom", .help = "which image row holds the smallest roughness (default top)", .dest = &origin},
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "directory for " BK_LUT_EXR " and " BK_LUT_CSV " (replaced whole)", .dest = &out, .required = 1},
		{.name = "--channels", .kind = CLI_STR, .metavar = "split|filament|full", .help = "R = A, G = B (default); Filament's B, A + B, cloth; or A, B, cloth, E_avg", .dest = &channels},
	};
	cli_cmd cmd = {"lut", "Writes the DFG look-up table the way engines sample it: x = NoV, y = perceptual\n"
	               "roughness, both at texel centres; R = A, G = B; ZIP-compressed OpenEXR with the\n"
	               "conventions as header attributes, and the same table as CSV (full precision):\n"
	               "DIR/" BK_LUT_EXR " and DIR/" BK_LUT_CSV ", one directory so the pair is always from one run.",
	               "--size N --out DIR [--f0 F] [--r-range LO:HI] [--warp none|sqrt] [--smith MODEL]\n"
	               "       [--samples N | --tol T] [--precision single|half] [--origin top|bottom]\n"
	               "       [--channels split|filament|full]",
	               "origin top: the first scanline of the file (top of the image as displayed) is\n"
	               "r = 0.5/N, so texture(lut, vec2(NoV, r)) is right wherever uv (0,0) is the first\n"
	               "texel in memory (D3D, Vulkan, Metal, and GL when rows are uploaded in file order).\n"
	               "origin bottom: the last scanline is r = 0.5/N, for loaders that flip images.\n"
	               "A LUT laid out for a scene (brdfkit scene names the command): --f0 folds one f0\n"
	               "into a single channel R = f0*A + B; --r-range LO:HI puts the rows over LO..HI,\n"
	               "sampled at v = (r - LO)/(HI - LO); --warp sqrt samples x at u = sqrt(NoV). The\n"
	               "EXR header and the CSV's comments state the layout.\n"
	               "--channels filament: R = B, G = E = A + B (multiscatter: 1 + f0*(1/G - 1)), B = cloth\n"
	               "(the sheen albedo, Charlie D and Neubelt V), as Filament's cmgen bakes its DFG;\n"
	               "--channels full: R = A, G = B, B = cloth, A = E_avg(r) (Kulla & Conty 2017).\n"
	               "lut --specular writes the low tier's specular LUT instead (brdfkit lut --specular --help).",
	               opts, 11, 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &lut_table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, (int[]){samples ? BY_BAKE : BY_QUADRATURE})))
		return rc == 1 ? 0 : rc;
	cli_prec prec;
	if (cli_precision(precision, CLI_PREC_BIT(CLI_PREC_SINGLE) | CLI_PREC_BIT(CLI_PREC_HALF), &prec))
		return 2;
	bk_lut_desc d = {.L = {(int)size, (int)size, 0, 1, BK_LUT_WARP_NONE, f0}, .half = prec == CLI_PREC_HALF, .samples = samples,
	                 .tol = tol, .command = bk_out_command()};
	if (parse_smith("lut", smith, &d.smith))
		return 2;
	if (r_range && cli_range("--r-range", r_range, 0, 1, &d.L.r_lo, &d.L.r_hi))
		return 2;
	static const char *const warps[] = {"none", "sqrt"}, *const origins[] = {"top", "bottom"};
	int w = cli_choice("--warp", warp, warps, 2);
	if (w < 0 || cli_choice("--origin", origin, origins, 2) < 0)
		return 2;
	d.L.warp = w ? BK_LUT_WARP_SQRT : BK_LUT_WARP_NONE;
	static const char *const chans[] = {"split", "filament", "full"};
	int ch = cli_choice("--channels", channels, chans, 3);
	if (ch < 0)
		return 2;
	d.chan = (bk_lut_chan)ch;
	if (d.chan != BK_LUT_SPLIT && !isnan(f0))
		return cli_bad("--f0 folds A and B into one channel; --channels %s keeps them apart", channels);
	d.origin_top = strcmp(origin, "top") == 0;

	/* begun before minutes of integration, so a bad --out fails first */
	char err[512];
	bk_out_dir od;
	if (bk_out_dir_begin(&od, out, NULL, err, sizeof err))
		return cli_fail("lut", "--out %s", err);
	size_t n = (size_t)size * (size_t)size;
	double *A = malloc(n * sizeof *A), *B = malloc(n * sizeof *B);
	if (!A || !B) {
		free(A);
		free(B);
		bk_out_dir_abort(&od);
		return cli_fail("lut", "out of memory for a %ldx%ld table", size, size);
	}
	/* M8: --size 4096 --samples 2^30 would run for years: said before (rates measured
	 * at --size 64 and 128: about 1.4e7 bake samples a second, 0.4 ms a texel's quadrature) */
	double texels = (double)size * (double)size;
	cli_estimate("the table", samples ? texels * (double)samples / 1.4e7 : texels * 4e-4, 0,
	             samples ? "about 1.4e7 samples a second" : "about 0.4 ms a texel");
	rc = bk_dfg_lut_layout(&d.L, d.smith, (unsigned)samples, tol, A, B, cli_progress, "lut rows");
	if (rc == 0)
		for (size_t k = 0; k < n && rc == 0; k++)
			if (!isfinite(A[k]) || !isfinite(B[k]))
				rc = -1;
	double *cloth = NULL, *e_avg = NULL;
	if (rc == 0 && d.chan != BK_LUT_SPLIT) {
		cloth = malloc(n * sizeof *cloth);
		e_avg = malloc((size_t)size * sizeof *e_avg);
		rc = !cloth || !e_avg ? -1 : bk_lut_extra(&d, cloth, e_avg, cli_progress, "lut cloth and E_avg rows");
		for (size_t k = 0; k < n && rc == 0; k++)
			if (!isfinite(cloth[k]) || (k < (size_t)size && !isfinite(e_avg[k])))
				rc = -1;
		d.cloth = cloth;
		d.e_avg = e_avg;
	}
	if (rc) {
		bk_out_dir_abort(&od);
		rc = cli_fail("lut", "integration failed (non-finite value)");
	} else if (bk_lut_write(&d, od.tmp, A, B, err, sizeof err)) {
		bk_out_dir_abort(&od);
		rc = cli_fail("lut", "%s: writing the results failed: %s", out, err);
	} else if (bk_out_dir_commit(&od, err, sizeof err)) {
		rc = cli_fail("lut", "--out %s", err);
	}
	free(A);
	free(B);
	free(cloth);
	free(e_avg);
	return rc;
}
