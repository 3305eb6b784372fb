/*
 * catalog.c — the published approximations, each as formula-language text with
 * its citation, its published constants as parameter defaults and its
 * convention. Facts: shared/references/approximations.md; the mobile talk is
 * seeds/001. tests/test_catalog.c checks every entry against the published
 * formula written out again in plain C.
 *
 * How the entries are written:
 *   - every published numeric constant is a parameter p0.. whose default is the
 *     published value, written in C exactly as the source writes it (so
 *     (0.0275 - 0.25*0.04)/0.96 stays that expression); structural constants
 *     stay literal: the 1/4 of V = G/(4 NoL NoV), π, Schlick's exponent 5 and
 *     the integer powers 3 and 4 (a parameter exponent would turn two multiplies
 *     into pow, a complex op), the 1 and 0.5 of mixes and rational normalisations;
 *     each convention says which constants are parameters;
 *   - values are brdfkit's: physical BRDF (1/π included: sources in Unity's or
 *     Unreal-mobile's π-scaled units are divided by π), V includes the 1/4,
 *     r is perceptual roughness and a = r^2; where a source names its roughness
 *     differently its mapping to r or a is written into the form;
 *   - "env": result = f0·A + B with form = A, form_b = B; "env_f0": the source's
 *     result is not linear in f0 (saturate, 50·f0 gating, a reflectivity inside
 *     a mix) and the single form reads f0;
 *   - where a source is ambiguous each reading is its own entry.
 *
 * The form language has no locals outside term definitions, so shared pieces
 * are C string macros; the parser shares the repeated subexpressions (CSE).
 */
#include "catalog.h"

#include <stdio.h>
#include <string.h>

#define PI "3.141592653589793"

/* ---- the mobile talk and Unity's shipped version ------------------------------ */

/* Unity URP's d and specularTerm (π-scaled, without specColor), alpha floored
 * as URP does: roughness = max(a, HALF_MIN_SQRT), roughness2 = max(.^2, HALF_MIN). */
#define URP_A  "max(a, p6)"
#define URP_A2 "max(" URP_A "*" URP_A ", p7)"
#define URP_D  "(NoH*NoH*(" URP_A2 " - 1) + p3)"
#define URP_TERM URP_A2 "/(" URP_D "*" URP_D "*max(p0, LoH*LoH)*(p1*" URP_A " + p2))"

/* ---- Karis 2014 EnvBRDFApprox: t = r*c0 + c1, c0 = p0..p3, c1 = p4..p7 ---------- */
#define KT0 "(p0*r + p4)"
#define KT1 "(p1*r + p5)"
#define KT2 "(p2*r + p6)"
#define KT3 "(p3*r + p7)"
#define KQ "(min(" KT0 "*" KT0 ", exp2(p8*NoV))*" KT0 " + " KT1 ")"
#define KA "(p9*" KQ " + " KT2 ")"
#define KB "(p10*" KQ " + " KT3 ")"
/* the non-metal variant: c0.xy = p0, p1; c1.xy = p2, p3 */
#define KN0 "(p0*r + p2)"

/* ---- Lazarov 2013 with gloss G (a macro defined per reading) ------------------- */
#define LZ_A0(G) "(p0*" G "*min(p1*" G ", exp2(p6*NoV)) + p2*" G " + p4)"
#define LZ(G) "saturate(" LZ_A0(G) " + f0*(p3*" G " + p5 - " LZ_A0(G) "))"
#define G_1MR "(1 - r)"
#define G_BP(P) "saturate(log2(2/(a*a) - 2)/log2(" P "))"
#define G_1MSQRTR "(1 - sqrt(r))"

/* ---- Narkowicz 2014, Lazarov form: t = g*p0v + p1v, p0v = p0..p3, p1v = p4..p7 -- */
#define NZ_BIAS(G) "saturate((p0*" G " + p4)*min(p1*" G " + p5, exp2(p8*NoV)) + p2*" G " + p6)"
#define NZ_DELTA(G) "saturate(p3*" G " + p7)"
#define NZ(G) "(f0*(" NZ_DELTA(G) " - " NZ_BIAS(G) ") + " NZ_BIAS(G) "*saturate(p9*f0))"

/* ---- Narkowicz 2014, polynomial: x = g, y = NoV; b1..b6 = p0..p5, d0..d6 = p6..p12 */
#define NP_BIAS(X) "saturate(min(p0*" X " + p1*" X "*" X ", p2 + p3*NoV + p4*NoV*NoV + p5*NoV*NoV*NoV))"
#define NP_DELTA(X) "saturate(p6 + p7*" X " + p8*NoV + p9*" X "*" X " + p10*" X "*NoV + p11*NoV*NoV + p12*" X "*" X "*" X ")"
/* at reflectance F ("f0", or "1" for the ms entries' directional albedo) */
#define NP_F(X, F) "(" F "*(" NP_DELTA(X) " - " NP_BIAS(X) ") + " NP_BIAS(X) "*saturate(p13*" F "))"
#define NP(X) NP_F(X, "f0")

/* ---- Pesce & Iwanicki 2015 (m = a) --------------------------------------------- */
#define PI_BIAS "exp2(-(p0*NoV + p1*a))"
#define PI_SCALE "(1 - " PI_BIAS " - a*max(" PI_BIAS ", min(r, p2 + p3*NoV) - p4))"

/* ---- Ross-based (m = a) --------------------------------------------------------- */
#define ROSS_F "((1 - NoV)^(5*exp(-p0*a))/(1 + p1*a^p2))"

/* ---- MaterialX rational fit, x = NoV, y = a: r = c0 + c1 x + c2 y + c3 xy + c4 x^2
 * + c5 y^2 + c6 x^2 y + c7 x y^2 + c8 x^2 y^2, component by component. ----------- */
#define MX(c0, c1, c2, c3, c4, c5, c6, c7, c8)                                         \
	"(" c0 " + " c1 "*NoV + " c2 "*a + " c3 "*NoV*a + " c4 "*NoV*NoV + " c5 "*a*a + " c6 \
	"*NoV*NoV*a + " c7 "*NoV*a*a + " c8 "*NoV*NoV*a*a)"
#define MX_X MX("0.1003", "-0.6303", "9.748", "-2.038", "29.34", "-8.245", "-26.44", "19.99", "-5.448")
#define MX_Y MX("0.9345", "-2.323", "2.229", "-3.748", "1.424", "-0.7684", "1.436", "0.2913", "0.6286")
#define MX_Z MX("1", "-1.765", "8.263", "11.53", "28.96", "-7.507", "-36.11", "15.86", "33.37")
#define MX_W MX("1", "0.2281", "15.94", "-55.83", "13.08", "41.26", "54.9", "300.2", "-285.1")

/* ---- Unity environment Fresnel blend (reflectivity read as f0) ------------------ */
#define UNITY_ENV_LERP "mix(f0, saturate(1 - r + f0), (1 - NoV)^4)"

/* ---- Unreal PhongApprox; R·L = 2 NoV NoL - V·L with V·L = 2 LoH^2 - 1 ------------ */
#define PA_RCP "rcp(sq(max(r*r, p0)))"
#define PA_C "(p1*" PA_RCP " + p2)"
#define PA_ROL "max(0, 2*NoV*NoL - 2*LoH*LoH + 1)"
#define PA_LOBE "min(" PA_RCP "*exp2(" PA_C "*" PA_ROL " - " PA_C "), " PA_RCP ")"

#define TALK "\"Optimizing PBR for Mobile\" (Unity), SIGGRAPH 2015 course Moving Mobile " \
             "Graphics (seed 001; the seed does not name its author: R. Zioma from memory, unverified)"
#define URP "Unity Technologies, Universal Render Pipeline ShaderLibrary/BRDF.hlsl"
#define KARIS14 "B. Karis 2014, \"Physically Based Shading on Mobile\" (Unreal Engine blog); " \
                "Unreal Engine BRDF.ush"
#define MS_AT1 "the directional albedo E(NoV, r) = A + B of single-scattering GGX with F = 1 (target ms), " \
               "read as the source's environment BRDF at f0 = 1 (f0 A + B = E there); "
#define NARKO "K. Narkowicz 2014, \"Analytical DFG Term for IBL\" (blog, 2014-12-27)"
#define LAZ "D. Lazarov 2013, \"Getting More Physical in Call of Duty: Black Ops II\", SIGGRAPH " \
            "2013 Physically Based Shading course (notes unverified; consistent code copies)"

static const bk_catalog_entry entries[] = {
	/* ---- combined V·F and the whole specular lobe ------------------------------- */
	{"vf_talk_r", "VF", "f0/(4*LoH*LoH*(r + p0))", NULL, 1, {0.5}, TALK ", final specular BRDF slide",
	 "talk's V*F = specColor/(LoH^2 (roughness + 0.5)) without the 1/4, which the talk writes into the "
	 "final BRDF's denominator 4π(...)^2 LoH^2 (roughness + 0.5); brdfkit's V = G/(4 NoL NoV), so the 1/4 "
	 "is included here: D_ggx * this = the printed BRDF. Roughness read as perceptual r (the talk's GGX is "
	 "in roughness^4 = a^2, so its roughness is r); specColor = f0 applied at the end (Schüler's insight), "
	 "no f90. Parameter: p0 = 0.5 (the '+0.5'); the 4 stays literal"},
	{"vf_talk_a", "VF", "f0/(4*LoH*LoH*(a + p0))", NULL, 1, {0.5}, TALK ", final specular BRDF slide",
	 "second reading of the talk's V*F: the '+0.5' on alpha a = r^2 (Unity's reading: its 'roughness' is "
	 "alpha), without Unity's LoH^2 floor; 1/4 included as in vf_talk_r. Parameter: p0 = 0.5"},
	{"dvf_talk_r", "DVF", "f0*r^4/(4*" PI "*sq(NoH*NoH*(r^4 - 1) + 1)*LoH*LoH*(r + p0))", NULL, 1, {0.5},
	 TALK ", final specular BRDF slide",
	 "the printed BRDF_spec = roughness^4/(4π (NoH^2 (roughness^4 - 1) + 1)^2 LoH^2 (roughness + 0.5)) * "
	 "specColor, roughness = perceptual r, specColor = f0; physical (1/π included), without NoL. "
	 "Parameter: p0 = 0.5; 4 and π literal"},
	{"vf_talk_unity_urp", "VF", "f0/(max(p0, LoH*LoH)*(p1*a + p2))", NULL, 3, {0.1, 4.0, 2.0},
	 URP ", DirectBRDFSpecular (cites the talk); built-in UnityStandardBRDF BRDF2_Unity_PBS, linear "
	 "space, ships the same function written (roughness + 0.5)*4",
	 "Unity's roughness is alpha a = r^2, so the '+0.5' is on a; normalizationTerm = 4a + 2 = 4(a + 0.5) "
	 "carries the 1/4 of V; LoH^2 floored at 0.1. Unity's specularTerm is π x the physical BRDF with D "
	 "lacking its 1/π: the V*F factor itself has no π, so this equals brdfkit's V*F (times D_ggx(NoH,a) "
	 "gives dvf_unity_urp up to Unity's +1.00001). specColor = f0 applied after. Parameters: p0 = 0.1 "
	 "(LoH^2 floor), p1 = 4, p2 = 2"},
	{"dvf_unity_urp", "DVF",
	 "f0*a*a/(" PI "*sq(NoH*NoH*(a*a - 1) + p3)*max(p0, LoH*LoH)*(p1*a + p2))", NULL, 4,
	 {0.1, 4.0, 2.0, 1.00001}, URP ", DirectBRDFSpecular",
	 "specularTerm = roughness2/(d^2 max(0.1, LoH^2)(4 roughness + 2)), d = NoH^2 (roughness2 - 1) + "
	 "1.00001, roughness = a, roughness2 = a^2; Unity's value is π x physical (no 1/π in D), divided by π "
	 "here; specColor = f0, without NoL. URP's fp16 floors max(a, 2^-7), max(a^2, 2^-14) are left out "
	 "(they act only below r = 0.0884; see dvf_unity_urp_half). Parameters: p0 = 0.1, p1 = 4, p2 = 2, "
	 "p3 = 1.00001"},
	{"dvf_unity_urp_half", "DVF", "f0*clamp(" URP_TERM " - p4, 0, p5)/" PI, NULL, 8,
	 {0.1, 4.0, 2.0, 1.00001, 6.103515625e-5, 1000.0, 0.0078125, 6.103515625e-5},
	 URP ", DirectBRDFSpecular with REAL_IS_HALF, and InitializeBRDFData's roughness floors",
	 "dvf_unity_urp as it runs on half-precision targets: roughness = max(a, HALF_MIN_SQRT), roughness2 "
	 "= max(roughness^2, HALF_MIN); specularTerm - HALF_MIN then clamped to [0, 1000] (older versions "
	 "clamp to 100), all on Unity's π-scaled term before specColor = f0; divided by π for the physical "
	 "value. Parameters: p0 = 0.1, p1 = 4, p2 = 2, p3 = 1.00001, p4 = HALF_MIN = 2^-14, p5 = 1000, "
	 "p6 = HALF_MIN_SQRT = 2^-7, p7 = HALF_MIN (redundant with p6 at the defaults, shipped anyway)"},
	{"dvf_unity_builtin_gamma", "DVF",
	 "f0*sq(a/(max(p0, LoH)*(p1 + a)*(NoH*NoH*(a*a - 1) + p2)))/" PI, NULL, 3, {0.32, 1.5, 1.00001},
	 "Unity Technologies, built-in UnityStandardBRDF.cginc BRDF2_Unity_PBS, UNITY_COLORSPACE_GAMMA",
	 "gamma-space variant a/(max(0.32, LoH)(1.5 + a) d), d = NoH^2 (a^2 - 1) + 1.00001, a = alpha: it "
	 "approximates sqrt of the linear-space π-scaled term (the talk's gamma-2.0 hack: sqrt(specIntensity) "
	 "* specColor_sRGB), so this entry squares it to get back a linear intensity and divides by π; "
	 "specColor = f0. Parameters: p0 = 0.32, p1 = 1.5, p2 = 1.00001"},
	{"spec_unreal_phongapprox", "DVF", "f0*" PA_LOBE "/" PI, NULL, 3, {0.008, 0.72134752, 0.39674113},
	 KARIS14 "; Unreal Engine mobile base pass PhongApprox (\"7 instr\")",
	 "a = max(r^2, 0.008); lobe = min(exp2(c RoL - c)/a^2, 1/a^2), c = 0.72134752/a^2 + 0.39674113 (= "
	 "(0.5/a^2 + 0.275)/ln 2: spherical-Gaussian Phong with n = 0.5/a^2 - 0.5); RoL = max(0, R.L) = "
	 "max(0, 2 NoV NoL - 2 LoH^2 + 1). Unreal mobile multiplies SpecularColor by the lobe in π-scaled "
	 "units (its diffuse has no 1/π): divided by π here, SpecularColor = f0 (Unreal passes "
	 "EnvBRDFApprox(f0, r, NoV) there). Note: the lobe's peak 1/(π a^2) is 4x GGX D*V*F's f0/(4π a^2) "
	 "at NoV = NoL = 1. Parameters: p0 = 0.008, p1 = 0.72134752, p2 = 0.39674113"},
	{"fv_schuler", "VF", "f0/(4*LoH*LoH*LoH)", NULL, 0, {0},
	 "C. Schüler 2009, \"An Efficient and Physically Plausible Real-Time Shading Model\", ShaderX7 "
	 "ch. 2.5 (unverified; quoted via Unity and the mobile talk)",
	 "F = f0/LoH combined with Kelemen's V = 1/(4 LoH^2): V*F = f0/(4 LoH^3), 1/4 included; no "
	 "parameters (no published numeric constant)"},

	/* ---- visibility ---------------------------------------------------------- */
	{"v_hammon", "V", "0.5/mix(2*NoL*NoV, NoL + NoV, a)", NULL, 0, {0},
	 "E. Hammon Jr. 2017, \"PBR Diffuse Lighting for GGX+Smith Microsurfaces\", GDC (slides unverified; "
	 "quoted by Filament); identical to Unreal Vis_SmithJointApprox and Unity's joint approximation",
	 "mix weight a = alpha = r^2; V includes the 1/4 (0.5/mix(...) = 1/(4 * mix(...)/2)); no parameters: "
	 "0.5 and 2 are the correlated Smith form's structure. Unity states ~10 % worst-case relative error"},
	{"v_kelemen", "V", "0.25/(LoH*LoH)", NULL, 0, {0},
	 "C. Kelemen, L. Szirmay-Kalos 2001, \"A Microfacet Based Coupled Specular-Matte BRDF Model with "
	 "Importance Sampling\", Eurographics short paper",
	 "V = 1/(4 LoH^2), 1/4 included; no roughness, no parameters"},
	{"v_kelemen_unreal", "V", "1/(4*LoH*LoH + p0)", NULL, 1, {1e-5},
	 "Unreal Engine BRDF.ush Vis_Kelemen (Kelemen & Szirmay-Kalos 2001)",
	 "V = rcp(4 VoH^2 + 1e-5), VoH = LoH; 1/4 included. Parameter: p0 = 1e-5"},
	{"v_kelemen_hable", "V", "0.25/(LoH*LoH*(1 - sq(p0*a)) + sq(p0*a))", NULL, 1, {0.5},
	 "J. Hable 2014, \"Optimizing GGX Shaders with dot(L,H)\" (blog)",
	 "modified KSK with k = p0 * alpha, k = a/2 (Schlick's k for GGX), a = r^2; Hable's vis = 1/(LoH^2 "
	 "(1 - k^2) + k^2) omits the 1/4, included here (V = vis/4). Parameter: p0 = 0.5"},
	{"v_kelemen_talk_r", "V", "0.25/(LoH*LoH*(1 - r*r) + r*r)", NULL, 0, {0}, TALK ", V_SKSm slide",
	 "modified KSK as the talk prints it, 1/(LoH^2 (1 - roughness^2) + roughness^2), roughness read as "
	 "perceptual r (k = r; the talk's GGX uses roughness^4 = a^2); the talk omits the 1/4, included here. "
	 "No parameters"},
	{"v_kelemen_talk_a", "V", "0.25/(LoH*LoH*(1 - a*a) + a*a)", NULL, 0, {0}, TALK ", V_SKSm slide",
	 "second reading of the talk's modified KSK: roughness read as alpha (k = a = r^2, against Hable's "
	 "k = a/2); 1/4 included. No parameters"},

	/* ---- Fresnel ------------------------------------------------------------- */
	{"f_schlick_sg", "F", "f0 + (1 - f0)*exp2((p0*LoH + p1)*LoH)", NULL, 2, {-5.55473, -6.98316},
	 "B. Karis 2013, \"Real Shading in Unreal Engine 4\", SIGGRAPH course notes (spherical-Gaussian "
	 "Schlick)",
	 "(1 - LoH)^5 replaced by exp2((-5.55473 LoH - 6.98316) LoH); f90 = 1. Parameters: p0 = -5.55473, "
	 "p1 = -6.98316"},
	{"f_schlick_unreal_gated", "F", "saturate(p0*f0)*(1 - LoH)^5 + (1 - (1 - LoH)^5)*f0", NULL, 1, {50.0},
	 "Unreal Engine BRDF.ush F_Schlick",
	 "Schlick with f90 = saturate(50 f0) (Unreal gates on the green channel; grey f0 here): reflectances "
	 "below 2 % are treated as shadowing. Exponent 5 literal. Parameter: p0 = 50"},
	{"f_schlick_filament_gated", "F", "f0 + (saturate(3*p0*p1*f0) - f0)*(1 - LoH)^5", NULL, 2, {50.0, 0.33},
	 "Google Filament shaders (f90 = saturate(dot(f0, vec3(50.0 * 0.33))))",
	 "Schlick with f90 = saturate(dot(f0, 50*0.33)); grey f0, so the dot is 3*50*0.33*f0 = 49.5 f0 (the 3 "
	 "is the channel count, literal). Parameters: p0 = 50, p1 = 0.33"},

	/* ---- environment BRDF ------------------------------------------------------ */
	{"env_talk_r", "env", "1", "(1 - max(r, NoV))^3", 0, {0},
	 TALK ", Environment BRDF slide (roughness convention unverified; Filament's documentation quotes it)",
	 "BRDF_env = (1 - max(roughness, NoV))^3 + specColor: A = 1, B = (1 - max(r, NoV))^3, roughness read "
	 "as perceptual r. No parameters: the cube and the unit weight of specColor are structural (the talk "
	 "avoids complex ops by design; a parameter exponent would need pow)"},
	{"env_talk_a", "env", "1", "(1 - max(a, NoV))^3", 0, {0},
	 TALK ", Environment BRDF slide (roughness convention unverified)",
	 "second reading of the talk's environment BRDF: roughness read as alpha a = r^2; A = 1, "
	 "B = (1 - max(a, NoV))^3. No parameters"},
	{"env_karis2014", "env_f0", "f0*" KA " + saturate(p11*f0)*" KB, NULL, 12,
	 {-1.0, -0.0275, -0.572, 0.022, 1.0, 0.0425, 1.04, -0.04, -9.28, -1.04, 1.04, 50.0},
	 KARIS14 " EnvBRDFApprox (adapted from Lazarov 2013 to Unreal's G)",
	 "r perceptual; t = r c0 + c1, q = min(t.x^2, exp2(-9.28 NoV)) t.x + t.y, A = -1.04 q + t.z, "
	 "B = 1.04 q + t.w; result f0 A + saturate(50 f0) B (the gating makes it non-linear in f0, hence "
	 "env_f0). Unreal's check: 0.4524 f0 - 0.0024 at r = 1, NoV = 1. The LUT it was fitted to is not "
	 "documented. Parameters: p0..p3 = c0 = (-1, -0.0275, -0.572, 0.022), p4..p7 = c1 = (1, 0.0425, 1.04, "
	 "-0.04), p8 = -9.28, p9 = -1.04, p10 = 1.04, p11 = 50"},
	{"env_karis2014_split", "env", KA, KB, 11,
	 {-1.0, -0.0275, -0.572, 0.022, 1.0, 0.0425, 1.04, -0.04, -9.28, -1.04, 1.04},
	 KARIS14 " EnvBRDFApprox, without the saturate(50 f0) gate",
	 "env_karis2014's A and B as a split-sum pair, f0 A + B, i.e. without the gating (equal to the "
	 "gated version for f0 >= 0.02). Parameters as env_karis2014 p0..p10"},
	{"env_karis2014_nonmetal", "env_f0", "min(" KN0 "*" KN0 ", exp2(p4*NoV))*" KN0 " + (p1*r + p3)", NULL, 5,
	 {-1.0, -0.0275, 1.0, 0.0425, -9.28}, KARIS14 " EnvBRDFApproxNonmetal",
	 "the whole environment BRDF for f0 = 0.04 only ('same as EnvBRDFApprox(0.04, ...)': it returns q); "
	 "the form does not read f0, compare it with f0 A + B at f0 = 0.04. Parameters: p0, p1 = c0.xy = "
	 "(-1, -0.0275), p2, p3 = c1.xy = (1, 0.0425), p4 = -9.28"},
	{"env_lazarov2013", "env_f0", LZ(G_BP("p7")), NULL, 8,
	 {1 / 0.96, 0.475, (0.0275 - 0.25 * 0.04) / 0.96, 0.25, (0.015 - 0.75 * 0.04) / 0.96, 0.75, -9.28,
	  8192.0},
	 LAZ,
	 "fitted to normalised Blinn-Phong with Schlick-Smith V, not GGX, its gloss g defined by the "
	 "Blinn-Phong exponent 8192^g; here read through the Blinn-Phong/GGX equivalence of D_blinn_phong, "
	 "8192^g = 2/a^2 - 2, g = saturate(log2(2/a^2 - 2)/log2(8192)) (clamped to the gloss range [0,1]: "
	 "g = 1 below r = 0.125; a = 1 gives log2(0) = -inf, g = 0). t = g (1/0.96, 0.475, (0.0275 - "
	 "0.25*0.04)/0.96, 0.25) + (0, 0, (0.015 - 0.75*0.04)/0.96, 0.75); a0 = t.x min(t.y, exp2(-9.28 NoV)) "
	 "+ t.z, a1 = t.w; result saturate(a0 + f0 (a1 - a0)) (saturate: env_f0). Parameters: p0 = 1/0.96, "
	 "p1 = 0.475, p2 = (0.0275 - 0.25*0.04)/0.96, p3 = 0.25, p4 = (0.015 - 0.75*0.04)/0.96, p5 = 0.75, "
	 "p6 = -9.28, p7 = 8192"},
	{"env_lazarov2013_g1mr", "env_f0", LZ(G_1MR), NULL, 7,
	 {1 / 0.96, 0.475, (0.0275 - 0.25 * 0.04) / 0.96, 0.25, (0.015 - 0.75 * 0.04) / 0.96, 0.75, -9.28},
	 LAZ ", gloss mapping of common copies",
	 "as env_lazarov2013 with the other reading of gloss, g = 1 - r (gloss as smoothness). Parameters "
	 "p0..p6 as env_lazarov2013"},
	{"env_narkowicz2014_lazarov", "env_f0", NZ(G_1MSQRTR), NULL, 10,
	 {0.5745, 1.548, -0.02397, 1.301, 0.5753, -0.2511, -0.02066, 0.4755, -7.672, 50.0}, NARKO ", EnvDFGLazarov",
	 "gloss g = 1 - sqrt(r): his LUT generator of that date used alpha = (1 - g)^4 with a = r^2, fitted "
	 "to uncorrelated exact Smith. t = g p0v + p1v; bias = saturate(t.x min(t.y, exp2(-7.672 NoV)) + t.z); "
	 "delta = saturate(t.w); result f0 (delta - bias) + saturate(50 f0) bias (gated: env_f0). "
	 "Parameters: p0..p3 = (0.5745, 1.548, -0.02397, 1.301), p4..p7 = (0.5753, -0.2511, -0.02066, 0.4755), "
	 "p8 = -7.672, p9 = 50"},
	{"env_narkowicz2014_lazarov_g1mr", "env_f0", NZ(G_1MR), NULL, 10,
	 {0.5745, 1.548, -0.02397, 1.301, 0.5753, -0.2511, -0.02066, 0.4755, -7.672, 50.0},
	 NARKO ", EnvDFGLazarov (gloss mapping of third-party copies)",
	 "as env_narkowicz2014_lazarov with the other reading of gloss, g = 1 - r (copies disagree on the "
	 "mapping). Parameters as env_narkowicz2014_lazarov"},
	{"env_narkowicz2014_poly", "env_f0", NP(G_1MSQRTR), NULL, 14,
	 {-0.1688, 1.895, 0.9903, -4.853, 8.404, -5.069, 0.6045, 1.699, -0.5228, -3.603, 1.404, 0.1939, 2.661,
	  50.0},
	 NARKO ", EnvDFGPolynomial",
	 "x = g = 1 - sqrt(r) (see env_narkowicz2014_lazarov), y = NoV; bias = saturate(min(b1 x + b2 x^2, "
	 "b3 + b4 y + b5 y^2 + b6 y^3)); delta = saturate(d0 + d1 x + d2 y + d3 x^2 + d4 x y + d5 y^2 + "
	 "d6 x^3); result f0 (delta - bias) + saturate(50 f0) bias (gated: env_f0). Parameters: p0..p5 = "
	 "b1..b6 = (-0.1688, 1.895, 0.9903, -4.853, 8.404, -5.069), p6..p12 = d0..d6 = (0.6045, 1.699, "
	 "-0.5228, -3.603, 1.404, 0.1939, 2.661), p13 = 50"},
	{"env_narkowicz2014_poly_g1mr", "env_f0", NP(G_1MR), NULL, 14,
	 {-0.1688, 1.895, 0.9903, -4.853, 8.404, -5.069, 0.6045, 1.699, -0.5228, -3.603, 1.404, 0.1939, 2.661,
	  50.0},
	 NARKO ", EnvDFGPolynomial (gloss mapping of third-party copies)",
	 "as env_narkowicz2014_poly with x = g = 1 - r. Parameters as env_narkowicz2014_poly"},
	{"env_pesce_iwanicki2015", "env_f0", "saturate(f0*" PI_SCALE " + " PI_BIAS ")", NULL, 5,
	 {7.0, 4.0, 0.739, 0.323, 0.434},
	 "M. Iwanicki, A. Pesce 2015, \"Approximate Models for Physically Based Rendering\", SIGGRAPH "
	 "course",
	 "m = alpha = r^2 (the min uses perceptual r); bias = exp2(-(7 NoV + 4 m)); b = min(r, 0.739 + "
	 "0.323 NoV) - 0.434; scale = 1 - bias - m max(bias, b); result saturate(f0 scale + bias) (saturate: "
	 "env_f0). Parameters: p0 = 7, p1 = 4, p2 = 0.739, p3 = 0.323, p4 = 0.434"},
	{"env_ross", "env_f0", "saturate(f0*(1 - " ROSS_F ") + " ROSS_F ")", NULL, 3, {2.69, 22.7, 1.5},
	 "Schlick-style fit to the mean Fresnel of the Ross et al. 2005 BRDF (Bruneton, Neyret, Holzschuch "
	 "2010, inria-00443630), as NVIDIA MathLib's EnvironmentTerm_Ross with m = alpha (attribution "
	 "unverified)",
	 "m = alpha = r^2; f = (1 - NoV)^(5 exp(-2.69 m))/(1 + 22.7 m^1.5); result saturate(f0 (1 - f) + f) "
	 "(written with its saturate: env_f0; for f0 in [0,1] the saturate is inactive and this is f0 A + B "
	 "with A = 1 - f, B = f). Schlick's 5 literal. Parameters: p0 = 2.69, p1 = 22.7, p2 = 1.5"},
	{"env_materialx", "env", "saturate(" MX_X "/" MX_Z ")", "saturate(" MX_Y "/" MX_W ")", 0, {0},
	 "ASWF MaterialX, mx_microfacet_specular.glsl, mx_ggx_dir_albedo_analytic (rational fit to Monte "
	 "Carlo GGX directional albedo)",
	 "x = NoV, y = alpha = r^2; height-correlated Smith G2; A = clamp(r.x/r.z, 0, 1), B = clamp(r.y/r.w, "
	 "0, 1), F90 = 1. Its 34 fitted constants stay LITERAL: they exceed BK_MAX_PARAMS = 16 (A alone "
	 "needs 17), so this entry has no free parameters"},
	{"env_unity_urp", "env_f0", "1/(a*a + 1)*" UNITY_ENV_LERP, NULL, 0, {0},
	 URP ", EnvironmentBRDFSpecular",
	 "surfaceReduction 1/(roughness2 + 1) with roughness2 = a^2 (Unity's roughness is alpha) times "
	 "lerp(specular, grazingTerm, (1 - NoV)^4) (Unity's pow4, not Schlick's 5), grazingTerm = "
	 "saturate(smoothness + reflectivity), smoothness = 1 - r; reflectivity read as f0 (specular setup, "
	 "grey f0; exact for dielectrics of the metallic setup, whose reflectivity is 0.04 + 0.96 metallic, "
	 "not f0, for metals). Non-linear in f0 through the saturate: env_f0. Dimensionless (no π). No "
	 "parameters (only structural 1s and the power 4); URP's HALF_MIN floor on roughness2 left out"},
	{"env_unity_builtin_brdf2", "env_f0", "(1 - a*r*(p0 - p1*r))*" UNITY_ENV_LERP, NULL, 2, {0.6, 0.08},
	 "Unity Technologies, built-in UnityStandardBRDF.cginc BRDF2_Unity_PBS (linear space)",
	 "surfaceReduction = 1 - roughness perceptualRoughness (0.6 - 0.08 perceptualRoughness) = "
	 "1 - a r (0.6 - 0.08 r), times FresnelLerpFast(specColor, grazingTerm, NoV) = lerp(f0, "
	 "saturate(1 - r + reflectivity), (1 - NoV)^4), reflectivity read as f0 (see env_unity_urp): env_f0. "
	 "Parameters: p0 = 0.6, p1 = 0.08"},

	/* ---- multiple scattering: the directional albedo E = A + B (F = 1) ----------- */
	{"ms_materialx", "ms", "saturate(" MX_X "/" MX_Z ") + saturate(" MX_Y "/" MX_W ")", NULL, 0, {0},
	 "ASWF MaterialX, mx_microfacet_specular.glsl: mx_ggx_dir_albedo_analytic(NdotV, alpha, 1, 1), the Ess "
	 "that mx_ggx_energy_compensation divides by (1 + Fss (1 - Ess)/Ess; the compensation's call quoted from "
	 "memory, unverified; the fit as env_materialx)",
	 MS_AT1 "x = NoV, y = alpha = r^2, height-correlated Smith; clamp(r.x/r.z, 0, 1) + clamp(r.y/r.w, 0, 1). "
	 "Its 34 fitted constants stay literal (more than BK_MAX_PARAMS, as env_materialx): no free parameters"},
	{"ms_karis2014", "ms", KA " + " KB, NULL, 11,
	 {-1.0, -0.0275, -0.572, 0.022, 1.0, 0.0425, 1.04, -0.04, -9.28, -1.04, 1.04},
	 KARIS14 " EnvBRDFApprox at SpecularColor = 1",
	 MS_AT1 "A + B of env_karis2014_split (the 50 f0 gate is 1 at f0 = 1), written as shipped: q cancels "
	 "(-1.04 q + 1.04 q), so E = 1 - 0.55 r with no NoV dependence; Unreal's printed check 0.4524 - 0.0024 "
	 "= 0.45 at r = 1, NoV = 1. Parameters as env_karis2014_split"},
	{"ms_narkowicz2014_poly", "ms", NP_F(G_1MSQRTR, "1"), NULL, 14,
	 {-0.1688, 1.895, 0.9903, -4.853, 8.404, -5.069, 0.6045, 1.699, -0.5228, -3.603, 1.404, 0.1939, 2.661,
	  50.0},
	 NARKO ", EnvDFGPolynomial at f0 = 1",
	 MS_AT1 "env_narkowicz2014_poly with f0 = 1 written in (1 (delta - bias) + bias saturate(50): E = delta "
	 "= saturate(d0 + d1 x + d2 y + d3 x^2 + d4 x y + d5 y^2 + d6 x^3), x = 1 - sqrt(r), y = NoV; fitted "
	 "to uncorrelated Smith). Parameters as env_narkowicz2014_poly"},
	{"ms_pesce_iwanicki2015", "ms", "saturate(1*" PI_SCALE " + " PI_BIAS ")", NULL, 5,
	 {7.0, 4.0, 0.739, 0.323, 0.434},
	 "M. Iwanicki, A. Pesce 2015, \"Approximate Models for Physically Based Rendering\", SIGGRAPH "
	 "course, at f0 = 1",
	 MS_AT1 "env_pesce_iwanicki2015 with f0 = 1: saturate(scale + bias), m = alpha = r^2. Parameters as "
	 "env_pesce_iwanicki2015"},

	/* ---- sheen: the Charlie sheen albedo (Filament's cloth DFG channel) ---------- */
	{"sheen_materialx", "sheen",
	 "saturate((p0 + p1*NoV + p2*a + p3*NoV*a + p4*NoV*NoV + p5*a*a)/(1 + p6*NoV + p7*a + p8*NoV*a + p9*NoV*NoV + "
	 "p10*a*a))",
	 NULL, 11,
	 {13.67300, -68.78018, 799.08825, -905.00061, 60.28956, 1086.96473, 61.57746, 442.78211, 2597.49308, 121.81241,
	  3045.55075},
	 "ASWF MaterialX, mx_microfacet_sheen.glsl, mx_imageworks_sheen_dir_albedo_curve_fit (\"rational curve fit "
	 "approximation for the directional albedo of Imageworks sheen\"), clamped by mx_imageworks_sheen_dir_albedo",
	 "fitted to MaterialX's own sheen BRDF, mx_imageworks_sheen_NDF (Estevez & Kulla 2017's Charlie D) times "
	 "Neubelt & Pettineo's 1/(4 (NoL + NoV - NoL NoV)), F = 1: target sheen's integrand. MaterialX passes its "
	 "sheen roughness straight to the NDF as the Charlie exponent's a, so its 'roughness' here is a = r^2 "
	 "(brdfkit's D_charlie(NoH, a), Filament's cloth alpha). r = vec2(c0) + vec2(c1) NoV + vec2(c2) a + "
	 "vec2(c3) NoV a + vec2(c4) NoV^2 + vec2(c5) a^2, result clamp(r.x/r.y, 0, 1); the 1 of r.y's constant "
	 "term is structural. Parameters: p0..p5 = r.x's (13.67300, -68.78018, 799.08825, -905.00061, 60.28956, "
	 "1086.96473), p6..p10 = r.y's (61.57746, 442.78211, 2597.49308, 121.81241, 3045.55075)"},
};

#define NENTRIES (sizeof entries / sizeof entries[0])

size_t bk_catalog_count(void) { return NENTRIES; }

const bk_catalog_entry *bk_catalog_at(size_t i) { return i < NENTRIES ? &entries[i] : NULL; }

const bk_catalog_entry *bk_catalog_find(const char *name)
{
	if (!name)
		return NULL;
	for (size_t i = 0; i < NENTRIES; i++)
		if (strcmp(entries[i].name, name) == 0)
			return &entries[i];
	return NULL;
}

bk_form *bk_catalog_form(const char *name, double *params, bk_form_error *err)
{
	const bk_catalog_entry *e = bk_catalog_find(name);
	if (!e) {
		if (err) {
			err->column = 0;
			/* the name quoted as the user gave it, cut to fit the message */
			snprintf(err->message, sizeof err->message, "unknown catalog form '%.150s'", name ? name : "(null)");
		}
		return NULL;
	}
	bk_form *f = bk_form_parse(e->form, err);
	if (f && params)
		for (int k = 0; k < BK_MAX_PARAMS; k++)
			params[k] = k < e->nparams ? e->defaults[k] : 0;
	return f;
}
