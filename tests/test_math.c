/*
 * test_math.c — a form as LaTeX, SymPy and MathML (brdf/ir_math.c): known
 * forms give the text worked out by hand from brdf/ir_ops.h's meanings, with
 * parentheses where precedence needs them and nowhere else, and each check
 * has a control (another constant, another operation) that changes the text.
 * tests/cli_formula.sh evaluates the SymPy text against brdfkit eval.
 */
#include "brdf_math.h"

#include <criterion/criterion.h>
#include <stdlib.h>
#include <string.h>

static char *math(const char *text, bk_math_lang lang, const double *p, int digits)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	cr_assert_not_null(f, "%s", text);
	char *s = bk_form_math(f, lang, p, digits);
	bk_form_free(f);
	cr_assert_not_null(s);
	return s;
}

static void expect(const char *text, bk_math_lang lang, const double *p, int digits, const char *want)
{
	char *s = math(text, lang, p, digits);
	cr_expect_str_eq(s, want, "%s", text);
	free(s);
}

/* f0/(LoH*LoH*(r + p0)) at p0 = 0.5: a fraction over a product whose last
 * factor is a sum (parenthesised), LoH*LoH (one register, shared) as LoH
 * squared, f0 as f with subscript 0, LoH one word. */
Test(math, mathml_of_a_known_form)
{
	double p[] = {0.5};
	expect("f0/(LoH*LoH*(r + p0))", BK_MATH_MATHML, p, 4,
	       "<math><mrow><mfrac><mrow><msub><mi>f</mi><mn>0</mn></msub></mrow><mrow><mrow><msup><mi>LoH</mi>"
	       "<mn>2</mn></msup><mo>&#x22C5;</mo><mrow><mo>(</mo><mrow><mi>r</mi><mo>+</mo><mn>0.5</mn></mrow>"
	       "<mo>)</mo></mrow></mrow></mrow></mfrac></mrow></math>");
	/* control: another constant is another text */
	double q[] = {0.25};
	char *s = math("f0/(LoH*LoH*(r + p0))", BK_MATH_MATHML, q, 4);
	cr_expect(strstr(s, "<mn>0.25</mn>") && !strstr(s, "<mn>0.5</mn>"));
	free(s);
}

/* Only MathML Core elements (and no attribute, so no text of a file can
 * reach one) over every operation. */
Test(math, mathml_core_elements_only)
{
	double p[] = {0.1, 2};
	char *s = math("rsqrt(NoV + p0) - rcp(LoH)*sqrt(r) + log(1 + abs(-NoV*p1)) + clamp(NoV, p0, 0.8) + "
	               "exp(-r)*pow(f0, 0.5) + mix(a, NoL, NoH) + log2(1 + r) + exp2(-r) + saturate(1 - NoV) + "
	               "min(r, max(a, 1e-5)) + 1e9*r",
	               BK_MATH_MATHML, p, 4);
	static const char *const core[] = {"math", "mrow", "mi", "mn", "mo", "mfrac", "msup", "msub", "msqrt"};
	int n = 0;
	for (const char *t = strchr(s, '<'); t; t = strchr(t + 1, '<')) {
		const char *name = t[1] == '/' ? t + 2 : t + 1;
		size_t len = strcspn(name, ">");
		int known = 0;
		for (size_t k = 0; k < sizeof core / sizeof core[0]; k++)
			known |= strlen(core[k]) == len && !strncmp(core[k], name, len);
		cr_expect(known, "element '%.*s' is not MathML Core", (int)len, name);
		n++;
	}
	cr_expect_gt(n, 100);
	cr_expect(strstr(s, "<msqrt>") && strstr(s, "<msup>") && strstr(s, "<mi>clamp</mi>"));
	cr_expect(strstr(s, "<mn>1</mn><mo>&#xD7;</mo><msup><mn>10</mn><mrow><mn>9</mn></mrow></msup>"),
	          "1e9 as 1 x 10^9: %s", s);
	free(s);
}

/* LaTeX: precedence. a - (b - c) keeps its parentheses, (a - b) - c needs
 * none; a power's base is wrapped unless an atom; x + (-0.5) is x - 0.5;
 * a number leads a product. Controls: the other association. */
Test(math, latex_precedence)
{
	expect("NoV - (r - LoH)", BK_MATH_LATEX, NULL, 0, "\\mathrm{NoV} - \\left(r - \\mathrm{LoH}\\right)");
	expect("(NoV - r) - LoH", BK_MATH_LATEX, NULL, 0, "\\mathrm{NoV} - r - \\mathrm{LoH}");
	expect("pow(1 - NoV, p0)", BK_MATH_LATEX, NULL, 0, "\\left(1 - \\mathrm{NoV}\\right)^{p_{0}}");
	double p[] = {-0.5, 3};
	expect("NoV + p0", BK_MATH_LATEX, p, 0, "\\mathrm{NoV} - 0.5");
	expect("r*p1", BK_MATH_LATEX, p, 0, "3 \\cdot r");
	/* a product's factors flattened, numbers first, a repeated one a power */
	expect("LoH*(4*LoH)*r", BK_MATH_LATEX, NULL, 0, "4 \\cdot \\mathrm{LoH}^{2} \\cdot r");
	expect("LoH*(4*LoH)*r", BK_MATH_SYMPY, NULL, 0, "4*LoH**2*r");
	expect("sqrt(r)/exp2(-NoV)", BK_MATH_LATEX, NULL, 0, "\\frac{\\sqrt{r}}{2^{-\\mathrm{NoV}}}");
}

/* SymPy: the meanings written out (mix as x + (y - x) t, saturate and clamp
 * as Min/Max, log2 as log(x, 2)), parameters symbolic. */
Test(math, sympy_meanings)
{
	expect("mix(NoV, r, a)", BK_MATH_SYMPY, NULL, 0, "NoV + (r - NoV)*a");
	expect("saturate(r - p0)", BK_MATH_SYMPY, NULL, 0, "sp.Min(sp.Max(r - p0, 0), 1)");
	expect("clamp(NoV, p0, p1)", BK_MATH_SYMPY, NULL, 0, "sp.Min(sp.Max(NoV, p0), p1)");
	expect("log2(r)/(NoV*LoH)", BK_MATH_SYMPY, NULL, 0, "sp.log(r, 2) / (NoV*LoH)");
	/* control: division by a product keeps its parentheses, by a power none */
	expect("log2(r)/pow(NoV, p0)", BK_MATH_SYMPY, NULL, 0, "sp.log(r, 2) / NoV**p0");
}
