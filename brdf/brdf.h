/*
 * brdf.h — libbrdf: exact BRDF terms, published approximations, reference integrals.
 *
 * CONVENTIONS (every function in this library follows them; a term that takes a
 * source's own convention says so in its name and its comment)
 *
 *   r      perceptual roughness in [0, 1] (what artists paint).
 *   a      alpha = r*r. GGX, Beckmann and Smith terms take a; a2 = a*a.
 *   NoV, NoL, NoH, LoH
 *          cosines on the upper hemisphere of a +Z normal N; V is the view
 *          direction, L the light direction, H = normalize(V + L), so LoH = VoH.
 *   D      normal distribution, normalised so that ∫ D(h) NoH dω_h = 1.
 *   V      visibility G / (4 NoL NoV): the 1/4 is folded in. (Hable's and the
 *          mobile talk's printed "V" leave the 1/4 out; their entries here add it.)
 *   F      Fresnel. Schlick: F = f0 + (f90 - f0)(1 - LoH)^5, f90 = 1 unless a term
 *          says otherwise; f0 is the normal-incidence reflectance (0.04 for common
 *          dielectrics, glass of index 1.5).
 *   Fd     diffuse, with the 1/π included (Lambert = 1/π), albedo multiplied outside.
 *   specular BRDF = D·V·F; the rendered quantity is BRDF·NoL.
 *   Split-sum environment BRDF (Karis 2013): for Schlick F with f90 = 1,
 *          ∫ D·V·F·NoL dω_l = f0·A(NoV, r) + B(NoV, r), where
 *          A = ∫ D·V·NoL·(1 - Fc), B = ∫ D·V·NoL·Fc, Fc = (1 - LoH)^5.
 *   All values are physical (no π-scaled "Unity" BRDF values, no 1/4 dropped).
 *
 * Glossary of prefixes: bk_D_ (distribution), bk_Lambda_/bk_G1_ (Smith masking),
 * bk_V_ (visibility), bk_F_ (Fresnel), bk_Fd_ (diffuse), bk_term_ (the registry),
 * bk_dfg_ (split-sum integrals), bk_albedo (directional albedo).
 */
#ifndef BRDF_H
#define BRDF_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" { /* C linkage for a C++ program (tests/install.sh links one) */
#endif

#define BK_VERSION "0.1.0"
#define BK_PI 3.14159265358979323846

/* ---- D: normal distributions --------------------------------------------- */

double bk_D_ggx(double NoH, double a);
/* The same with sin^2 of the half-vector angle given, for callers that know the
 * angle: keeps full precision at the peak of very smooth surfaces. */
double bk_D_ggx_sin2(double sin2h, double NoH, double a);
double bk_D_beckmann(double NoH, double a);
double bk_D_blinn_phong(double NoH, double a);
double bk_D_blinn_phong_sg(double NoH, double a);
/* Blinn-Phong exponent for a given alpha (Walter et al. 2007): n = 2/a^2 - 2. */
double bk_blinn_phong_exponent(double a);

/* ---- Smith masking: Lambda, G1, and the visibility built from them ------- */

double bk_Lambda_ggx(double NoX, double a);
double bk_G1_ggx(double NoX, double a);
double bk_Lambda_beckmann(double NoX, double a);
double bk_G1_beckmann(double NoX, double a);

double bk_V_smith_ggx_separable(double NoV, double NoL, double a);
double bk_V_smith_ggx_correlated(double NoV, double NoL, double a);
/* H with density D_ggx(h) NoH from two uniform numbers in [0, 1). */
void bk_ggx_sample_h(double u1, double u2, double a, double h[3]);

/* ---- V: published approximations ------------------------------------------ */

double bk_V_schlick_ggx(double NoV, double NoL, double k);
double bk_V_schlick_ggx_ibl(double NoV, double NoL, double a);     /* k = a/2 */
double bk_V_schlick_ggx_direct(double NoV, double NoL, double r);  /* k = (r+1)^2/8 */
double bk_V_kelemen(double LoH);
double bk_V_kelemen_hable(double LoH, double a);
double bk_V_kelemen_talk(double LoH, double r);
double bk_V_neubelt(double NoV, double NoL);
double bk_V_neumann(double NoV, double NoL);
double bk_V_implicit(void);
double bk_V_cook_torrance(double NoV, double NoL, double NoH, double VoH);
double bk_V_hammon(double NoV, double NoL, double a);

/* ---- F: Fresnel ------------------------------------------------------------ */

double bk_F_schlick(double f0, double f90, double LoH);
double bk_F_schlick_sg(double f0, double f90, double LoH);
double bk_F_schuler(double f0, double LoH);
/* Exact dielectric reflectance for relative index eta (transmitted / incident
 * side); the s and p reflectances separately, and their unpolarised mean. */
void bk_fresnel_dielectric_sp(double cos_i, double eta, double *Rs, double *Rp);
double bk_F_dielectric(double cos_i, double eta);
double bk_F_conductor(double cos_i, double eta, double k);
/* Normal-incidence reflectance of a complex index n + ik, and the real index of a
 * dielectric with reflectance f0: n = (1 + sqrt f0)/(1 - sqrt f0), f0 < 1. */
double bk_f0_from_ior(double eta, double k);
double bk_ior_from_f0(double f0);

/* ---- Fd: diffuse ---------------------------------------------------------- */

double bk_Fd_lambert(void);
double bk_Fd_burley(double NoV, double NoL, double LoH, double r);
double bk_Fd_oren_nayar(double NoV, double NoL, double VoL, double sigma);

/* ---- The term registry ---------------------------------------------------
 * Every term above, by name, with one uniform evaluator so that integrators,
 * the command-line tool and (later) the formula IR reach them the same way.
 * Names are the IR's spelling: "D_ggx", "V_smith_ggx_correlated", "F_schlick".
 */

typedef enum bk_role { BK_ROLE_D, BK_ROLE_V, BK_ROLE_F, BK_ROLE_FD } bk_role;

/* One evaluation point. The geometry cosines must be mutually consistent
 * (bk_sample_geometry builds them); a = r*r is derived, never set alone
 * (bk_sample_roughness sets both). */
typedef struct bk_sample {
	double NoV, NoL, NoH, LoH; /* LoH = VoH */
	double r, a;               /* perceptual roughness and alpha = r*r */
	double f0, f90;            /* Schlick parameters */
	double eta, k;             /* complex index n + ik for the exact Fresnel terms */
} bk_sample;

typedef struct bk_term {
	const char *name;       /* IR spelling, e.g. "V_smith_ggx_correlated" */
	bk_role role;
	const char *args;       /* the C function's arguments, e.g. "NoV,NoL,a" */
	const char *summary;    /* what it computes, one line */
	const char *convention; /* roughness meaning, 1/4 and π conventions */
	const char *citation;   /* authors, year, title; "unverified" where so */
	double (*eval)(const bk_sample *s);
} bk_term;

size_t bk_term_count(void);
const bk_term *bk_term_at(size_t i);
/* Finds a term by its full name ("D_ggx") or, when role is given, by the name
 * without the role prefix ("ggx"). Returns NULL when none matches. */
const bk_term *bk_term_find(const char *name);
const bk_term *bk_term_find_role(bk_role role, const char *name);
const char *bk_role_name(bk_role role);

/* Fills the geometry of s (NoV, NoL, NoH, LoH) from the polar angle of V, the
 * polar angle of L and their azimuth difference phi (radians); the material
 * fields are left as they are. Angles within ±8 take brdfkit's sin and cos
 * (bk_dsin, bk_dcos), so the same bits on every x86-64 machine. */
void bk_sample_geometry(bk_sample *s, double theta_v, double theta_l, double phi);
void bk_sample_roughness(bk_sample *s, double r);

/* ---- Reference integrals ---------------------------------------------------
 * Deterministic: nested adaptive Gauss-Kronrod quadrature over the half vector.
 * See brdf/integrate.c for the parametrisation and the error control.
 */

typedef enum bk_smith {
	BK_SMITH_CORRELATED, /* bk_V_smith_ggx_correlated (Heitz 2014) */
	BK_SMITH_SEPARABLE,  /* bk_V_smith_ggx_separable */
	BK_SMITH_SCHLICK,    /* bk_V_schlick_ggx_ibl, k = a/2 (Karis 2013) */
	BK_SMITH_COUNT
} bk_smith;

const char *bk_smith_name(bk_smith m);            /* "correlated", ... */
double bk_V_smith(bk_smith m, double NoV, double NoL, double a);
int bk_smith_parse(const char *s, bk_smith *out); /* 0 on success */

typedef struct bk_quad_stats {
	double err;   /* the quadrature's own absolute error estimate */
	long evals;   /* integrand evaluations */
	int converged;/* 1 if the requested tolerance was met */
} bk_quad_stats;

/* Default absolute tolerance of the reference integrals. The outer and inner
 * quadratures share it; the tests check the result against an independent
 * brute-force integration to 1e-6, the accuracy the library promises. */
#define BK_DFG_TOL 1e-8

/* Split-sum A and B for GGX D, Schlick F (f90 = 1) and the given Smith model.
 * NoV in (0, 1], r in [0, 1]; r = 0 returns the exact smooth limit
 * A = 1 - (1 - NoV)^5, B = (1 - NoV)^5. stats may be NULL. Returns 0, or -1 on
 * an argument out of range. */
int bk_dfg(double NoV, double r, bk_smith m, double tol, double *A, double *B,
           bk_quad_stats *stats);

/* The engines' usual bake: n Hammersley points, GGX importance sampling of H,
 * as in Karis 2013's IntegrateBRDF. Deterministic, but with Monte Carlo error. */
int bk_dfg_hammersley(double NoV, double r, bk_smith m, unsigned n, double *A,
                      double *B);

/* Directional albedo ∫ D·V·F·NoL dω_l of any registered D, V and F at the
 * material in s (r, f0, f90, eta, k; the geometry of s is ignored). Lobes
 * below what doubles resolve take the smooth limit H = N, except the sheen
 * D terms, whose mass goes to the horizon instead (integrate.c). Registry
 * D terms see only NoH, whose rounding limits them near the peak to a relative
 * error of about 1e-16/a2 (1e-6 at r = 0.003); bk_dfg does not have this limit. */
int bk_albedo(const bk_term *D, const bk_term *V, const bk_term *F,
              const bk_sample *material, double NoV, double tol, double *out,
              bk_quad_stats *stats);

/* ---- DFG look-up table ---------------------------------------------------
 * size x size texels; texel (i, j) holds NoV = (i + 0.5)/size and perceptual
 * roughness r = (j + 0.5)/size, both at texel centres. Arrays are row-major in
 * j (roughness); the file writer decides which row is on top. samples = 0 uses
 * the deterministic integrator, otherwise the Hammersley bake with that many
 * samples. progress, if not NULL, is called after each row. */
typedef void (*bk_progress_fn)(void *ctx, int done, int total);
int bk_dfg_lut(int size, bk_smith m, unsigned samples, double tol, double *A,
               double *B, bk_progress_fn progress, void *ctx);

/* A LUT laid out for one scene (brdfkit scene): nu x nr texels, rows only
 * over the scene's roughness range, the NoV axis warped so that texels crowd
 * where B bends (grazing angles), optionally f0 folded into one channel.
 * Texel (i, j) sits at the texel centre u = (i + 0.5)/nu, v = (j + 0.5)/nr of
 * the texture coordinates
 *   u = warp(NoV)                       none: NoV; sqrt: sqrt(NoV)
 *   v = (r - r_lo)/(r_hi - r_lo)
 * so a shader samples texture(lut, vec2(warp(NoV), r*scale + offset)). sqrt
 * puts texel i at NoV = ((i + 0.5)/nu)^2: at smooth roughness B falls from 1
 * to its plateau within NoV ~ a of 0, where uniform texels are too coarse,
 * and B is smooth near NoV = 1 where the spacing doubles. (NoV (2 - NoV),
 * two ALU ops instead of a square root, was tried: its spacing near NoV = 1
 * grows as the square root of the texel size and it lost on rough scenes.)
 * {size, size, 0, 1, NONE, NaN} is bk_dfg_lut's layout. */
typedef enum bk_lut_warp { BK_LUT_WARP_NONE, BK_LUT_WARP_SQRT, BK_LUT_WARPS } bk_lut_warp;
typedef struct bk_lut_layout {
	int nu, nr;          /* texels along NoV (x) and r (y) */
	double r_lo, r_hi;   /* 0 <= r_lo < r_hi <= 1 */
	bk_lut_warp warp;
	double f0;           /* NaN: two channels A, B; a value: one channel f0 A + B */
} bk_lut_layout;
const char *bk_lut_warp_name(bk_lut_warp w); /* "none", "sqrt" */
const char *bk_lut_warp_form(bk_lut_warp w); /* the coordinate u in the formula language */
/* u and v of a point (clamped to [0, 1]), and the NoV and r of texel i or j. */
double bk_lut_u(const bk_lut_layout *L, double NoV);
double bk_lut_v(const bk_lut_layout *L, double r);
double bk_lut_texel_nov(const bk_lut_layout *L, int i);
double bk_lut_texel_r(const bk_lut_layout *L, int j);
/* 0 when L is a valid layout, else -1. */
int bk_lut_layout_check(const bk_lut_layout *L);
/* A and B at L's texels (nu*nr each, row-major in r) as bk_dfg_lut computes
 * them; a one-channel layout is folded by the caller (f0 A + B). */
int bk_dfg_lut_layout(const bk_lut_layout *L, bk_smith m, unsigned samples, double tol, double *A, double *B,
                      bk_progress_fn progress, void *ctx);

/* ---- Multiple scattering: energy compensation (brdf/multiscatter.c) -------
 * Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks"
 * (SIGGRAPH course Physically Based Shading in Theory and Practice). GGX D with
 * an exact Smith model m, F = 1:
 *   E(NoV, r)  = ∫ D·V·NoL dω_l, the single-scattering directional albedo; with
 *                F = 1 it is the split sum's A + B (bk_dfg), and Filament's DFG
 *                LUT keeps it in its second channel (dfg.y).
 *   E_avg(r)   = 2 ∫_0^1 E(μ) μ dμ, its cosine-weighted average.
 *   f_ms       = (1 - E(NoV)) (1 - E(NoL)) / (π (1 - E_avg)), the compensation
 *                lobe: ∫ (f_ss + f_ms) NoL dω_l = 1 for every NoV (white furnace).
 *   F_avg      = 2 ∫_0^1 F(μ) μ dμ; for Schlick f0 + (f90 - f0)/21.
 *   With Fresnel, f_ms is scaled by F_avg² E_avg / (1 - F_avg (1 - E_avg)).
 * The single-lobe alternative (Turquin 2019, "Practical multiple scattering
 * compensation for microfacet models"; Filament's energyCompensation) scales
 * f_ss by 1 + f0 (1/E(NoV) - 1).
 */
/* E = A + B of bk_dfg for Smith model m (correlated or separable; Schlick's
 * approximate V is accepted too). NoV in (0, 1], r in [0, 1]. 0, or -1 on an
 * argument out of range. */
int bk_ms_E(double NoV, double r, bk_smith m, double tol, double *E);
/* E_avg(r) by adaptive Gauss-Kronrod over μ of bk_ms_E's values; tol is the
 * absolute tolerance of the result (each E is integrated to tol/4). stats may
 * be NULL. 0, or -1 on an argument out of range. */
int bk_ms_E_avg(double r, bk_smith m, double tol, double *E_avg, bk_quad_stats *stats);
/* The compensation lobe f_ms from E at the two directions and E_avg; 0 when
 * E_avg = 1 (nothing to compensate: r = 0). */
double bk_ms_lobe(double E_o, double E_i, double E_avg);
/* F_avg of Schlick's F with f0, f90: f0 + (f90 - f0)/21 (2 ∫ (1-μ)^5 μ dμ = 1/21). */
double bk_ms_F_avg_schlick(double f0, double f90);
/* The factor Kulla & Conty scale f_ms by for a Fresnel of average F_avg:
 * F_avg² E_avg / (1 - F_avg (1 - E_avg)); 1 at F_avg = 1. */
double bk_ms_fresnel_scale(double F_avg, double E_avg);
/* Turquin 2019 / Filament: 1 + f0 (1/E - 1), the factor on f_ss. E in (0, 1]. */
double bk_ms_energy_compensation(double f0, double E);

/* ---- Sheen and cloth (brdf/sheen.c, sheen_albedo.c) -----------------------
 * a = r^2 as everywhere (Filament's cloth passes its alpha, r^2, to D). */
/* Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF": the
 * "Charlie" distribution (2 + 1/a) sin(θh)^(1/a) / (2π), a in (0, 1];
 * normalised; 0 at a = 0 (its limit for NoH > 0). */
double bk_D_charlie(double NoH, double a);
/* Ashikhmin & Premože 2007, "Distribution-based BRDFs" (velvet), as Filament's
 * D_Ashikhmin: (1 + 4 exp(-cot²θh/a²)/sin⁴θh) / (π (1 + 4 a²)); normalised. */
double bk_D_ashikhmin(double NoH, double a);
/* The sheen directional albedo ∫ D_charlie(a)·V_neubelt·NoL dω_l, F = 1: the
 * cloth channel Filament bakes into its DFG LUT's third channel (cmgen,
 * DFV_Charlie). NoV in (0, 1], r in [0, 1] (r = 0: 0, the limit). stats may be
 * NULL. 0, or -1 on an argument out of range. Tested to 1e-6 (relative above
 * 1: Neubelt's V is not energy conserving, the albedo is 21.6 at NoV =
 * 0.001, r = 1/64) for NoV in [0.01, 1], r in [0.02, 1]. */
int bk_sheen_albedo(double NoV, double r, double tol, double *E, bk_quad_stats *stats);

/* ---- Formula IR -------------------------------------------------------------
 * A candidate form typed as text, e.g. "1/(LoH*LoH*(r+p0))", compiled once to a
 * flat SSA instruction list (brdf/ir_ops.h documents the format) that drives
 * evaluation in three precisions, derivatives, op counts and code generation.
 *
 * Language: inputs NoV NoL NoH LoH VoH (= LoH) r a f0 (a = r*r is an input, not
 * a parameter); parameters p0..p15; numbers; + - * / ^ with the usual precedence
 * (^ binds tighter than unary minus: -x^2 = -(x^2); ^ is right-associative);
 * functions sqrt rsqrt rcp exp exp2 log log2 pow min max clamp saturate mix abs
 * sq; and every term of the registry by name, e.g. D_ggx(NoH, a).
 */

typedef enum bk_input {
	BK_IN_NOV, BK_IN_NOL, BK_IN_NOH, BK_IN_LOH, BK_IN_R, BK_IN_A, BK_IN_F0, BK_IN_COUNT
} bk_input;

#define BK_MAX_PARAMS 16

typedef struct bk_form bk_form;

/* The first error of a parse: 1-based column and "what: detail near 'token'". */
typedef struct bk_form_error {
	int column;
	char message[200];
} bk_form_error;

/* Limits of a form, each an error naming it rather than a crash or a silent
 * cut: text length (columns stay ints; the catalog's longest form is a few
 * hundred characters), nesting of parentheses, calls and operators (the
 * parser recurses), and instructions after term expansion (ir_code.c). */
#define BK_FORM_MAX_LEN 16384
#define BK_FORM_MAX_DEPTH 200
#define BK_FORM_MAX_INSTR 4096

bk_form *bk_form_parse(const char *text, bk_form_error *err);
void bk_form_free(bk_form *f);
/* A copy of a parsed form (NULL when out of memory): a second owner of the
 * same IR without parsing its text again. */
bk_form *bk_form_dup(const bk_form *f);
const char *bk_form_text(const bk_form *f);
int bk_form_nparams(const bk_form *f);     /* highest p index used + 1 */
/* The index of the parameter named by text[0..len) ("p0".."p15"), or -1: the
 * language's one rule for the names, which the parser and every reader of
 * pN=VALUE words and p0=X;p1=Y lists apply ("p01" is no second name for p1). */
int bk_param_index(const char *text, size_t len);
unsigned bk_form_inputs(const bk_form *f); /* bit i set: input i is read */
unsigned bk_form_params(const bk_form *f); /* bit k set: p_k is read */
const char *bk_input_name(bk_input i);
/* The constants the compiled form uses (after folding), up to max of them;
 * returns how many there are. What a shader will spell as literals. */
int bk_form_constants(const bk_form *f, double *k, int max);

/* BK_FLD: long double, the reference the stability analysis measures the
 * others against (x87 80-bit on x86-64: 64-bit significand). */
typedef enum bk_precision { BK_F64, BK_F32, BK_F16, BK_FLD } bk_precision;
const char *bk_precision_name(bk_precision p);

/* IEEE binary16 rounding of x (nearest, ties to even; overflow to ±inf;
 * subnormals kept), returned as a double. */
double bk_half_round(double x);

/* Evaluates f at n samples. in[i] holds n values of input i (NULL if the form
 * does not read it), params the form's parameters. In BK_F32 and BK_F16 inputs,
 * parameters and constants are rounded to the precision on load and every
 * operation's result is rounded (BK_F16: what a mediump GPU does). Returns 0,
 * or -1 if an input the form reads is NULL. */
int bk_form_eval(const bk_form *f, bk_precision prec, size_t n,
                 const double *const in[BK_IN_COUNT], const double *params, double *out);

/* BK_F16 measured against a target y (n values): per sample, of the two
 * orders a driver may take for each mad and mix (rounded twice, or fused
 * once), the value farther from y[k] (NaN over inf over a number; where y[k]
 * is not finite, the unfused one). bk_form_eval's BK_F16 keeps the order
 * farther from the form's own f64 value instead, which against a target can
 * land between the two orders' errors; an error computed from these values
 * holds whichever order the driver takes (tests/vk holds lavapipe to it).
 * 0, or -1 as bk_form_eval. */
int bk_form_eval_half_vs(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT], const double *params,
                         const double *y, double *out);

/* What happened inside an evaluation, per sample (bits of flags[k]): an
 * operation made a NaN from non-NaN operands, overflowed to infinity from
 * finite operands (past 65504 in half; a constant, parameter or input the
 * precision cannot hold counts too), or gave a nonzero result below the
 * precision's smallest normal (flushed to zero on GPUs that flush). Every
 * operation is seen, also one whose result a later min, max or clamp hides,
 * whatever the final value. first_op
 * holds, per bit, the first instruction index it happened at (-1: never). */
#define BK_FLAG_NAN 1u
#define BK_FLAG_OVERFLOW 2u
#define BK_FLAG_SUBNORMAL 4u
int bk_form_eval_flags(const bk_form *f, bk_precision prec, size_t n,
                       const double *const in[BK_IN_COUNT], const double *params, double *out,
                       unsigned char *flags, int first_op[3]);

/* Values and the Jacobian d out[k] / d p_j into jac[k * nparams + j], double
 * precision, reverse mode over the same blocks. */
int bk_form_eval_diff(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT],
                      const double *params, double *out, double *jac);

/* A form bound to fixed samples, evaluated many times with changing parameters
 * (a fit): the operations that read no parameter are computed once, at the
 * first call, and kept (the results are bk_form_eval_diff's and bk_form_eval's
 * in f64, bit for bit). The form and the n samples of in must outlive it; one
 * bound form is used by one thread at a time. NULL when out of memory or when
 * what it would keep exceeds about 256 MB. */
typedef struct bk_form_bound bk_form_bound;
bk_form_bound *bk_form_bind(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT]);
/* Values into out and, when jac is not NULL, the Jacobian as bk_form_eval_diff.
 * out (n values) must not overlap the samples: it is written as the blocks
 * are computed, and the samples are read in place at every call. */
int bk_form_bound_eval(bk_form_bound *b, const double *params, double *out, double *jac);
/* The same values, and the same Jacobian by columns: d out[k] / d p_j into
 * cols[j][k] for each j < the form's parameter count whose cols[j] is not
 * NULL (cols NULL: values only). The column layout a least-squares solver
 * takes (no transpose after) and, in the sweep, contiguous stores where the
 * row-major layout strides by the parameter count; bit for bit
 * bk_form_bound_eval's jac[k * np + j]. */
int bk_form_bound_eval_cols(bk_form_bound *b, const double *params, double *out, double *const *cols);
void bk_form_bound_free(bk_form_bound *b);

/* Op counts by class, after constant folding, common subexpressions, small
 * integer powers to multiplies and a*b + c to one multiply-add. */
typedef enum bk_opclass {
	BK_K_FREE, BK_K_ADD, BK_K_MUL, BK_K_MAD, BK_K_MINMAX, BK_K_SATURATE,
	BK_K_RCP, BK_K_DIV, BK_K_SQRT, BK_K_RSQRT, BK_K_EXP2, BK_K_LOG2, BK_K_COUNT
} bk_opclass;

typedef struct bk_ops {
	int n[BK_K_COUNT];
	int simple, complex; /* complex: rcp div sqrt rsqrt exp2 log2 */
} bk_ops;

/* The cost model: one number per form, simple * simple_cost + complex *
 * complex_cost (the talk: many simple ops per cycle, only one complex). */
#define BK_COST_SIMPLE 1.0
#define BK_COST_COMPLEX 4.0

void bk_form_count(const bk_form *f, bk_ops *ops);
/* Adds the counts of the form text to ops (a shader's pieces counted one by
 * one and summed, as a LUT's coordinates are). 0, or -1 if it does not parse. */
int bk_form_count_add(const char *text, bk_ops *ops);
const char *bk_opclass_name(bk_opclass k);
int bk_opclass_is_complex(bk_opclass k);
double bk_ops_cost(const bk_ops *ops, double simple_cost, double complex_cost);

/* Named cost models (--cost-model NAME in ops, compare and search): the
 * weights of simple and complex ops. "ir" is the default above; "aco-CHIP"
 * are least-squares fits of AMD's instruction counts (brdfkit gpucost
 * --calibrate --chips CHIP) over the catalog and make results' search
 * fronts, so a cost reads as about that many ACO instructions on that chip.
 * bk_cost_model_find: NULL for an unknown name; bk_cost_model_at: the i-th
 * model, NULL past the last. */
typedef struct bk_cost_model {
	const char *name;
	double simple, complex;
} bk_cost_model;
const bk_cost_model *bk_cost_model_find(const char *name);
const bk_cost_model *bk_cost_model_at(size_t i);

/* Code generation: one function evaluating f, its parameters baked in as
 * constants, deterministic text. Every function opens with a provenance
 * comment (form, source, conventions, fitted domain and error when known, op
 * counts, the command that made it) and says DO NOT EDIT. */
typedef enum bk_lang { BK_LANG_C, BK_LANG_GLSL, BK_LANG_HLSL } bk_lang;

typedef struct bk_emit_info {
	const char *name;        /* function name; "brdfkit_form" if NULL */
	const char *source;      /* citation or "user form"; may be NULL */
	const char *conventions; /* roughness meaning, 1/4 in V, NoL in or out; may be NULL */
	const char *domain;      /* fitted domain, when known; may be NULL */
	const char *error;       /* fitted error, when known; may be NULL */
	const char *command;     /* the command line that produced it; may be NULL */
} bk_emit_info;

/* bk_form_emit's precision (its half argument), the type each language is
 * written in:
 *   BK_EMIT_SINGLE   C float, GLSL highp float, HLSL float;
 *   BK_EMIT_RELAXED  GLSL mediump float, HLSL min16float: fp16 where the GPU
 *                    has it (the portable half code);
 *   BK_EMIT_F16      explicit 16-bit types: GLSL float16_t (its literals hf;
 *                    GL_EXT_shader_explicit_arithmetic_types_float16), HLSL
 *                    half (literals h; dxc -enable-16bit-types, shader model
 *                    6.2: without it half is float).
 * C is float in all three. Under either half precision every constant and
 * baked-in parameter is written as the binary16 value bk_form_eval's BK_F16
 * computes with (bk_half_round of its float), in C too, so that each file of
 * a half front holds the same numbers as the error stated for it. */
enum { BK_EMIT_SINGLE = 0, BK_EMIT_RELAXED = 1, BK_EMIT_F16 = 2 };

/* Returns malloc'd source text, or NULL (out of memory, params missing for a
 * form that has parameters, a half outside BK_EMIT_*, or a name
 * bk_lang_reserved refuses). */
char *bk_form_emit(const bk_form *f, bk_lang lang, int half, const double *params,
                   const bk_emit_info *info);

/* What a front member's code needs so that members swap at one call site
 * (bk_form_emit_styled; NULL or zeros: bk_form_emit's function). inputs:
 * bit i, bk_input i: the signature's inputs, in bk_input order, whether f
 * reads them or not; a, when f reads it and inputs has r but not a, is
 * computed first as a = r*r (one mul more than the op counts, which are
 * f's; the line says so); any other input f reads outside inputs makes the
 * emitter return NULL. named_params: each parameter a local constant
 * NAME_pK at the top of the body (NAME the function's), read by name: the
 * same values, the same op counts. */
typedef struct bk_emit_style {
	unsigned inputs;
	int named_params;
} bk_emit_style;
char *bk_form_emit_styled(const bk_form *f, bk_lang lang, int half, const double *params, const bk_emit_info *info,
                          const bk_emit_style *style);

/* A split-sum pair (f0·A + B) as engines call it: bk_form_emit_styled of
 * fa as NAME_A and of fb as NAME_B (info's name NAME, "brdfkit_form" if
 * NULL; the same style for both, its inputs style->inputs or else those
 * either reads), then NAME(inputs) returning both: GLSL vec2 (A, B), HLSL float2, C
 * through two pointers (void NAME(inputs, float *A, float *B)). params are
 * the pair's (numbered across A and B). Malloc'd text, or NULL as
 * bk_form_emit. */
char *bk_form_emit_pair(const bk_form *fa, const bk_form *fb, bk_lang lang, int half, const double *params,
                        const bk_emit_info *info, const bk_emit_style *style);

/* 1 if name cannot be the generated function's name in lang: not an
 * identifier (a letter or _, then letters, digits and _), a keyword or
 * reserved word, a type, a name the language's standard library (C's
 * <math.h>, every GLSL built-in function, every HLSL intrinsic) or entry
 * point (main) has, a reserved identifier (C's _name, GLSL's gl_ and __),
 * longer than BK_NAME_MAX, an input or a temporary tN of the body; 0 if it
 * can (brdf/ir_names.c lists them). */
#define BK_NAME_MAX 63 /* C11 5.2.4.1: significant initial characters of an internal identifier */
int bk_lang_reserved(bk_lang lang, const char *name);
/* 1 if name is an identifier of all three languages: a letter or _, then
 * letters, digits and _ (ASCII; C11 6.4.2.1, GLSL ES 3.00 3.7, HLSL's C
 * rules); 0 if not, or empty. */
int bk_identifier(const char *name);
/* The i-th entry of lang's table of reserved names, NULL past the end. */
const char *bk_lang_word(bk_lang lang, size_t i);

/* 1 if the generated code would compute a constant that is not finite: a
 * literal or parameter past FLT_MAX, or an operation on constants (params
 * baked in; NULL: parameters are not constants) whose single-precision result
 * is NaN or infinite, e.g. sqrt(-1), 1/0, or a division by a constant zero
 * (NoV / 0); what names the first, e.g. "sqrt(-1) is NaN in single
 * precision". 0 if none, -1 if out of memory. */
int bk_form_nonfinite(const bk_form *f, const double *params, char *what, size_t len);

/* How many constants the code computes (literals, baked-in parameters,
 * operations on them) are finite and non-zero in double but infinite, NaN,
 * 0 or subnormal in prec (BK_F32: C float, highp, HLSL float; BK_F16:
 * mediump, half), e.g. exp2(127.99) in half, 1e-46 in float; what names the
 * first ("exp2(127.99) is +inf in half precision"). -1 if out of memory. */
int bk_form_const_range(const bk_form *f, const double *params, bk_precision prec, char *what, size_t len);

/* How many clamp(x, lo, hi) have fixed bounds (literals, baked-in
 * parameters) with lo > hi: the result is hi wherever x is, and GLSL and
 * HLSL leave clamp() undefined there (the code spells min(max(x, lo), hi)
 * instead); what names the first ("clamp(x, 1, 0)"). */
int bk_form_clamp_reversed(const bk_form *f, const double *params, char *what, size_t len);

/* 1 if f (at params; NULL only for a form without parameters) is NaN or
 * infinite in double precision at every sample of a grid over the domain of
 * the inputs it reads (each in {0, 1e-3, 0.3, 0.7, 1}; a = r*r when it reads
 * both), e.g. NoV/0, 1/(NoV - NoV), sqrt(NoV - 2): no value to emit, count or
 * time. what names the first sample, e.g. "NoV = 0: NaN" ("it reads no
 * input: +inf"). 0 if it is finite somewhere, -1 if out of memory. */
int bk_form_nowhere_finite(const bk_form *f, const double *params, char *what, size_t len);

/* How many samples of bk_form_nowhere_finite's grid prec cannot hold f's
 * value at (params as there), when it holds it at none of them: the code
 * emitted in prec (BK_F32: C float, highp, HLSL float; BK_F16: mediump,
 * half) computes +inf or NaN where double is finite, or 0 or a subnormal
 * (0 where GPUs flush) where double is not 0, at every sample where double
 * has a value, e.g. (NoV+300)*(NoV+300) in half. A sample where double is
 * not finite, or 0 and prec finite, does not count. 0 if prec holds the value
 * at some sample (or no sample counts); what names the first lost one
 * ("NoV = 0: 90000 is +inf in half precision"). -1 if out of memory or prec
 * is not BK_F32 or BK_F16. */
int bk_form_range_lost(const bk_form *f, const double *params, bk_precision prec, char *what, size_t len);

/* src as text inside a generated comment: the one rule for every comment
 * brdfkit writes (C block comments, GLSL and HLSL line comments, CSV '#'
 * lines), so that nothing a user typed can end the comment or start code.
 * "*" "/" and "/" "*" get a space between them (the first would end a block
 * comment, the second is C's -Wcomment error); a line break becomes newline
 * (NULL: a space); every other control character (CR, tab, ESC, DEL) a space;
 * a backslash, or the trigraph "??" "/", with only blanks after it up to a
 * line break or the end gets a '.' after it, so no line ends in a line
 * continuation. The caller puts no '*' or
 * '/' right beside it. Writes at most cap bytes with the NUL (dst may be NULL
 * when cap is 0) and returns the escaped text's whole length, as snprintf. */
size_t bk_comment_text(char *dst, size_t cap, const char *src, const char *newline);

/* sin, cos and acos with the same bits on every x86-64 machine (glibc's own
 * pick FMA or non-FMA code at run time): for reference integrals that must
 * not depend on the CPU (brdf/dmath.c states domain and precision). */
double bk_dsin(double x); /* |x| <= 8 */
double bk_dcos(double x); /* |x| <= 8 */
double bk_dacos(double c); /* c in [-1, 1] */
/* exp2, log2, pow, exp, log, log10 and log1p with the same bits on every x86-64
 * machine (glibc's log2, log, log10, log1p, exp and pow pick FMA or non-FMA code
 * at run time): the IR's f64 ops, the reference terms and the plots use
 * them; within 0.65 ulp for normal results, 0.75 for subnormal ones
 * (brdf/dmath.c states each); C11's specials. */
double bk_dexp2(double x);
double bk_dlog2(double x);
double bk_dpow(double x, double y);
double bk_dexp(double x);
double bk_dlog(double x);
double bk_dlog10(double x);
/* log1p, for the robust losses (Cauchy's): within 0.51 ulp, C11's specials */
double bk_dlog1p(double u);
/* erfc, for Beckmann's Smith Λ: within 4.5 ulp for normal results */
double bk_derfc(double x);

#ifdef __cplusplus
}
#endif

#endif
