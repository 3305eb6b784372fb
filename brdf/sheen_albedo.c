/*
 * sheen_albedo.c — the sheen directional albedo, the cloth channel Filament
 * bakes (cmgen's DFV_Charlie_Uniform): Charlie D × Neubelt V × NoL over the
 * hemisphere, F = 1. Apart from sheen.c's distributions because it calls the
 * registry, which calls them (brdf/ keeps its calls free of loops).
 */
#include "brdf.h"

/* The registry's D_charlie, V_neubelt and F_schlick with f0 = f90 = 1 (exactly
 * 1) through bk_albedo's half-vector integrator: the cloth channel is one more
 * D·V·F, not a second integrator. */
int bk_sheen_albedo(double NoV, double r, double tol, double *E, bk_quad_stats *stats)
{
	if (!(NoV > 0.0 && NoV <= 1.0) || !(r >= 0.0 && r <= 1.0) || !(tol > 0.0))
		return -1;
	if (r == 0.0) {
		*E = 0.0;
		if (stats)
			*stats = (bk_quad_stats){0.0, 0, 1};
		return 0;
	}
	bk_sample mat = {0};
	bk_sample_roughness(&mat, r);
	mat.f0 = 1.0;
	mat.f90 = 1.0;
	return bk_albedo(bk_term_find("D_charlie"), bk_term_find("V_neubelt"), bk_term_find("F_schlick"), &mat, NoV,
	                 tol, E, stats);
}
