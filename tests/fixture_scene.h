/*
 * fixture_scene.h — the one-set scene the scene tests specialise for
 * (tests/test_scene.c, test_shared.c, test_scene_refits.c): a dielectric at
 * f0 = 0.04, roughness in [r_lo, 1], needing one term. One place, so that the
 * tests that compare refits and references build the same set.
 */
#ifndef TESTS_FIXTURE_SCENE_H
#define TESTS_FIXTURE_SCENE_H

#include "scene.h"

#include <string.h>

typedef enum { FX_NEEDS_VF, FX_NEEDS_ENV } fx_need;

static inline bk_scene_set fx_scene_set(double r_lo, fx_need need)
{
	bk_scene_set s;
	memset(&s, 0, sizeof s);
	strcpy(s.name, "t");
	s.r_lo = r_lo;
	s.r_hi = 1;
	s.f0_lo = s.f0_hi = 0.04;
	s.needs.vf = need == FX_NEEDS_VF;
	s.needs.env = need == FX_NEEDS_ENV;
	s.needs.fixed_f0 = 1;
	s.needs.f0 = 0.04;
	return s;
}

#endif
