/*
 * render.c — the sphere grid of brdfkit render: geometry, sky and split-sum
 * inputs on the CPU, the shading on lavapipe from emitted GLSL and on the CPU
 * from the IR (see render.h for the scene).
 */
#include "render.h"

#include "clock.h"
#include "gpucost.h"
#include "out.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const term_names[BK_RT_COUNT] = {"vf", "d", "v", "f", "dvf", "env"};

const char *bk_render_term_name(bk_render_term t)
{
	return t >= 0 && t < BK_RT_COUNT ? term_names[t] : "?";
}

int bk_render_term_parse(const char *s, bk_render_term *t)
{
	if (!strcmp(s, "vf2d")) {
		*t = BK_RT_VF;
		return 0;
	}
	for (int i = 0; i < BK_RT_COUNT; i++)
		if (!strcmp(s, term_names[i])) {
			*t = (bk_render_term)i;
			return 0;
		}
	return -1;
}

int bk_render_term_of_target(const char *target, bk_render_term *t)
{
	static const struct { const char *target; bk_render_term t; } map[] = {
		{"VF", BK_RT_VF}, {"DVF", BK_RT_DVF}, {"V", BK_RT_V}, {"F", BK_RT_F},
		{"D", BK_RT_D},   {"env", BK_RT_ENV}, {"env_f0", BK_RT_ENV}};
	for (size_t i = 0; i < sizeof map / sizeof *map; i++)
		if (!strcmp(target, map[i].target)) {
			*t = map[i].t;
			return 0;
		}
	return -1;
}

/* ---- the scene's constants (render.h states them) ------------------------------ */

static const double light_e[3] = {3.0, 2.9, 2.7};
static const double albedo[3] = {0.30, 0.04, 0.03};
static const double f0_row[2][3] = {{0.04, 0.04, 0.04}, {1.00, 0.71, 0.29}};
static const double background[3] = {0.02, 0.02, 0.025};
/* NoV floor: a pixel centre can fall arbitrarily near the silhouette, NoV
 * -> 0, where V terms divide by zero; 1e-3 keeps every form in its domain
 * (engines clamp NoV alike) and is a normal number in half. */
#define NOV_MIN 1e-3
/* the camera's distance from each sphere's centre, in radii: a 50 mm lens
 * framing a head-sized sphere from about 1.5 m is near 4 */
#define CAM_DIST 4.0
/* the DFG per column: 129 nodes in sqrt(NoV), which crowds them where B
 * bends at grazing angles (tests/test_render.c: within 1e-4 of bk_dfg) */
#define DFG_NODES 129
/* the prefilter's and irradiance's fixed grid: 24 x 48 = 1152 directions,
 * enough that the sky's sun glow (width about 1/sqrt(200) rad) shows no
 * rings on the roughest spheres at 640 pixels */
#define GRID_U 24
#define GRID_PHI 48

static void normalize3(double v[3])
{
	double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	v[0] /= l, v[1] /= l, v[2] /= l;
}

static double dot3(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void light_dir(double L[3])
{
	L[0] = 0.5, L[1] = 0.6, L[2] = 0.62;
	normalize3(L);
}

static double smoothstep(double e0, double e1, double x)
{
	double t = fmin(fmax((x - e0) / (e1 - e0), 0), 1);
	return t * t * (3 - 2 * t);
}

void bk_render_sky(const double d[3], double rgb[3])
{
	static const double ground[3] = {0.20, 0.16, 0.12}, horizon[3] = {0.90, 0.85, 0.80},
	                    zenith[3] = {0.20, 0.35, 0.80}, sun[3] = {1, 0.95, 0.85};
	double L[3], P[3] = {-0.6, 0.4, 0.7};
	light_dir(L);
	normalize3(P);
	double t = smoothstep(-0.05, 0.05, d[1]), s = sqrt(fmax(d[1], 0));
	double glow = 8 * bk_dexp(200 * (dot3(d, L) - 1)), patch = 4 * bk_dexp(40 * (dot3(d, P) - 1));
	for (int c = 0; c < 3; c++) {
		double sky = horizon[c] + (zenith[c] - horizon[c]) * s;
		rgb[c] = ground[c] + (sky - ground[c]) * t + glow * sun[c] + patch;
	}
}

static void sky_fn(void *ctx, const double d[3], double rgb[3])
{
	(void)ctx;
	bk_render_sky(d, rgb);
}

/* An orthonormal frame (t1, t2, n) around unit n. */
static void frame(const double n[3], double t1[3], double t2[3])
{
	double up[3] = {0, 0, 1};
	if (fabs(n[2]) > 0.9)
		up[0] = 1, up[2] = 0;
	t1[0] = up[1] * n[2] - up[2] * n[1];
	t1[1] = up[2] * n[0] - up[0] * n[2];
	t1[2] = up[0] * n[1] - up[1] * n[0];
	normalize3(t1);
	t2[0] = n[1] * t1[2] - n[2] * t1[1];
	t2[1] = n[2] * t1[0] - n[0] * t1[2];
	t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

void bk_render_prefilter(bk_render_env_fn env, void *ctx, const double R[3], double a, double rgb[3])
{
	double t1[3], t2[3], sum[3] = {0, 0, 0}, wsum = 0;
	frame(R, t1, t2);
	for (int i = 0; i < GRID_U; i++)
		for (int j = 0; j < GRID_PHI; j++) {
			double hl[3], h[3], l[3], c[3];
			bk_ggx_sample_h((i + 0.5) / GRID_U, (j + 0.5) / GRID_PHI, a, hl);
			for (int k = 0; k < 3; k++)
				h[k] = hl[0] * t1[k] + hl[1] * t2[k] + hl[2] * R[k];
			double rh = dot3(R, h);
			for (int k = 0; k < 3; k++)
				l[k] = 2 * rh * h[k] - R[k];
			double w = dot3(R, l);
			if (w <= 0)
				continue;
			env(ctx, l, c);
			for (int k = 0; k < 3; k++)
				sum[k] += w * c[k];
			wsum += w;
		}
	for (int k = 0; k < 3; k++)
		rgb[k] = wsum > 0 ? sum[k] / wsum : 0;
}

void bk_render_irradiance(bk_render_env_fn env, void *ctx, const double N[3], double rgb[3])
{
	double t1[3], t2[3], sum[3] = {0, 0, 0};
	frame(N, t1, t2);
	for (int i = 0; i < GRID_U; i++)
		for (int j = 0; j < GRID_PHI; j++) {
			double u = (i + 0.5) / GRID_U, phi = 2 * BK_PI * (j + 0.5) / GRID_PHI, s = sqrt(u), d[3], c[3];
			for (int k = 0; k < 3; k++)
				d[k] = s * bk_dcos(phi) * t1[k] + s * bk_dsin(phi) * t2[k] + sqrt(1 - u) * N[k];
			env(ctx, d, c);
			for (int k = 0; k < 3; k++)
				sum[k] += c[k];
		}
	for (int k = 0; k < 3; k++)
		rgb[k] = sum[k] / (GRID_U * GRID_PHI);
}

/* ---- the DFG per roughness: nodes in u = sqrt(NoV), Catmull-Rom ---------------- */

static double node_u(int i)
{
	double u0 = sqrt(NOV_MIN);
	return u0 + (1 - u0) * i / (DFG_NODES - 1);
}

static int dfg_table(double r, double *A, double *B)
{
	for (int i = 0; i < DFG_NODES; i++) {
		double u = node_u(i);
		if (bk_dfg(fmin(u * u, 1), r, BK_SMITH_CORRELATED, BK_DFG_TOL, &A[i], &B[i], NULL))
			return -1;
	}
	return 0;
}

static double catmull_rom(const double *y, double NoV)
{
	double u0 = sqrt(NOV_MIN), x = (sqrt(fmax(NoV, NOV_MIN)) - u0) / (1 - u0) * (DFG_NODES - 1);
	int k = (int)floor(x);
	if (k >= DFG_NODES - 1)
		k = DFG_NODES - 2;
	if (k < 0)
		k = 0;
	double t = x - k;
	double p0 = y[k > 0 ? k - 1 : 0], p1 = y[k], p2 = y[k + 1], p3 = y[k + 2 < DFG_NODES ? k + 2 : DFG_NODES - 1];
	return 0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t * t + (3 * p1 - p0 - 3 * p2 + p3) * t * t * t);
}

int bk_render_dfg(double NoV, double r, double *A, double *B)
{
	double ta[DFG_NODES], tb[DFG_NODES];
	if (dfg_table(r, ta, tb))
		return -1;
	*A = catmull_rom(ta, NoV);
	*B = catmull_rom(tb, NoV);
	return 0;
}

/* ---- geometry ----------------------------------------------------------------- */

void bk_render_geom_free(bk_render_geom *g)
{
	free(g->in);
	free(g->pixel);
	free(g->sphere);
	free(g->background);
	memset(g, 0, sizeof *g);
}

int bk_render_geometry(const bk_render_scene *s, bk_render_env_fn env, void *ctx, bk_render_geom *g, char *err,
                       size_t errlen)
{
	memset(g, 0, sizeof *g);
	if (!env)
		env = sky_fn;
	if (s->cell < BK_RENDER_MIN_CELL || s->ncols < 1 || s->ncols > BK_RENDER_MAX_COLS || s->cell > BK_RENDER_MAX_CELL) {
		snprintf(err, errlen, "a scene of %d columns of %d pixels", s->ncols, s->cell);
		return -1;
	}
	g->ncols = s->ncols;
	g->width = s->cell * s->ncols;
	g->height = 2 * s->cell;
	size_t npix = (size_t)g->width * (size_t)g->height;
	g->sphere = malloc(npix * sizeof *g->sphere);
	g->background = malloc(npix * 3 * sizeof *g->background);
	g->in = malloc(npix * 3 * BK_RENDER_STRIDE * sizeof *g->in);
	g->pixel = malloc(npix * 3 * sizeof *g->pixel);
	double (*ta)[DFG_NODES] = malloc(sizeof(double[DFG_NODES]) * (size_t)s->ncols * 2);
	if (!g->sphere || !g->background || !g->in || !g->pixel || !ta) {
		free(ta);
		bk_render_geom_free(g);
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	double (*tb)[DFG_NODES] = ta + s->ncols;
	for (int c = 0; c < s->ncols; c++)
		if (dfg_table(s->r[c], ta[c], tb[c])) {
			free(ta);
			bk_render_geom_free(g);
			snprintf(err, errlen, "roughness %g is out of the DFG's range", s->r[c]);
			return -1;
		}
	double L[3];
	light_dir(L);
	/* each sphere seen by its own pinhole camera at CAM_DIST radii on +z,
	 * its silhouette on the cell's circle of radius 0.45 cell: V, H and LoH
	 * change across the sphere as under a real camera (an orthographic view
	 * with a directional light would hold LoH constant on the whole image) */
	double rad = 0.45 * s->cell, t = 1 / sqrt(CAM_DIST * CAM_DIST - 1); /* tan of the silhouette's half-angle */
	for (int y = 0; y < g->height; y++)
		for (int x = 0; x < g->width; x++) {
			size_t p = (size_t)y * (size_t)g->width + (size_t)x;
			int row = y / s->cell, col = x / s->cell;
			double u = (x + 0.5 - (col + 0.5) * s->cell) / rad, v = -(y + 0.5 - (row + 0.5) * s->cell) / rad;
			double D[3] = {u * t, v * t, -1}, C[3] = {0, 0, CAM_DIST};
			normalize3(D);
			double b = dot3(C, D), disc = b * b - (CAM_DIST * CAM_DIST - 1);
			if (disc <= 0) {
				g->sphere[p] = -1;
				for (int c = 0; c < 3; c++)
					g->background[p * 3 + c] = (float)background[c];
				continue;
			}
			g->sphere[p] = row * s->ncols + col;
			double hit = -b - sqrt(disc), N[3], V[3], H[3];
			for (int k = 0; k < 3; k++) {
				N[k] = C[k] + hit * D[k]; /* the unit sphere at the origin */
				V[k] = -D[k];
			}
			normalize3(N);
			for (int k = 0; k < 3; k++)
				H[k] = L[k] + V[k];
			normalize3(H);
			double r = s->r[col], a = r * r;
			double NoV = dot3(N, V), R[3], pref[3], irr[3];
			for (int k = 0; k < 3; k++)
				R[k] = 2 * NoV * N[k] - V[k];
			NoV = fmax(NoV, NOV_MIN);
			double NoL = fmax(dot3(N, L), 0), NoH = fmax(dot3(N, H), 0), LoH = dot3(L, H);
			bk_render_prefilter(env, ctx, R, a, pref);
			if (row == 0)
				bk_render_irradiance(env, ctx, N, irr);
			double A = catmull_rom(ta[col], NoV), B = catmull_rom(tb[col], NoV);
			for (int c = 0; c < 3; c++) {
				g->background[p * 3 + c] = NAN;
				float *in = g->in + g->n * BK_RENDER_STRIDE;
				double diff = row == 0 ? albedo[c] * (light_e[c] * NoL / BK_PI + irr[c]) : 0;
				double vals[BK_RENDER_STRIDE] = {NoV, NoL, NoH, LoH, r, a, f0_row[row][c], light_e[c], pref[c], A,
				                                 B, diff};
				for (int k = 0; k < BK_RENDER_STRIDE; k++)
					in[k] = (float)vals[k];
				g->pixel[g->n++] = (int)(p * 3 + (size_t)c);
			}
		}
	free(ta);
	return 0;
}

/* ---- the shader ----------------------------------------------------------------- */

static const char *const exact_text[3] = {"D_ggx(NoH, a)", "V_smith_ggx_correlated(NoV, NoL, a)",
                                          "F_schlick(f0, 1, LoH)"};
static const char *const exact_name[3] = {"bk_exact_D", "bk_exact_V", "bk_exact_F"};

/* name(args) with the inputs f reads, in brdf.h's order (the emitted signature's). */
static void put_call(bk_strbuf *b, const char *name, const bk_form *f)
{
	unsigned in = bk_form_inputs(f);
	const char *sep = "";
	bk_sb_put(b, "%s(", name);
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (in >> c & 1) {
			bk_sb_put(b, "%s%s", sep, bk_input_name((bk_input)c));
			sep = ", ";
		}
	bk_sb_put(b, ")");
}

static int put_function(bk_strbuf *b, const bk_form *f, const double *params, const char *name, const char *source,
                        bk_precision prec)
{
	bk_emit_info info = {.name = name, .source = source, .command = bk_out_command()};
	char *text = bk_form_emit(f, BK_LANG_GLSL, 0, params, &info);
	char *h = text && prec == BK_F16 ? bk_lvp_half_text(text) : NULL;
	if (!text || (prec == BK_F16 && !h)) {
		free(text);
		return -1;
	}
	bk_sb_put(b, "%s\n", h ? h : text);
	free(text);
	free(h);
	return 0;
}

/* The exact terms' forms, parsed once per call (cheap). */
static int exact_forms(bk_form *ex[3])
{
	for (int i = 0; i < 3; i++) {
		bk_form_error e;
		if (!(ex[i] = bk_form_parse(exact_text[i], &e))) {
			for (int j = 0; j < i; j++)
				bk_form_free(ex[j]);
			return -1;
		}
	}
	return 0;
}

/* The shading of one sample, spelled in the order render.h states; term t's
 * factor is the candidate's call when cand, else the exact one. */
static void put_shading(bk_strbuf *b, const bk_render_cand *c, bk_form *const ex[3], int cand)
{
	const char *T = "T";
	bk_sb_put(b, "\t\t%s spec = %s(0.0);\n\t\tif (NoL > %s(0.0))\n\t\t\tspec = ", T, T, T);
	if (cand && c->term == BK_RT_DVF)
		put_call(b, "bk_cand", c->form);
	else {
		for (int i = 0; i < 3; i++) {
			int mine = cand && ((c->term == BK_RT_D && i == 0) || (c->term == BK_RT_V && i == 1) ||
			                    (c->term == BK_RT_F && i == 2));
			if (cand && c->term == BK_RT_VF && i == 2)
				continue; /* V·F is one call, put at i == 1 */
			if (i)
				bk_sb_put(b, " * ");
			if (cand && c->term == BK_RT_VF && i == 1)
				put_call(b, "bk_cand", c->form);
			else if (mine)
				put_call(b, "bk_cand", c->form);
			else
				put_call(b, exact_name[i], ex[i]);
		}
	}
	bk_sb_put(b, " * NoL * light;\n\t\t%s env = ", T);
	if (cand && c->term == BK_RT_ENV && c->form_b) {
		bk_sb_put(b, "f0 * ");
		put_call(b, "bk_cand", c->form);
		bk_sb_put(b, " + ");
		put_call(b, "bk_cand_b", c->form_b);
	} else if (cand && c->term == BK_RT_ENV)
		put_call(b, "bk_cand", c->form);
	else
		bk_sb_put(b, "f0 * EA + EB");
	bk_sb_put(b, ";\n\t\tres = spec + pref * env + diff;\n");
}

char *bk_render_shader(const bk_render_cand *c, bk_precision prec)
{
	bk_form *ex[3];
	if (exact_forms(ex))
		return NULL;
	bk_strbuf b = {0};
	bk_lvp_head(&b, prec);
	bk_sb_put(&b, "#define T %s\n\n", prec == BK_F16 ? "float16_t" : "float");
	int bad = 0;
	for (int i = 0; i < 3; i++)
		bad |= put_function(&b, ex[i], NULL, exact_name[i], "brdfkit render: the exact term", prec);
	bad |= put_function(&b, c->form, c->params, "bk_cand", c->label, prec);
	if (c->form_b)
		bad |= put_function(&b, c->form_b, c->params, "bk_cand_b", c->label, prec);
	static const char *const slot[BK_RENDER_STRIDE] = {"NoV", "NoL", "NoH", "LoH", "r", "a", "f0",
	                                                   "light", "pref", "EA", "EB", "diff"};
	bk_sb_put(&b, "void main()\n{\n\tuint k = gl_GlobalInvocationID.x;\n\tif (k >= pc.n)\n\t\treturn;\n"
	              "\tuint i = (pc.in_off + k) * %du;\n", BK_RENDER_STRIDE);
	for (int s = 0; s < BK_RENDER_STRIDE; s++)
		bk_sb_put(&b, "\tT %s = T(inb.v[i + %du]);\n", slot[s], s);
	bk_sb_put(&b, "\tT res;\n\tif (pc.fn == 0u) {\n");
	put_shading(&b, c, ex, 0);
	bk_sb_put(&b, "\t} else {\n");
	put_shading(&b, c, ex, 1);
	bk_sb_put(&b, "\t}\n\toutb.v[pc.out_off + k] = float(res);\n}\n");
	for (int i = 0; i < 3; i++)
		bk_form_free(ex[i]);
	if (bad || b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

/* ---- running it ----------------------------------------------------------------- */

static void fill_background(const bk_render_geom *g, float *img)
{
	memcpy(img, g->background, (size_t)g->width * (size_t)g->height * 3 * sizeof *img);
}

int bk_render_gpu(bk_lvp *v, const bk_render_geom *g, const bk_render_cand *c, bk_precision prec, float *img[2],
                  double seconds[2], char *err, size_t errlen)
{
	char *glsl = bk_render_shader(c, prec);
	if (!glsl) {
		snprintf(err, errlen, "cannot write the shader (out of memory, or a form the emitter refuses)");
		return -1;
	}
	double t0 = bk_clock_now();
	size_t nw = 0;
	char log[1024];
	unsigned *spirv = bk_gpucost_spirv(glsl, &nw, log, sizeof log);
	free(glsl);
	seconds[0] = bk_clock_now() - t0;
	if (!spirv) {
		snprintf(err, errlen, "glslang refused the render shader: %.900s", log);
		return -1;
	}
	/* dispatches of at most 2^20 invocations (16384 workgroups, far under the limit) */
	const size_t chunk = (size_t)1 << 20;
	int nd = 0, cap = 2 * (int)((g->n + chunk - 1) / chunk) + 2;
	bk_lvp_dispatch *d = calloc((size_t)cap, sizeof *d);
	float *out = malloc((2 * g->n + 1) * sizeof *out);
	int rc = d && out ? 0 : -1;
	if (rc)
		snprintf(err, errlen, "out of memory");
	for (int fn = 0; !rc && fn < 2; fn++)
		for (size_t o = 0; o < g->n; o += chunk)
			d[nd++] = (bk_lvp_dispatch){0, (uint32_t)fn, (uint32_t)o, (uint32_t)(fn * g->n + o),
			                            (uint32_t)(g->n - o < chunk ? g->n - o : chunk)};
	double t[2] = {0, 0};
	unsigned *const sp[1] = {spirv};
	if (!rc)
		rc = bk_lvp_run(v, sp, &nw, 1, g->in, g->n * BK_RENDER_STRIDE + 1, d, nd, out, 2 * g->n + 1, t, err, errlen);
	seconds[1] = t[0] + t[1];
	for (int k = 0; !rc && k < 2; k++) {
		fill_background(g, img[k]);
		for (size_t s = 0; s < g->n; s++)
			img[k][g->pixel[s]] = out[k * g->n + s];
	}
	free(spirv);
	free(d);
	free(out);
	return rc;
}

static double h16(double x, bk_precision prec)
{
	return prec == BK_F16 ? bk_half_round(x) : x;
}

int bk_render_cpu(const bk_render_geom *g, const bk_render_cand *c, bk_precision prec, float *img[2])
{
	bk_form *ex[3];
	if (exact_forms(ex))
		return -1;
	size_t n = g->n ? g->n : 1;
	double *col = malloc(sizeof(double) * n * (BK_RENDER_STRIDE + 5));
	int rc = col ? 0 : -1;
	if (!rc) {
		double *s[BK_RENDER_STRIDE], *val[5]; /* D, V, F exact; cand, cand_b */
		for (int k = 0; k < BK_RENDER_STRIDE; k++)
			s[k] = col + (size_t)k * n;
		for (int k = 0; k < 5; k++)
			val[k] = col + (size_t)(BK_RENDER_STRIDE + k) * n;
		for (size_t i = 0; i < g->n; i++)
			for (int k = 0; k < BK_RENDER_STRIDE; k++)
				s[k][i] = g->in[i * BK_RENDER_STRIDE + (size_t)k];
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = s[k]; /* the slots open with the form inputs in brdf.h's order */
		bk_precision ip = prec == BK_F16 ? BK_F16 : BK_F64;
		for (int k = 0; k < 3 && !rc; k++)
			rc = bk_form_eval(ex[k], ip, g->n, in, NULL, val[k]);
		if (!rc)
			rc = bk_form_eval(c->form, ip, g->n, in, c->params, val[3]);
		if (!rc && c->form_b)
			rc = bk_form_eval(c->form_b, ip, g->n, in, c->params, val[4]);
		for (int k = 0; k < 2 && !rc; k++) {
			fill_background(g, img[k]);
			for (size_t i = 0; i < g->n; i++) {
				double x[BK_RENDER_STRIDE];
				for (int j = 0; j < BK_RENDER_STRIDE; j++)
					x[j] = h16(s[j][i], prec);
				double D = val[0][i], V = val[1][i], F = val[2][i], cv = val[3][i], spec = 0, env;
				if (k && c->term == BK_RT_D)
					D = cv;
				if (k && c->term == BK_RT_V)
					V = cv;
				if (k && c->term == BK_RT_F)
					F = cv;
				if (x[BK_RS_NOL] > 0) {
					if (k && c->term == BK_RT_DVF)
						spec = cv;
					else if (k && c->term == BK_RT_VF)
						spec = h16(D * cv, prec);
					else
						spec = h16(h16(D * V, prec) * F, prec);
					spec = h16(h16(spec * x[BK_RS_NOL], prec) * x[BK_RS_LIGHT], prec);
				}
				if (k && c->term == BK_RT_ENV)
					env = c->form_b ? h16(h16(x[BK_RS_F0] * cv, prec) + val[4][i], prec) : cv;
				else
					env = h16(h16(x[BK_RS_F0] * x[BK_RS_EA], prec) + x[BK_RS_EB], prec);
				double res = h16(h16(spec + h16(x[BK_RS_PREF] * env, prec), prec) + x[BK_RS_DIFF], prec);
				img[k][g->pixel[i]] = (float)res;
			}
		}
	}
	free(col);
	for (int i = 0; i < 3; i++)
		bk_form_free(ex[i]);
	return rc;
}

double bk_render_display(double x)
{
	if (!(x > 0))
		return 0;
	double t = isinf(x) ? 1 : x / (1 + x);
	return t <= 0.0031308 ? 12.92 * t : t >= 1 ? 1 : 1.055 * bk_dpow(t, 1 / 2.4) - 0.055;
}
