/*
 * cmd_dfg.c — brdfkit dfg (A, B at points) and brdfkit lut (the engine LUT as
 * OpenEXR with its conventions in the header, and the same values as CSV).
 */
#include "brdf.h"
#include "cli.h"
#include "cmd.h"
#include "exr.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const smith_text[BK_SMITH_COUNT] = {
	"correlated: exact height-correlated Smith GGX (Heitz 2014)",
	"separable: exact separable Smith GGX, G1(v) G1(l)",
	"schlick: Schlick-GGX with k = a/2 (Karis 2013)",
};

static int parse_smith(const char *cmd, const char *s, bk_smith *m)
{
	if (bk_smith_parse(s, m) == 0)
		return 0;
	fprintf(stderr, "brdfkit %s: --smith: unknown model '%s' (expected correlated, separable or schlick)\n",
	        cmd, s);
	return 2;
}

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
	               opts, 5};
	int rc = cli_parse(&cmd, argc, argv);
	if (rc)
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

/* "x.exr" -> "x.csv"; the caller has checked the suffix. */
static void csv_path(const char *exr, char *buf, size_t len)
{
	snprintf(buf, len, "%.*s.csv", (int)(strlen(exr) - 4), exr);
}

static int ends_with(const char *s, const char *suffix)
{
	size_t n = strlen(s), k = strlen(suffix);
	return n >= k && strcmp(s + n - k, suffix) == 0;
}

typedef struct lut_desc {
	int size, half, top;
	bk_smith m;
	long samples;
	double tol;
	char method[160], origin[200], command[1024];
} lut_desc;

static void write_csv_header(FILE *f, const lut_desc *d)
{
	fprintf(f, "# brdfkit %s DFG LUT, %dx%d, Smith %s\n", BK_VERSION, d->size, d->size,
	        smith_text[d->m]);
	fprintf(f, "# f0*A + B = integral of D*V*F*NoL over the light hemisphere; GGX D, Schlick F with f90 = 1\n");
	fprintf(f, "# nov and roughness (perceptual, alpha = r^2) at texel centres (i + 0.5)/%d; method: %s\n",
	        d->size, d->method);
	fprintf(f, "# command: %s\n", d->command);
	fputs("nov,roughness,A,B\n", f);
}

static int write_lut(const lut_desc *d, const char *out, const double *A, const double *B)
{
	int n = d->size;
	float *R = malloc(sizeof(float) * n * n), *G = malloc(sizeof(float) * n * n);
	char csv[4200], err[512];
	cli_out co;
	if (!R || !G) {
		free(R);
		free(G);
		return cli_fail("lut", "out of memory for a %dx%d table", n, n);
	}
	/* File row y holds roughness row j: y = j with the origin at the top. */
	for (int y = 0; y < n; y++) {
		int j = d->top ? y : n - 1 - y;
		for (int i = 0; i < n; i++) {
			R[(size_t)y * n + i] = (float)A[(size_t)j * n + i];
			G[(size_t)y * n + i] = (float)B[(size_t)j * n + i];
		}
	}
	csv_path(out, csv, sizeof csv);
	if (cli_out_open(&co, csv, err, sizeof err)) {
		free(R);
		free(G);
		return cli_fail("lut", "%s", err);
	}
	write_csv_header(co.f, d);
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++)
			fprintf(co.f, "%.9g,%.9g,%.9g,%.9g\n", (i + 0.5) / n, (j + 0.5) / n,
			        A[(size_t)j * n + i], B[(size_t)j * n + i]);

	char smith[128];
	snprintf(smith, sizeof smith, "%s", smith_text[d->m]);
	const bk_exr_attr attrs[] = {
		{"brdfkit:version", BK_EXR_ATTR_STRING, BK_VERSION, 0},
		{"brdfkit:axes", BK_EXR_ATTR_STRING, "x: NoV = (i + 0.5)/width at texel centres; y: perceptual roughness r = (j + 0.5)/height", 0},
		{"brdfkit:origin", BK_EXR_ATTR_STRING, d->origin, 0},
		{"brdfkit:roughness", BK_EXR_ATTR_STRING, "perceptual roughness r, linear in y; GGX alpha = r^2", 0},
		{"brdfkit:channels", BK_EXR_ATTR_STRING, "R = A (scale of f0), G = B (bias): f0*A + B = integral of D*V*F*NoL, GGX D, Schlick F with f90 = 1; linear data, never load as sRGB", 0},
		{"brdfkit:smith", BK_EXR_ATTR_STRING, smith, 0},
		{"brdfkit:method", BK_EXR_ATTR_STRING, d->method, 0},
		{"brdfkit:samples", BK_EXR_ATTR_INT, NULL, (int)d->samples},
		{"brdfkit:command", BK_EXR_ATTR_STRING, d->command, 0},
	};
	const char *names[2] = {"R", "G"};
	const float *data[2] = {R, G};
	int bad = bk_exr_write(out, n, n, 2, names, data, d->half, attrs,
	                       (int)(sizeof attrs / sizeof attrs[0]), err, sizeof err);
	free(R);
	free(G);
	if (bad) {
		cli_out_abort(&co);
		return cli_fail("lut", "%s", err);
	}
	if (cli_out_commit(&co, err, sizeof err)) {
		remove(out); /* keep the pair together: no EXR without its CSV */
		return cli_fail("lut", "%s", err);
	}
	return 0;
}

static void join_command(char *buf, size_t len, int argc, char **argv)
{
	size_t k = (size_t)snprintf(buf, len, "brdfkit lut");
	for (int i = 0; i < argc && k < len; i++)
		k += (size_t)snprintf(buf + k, len - k, " %s", argv[i]);
}

int cmd_lut(int argc, char **argv)
{
	long size = 0, samples = 0;
	const char *smith = "correlated", *origin = "top", *out = NULL;
	int half = 0;
	double tol = 1e-6;
	cli_opt opts[] = {
		{.name = "--size", .kind = CLI_INT, .metavar = "N", .help = "texels per side", .dest = &size, .lo = 1, .hi = 4096, .required = 1},
		{.name = "--smith", .kind = CLI_STR, .metavar = "MODEL", .help = "correlated (default), separable or schlick", .dest = &smith},
		{.name = "--samples", .kind = CLI_INT, .metavar = "N", .help = "Hammersley Monte Carlo bake with N samples (default: deterministic)", .dest = &samples, .lo = 1, .hi = 1 << 30},
		{.name = "--tol", .kind = CLI_NUM, .metavar = "T", .help = "tolerance of the deterministic integrator (default 1e-6)", .dest = &tol, .lo = 1e-13, .hi = 0.1},
		{.name = "--half", .kind = CLI_FLAG, .help = "store half floats (default float32)", .dest = &half},
		{.name = "--origin", .kind = CLI_STR, .metavar = "top|bottom", .help = "which image row holds the smallest roughness (default top)", .dest = &origin},
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE.exr", .help = "output; FILE.csv is written beside it", .dest = &out, .required = 1},
	};
	cli_cmd cmd = {"lut", "Writes the DFG look-up table the way engines sample it: x = NoV, y = perceptual\n"
	               "roughness, both at texel centres; R = A, G = B; ZIP-compressed OpenEXR with the\n"
	               "conventions as header attributes, and the same table as CSV (full precision).",
	               "--size N --out FILE.exr [--smith MODEL] [--samples N | --tol T] [--half] [--origin top|bottom]",
	               "origin top: the first scanline of the file (top of the image as displayed) is\n"
	               "r = 0.5/N, so texture(lut, vec2(NoV, r)) is right wherever uv (0,0) is the first\n"
	               "texel in memory (D3D, Vulkan, Metal, and GL when rows are uploaded in file order).\n"
	               "origin bottom: the last scanline is r = 0.5/N, for loaders that flip images.",
	               opts, 7};
	int rc = cli_parse(&cmd, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	lut_desc d = {.size = (int)size, .half = half, .samples = samples, .tol = tol};
	if (parse_smith("lut", smith, &d.m))
		return 2;
	if (strcmp(origin, "top") != 0 && strcmp(origin, "bottom") != 0) {
		fprintf(stderr, "brdfkit lut: --origin: expected top or bottom, got '%s'\n", origin);
		return 2;
	}
	if (!ends_with(out, ".exr") || strlen(out) == 4) {
		fprintf(stderr, "brdfkit lut: --out: expected a file name ending in .exr, got '%s'\n", out);
		return 2;
	}
	d.top = strcmp(origin, "top") == 0;
	snprintf(d.origin, sizeof d.origin, d.top
	         ? "top: scanline 0 (first in file, top as displayed) holds r = 0.5/height; uv (0,0) = first texel"
	         : "bottom: the last scanline (bottom as displayed) holds r = 0.5/height; first scanline r = 1 - 0.5/height");
	if (samples)
		snprintf(d.method, sizeof d.method, "Hammersley Monte Carlo, GGX importance sampling, %ld samples", samples);
	else
		snprintf(d.method, sizeof d.method, "deterministic adaptive Gauss-Kronrod over the half vector, tol %g", tol);
	join_command(d.command, sizeof d.command, argc, argv);

	size_t n = (size_t)size * (size_t)size;
	double *A = malloc(n * sizeof *A), *B = malloc(n * sizeof *B);
	if (!A || !B) {
		free(A);
		free(B);
		return cli_fail("lut", "out of memory for a %ldx%ld table", size, size);
	}
	rc = bk_dfg_lut((int)size, d.m, (unsigned)samples, tol, A, B, cli_progress, "lut rows");
	if (rc == 0)
		for (size_t k = 0; k < n && rc == 0; k++)
			if (!isfinite(A[k]) || !isfinite(B[k]))
				rc = -1;
	rc = rc ? cli_fail("lut", "integration failed (non-finite value)") : write_lut(&d, out, A, B);
	free(A);
	free(B);
	return rc;
}
