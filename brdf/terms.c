/*
 * terms.c — the term registry: every exact term and published approximation of
 * the library by name, with its convention and citation, behind one evaluator
 * signature. Callers select variants by name here instead of editing call sites
 * (Filament's habit); the names are the formula IR's spelling.
 */
#include "brdf.h"

#include <math.h>
#include <string.h>

/* Adapters from the uniform sample to each C function's own arguments. */
static double d_ggx(const bk_sample *s) { return bk_D_ggx(s->NoH, s->a); }
static double d_beckmann(const bk_sample *s) { return bk_D_beckmann(s->NoH, s->a); }
static double d_bp(const bk_sample *s) { return bk_D_blinn_phong(s->NoH, s->a); }
static double d_bp_sg(const bk_sample *s) { return bk_D_blinn_phong_sg(s->NoH, s->a); }
static double d_charlie(const bk_sample *s) { return bk_D_charlie(s->NoH, s->a); }
static double d_ashikhmin(const bk_sample *s) { return bk_D_ashikhmin(s->NoH, s->a); }

static double v_sep(const bk_sample *s) { return bk_V_smith_ggx_separable(s->NoV, s->NoL, s->a); }
static double v_cor(const bk_sample *s) { return bk_V_smith_ggx_correlated(s->NoV, s->NoL, s->a); }
static double v_sibl(const bk_sample *s) { return bk_V_schlick_ggx_ibl(s->NoV, s->NoL, s->a); }
static double v_sdir(const bk_sample *s) { return bk_V_schlick_ggx_direct(s->NoV, s->NoL, s->r); }
static double v_ksk(const bk_sample *s) { return bk_V_kelemen(s->LoH); }
static double v_hable(const bk_sample *s) { return bk_V_kelemen_hable(s->LoH, s->a); }
static double v_talk(const bk_sample *s) { return bk_V_kelemen_talk(s->LoH, s->r); }
static double v_neubelt(const bk_sample *s) { return bk_V_neubelt(s->NoV, s->NoL); }
static double v_neumann(const bk_sample *s) { return bk_V_neumann(s->NoV, s->NoL); }
static double v_implicit(const bk_sample *s) { (void)s; return bk_V_implicit(); }
static double v_ct(const bk_sample *s) { return bk_V_cook_torrance(s->NoV, s->NoL, s->NoH, s->LoH); }
static double v_hammon(const bk_sample *s) { return bk_V_hammon(s->NoV, s->NoL, s->a); }

static double f_schlick(const bk_sample *s) { return bk_F_schlick(s->f0, s->f90, s->LoH); }
static double f_sg(const bk_sample *s) { return bk_F_schlick_sg(s->f0, s->f90, s->LoH); }
static double f_schuler(const bk_sample *s) { return bk_F_schuler(s->f0, s->LoH); }
static double f_diel(const bk_sample *s) { return bk_F_dielectric(s->LoH, s->eta); }
static double f_cond(const bk_sample *s) { return bk_F_conductor(s->LoH, s->eta, s->k); }

static double fd_lambert(const bk_sample *s) { (void)s; return bk_Fd_lambert(); }
static double fd_burley(const bk_sample *s) { return bk_Fd_burley(s->NoV, s->NoL, s->LoH, s->r); }
/* VoL = 2 LoH^2 - 1, since LoH^2 = (1 + VoL)/2 for the half vector. */
static double fd_on(const bk_sample *s)
{
	return bk_Fd_oren_nayar(s->NoV, s->NoL, 2.0 * s->LoH * s->LoH - 1.0, s->r);
}

#define A_ "a = r^2; "
static const bk_term terms[] = {
	{"D_ggx", BK_ROLE_D, "NoH,a", "GGX / Trowbridge-Reitz normal distribution",
	 A_ "normalised, ∫ D NoH dω = 1",
	 "Walter, Marschner, Li, Torrance 2007, Microfacet Models for Refraction through Rough Surfaces", d_ggx},
	{"D_beckmann", BK_ROLE_D, "NoH,a", "Beckmann normal distribution",
	 A_ "a is the RMS slope; normalised",
	 "Beckmann & Spizzichino 1963, The Scattering of Electromagnetic Waves from Rough Surfaces", d_beckmann},
	{"D_blinn_phong", BK_ROLE_D, "NoH,a", "normalised Blinn-Phong, (n+2)/(2π) NoH^n",
	 A_ "n = 2/a^2 - 2 (Walter 2007); normalised",
	 "Blinn 1977, Models of Light Reflection for Computer Synthesized Pictures", d_bp},
	{"D_blinn_phong_sg", BK_ROLE_D, "NoH,a", "spherical-Gaussian Blinn-Phong, (n+2)/(2π) exp((n+0.775)(NoH-1))",
	 A_ "n = 2/a^2 - 2; not exactly normalised (1 + 0.225/n for large n, 0.785 at r = 1)",
	 "Lagarde 2012, Spherical Gaussian approximation for Blinn-Phong, Phong and Fresnel (read via a secondary copy)", d_bp_sg},

	{"V_smith_ggx_separable", BK_ROLE_V, "NoV,NoL,a", "exact Smith GGX, separable G1(v) G1(l) / (4 NoL NoV)",
	 A_ "V includes 1/(4 NoL NoV)",
	 "Walter et al. 2007; Heitz 2014, Understanding the Masking-Shadowing Function", v_sep},
	{"V_smith_ggx_correlated", BK_ROLE_V, "NoV,NoL,a", "exact Smith GGX, height-correlated 1/(1+Λv+Λl) / (4 NoL NoV)",
	 A_ "V includes 1/(4 NoL NoV)",
	 "Heitz 2014, Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", v_cor},
	{"V_schlick_ggx_ibl", BK_ROLE_V, "NoV,NoL,a", "Schlick-GGX, 0.25/((NoV(1-k)+k)(NoL(1-k)+k)), k = a/2",
	 A_ "k = a/2 (Unreal Vis_Schlick); V includes 1/4",
	 "Karis 2013, Real Shading in Unreal Engine 4", v_sibl},
	{"V_schlick_ggx_direct", BK_ROLE_V, "NoV,NoL,r", "Schlick-GGX with the 'hotness' remap k = (r+1)^2/8",
	 "k from perceptual r; V includes 1/4",
	 "Karis 2013, Real Shading in Unreal Engine 4, course notes (unverified; as LearnOpenGL reproduces it)", v_sdir},
	{"V_kelemen", BK_ROLE_V, "LoH", "Kelemen-Szirmay-Kalos, 0.25/LoH^2",
	 "no roughness; V includes 1/4",
	 "Kelemen & Szirmay-Kalos 2001, A Microfacet Based Coupled Specular-Matte BRDF Model with Importance Sampling", v_ksk},
	{"V_kelemen_hable", BK_ROLE_V, "LoH,a", "modified KSK, 0.25/(LoH^2(1-k^2)+k^2), k = a/2",
	 A_ "k = a/2; Hable's vis omits the 1/4, added here",
	 "Hable 2014, Optimizing GGX Shaders with dot(L,H)", v_hable},
	{"V_kelemen_talk", BK_ROLE_V, "LoH,r", "modified KSK as the mobile talk prints it, 0.25/(LoH^2(1-r^2)+r^2)",
	 "talk's roughness read as perceptual r; the talk omits the 1/4, added here",
	 "Unity 2015, Optimizing PBR for Mobile, SIGGRAPH 2015 course Moving Mobile Graphics (seed 001; author R. Zioma from memory, unverified)", v_talk},
	{"V_neubelt", BK_ROLE_V, "NoV,NoL", "1/(4(NoL + NoV - NoL NoV))",
	 "no roughness; V includes 1/4",
	 "Neubelt & Pettineo 2013, Crafting a Next-Gen Material Pipeline for The Order: 1886", v_neubelt},
	{"V_neumann", BK_ROLE_V, "NoV,NoL", "1/(4 max(NoL, NoV))",
	 "no roughness; V includes 1/4",
	 "Neumann, Neumann, Szirmay-Kalos 1999 (as Unreal's Vis_Neumann)", v_neumann},
	{"V_implicit", BK_ROLE_V, "", "implicit G = NoL NoV, V = 1/4",
	 "constant",
	 "Hoffman 2010, Physically-Based Shading Models in Film and Game Production", v_implicit},
	{"V_cook_torrance", BK_ROLE_V, "NoV,NoL,NoH,VoH", "Cook-Torrance V-groove G = min(1, 2NoH NoV/VoH, 2NoH NoL/VoH), / (4 NoL NoV)",
	 "no roughness; V includes 1/(4 NoL NoV)",
	 "Cook & Torrance 1982, A Reflectance Model for Computer Graphics", v_ct},
	{"V_hammon", BK_ROLE_V, "NoV,NoL,a", "fast height-correlated approximation, 0.5/mix(2 NoL NoV, NoL + NoV, a)",
	 A_ "= Unreal Vis_SmithJointApprox, Unity's joint approximation; V includes 1/4",
	 "Hammon 2017, PBR Diffuse Lighting for GGX+Smith Microsurfaces (slides unverified; quoted by Filament)", v_hammon},

	{"F_schlick", BK_ROLE_F, "f0,f90,LoH", "Schlick, f0 + (f90 - f0)(1 - LoH)^5",
	 "f0 normal-incidence reflectance, f90 = 1 by default",
	 "Schlick 1994, An Inexpensive BRDF Model for Physically-based Rendering", f_schlick},
	{"F_schlick_sg", BK_ROLE_F, "f0,f90,LoH", "Schlick with (1-LoH)^5 ≈ exp2((-5.55473 LoH - 6.98316) LoH)",
	 "f0, f90 as F_schlick",
	 "Karis 2013, Real Shading in Unreal Engine 4 (spherical-Gaussian Fresnel)", f_sg},
	{"F_schuler", BK_ROLE_F, "f0,LoH", "Schüler, f0/LoH (pairs with Kelemen V)",
	 "unbounded at LoH -> 0; not a reflectance alone",
	 "Schüler 2009, An Efficient and Physically Plausible Real-Time Shading Model, ShaderX7 2.5 (as the mobile talk quotes it; unverified)", f_schuler},
	{"F_dielectric", BK_ROLE_F, "LoH,eta", "exact unpolarised dielectric Fresnel, with total internal reflection",
	 "eta = n_t/n_i real; from f0: eta = (1+sqrt f0)/(1-sqrt f0)",
	 "Born & Wolf, Principles of Optics, 1.5", f_diel},
	{"F_conductor", BK_ROLE_F, "LoH,eta,k", "exact unpolarised conductor Fresnel for complex index eta + ik",
	 "outside medium of index 1",
	 "Lagarde 2013, Memo on Fresnel equations (the closed form of pbrt-v3 FrConductor)", f_cond},

	{"Fd_lambert", BK_ROLE_FD, "", "Lambert, 1/π",
	 "1/π included; albedo outside",
	 "Lambert 1760, Photometria", fd_lambert},
	{"Fd_burley", BK_ROLE_FD, "NoV,NoL,LoH,r", "Disney diffuse with retro-reflection, f90 = 0.5 + 2 r LoH^2",
	 "perceptual r; 1/π included; not energy conserving",
	 "Burley 2012, Physically-Based Shading at Disney", fd_burley},
	{"Fd_oren_nayar", BK_ROLE_FD, "NoV,NoL,VoL,sigma", "Oren-Nayar qualitative model",
	 "registry passes sigma = r (radians) and VoL = 2 LoH^2 - 1; 1/π included",
	 "Oren & Nayar 1994, Generalization of Lambert's Reflectance Model", fd_on},

	/* Appended, not grouped with the D terms above: a term's index is its
	 * operation number in search grammars (fit/expr.c TERM0 + t), hashed
	 * into checkpoints, so existing terms keep theirs. */
	{"D_charlie", BK_ROLE_D, "NoH,a", "Charlie sheen distribution, (2 + 1/a) sin(θh)^(1/a) / (2π)",
	 A_ "a in (0, 1] (Filament's cloth passes r^2); normalised; pairs with V_neubelt",
	 "Estevez & Kulla 2017, Production Friendly Microfacet Sheen BRDF", d_charlie},
	{"D_ashikhmin", BK_ROLE_D, "NoH,a", "velvet, (1 + 4 exp(-cot^2θh/a^2)/sin^4θh) / (π(1 + 4a^2))",
	 A_ "as Filament's D_Ashikhmin; normalised",
	 "Ashikhmin & Premoze 2007, Distribution-based BRDFs", d_ashikhmin},
};
#undef A_

static const char *const role_names[] = {"D", "V", "F", "Fd"};

size_t bk_term_count(void) { return sizeof terms / sizeof terms[0]; }

const bk_term *bk_term_at(size_t i)
{
	return i < bk_term_count() ? &terms[i] : NULL;
}

const char *bk_role_name(bk_role role) { return role_names[role]; }

const bk_term *bk_term_find(const char *name)
{
	for (size_t i = 0; i < bk_term_count(); i++)
		if (strcmp(terms[i].name, name) == 0)
			return &terms[i];
	return NULL;
}

/* "ggx" with role D finds "D_ggx"; the full name is accepted too, but only for
 * a term of that role. */
const bk_term *bk_term_find_role(bk_role role, const char *name)
{
	size_t plen = strlen(role_names[role]);
	for (size_t i = 0; i < bk_term_count(); i++) {
		const bk_term *t = &terms[i];
		if (t->role != role)
			continue;
		if (strcmp(t->name, name) == 0 || strcmp(t->name + plen + 1, name) == 0)
			return t;
	}
	return NULL;
}

/* sin and cos of an angle: brdf/dmath.c's on |x| <= 8 (every angle of the
 * hemisphere and a turn of φ either way), so the geometry's bits do not
 * depend on the CPU (glibc's sin and cos have FMA variants); libm's beyond,
 * where dmath's range reduction does not reach. */
static double sin_any(double x) { return fabs(x) <= 8.0 ? bk_dsin(x) : sin(x); }
static double cos_any(double x) { return fabs(x) <= 8.0 ? bk_dcos(x) : cos(x); }

/* V = (sin θv, 0, cos θv), L = (sin θl cos φ, sin θl sin φ, cos θl), H their
 * normalised sum. |V + L|^2 = 2 + 2 VoL, so LoH = sqrt((1 + VoL)/2). */
void bk_sample_geometry(bk_sample *s, double theta_v, double theta_l, double phi)
{
	double v[3] = {sin_any(theta_v), 0.0, cos_any(theta_v)};
	double l[3] = {sin_any(theta_l) * cos_any(phi), sin_any(theta_l) * sin_any(phi), cos_any(theta_l)};
	double VoL = v[0] * l[0] + v[1] * l[1] + v[2] * l[2];
	double len = sqrt(2.0 + 2.0 * VoL);
	s->NoV = v[2];
	s->NoL = l[2];
	s->NoH = len > 0.0 ? (v[2] + l[2]) / len : 0.0;
	s->LoH = 0.5 * len;
}

void bk_sample_roughness(bk_sample *s, double r)
{
	s->r = r;
	s->a = r * r;
}
