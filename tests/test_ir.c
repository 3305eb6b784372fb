/*
 * test_ir.c — the formula IR: the half rounding rule against the compiler's
 * binary16, parse errors (their text is part of the contract), precedence,
 * what the compiler produced (op lists and counts, the talk's claims),
 * agreement of every term's definition with its C function, and derivatives
 * against central differences.
 */
#include "brdf.h"
#include "ir.h"
#include "fuzz/exercise.h"

#include <criterion/criterion.h>
#include <dirent.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static bk_form *parse_ok(const char *text)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "'%s': col %d: %s", text, e.column, e.message);
	return f;
}

static double eval1(const char *text, bk_precision p, const double *params)
{
	double NoV = 0.5, NoL = 0.7, NoH = 0.9, LoH = 0.8, r = 0.5, a = 0.25, f0 = 0.04, out;
	const double *in[BK_IN_COUNT] = {&NoV, &NoL, &NoH, &LoH, &r, &a, &f0};
	bk_form *f = parse_ok(text);
	cr_assert_eq(bk_form_eval(f, p, 1, in, params, &out), 0);
	bk_form_free(f);
	return out;
}

/* ---- half precision -------------------------------------------------------- */

/* The rule written in half.c against gcc's _Float16 conversion (round to
 * nearest even, IEEE binary16), over 200k float bit patterns spread across all
 * exponents, and the landmarks: max 65504, the overflow tie 65520, the
 * smallest normal 2^-14 and subnormal 2^-24. */
Test(half, rounding_matches_binary16)
{
	unsigned s = 1;
	for (int i = 0; i < 200000; i++) {
		s = s * 1664525u + 1013904223u;
		float x;
		unsigned bits = s & 0xC7FFFFFFu; /* keep exponents within half's reach and beyond */
		memcpy(&x, &bits, sizeof x);
		if (!isfinite(x))
			continue;
		__extension__ _Float16 h = (_Float16)x;
		cr_assert(bk_half_round(x) == (double)h || (isnan(bk_half_round(x)) && isnan((double)h)),
		          "x = %a: %a vs %a", (double)x, bk_half_round(x), (double)h);
	}
	cr_assert_eq(bk_half_round(65504.0), 65504.0);
	cr_assert(isinf(bk_half_round(65520.0)) && bk_half_round(65519.99) == 65504.0);
	cr_assert_eq(bk_half_round(0x1p-14), 0x1p-14);
	cr_assert_eq(bk_half_round(0x1p-24), 0x1p-24);
	cr_assert_eq(bk_half_round(0x1p-26), 0.0);
	cr_assert_eq(bk_half_round(1.0 + 0x1p-11), 1.0); /* tie to even */
	cr_assert_eq(bk_half_round(1.0 + 3 * 0x1p-11), 1.0 + 0x1p-9);
}

/* In half, 1/(LoH^2 (r + 0.5)) overflows past 65504 where single does not:
 * the reason the talk's Unity version clamps LoH^2. */
Test(half, overflow_shows_in_f16_only)
{
	double LoH = 0.003, r = 0.1, p = 0.5, o16, o32;
	const double *in[BK_IN_COUNT] = {NULL, NULL, NULL, &LoH, &r, NULL, NULL};
	bk_form *f = parse_ok("1/(LoH*LoH*(r+p0))");
	bk_form_eval(f, BK_F16, 1, in, &p, &o16);
	bk_form_eval(f, BK_F32, 1, in, &p, &o32);
	bk_form_free(f);
	cr_assert(isinf(o16) && isfinite(o32) && fabs(o32 - 1.0 / (LoH * LoH * 0.6)) < 1e-2 * o32, "%g %g", o16, o32);
}

/* f32 is single precision after every operation: NoV*NoL + f0 in float. */
Test(half, f32_rounds_like_float)
{
	float want = (float)0.5 * (float)0.7;
	want = want + (float)0.04;
	cr_assert_eq(eval1("NoV*NoL + f0", BK_F32, NULL), (double)want);
	double h = bk_half_round(bk_half_round(bk_half_round(0.5) * bk_half_round(0.7)) + bk_half_round(0.04));
	cr_assert_eq(eval1("NoV*NoL + f0", BK_F16, NULL), h);
}

/* ---- parsing ----------------------------------------------------------------- */

static void expect_error(const char *text, int column, const char *message)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_null(f, "'%s' parsed", text);
	cr_assert_eq(e.column, column, "'%s': column %d, want %d (%s)", text, e.column, column, e.message);
	cr_assert_str_eq(e.message, message, "'%s'", text);
}

/* bk_form_params: the parameters a form reads, a gap kept (p0 and p2: not
 * p1), so every command can refuse one (issue 39 M14); bk_form_nparams is
 * the highest + 1. */
Test(parse, params_read_as_a_mask)
{
	static const struct {
		const char *text;
		unsigned mask;
		int np;
	} c[] = {{"NoV", 0, 0}, {"p0*NoV", 1, 1}, {"p0+p2*NoV", 5, 3}, {"p15", 1u << 15, 16}, {"p1*p0+p1", 3, 2}};
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		bk_form *f = bk_form_parse(c[i].text, NULL);
		cr_assert_not_null(f, "%s", c[i].text);
		cr_expect_eq(bk_form_params(f), c[i].mask, "%s", c[i].text);
		cr_expect_eq(bk_form_nparams(f), c[i].np, "%s", c[i].text);
		bk_form_free(f);
	}
}

/* bk_form_dup: a second owner of a parsed form (a scene's choice keeps its
 * candidate's IR, issue 42 "parsed once") reads as the parse of the same
 * text does, in every precision, bit for bit, and outlives the original. The
 * control: a form that differs by one constant does not. */
Test(parse, dup_is_the_parse_of_the_same_text)
{
	const char *text = "p0*F_schlick(f0, 1, LoH)/(4*LoH*LoH*(a + p2)) + saturate(NoV - r)";
	double p[BK_MAX_PARAMS] = {1.25, 0, 0.0625};
	bk_form *f = parse_ok(text), *d = bk_form_dup(f), *other = parse_ok("p0*F_schlick(f0, 1, LoH)/(4*LoH*LoH*(a + p2)) + saturate(NoV - 0.5*r)");
	cr_assert_not_null(d);
	bk_ops of, od;
	bk_form_count(f, &of);
	bk_form_count(d, &od);
	cr_expect_eq(memcmp(&of, &od, sizeof of), 0);
	bk_form_free(f); /* the copy owns all it reads */
	f = parse_ok(text);
	cr_expect_str_eq(bk_form_text(d), text);
	cr_expect_eq(bk_form_nparams(d), bk_form_nparams(f));
	cr_expect_eq(bk_form_params(d), bk_form_params(f));
	cr_expect_eq(bk_form_inputs(d), bk_form_inputs(f));
	double NoV = 0.9, NoL = 0.7, NoH = 0.9, LoH = 0.6, r = 0.7, a = 0.49, f0 = 0.04; /* NoV > r: the two saturates differ */
	const double *in[BK_IN_COUNT] = {&NoV, &NoL, &NoH, &LoH, &r, &a, &f0};
	static const bk_precision prec[3] = {BK_F64, BK_F32, BK_F16};
	for (int k = 0; k < 3; k++) {
		double vf, vd, vo;
		cr_assert_eq(bk_form_eval(f, prec[k], 1, in, p, &vf), 0);
		cr_assert_eq(bk_form_eval(d, prec[k], 1, in, p, &vd), 0);
		cr_assert_eq(bk_form_eval(other, prec[k], 1, in, p, &vo), 0);
		cr_expect_eq(memcmp(&vf, &vd, sizeof vf), 0, "precision %d: %.17g against %.17g", k, vd, vf);
		cr_expect_neq(memcmp(&vf, &vo, sizeof vf), 0, "precision %d: the control reads the same", k);
	}
	bk_form_free(f);
	bk_form_free(d);
	bk_form_free(other);
}

Test(parse, errors_name_column_and_expectation)
{
	expect_error("1/(LoH*LoH*(r+p0)", 18, "expected ')' at end of form");
	expect_error("NoV +", 6, "expected a number, a name or '(' at end of form");
	expect_error("NoV * * 2", 7, "expected a number, a name or '(' near '*'");
	expect_error("sqrt(1, 2)", 1, "'sqrt' takes 1 argument, got 2 near 'sqrt'");
	expect_error("D_ggx(NoH)", 1, "'D_ggx' takes 2 arguments (NoH,a), got 1 near 'D_ggx'");
	expect_error("foo(1)", 1, "unknown function near 'foo'");
	expect_error("NoV + x", 7, "unknown name (inputs: NoV NoL NoH LoH VoH r a f0; parameters p0..p15) near 'x'");
	expect_error("p16 * 2", 1, "parameter out of range (p0..p15) near 'p16'");
	expect_error("NoV # 2", 5, "invalid character near '#'");
	expect_error("NoV NoL", 5, "expected an operator or the end of the form near 'NoL'");
	expect_error("(NoV", 5, "expected ')' at end of form");
	expect_error("min(NoV NoL)", 9, "expected ')' or ',' near 'NoL'");
	expect_error("", 1, "expected a number, a name or '(' at end of form");
	expect_error("inf", 1, "unknown name (inputs: NoV NoL NoH LoH VoH r a f0; parameters p0..p15) near 'inf'");
}

Test(parse, nesting_is_bounded)
{
	char buf[1200];
	memset(buf, '(', 600);
	strcpy(buf + 600, "1");
	memset(buf + 601, ')', 599);
	buf[1200 - 1] = '\0';
	bk_form_error e;
	cr_assert_null(bk_form_parse(buf, &e));
	cr_assert_str_eq(e.message, "expression nested too deeply (more than 200 levels) near '('");
}

/* "200 levels deep" (brdfkit(1)): 200 nested parentheses, calls or unary minus
 * are read, and give the value; 201 are refused. */
static char *nested(int n, const char *open, const char *inner, const char *close)
{
	size_t len = (size_t)n * (strlen(open) + strlen(close)) + strlen(inner) + 1;
	char *s = malloc(len), *p = s;
	cr_assert_not_null(s);
	for (int i = 0; i < n; i++)
		p += sprintf(p, "%s", open);
	p += sprintf(p, "%s", inner);
	for (int i = 0; i < n; i++)
		p += sprintf(p, "%s", close);
	return s;
}

Test(parse, two_hundred_levels_pass_and_201_do_not)
{
	static const char *const kind[][2] = {{"(", ")"}, {"abs(", ")"}, {"- ", ""}};
	for (size_t k = 0; k < sizeof kind / sizeof kind[0]; k++)
		for (int n = 199; n <= 201; n++) {
			char *text = nested(n, kind[k][0], "0.5", kind[k][1]);
			bk_form_error e;
			bk_form *f = bk_form_parse(text, &e);
			if (n <= 200) {
				cr_assert_not_null(f, "%d levels of %s: %s", n, kind[k][0], e.message);
				double want = k == 2 && n % 2 ? -0.5 : 0.5; /* an odd number of minus signs */
				cr_assert_eq(eval1(text, BK_F64, NULL), want, "%d levels of %s", n, kind[k][0]);
			} else {
				cr_assert_null(f, "%d levels of %s accepted", n, kind[k][0]);
				cr_assert_not_null(strstr(e.message, "nested too deeply (more than 200 levels)"), "%s", e.message);
			}
			bk_form_free(f);
			free(text);
		}
}

/* Precedence: ^ over unary minus over * / over + -; ^ right-associative. */
Test(parse, precedence_and_associativity)
{
	cr_assert_eq(eval1("-2^2", BK_F64, NULL), -4.0);
	cr_assert_eq(eval1("2^3^2", BK_F64, NULL), 512.0);
	cr_assert_eq(eval1("2*-3", BK_F64, NULL), -6.0);
	cr_assert_eq(eval1("1 - 2 - 3", BK_F64, NULL), -4.0);
	cr_assert_eq(eval1("8 / 2 / 2", BK_F64, NULL), 2.0);
	cr_assert_eq(eval1("2 + 3 * 4 ^ 2", BK_F64, NULL), 50.0);
	cr_assert_eq(eval1("2^-1", BK_F64, NULL), 0.5);
	cr_assert_eq(eval1("1.5e1 + .5", BK_F64, NULL), 15.5);
	cr_assert_eq(eval1("VoH", BK_F64, NULL), 0.8); /* = LoH */
}

/* ---- what the compiler produced ------------------------------------------------ */

static int count_op(const bk_form *f, bk_op op)
{
	int n = 0;
	for (int i = 0; i < f->n; i++)
		n += f->code[i].op == op;
	return n;
}

Test(code, sharing_folding_powers_and_fusion)
{
	bk_form *f = parse_ok("NoV*NoV + NoV*NoV"); /* shared product used twice: no MAD */
	cr_assert(count_op(f, BK_OP_MUL) == 1 && count_op(f, BK_OP_ADD) == 1 && f->n == 3);
	bk_form_free(f);
	f = parse_ok("NoV*NoL + f0");
	cr_assert(count_op(f, BK_OP_MAD) == 1 && count_op(f, BK_OP_MUL) == 0 && f->n == 4);
	bk_form_free(f);
	f = parse_ok("f0 - NoV*NoL"); /* c - a*b = mad(-a, b, c) */
	cr_assert(count_op(f, BK_OP_MAD) == 1 && count_op(f, BK_OP_NEG) == 1);
	bk_form_free(f);
	f = parse_ok("NoV^5"); /* x^5 = (x^2)^2 x: three multiplies */
	cr_assert(count_op(f, BK_OP_MUL) == 3 && count_op(f, BK_OP_POW) == 0);
	bk_form_free(f);
	f = parse_ok("pow(NoV, -2)");
	cr_assert(count_op(f, BK_OP_MUL) == 1 && count_op(f, BK_OP_RCP) == 1);
	bk_form_free(f);
	f = parse_ok("pow(NoV, 2.5)");
	cr_assert(count_op(f, BK_OP_POW) == 1);
	bk_form_free(f);
	f = parse_ok("NoL * NoV - NoV * NoL"); /* commutative operands are one register */
	cr_assert(count_op(f, BK_OP_MUL) == 1);
	bk_form_free(f);
	f = parse_ok("(1 + 2) * NoV * 1 + 0"); /* 3 folds; *1 and +0 vanish */
	cr_assert(f->n == 3 && count_op(f, BK_OP_CONST) == 1 && f->code[0].k == 3.0);
	bk_form_free(f);
}

/* Folding only where every precision agrees: 1/3 rounds once either way and
 * folds; 0.1*3 in half would round 0.1 first, so it stays a multiply. */
Test(code, folding_respects_every_precision)
{
	bk_form *f = parse_ok("1/3");
	cr_assert(f->n == 1 && f->code[0].op == BK_OP_CONST);
	bk_form_free(f);
	f = parse_ok("0.1*3");
	cr_assert(count_op(f, BK_OP_MUL) == 1);
	cr_assert_eq(eval1("0.1*3", BK_F16, NULL), bk_half_round(bk_half_round(0.1) * 3.0));
	bk_form_free(f);
	f = parse_ok("0*-1"); /* -0.0 is never folded into */
	cr_assert(count_op(f, BK_OP_CONST) != f->n);
	bk_form_free(f);
	f = parse_ok("1/0"); /* nor an infinity */
	cr_assert(count_op(f, BK_OP_DIV) == 1);
	bk_form_free(f);
}

static bk_ops ops_of(const char *text)
{
	bk_ops o;
	bk_form *f = parse_ok(text);
	bk_form_count(f, &o);
	bk_form_free(f);
	return o;
}

/* The talk's claims, out of the counter. Its specular BRDF (printed form,
 * r perceptual) has one division and no other complex op; its environment
 * BRDF has none; Karis's EnvBRDFApprox (the A term) has one exp2. */
Test(count, the_talks_claims)
{
	bk_ops o = ops_of("r^4 / (4*3.14159265*sq(NoH*NoH*(r^4 - 1) + 1) * LoH*LoH*(r + 0.5)) * f0");
	cr_assert(o.complex == 1 && o.n[BK_K_DIV] == 1, "complex %d div %d", o.complex, o.n[BK_K_DIV]);
	o = ops_of("(1 - max(r, NoV))^3 + f0");
	cr_assert(o.complex == 0 && o.simple > 0);
	o = ops_of("-1.04*(min((r*-1 + 1)^2, exp2(-9.28*NoV))*(r*-1 + 1) + (r*-0.0275 + 0.0425)) + (r*-0.572 + 1.04)");
	cr_assert(o.complex == 1 && o.n[BK_K_EXP2] == 1);
	cr_assert_eq(bk_ops_cost(&o, BK_COST_SIMPLE, BK_COST_COMPLEX), o.simple + 4.0);
	/* pow = log2 + mul + exp2; exp = mul + exp2; saturate and min are their own classes */
	o = ops_of("pow(NoV, p0)");
	cr_assert(o.n[BK_K_LOG2] == 1 && o.n[BK_K_MUL] == 1 && o.n[BK_K_EXP2] == 1 && o.complex == 2);
	o = ops_of("saturate(NoV) + min(NoL, 1)");
	cr_assert(o.n[BK_K_SATURATE] == 1 && o.n[BK_K_MINMAX] == 1 && o.n[BK_K_ADD] == 1);
}

/* ---- terms in the language ----------------------------------------------------- */

/* Every registry term's IR definition agrees with its C function to 1e-12
 * relative over a grid of the physical domain (cosines in (0, 1], r in
 * (0, 1]), in double precision. The argument names of the C function map to
 * the sample; Oren-Nayar takes VoL = 2 LoH^2 - 1 and sigma = r as the
 * registry does. */
Test(terms, ir_definitions_match_c)
{
	const double th[] = {0.1, 0.6, 1.2, 1.5}, rs[] = {0.05, 0.3, 0.7, 1.0}, phis[] = {0.0, 1.0, 3.0};
	for (size_t t = 0; t < bk_term_count(); t++) {
		const bk_term *term = bk_term_at(t);
		for (size_t i = 0; i < 4; i++)
			for (size_t j = 0; j < 4; j++)
				for (size_t q = 0; q < 3; q++)
					for (size_t m = 0; m < 4; m++) {
						bk_sample s = {.f0 = 0.04, .f90 = 1.0, .eta = 1.5, .k = 0.0};
						if (strcmp(term->name, "F_conductor") == 0)
							s.eta = 0.2, s.k = 3.0;
						bk_sample_geometry(&s, th[i], th[j], phis[q]);
						bk_sample_roughness(&s, rs[m]);
						if (s.NoV <= 0 || s.NoL <= 0)
							continue;
						char call[256], args[160] = "";
						const char *p = term->args;
						while (*p) {
							const char *e = strchr(p, ',');
							size_t len = e ? (size_t)(e - p) : strlen(p);
							double v = 0;
							if (!strncmp(p, "NoV", len)) v = s.NoV;
							else if (!strncmp(p, "NoL", len)) v = s.NoL;
							else if (!strncmp(p, "NoH", len)) v = s.NoH;
							else if (!strncmp(p, "LoH", len) || !strncmp(p, "VoH", len)) v = s.LoH;
							else if (!strncmp(p, "r", len) || !strncmp(p, "sigma", len)) v = s.r;
							else if (!strncmp(p, "a", len)) v = s.a;
							else if (!strncmp(p, "f0", len)) v = s.f0;
							else if (!strncmp(p, "f90", len)) v = s.f90;
							else if (!strncmp(p, "eta", len)) v = s.eta;
							else if (!strncmp(p, "k", len)) v = s.k;
							else if (!strncmp(p, "VoL", len)) v = 2 * s.LoH * s.LoH - 1;
							else cr_assert_fail("%s: unmapped argument %.*s", term->name, (int)len, p);
							size_t k = strlen(args);
							snprintf(args + k, sizeof args - k, "%s%.17g", k ? ", " : "", v);
							p += len + (e != NULL);
						}
						snprintf(call, sizeof call, "%s(%s)", term->name, args);
						double want = term->eval(&s), got = eval1(call, BK_F64, NULL);
						if (!isfinite(want) || !isfinite(got))
							continue;
						cr_assert(fabs(got - want) <= 1e-12 * fabs(want) + 1e-300, "%s: %.17g vs %.17g", call, got, want);
					}
	}
}

/* ---- derivatives ----------------------------------------------------------------- */

/* Reverse mode against central differences, h = 1e-6·max(1, |p|): truncation
 * error ~h^2 f''' and rounding ~ε f/h, about 1e-9 relative here. */
Test(diff, matches_central_differences)
{
	const char *forms[] = {
		"1/(LoH*LoH*(r + p0))",
		"p0 + p1*exp2((p2*LoH + p3)*LoH)",
		"mix(p0, sqrt(p1 + NoV), saturate(p2*NoL)) / max(p3, a)",
		"pow(NoV, p0) * rsqrt(p1 + NoL*NoL) + log(p2 + r) - abs(p3 - NoH) + min(p0, p1)*rcp(p2)",
		"F_schlick(p0, p1, LoH) * V_smith_ggx_correlated(NoV, NoL, p2*p2)",
	};
	const double P[4] = {0.45, 0.9, 0.35, 0.2};
	enum { N = 64 };
	double NoV[N], NoL[N], NoH[N], LoH[N], r[N], a[N], f0[N];
	for (int k = 0; k < N; k++) {
		NoV[k] = 0.05 + 0.9 * k / N;
		NoL[k] = 0.95 - 0.8 * k / N;
		NoH[k] = 0.6 + 0.35 * ((k * 7) % N) / N;
		LoH[k] = 0.2 + 0.7 * ((k * 13) % N) / N;
		r[k] = 0.1 + 0.8 * ((k * 5) % N) / N;
		a[k] = r[k] * r[k];
		f0[k] = 0.04;
	}
	const double *in[BK_IN_COUNT] = {NoV, NoL, NoH, LoH, r, a, f0};
	for (size_t i = 0; i < sizeof forms / sizeof forms[0]; i++) {
		bk_form *f = parse_ok(forms[i]);
		int np = bk_form_nparams(f);
		double out[N], jac[N * 4], hi[N], lo[N], plain[N];
		cr_assert_eq(bk_form_eval_diff(f, N, in, P, out, jac), 0);
		bk_form_eval(f, BK_F64, N, in, P, plain);
		for (int k = 0; k < N; k++)
			cr_assert_eq(out[k], plain[k], "%s: value differs from eval", forms[i]);
		for (int j = 0; j < np; j++) {
			double p2[4];
			memcpy(p2, P, sizeof p2);
			double h = 1e-6 * fmax(1.0, fabs(P[j]));
			p2[j] = P[j] + h;
			bk_form_eval(f, BK_F64, N, in, p2, hi);
			p2[j] = P[j] - h;
			bk_form_eval(f, BK_F64, N, in, p2, lo);
			for (int k = 0; k < N; k++) {
				double fd = (hi[k] - lo[k]) / (2 * h), d = jac[k * np + j];
				cr_assert(fabs(d - fd) <= 1e-6 * (fabs(fd) + fabs(out[k])) + 1e-9,
				          "%s: d/dp%d at %d: %.12g vs %.12g", forms[i], j, k, d, fd);
			}
		}
		bk_form_free(f);
	}
}

/* An input the form reads must be supplied. */
Test(eval, missing_input_is_an_error)
{
	double x = 0.5, out;
	const double *in[BK_IN_COUNT] = {&x};
	bk_form *f = parse_ok("NoV * NoL");
	cr_assert_eq(bk_form_eval(f, BK_F64, 1, in, NULL, &out), -1);
	cr_assert_eq(bk_form_inputs(f), (1u << BK_IN_NOV) | (1u << BK_IN_NOL));
	bk_form_free(f);
}

/* min, max, clamp and saturate mean what C's fmin and fmax mean (C11 F.10.9.2:
 * a NaN operand is missing data, the other operand is the result), in every
 * precision and on every lane of a block, and agree with the C library's
 * fmin/fmax on signed zeros too, since the generated C calls fminf/fmaxf
 * (ir_eval.c writes them as selects so that they vectorise). Operands: every
 * ordered pair of NaN, -inf, -1, -0, +0, 0.5, 1, +inf. */
static int same_value(double x, double y)
{
	return isnan(x) ? isnan(y) : x == y && signbit(x) == signbit(y);
}

Test(eval, min_max_mean_fmin_fmax)
{
	static const double v[] = {NAN, -INFINITY, -1.0, -0.0, 0.0, 0.5, 1.0, INFINITY};
	enum { NV = sizeof v / sizeof v[0], N = NV * NV };
	double x[N], y[N], out[N];
	for (int i = 0; i < N; i++)
		x[i] = v[i / NV], y[i] = v[i % NV];
	const double *in[BK_IN_COUNT] = {x, y};
	static const char *const forms[] = {"min(NoV, NoL)", "max(NoV, NoL)", "clamp(NoV, NoL, 0.75)",
	                                    "saturate(NoV)"};
	for (int fi = 0; fi < 4; fi++) {
		bk_form *f = parse_ok(forms[fi]);
		for (int p = BK_F64; p <= BK_F16; p++) {
			cr_assert_eq(bk_form_eval(f, (bk_precision)p, N, in, NULL, out), 0);
			for (int i = 0; i < N; i++) {
				double a = x[i], b = y[i];
				double want = fi == 0 ? fmin(a, b) : fi == 1 ? fmax(a, b) : fi == 2 ? fmin(fmax(a, b), 0.75)
				                                                                   : fmin(fmax(a, 0.0), 1.0);
				cr_assert(same_value(out[i], want), "%s in %s at (%g, %g): %g, C says %g", forms[fi],
				          bk_precision_name((bk_precision)p), a, b, out[i], want);
			}
		}
		bk_form_free(f);
	}
	/* the cases the standard fixes, written out rather than taken from libm */
	cr_assert_eq(eval1("min(NoV, p0)", BK_F32, (double[]){NAN}), 0.5);
	cr_assert_eq(eval1("max(p0, NoV)", BK_F16, (double[]){NAN}), 0.5);
	cr_assert_eq(eval1("saturate(p0)", BK_F64, (double[]){NAN}), 0.0);
	cr_assert_eq(eval1("saturate(p0)", BK_F32, (double[]){-INFINITY}), 0.0);
}

/* ---- fuzzing regressions ---------------------------------------------------------- */

/* The harness's own steps on one input; crashes and sanitizer reports are
 * the failure (the sanitized run of make test). */
static int exercise(const char *text)
{
	int rc = bk_exercise_form(text);
	cr_assert(rc >= 0, "a step failed on '%s'", text);
	return rc;
}

static int replay_dir(const char *dir)
{
	DIR *d = opendir(dir);
	cr_assert_not_null(d, "%s missing (run make test from the top of the tree)", dir);
	int n = 0;
	for (struct dirent *e; (e = readdir(d));) {
		if (e->d_name[0] == '.' || !strcmp(e->d_name, "README"))
			continue;
		char path[512];
		snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
		FILE *fp = fopen(path, "rb");
		cr_assert_not_null(fp);
		/* whole, as the harness gets it: corpus entries sit past the limits */
		cr_assert_eq(fseek(fp, 0, SEEK_END), 0);
		long size = ftell(fp);
		rewind(fp);
		char *text = malloc((size_t)size + 1);
		cr_assert_not_null(text);
		size_t len = fread(text, 1, (size_t)size, fp);
		fclose(fp);
		text[len] = '\0';
		exercise(text);
		free(text);
		n++;
	}
	closedir(d);
	return n;
}

Test(fuzz, replay_corpus_and_regressions)
{
	cr_assert(replay_dir("tests/fuzz/corpus") >= 9);
	replay_dir("tests/fuzz/regress");
	/* inputs of the kinds the fuzzer found worth keeping: empty, deep, long */
	cr_assert_eq(exercise("(((((((((((((((((((((NoV)))))))))))))))))))))"), 1);
	cr_assert_eq(exercise("NoV/0 + log(-1) + sqrt(-NoL) + pow(0, -1) + rsqrt(0)"), 1);
	cr_assert_eq(exercise("p15*p0 - p15*p0"), 1);
	cr_assert_eq(exercise("\x01\xff"), 0);
}

/* ---- pow, exp and log in half: as the GPU runs them ---------------------------
 * A mediump GPU has no e^x, ln or x^y: it runs exp2(x log2 e), log2(x) ln 2
 * and exp2(y log2 x), each step in half with the constants held in half
 * (the op table's classes say the same). Computed here step by step with the
 * half rounding rule; the inputs are chosen where this differs from the
 * correctly rounded value (and must, for the test to mean anything). */

static double h(double x) { return bk_half_round(x); }

static double eval_at(const char *text, bk_precision p, double NoV, const double *params)
{
	double NoL = 0.5, NoH = 0.5, LoH = 0.5, r = 0.5, a = 0.25, f0 = 0.04, out;
	const double *in[BK_IN_COUNT] = {&NoV, &NoL, &NoH, &LoH, &r, &a, &f0};
	bk_form *f = parse_ok(text);
	cr_assert_eq(bk_form_eval(f, p, 1, in, params, &out), 0);
	bk_form_free(f);
	return out;
}

Test(eval, pow_exp_log_in_half_are_the_gpus_steps)
{
	const double l2e = h(1.4426950408889634), ln2 = h(0.6931471805599453);
	cr_assert_neq(l2e, 1.4426950408889634); /* log2(e) is not a half number */
	int differs = 0;
	for (double x = -9.5; x <= 10; x += 0.75) {
		double hx = h(x), want = h(exp2(h(hx * l2e)));
		double got = eval_at("exp(NoV)", BK_F16, x, NULL);
		cr_assert_eq(got, want, "exp(%g) in half: %a, step by step %a", hx, got, want);
		differs += got != h(exp(hx));
		double lx = fabs(x) + 0.3, hl = h(lx), wl = h(h(log2(hl)) * ln2);
		cr_assert_eq(eval_at("log(NoV)", BK_F16, lx, NULL), wl, "log(%g) in half", hl);
		double y[1] = {2.5}, wp = h(exp2(h(2.5 * h(log2(hl)))));
		cr_assert_eq(eval_at("pow(NoV, p0)", BK_F16, lx, y), wp, "pow(%g, 2.5) in half", hl);
	}
	cr_assert_gt(differs, 3, "exp in half never differs from the correctly rounded value (%d)", differs);
	/* pow is exp2(y log2 x) in every precision, GLSL's definition: a negative
	 * base is NaN (C's pow gives (-2)^2 = 4 and (-2)^3 = -8), 0^0 is NaN (C: 1),
	 * 0 to a positive power 0 and to a negative one NaN too (GLSL: undefined;
	 * C: +inf, and -inf for (-0)^-3) */
	static const bk_precision all[] = {BK_F64, BK_F32, BK_F16, BK_FLD};
	for (int q = 0; q < 4; q++) {
		double two[1] = {2}, three[1] = {3}, zero[1] = {0}, mthree[1] = {-3};
		const char *p = bk_precision_name(all[q]);
		cr_assert(isnan(eval_at("pow(NoV, p0)", all[q], -2, two)), "%s: (-2)^2", p);
		cr_assert(isnan(eval_at("pow(NoV, p0)", all[q], -2, three)), "%s: (-2)^3", p);
		cr_assert(isnan(eval_at("pow(NoV, p0)", all[q], 0, zero)), "%s: 0^0", p);
		cr_assert_eq(eval_at("pow(NoV, p0)", all[q], 0, two), 0.0, "%s: 0^2", p);
		cr_assert(isnan(eval_at("pow(NoV, p0)", all[q], -0.0, mthree)), "%s: (-0)^-3", p);
		cr_assert(isnan(eval_at("pow(NoV, p0)", all[q], 0.0, mthree)), "%s: 0^-3", p);
		cr_assert_eq(eval_at("pow(NoV, p0)", all[q], 1, two), 1.0, "%s: 1^2", p);
		/* x^9 is pow (only |k| <= 8 becomes multiplies): NaN below 0 too */
		cr_assert(isnan(eval_at("(NoV - 1)^9", all[q], 0.5, NULL)), "%s: (-0.5)^9", p);
		cr_assert_eq(eval_at("(NoV - 1)^3", all[q], 0.5, NULL), -0.125, "%s: (-0.5)^3 multiplies", p);
	}
	/* the value: within an ulp or two of libm's exp2(y log2 x), and of the
	 * correctly rounded pow (in double: 2^-50 relative) */
	double y[1] = {2.5};
	double v32 = eval_at("pow(NoV, p0)", BK_F32, 0.7, y), c32 = exp2f(2.5f * log2f(0.7f));
	cr_assert_leq(fabs(v32 - c32), 2 * (nextafterf((float)c32, 1) - (float)c32), "f32 %a against %a", v32, c32);
	double v64 = eval_at("pow(NoV, p0)", BK_F64, 0.7, y);
	cr_assert_leq(fabs(v64 - pow(0.7, 2.5)), 0x1p-50 * pow(0.7, 2.5));
}

/* ---- a form with no value anywhere on its inputs' domain ------------------------- */

static int nowhere(const char *text, const double *params, char *what, size_t len)
{
	bk_form *f = parse_ok(text);
	int rc = bk_form_nowhere_finite(f, params, what, len);
	bk_form_free(f);
	return rc;
}

Test(eval, nowhere_finite_forms_are_found)
{
	char what[96];
	cr_assert_eq(nowhere("NoV/0", NULL, what, sizeof what), 1);
	cr_assert_str_eq(what, "NoV = 0: NaN"); /* 0/0 at the first sample, inf elsewhere */
	cr_assert_eq(nowhere("1/(NoV - NoV)", NULL, what, sizeof what), 1);
	cr_assert_str_eq(what, "NoV = 0: +inf");
	cr_assert_eq(nowhere("sqrt(NoV - 2) + r", NULL, what, sizeof what), 1);
	cr_assert_str_eq(what, "NoV = 0, r = 0: NaN");
	cr_assert_eq(nowhere("log(NoV - NoV)", NULL, what, sizeof what), 1);
	double p[1] = {-1};
	cr_assert_eq(nowhere("sqrt(p0*NoV - 1)", p, what, sizeof what), 1);
	cr_assert_eq(nowhere("sqrt(p0)", p, what, sizeof what), 1);
	cr_assert_str_eq(what, "it reads no input: NaN");
	/* finite somewhere: a pole at one point, a value at one end, r/a = 1/r */
	cr_assert_eq(nowhere("NoV/NoL", NULL, what, sizeof what), 0);
	cr_assert_eq(nowhere("sqrt(NoV - 0.999)", NULL, what, sizeof what), 0);
	cr_assert_eq(nowhere("r/a", NULL, what, sizeof what), 0);
	p[0] = 1;
	cr_assert_eq(nowhere("sqrt(p0*NoV - 1)", p, what, sizeof what), 0);
	cr_assert_eq(nowhere("sqrt(p0*NoV - 1)", NULL, what, sizeof what), -1); /* parameters needed */
}

/* ---- a result the emitted precision cannot hold anywhere (M3) ------------------- */

static int lost(const char *text, bk_precision prec, char *what, size_t len)
{
	bk_form *f = parse_ok(text);
	int rc = bk_form_range_lost(f, NULL, prec, what, len);
	bk_form_free(f);
	return rc;
}

Test(eval, range_lost_everywhere_is_found)
{
	char what[128];
	/* the audit's two: finite in double, +inf in the emitted precision at every sample */
	cr_assert_eq(lost("(NoV+1e38)*(NoV+1e38)", BK_F32, what, sizeof what), 5);
	cr_assert_str_eq(what, "NoV = 0: 1e+76 is +inf in single precision");
	cr_assert_eq(lost("(NoV+300)*(NoV+300)", BK_F16, what, sizeof what), 5);
	cr_assert_str_eq(what, "NoV = 0: 90000 is +inf in half precision");
	/* underflow: not 0 in double, subnormal (0 where GPUs flush) or 0 */
	cr_assert_eq(lost("((NoV+1)*1e-20)*((NoV+1)*1e-20)", BK_F32, what, sizeof what), 5);
	cr_assert_str_eq(what, "NoV = 0: 1e-40 is subnormal in single precision");
	cr_assert_eq(lost("((NoV+1)*1e-30)*((NoV+1)*1e-30)", BK_F32, what, sizeof what), 5);
	cr_assert_str_eq(what, "NoV = 0: 1e-60 is 0 in single precision");
	/* a sample where double is 0 and the precision too does not count; one
	 * where double has no value (0/0) neither */
	cr_assert_eq(lost("(NoV*1e30)*(NoV*1e30)", BK_F32, what, sizeof what), 4);
	cr_assert_eq(lost("(NoV*1e30)*(NoV*1e30)/NoV", BK_F32, what, sizeof what), 4);
	/* negative controls: held at some sample (overflow at NoV = 1 only; in
	 * single precision's range; 0 everywhere, exactly) */
	cr_assert_eq(lost("(NoV*300)*(NoV*300)", BK_F16, what, sizeof what), 0);
	cr_assert_eq(lost("(NoV+300)*(NoV+300)", BK_F32, what, sizeof what), 0);
	cr_assert_eq(lost("(NoV+1e19)*(NoV+1e19)", BK_F32, what, sizeof what), 0);
	cr_assert_eq(lost("NoV*0", BK_F16, what, sizeof what), 0);
	cr_assert_eq(lost("NoV", BK_F64, what, sizeof what), -1); /* only the precisions code is emitted in */
}

/* bk_form_count_add sums the counts of pieces counted one by one: sqrt(NoV)
 * is one sqrt (complex), r*p0 + p1 one mad (simple); the sum is both, and a
 * text that does not parse adds nothing and says so. */
Test(ir, count_add_sums_pieces)
{
	bk_ops o;
	memset(&o, 0, sizeof o);
	cr_assert_eq(bk_form_count_add("sqrt(NoV)", &o), 0);
	cr_assert_eq(bk_form_count_add("r*p0 + p1", &o), 0);
	cr_assert_eq(o.n[BK_K_SQRT], 1);
	cr_assert_eq(o.n[BK_K_MAD], 1);
	cr_assert_eq(o.simple, 1);
	cr_assert_eq(o.complex, 1);
	bk_ops before = o;
	cr_assert_eq(bk_form_count_add("r*(", &o), -1);
	cr_assert(memcmp(&before, &o, sizeof o) == 0);
}
