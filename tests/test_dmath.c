/*
 * test_dmath.c — brdf/dmath.c: sin, cos and acos whose bits do not depend on
 * the CPU, checked against glibc's long double functions (an independent
 * implementation with 11 more bits) and at the angles where the value is known
 * exactly.
 */
#include "dmath.h"

#include <criterion/criterion.h>
#include <math.h>

/* π to double precision (PI is POSIX's, not C11's) */
#define PI 3.14159265358979323846

/* |got - ref| in units in the last place of the double nearest ref. */
static double ulps(double got, long double ref)
{
	double r = fabs((double)ref);
	double u = r == 0.0 ? 0x1p-1074 : nextafter(r, INFINITY) - r;
	return (double)(fabsl((long double)got - ref) / u);
}

Test(dmath, sin_cos_within_one_and_a_half_ulp_on_their_domain)
{
	double worst_s = 0, worst_c = 0;
	for (int i = -400000; i <= 400000; i++) {
		double x = 8.0 * i / 400000.0 + 1e-7 * (i % 7); /* off the grid too */
		if (fabs(x) > 8.0)
			continue;
		worst_s = fmax(worst_s, ulps(bk_dsin(x), sinl(x)));
		worst_c = fmax(worst_c, ulps(bk_dcos(x), cosl(x)));
	}
	cr_expect(worst_s <= 1.5, "sin: %.3f ulp", worst_s);
	cr_expect(worst_c <= 1.5, "cos: %.3f ulp", worst_c);
}

Test(dmath, acos_within_two_ulp_on_minus_one_to_one)
{
	double worst = 0;
	for (int i = -400000; i <= 400000; i++) {
		double c = i / 400000.0;
		worst = fmax(worst, ulps(bk_dacos(c), acosl(c)));
	}
	/* the ends, where acos has its square-root behaviour */
	const double ends[] = {1 - 0x1p-53, 1 - 0x1p-30, -1 + 0x1p-53, -1 + 0x1p-30, 0x1p-1074, -0.5, 0.5};
	for (size_t k = 0; k < sizeof ends / sizeof ends[0]; k++)
		worst = fmax(worst, ulps(bk_dacos(ends[k]), acosl(ends[k])));
	cr_expect(worst <= 2.0, "acos: %.3f ulp", worst);
}

Test(dmath, exact_angles)
{
	cr_expect_eq(bk_dcos(0.0), 1.0);
	cr_expect_eq(bk_dsin(0.0), 0.0);
	cr_expect_eq(bk_dsin(PI / 2), 1.0);      /* sin of the double nearest π/2 rounds to 1 */
	cr_expect_eq(bk_dacos(1.0), 0.0);
	cr_expect_eq(bk_dacos(0.0), PI / 2);     /* the double nearest π/2 */
	cr_expect_eq(bk_dacos(-1.0), PI);        /* the double nearest π */
	cr_expect(isnan(bk_dacos(1.5)));
	cr_expect(isnan(bk_dacos(NAN)));
	/* cos(π/3) = 1/2 and acos(1/2) = π/3, to rounding */
	cr_expect(fabs(bk_dcos(PI / 3) - 0.5) <= 0x1p-53);
	cr_expect(fabs(bk_dacos(0.5) - PI / 3) <= 0x1p-52);
}
