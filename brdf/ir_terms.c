/*
 * ir_terms.c — every term of the registry written in the formula language, so
 * that a form can call D_ggx(NoH, a) and get the same arithmetic the C function
 * does (tests: agreement to 1e-12 relative wherever both are finite, on the
 * physical domain; the C functions' explicit guards for NoH <= 0, a = 0 and
 * eta = inf have no counterpart here — a shader has none either).
 *
 * Bodies may define locals first: "name = expr; ...; expr". They see only their
 * own arguments and locals.
 */
#include "ir_terms.h"

#include <string.h>

#define PI "3.141592653589793"

static const bk_ir_term terms[] = {
	{"D_ggx", "NoH,a", "a*a / (" PI " * sq((1 - NoH)*(1 + NoH) + NoH*NoH*a*a))"},
	{"D_beckmann", "NoH,a", "c2 = NoH*NoH; exp(-((1 - NoH)*(1 + NoH)/c2) / (a*a)) / (" PI " * a*a * c2*c2)"},
	{"D_blinn_phong", "NoH,a", "n = 2/(a*a) - 2; (n + 2)/(2*" PI ") * pow(NoH, n)"},
	{"D_blinn_phong_sg", "NoH,a", "n = 2/(a*a) - 2; (n + 2)/(2*" PI ") * exp((n + 0.775)*(NoH - 1))"},

	{"D_charlie", "NoH,a", "(2 + 1/a) * pow((1 - NoH)*(1 + NoH), 0.5/a) / (2*" PI ")"},
	{"D_ashikhmin", "NoH,a",
	 "s2 = (1 - NoH)*(1 + NoH); (1 + 4*exp(-(NoH*NoH/s2)/(a*a))/(s2*s2)) / (" PI " * (1 + 4*a*a))"},

	{"V_smith_ggx_separable", "NoV,NoL,a",
	 "a2 = a*a; 1/((NoV + sqrt(a2 + (1 - a2)*NoV*NoV)) * (NoL + sqrt(a2 + (1 - a2)*NoL*NoL)))"},
	{"V_smith_ggx_correlated", "NoV,NoL,a",
	 "a2 = a*a; 0.5/(NoL*sqrt(NoV*NoV*(1 - a2) + a2) + NoV*sqrt(NoL*NoL*(1 - a2) + a2))"},
	{"V_schlick_ggx_ibl", "NoV,NoL,a", "k = 0.5*a; 0.25/((NoV*(1 - k) + k)*(NoL*(1 - k) + k))"},
	{"V_schlick_ggx_direct", "NoV,NoL,r", "k = (r + 1)*(r + 1)/8; 0.25/((NoV*(1 - k) + k)*(NoL*(1 - k) + k))"},
	{"V_kelemen", "LoH", "0.25/(LoH*LoH)"},
	{"V_kelemen_hable", "LoH,a", "k2 = 0.25*a*a; 0.25/(LoH*LoH*(1 - k2) + k2)"},
	{"V_kelemen_talk", "LoH,r", "r2 = r*r; 0.25/(LoH*LoH*(1 - r2) + r2)"},
	{"V_neubelt", "NoV,NoL", "0.25/(NoL + NoV - NoL*NoV)"},
	{"V_neumann", "NoV,NoL", "0.25/max(NoL, NoV)"},
	{"V_implicit", "", "0.25"},
	{"V_cook_torrance", "NoV,NoL,NoH,VoH", "min(0.25/(NoL*NoV), NoH/(2*VoH*max(NoL, NoV)))"},
	{"V_hammon", "NoV,NoL,a", "0.5/(2*NoL*NoV*(1 - a) + (NoL + NoV)*a)"},

	{"F_schlick", "f0,f90,LoH", "m = 1 - LoH; m2 = m*m; f0 + (f90 - f0)*m2*m2*m"},
	{"F_schlick_sg", "f0,f90,LoH", "f0 + (f90 - f0)*exp2((-5.55473*LoH - 6.98316)*LoH)"},
	{"F_schuler", "f0,LoH", "f0/LoH"},
	/* Total internal reflection without a branch: cos_t = 0 makes rs = rp = 1. */
	{"F_dielectric", "LoH,eta",
	 "c = saturate(LoH); ct = sqrt(max(0, 1 - (1 - c*c)/(eta*eta)));"
	 "rs = (c - eta*ct)/(c + eta*ct); rp = (eta*c - ct)/(eta*c + ct); 0.5*(rs*rs + rp*rp)"},
	{"F_conductor", "LoH,eta,k",
	 "c = saturate(LoH); c2 = c*c; s2 = 1 - c2; t0 = eta*eta - k*k - s2;"
	 "ab = sqrt(t0*t0 + 4*eta*eta*k*k); t1 = ab + c2; t2 = 2*c*sqrt(max(0, 0.5*(ab + t0)));"
	 "rs = (t1 - t2)/(t1 + t2); t3 = c2*ab + s2*s2; t4 = t2*s2; 0.5*(rs + rs*(t3 - t4)/(t3 + t4))"},

	{"Fd_lambert", "", "1/" PI},
	{"Fd_burley", "NoV,NoL,LoH,r",
	 "f90 = 0.5 + 2*r*LoH*LoH; F_schlick(1, f90, NoL) * F_schlick(1, f90, NoV) / " PI},
	{"Fd_oren_nayar", "NoV,NoL,VoL,sigma",
	 "s2 = sigma*sigma; (1 - 0.5*s2/(s2 + 0.33) + 0.45*s2/(s2 + 0.09) * max(0, VoL - NoV*NoL)/max(NoV, NoL)) / " PI},
};

const bk_ir_term *bk_ir_term_find(const char *name, size_t len)
{
	for (size_t i = 0; i < sizeof terms / sizeof terms[0]; i++)
		if (strlen(terms[i].name) == len && strncmp(terms[i].name, name, len) == 0)
			return &terms[i];
	return NULL;
}
