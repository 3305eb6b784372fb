/*
 * cmd_ir.c — the formula IR on the command line: brdfkit eval, ops, codegen and
 * catalog. A FORM argument is formula text, a catalog entry's name (an
 * environment entry's two forms are NAME:A and NAME:B), or a member of a
 * front.csv of brdfkit search as FILE.csv:NAME (FILE.csv:NAME:A, :B): the
 * file part ends at the last ".csv:", which no form contains (forms have no
 * ':').
 */
#include "brdf.h"
#include "brdf_math.h"
#include "catalog.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"
#include "form_check.h"
#include "member.h"
#include "msl.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A parsed FORM argument with the parameter values that go with it. */
typedef struct form_arg {
	bk_form *f;
	const bk_catalog_entry *entry; /* NULL for typed text */
	int named;                     /* a catalog entry or a front member: params baked in */
	int member;                    /* a front member: its parameters numbered across A and B */
	double params[BK_MAX_PARAMS];
	int have[BK_MAX_PARAMS];
	char label[160];
	char fname[BK_NAME_MAX + 1];   /* codegen's default function name; "" for none */
	char source[600], domain[600], error[160]; /* a front member's provenance */
	unsigned signature;            /* a front member: its front's one signature (member.h) */
} form_arg;

/* FILE.csv:NAME: the member's form (or form_b for :B), its parameters
 * baked in like a catalog entry's constants, and its provenance
 * (member.h), its form into fa->f (parsed as the file was read). */
static int load_member(const char *arg, form_arg *fa)
{
	cli_member m;
	int rc = cli_member_load(arg, 0, &m);
	if (rc)
		return rc;
	fa->named = fa->member = 1;
	for (int i = 0; i < m.np; i++) {
		fa->params[i] = m.p[i];
		fa->have[i] = 1;
	}
	snprintf(fa->label, sizeof fa->label, "%s%s", arg, "");
	snprintf(fa->fname, sizeof fa->fname, "%s", m.fname);
	snprintf(fa->source, sizeof fa->source, "%s", m.source);
	snprintf(fa->domain, sizeof fa->domain, "%s", m.domain);
	snprintf(fa->error, sizeof fa->error, "%s", m.errtext);
	fa->signature = m.signature;
	fa->f = m.f;
	m.f = NULL;
	cli_member_free(&m);
	return 0;
}

static int load_form(const char *cmd, const char *arg, form_arg *fa)
{
	memset(fa, 0, sizeof *fa);
	char name[128];
	const char *colon = cli_member_split(arg);
	if (colon)
		return load_member(arg, fa);
	colon = strchr(arg, ':');
	size_t len = colon ? (size_t)(colon - arg) : strlen(arg);
	const char *text = arg;
	if (len < sizeof name) {
		memcpy(name, arg, len);
		name[len] = '\0';
		fa->entry = bk_catalog_find(name);
	}
	if (fa->entry) {
		const bk_catalog_entry *e = fa->entry;
		int want_b = colon && (strcmp(colon + 1, "B") == 0 || strcmp(colon + 1, "b") == 0);
		if (e->form_b && !colon) {
			return cli_bad("'%s' has two forms (split sum): write %s:A or %s:B", name, name, name);
		}
		if (colon && (!e->form_b || (!want_b && strcmp(colon + 1, "A") && strcmp(colon + 1, "a")))) {
			return cli_bad("'%s': unknown part '%s'", name, colon + 1);
		}
		text = want_b ? e->form_b : e->form;
		for (int i = 0; i < e->nparams; i++) {
			fa->params[i] = e->defaults[i];
			fa->have[i] = 1;
		}
		snprintf(fa->label, sizeof fa->label, "%s%s", arg, "");
		fa->named = 1;
		if (strlen(arg) < sizeof fa->fname) {
			snprintf(fa->fname, sizeof fa->fname, "%s", arg);
			for (char *c = fa->fname; *c; c++)
				if (*c == ':')
					*c = '_';
		}
	} else {
		snprintf(fa->label, sizeof fa->label, "user form");
	}
	bk_form_error err;
	fa->f = bk_form_parse(text, &err);
	if (!fa->f) {
		fprintf(stderr, "brdfkit %s: %s:1:%d: %s\n", cmd, fa->entry ? name : "form", err.column, err.message);
		return 2;
	}
	return 0;
}

/* NAME=VALUE with a strict finite number. */
static int assignment(const char *arg, char *name, size_t nlen, double *v)
{
	const char *eq = strchr(arg, '=');
	if (!eq || eq == arg || (size_t)(eq - arg) >= nlen) {
		return cli_bad("expected NAME=VALUE, got '%s'", arg);
	}
	memcpy(name, arg, (size_t)(eq - arg));
	name[eq - arg] = '\0';
	if (cli_number(eq + 1, v)) {
		return cli_bad("%s: expected a finite number, got '%s'", name, eq + 1);
	}
	return 0;
}

/* p0..p15 from NAME=VALUE arguments; other names go to inputs (if not NULL).
 * Every parameter the form uses needs a value, and every pN= given must be
 * one it uses (form_check_params). */
static int bind(const char *cmd, char **pos, int npos, form_arg *fa, double *inputs, int *given)
{
	int given_p[BK_MAX_PARAMS] = {0};
	for (int i = 0; i < npos; i++) {
		char name[32];
		double v;
		int k, rc = form_param_set(NULL, pos[i], fa->params, given_p, &k); /* pN=VALUE: every command's one reader */
		if (rc == 2)
			return 2;
		if (rc == 1) {
			fa->have[k] = 1;
			continue;
		}
		if (assignment(pos[i], name, sizeof name, &v))
			return 2;
		for (int j = 0; j < i; j++) /* a second value would silently replace the first */
			if (strncmp(pos[j], name, strlen(name)) == 0 && pos[j][strlen(name)] == '=') {
				return cli_bad("%s given twice", name);
			}
		int found = 0;
		for (int k = 0; inputs && k < BK_IN_COUNT; k++)
			if (strcmp(name, bk_input_name((bk_input)k)) == 0 ||
			    (k == BK_IN_LOH && strcmp(name, "VoH") == 0)) {
				/* VoH = LoH for the half vector: both may be given, with one value */
				if (given[k] && inputs[k] != v) {
					return cli_bad("%s and %s differ: for the half vector VoH and LoH are the same cosine",
					               pos[given[k] - 1], pos[i]);
				}
				inputs[k] = v;
				given[k] = i + 1; /* which argument, for the message above */
				found = 1;
			}
		if (!found) {
			return cli_bad("unknown name '%s' (%s)", name,
			               inputs ? "inputs NoV NoL NoH LoH VoH r a f0, parameters p0..p15" : "parameters p0..p15");
		}
	}
	/* A split member's B may use p2..p4 of the pair's p0..p4, each with its
	 * value: the numbering is the member's, not the one form's. */
	unsigned used = bk_form_params(fa->f);
	for (int k = 0; fa->member && k < BK_MAX_PARAMS; k++)
		used |= (unsigned)fa->have[k] << k;
	return form_check_params(cmd, fa->named ? fa->label : "the form", used, fa->have, given_p);
}

/* Significant digits that read back as x: 0.1, not 0.10000000000000001. */
static int shortest(double x)
{
	char buf[32];
	for (int d = 1; d < 17; d++) {
		snprintf(buf, sizeof buf, "%.*g", d, x);
		if (strtod(buf, NULL) == x)
			return d;
	}
	return 17;
}

/* An input given that the form does not read would change nothing: refused
 * like an unused pN=, naming the argument. r acts through a = r*r where the
 * form reads a and a is not given. given[k]: 1 + the index of its argument. */
static int check_inputs(const bk_form *f, const char *name, char **args, const int *given)
{
	unsigned reads = bk_form_inputs(f);
	for (int k = 0; k < BK_IN_COUNT; k++) {
		int via_a = k == BK_IN_R && (reads >> BK_IN_A & 1) && !given[BK_IN_A];
		if (given[k] && !(reads >> k & 1) && !via_a) {
			const char *arg = args[given[k] - 1], *eq = strchr(arg, '=');
			return cli_bad("%.*s=VALUE has no effect: %s does not read %.*s", (int)(eq - arg), arg, name,
			               (int)(eq - arg), arg); /* VoH, not LoH, when VoH= was given */
		}
	}
	return 0;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* eval and catalog have no options: their tables are empty, so that the walk
 * sees them (an option added later without a rule is an internal error). */
static const char *const eval_setups[] = {"NoV NoV=0.5", NULL};
static const cli_table eval_table = {NULL, 0, NULL, 0, eval_setups};

int cmd_eval(int argc, char **argv)
{
	cli_cmd cmd = {"eval", "Evaluates a form at one point in double, single and half precision (half:\n"
	               "IEEE binary16 with rounding after every operation, as a mediump GPU).",
	               "'FORM'|NAME|FILE.csv:MEMBER [NoV=X NoL=X NoH=X LoH=X r=X a=X f0=X p0=X ...]",
	               "a defaults to r*r when r is given. Prints three lines: f64 VALUE, f32 VALUE, f16 VALUE.\n"
	               "FILE.csv:MEMBER is a member of a front.csv of brdfkit search, its parameters baked in\n"
	               "(MEMBER:A or MEMBER:B of a split sum); the file part ends at the last \".csv:\".",
	               NULL, 0, 33, 0, {0}};
	int rc = cli_parse_table(&cmd, &eval_table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	if (cli_form_positionals(&cmd, 0))
		return 2;
	if (cmd.npos < 1) {
		fprintf(stderr, "brdfkit eval: missing FORM (see brdfkit eval --help)\n");
		return 2;
	}
	form_arg fa;
	if ((rc = load_form("eval", cmd.pos[0], &fa)))
		return rc;
	double in[BK_IN_COUNT] = {0};
	int given[BK_IN_COUNT] = {0};
	if ((rc = bind("eval", cmd.pos + 1, cmd.npos - 1, &fa, in, given))) {
		bk_form_free(fa.f);
		return rc;
	}
	if ((rc = check_inputs(fa.f, fa.named ? fa.label : "the form", cmd.pos + 1, given))) {
		bk_form_free(fa.f);
		return rc;
	}
	if (given[BK_IN_R] && !given[BK_IN_A]) {
		in[BK_IN_A] = in[BK_IN_R] * in[BK_IN_R];
		given[BK_IN_A] = 1;
	}
	const double *ptr[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++) {
		ptr[k] = &in[k];
		if ((bk_form_inputs(fa.f) >> k & 1) && !given[k]) {
			bk_form_free(fa.f);
			return cli_bad("missing %s=VALUE (the form reads it)", bk_input_name((bk_input)k));
		}
	}
	/* digits that round-trip each precision: 17, 9 and 5 significant */
	static const char *const fmt[3] = {"%s %.17g\n", "%s %.9g\n", "%s %.5g\n"};
	double v[3];
	for (int p = BK_F64; p <= BK_F16; p++)
		bk_form_eval(fa.f, (bk_precision)p, 1, ptr, fa.params, &v[p]);
	/* The value is the product: a NaN or an infinity (a pole) is no answer to
	 * print. Single and half are shown as they come, overflow included: how
	 * they differ from double is what they are printed for. */
	if (!isfinite(v[BK_F64])) {
		char at[256] = "";
		size_t k = 0;
		for (int i = 0; i < BK_IN_COUNT && k < sizeof at; i++)
			if (bk_form_inputs(fa.f) >> i & 1)
				k += (size_t)snprintf(at + k, sizeof at - k, "%s %s=%.*g", k ? "" : " at",
				                      bk_input_name((bk_input)i), shortest(in[i]), in[i]);
		bk_form_free(fa.f);
		return cli_fail("eval", "value not finite%s: f64 %s", at,
		                isnan(v[BK_F64]) ? "nan" : v[BK_F64] > 0 ? "inf" : "-inf");
	}
	for (int p = BK_F64; p <= BK_F16; p++)
		printf(fmt[p], bk_precision_name((bk_precision)p), v[p]);
	bk_form_free(fa.f);
	return 0;
}

/* ops: the weights come from --simple-cost/--complex-cost or from a named
 * --cost-model, which sets both. */
enum { WEIGHTS_OPTIONS, WEIGHTS_MODEL };
static const cli_dim ops_dims[] = {
	{"weights", {"options", "model"}, {" without --cost-model", " with --cost-model"}},
};
static const cli_rule ops_rules[] = {
	{"--simple-cost", NULL, 0, 1u << WEIGHTS_OPTIONS, "it sets both weights", "2"},
	{"--complex-cost", NULL, 0, 1u << WEIGHTS_OPTIONS, "it sets both weights", "2"},
	{"--csv", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--cost-model", NULL, CLI_EVERYWHERE, 0, NULL, "ir"},
};
static const char *const ops_setups[] = {"NoV", "NoV --cost-model aco-navi21", NULL};
static const cli_table ops_table = {ops_dims, 1, ops_rules, sizeof ops_rules / sizeof ops_rules[0], ops_setups};

int cmd_ops(int argc, char **argv)
{
	int csv = 0;
	double cs = BK_COST_SIMPLE, cc = BK_COST_COMPLEX;
	const char *model = NULL;
	cli_opt opts[] = {
		{.name = "--csv", .kind = CLI_FLAG, .help = "rows class,count (with simple, complex, cost)", .dest = &csv},
		{.name = "--simple-cost", .kind = CLI_NUM, .metavar = "C", .help = "cost of a simple op (default 1)", .dest = &cs, .lo = 0, .hi = 1e6},
		{.name = "--complex-cost", .kind = CLI_NUM, .metavar = "C", .help = "cost of a complex op (default 4)", .dest = &cc, .lo = 0, .hi = 1e6},
		{.name = "--cost-model", .kind = CLI_STR, .metavar = "NAME", .help = "named weights: ir (1, 4; the default) or aco-CHIP (fitted to AMD instruction counts)", .dest = &model},
	};
	cli_cmd cmd = {"ops", "Counts a form's operations per class after constant folding, sharing of common\n"
	               "subexpressions, small integer powers to multiplies and a*b+c to one multiply-add.",
	               "'FORM'|NAME|FILE.csv:MEMBER [--csv] [--simple-cost C] [--complex-cost C] [--cost-model NAME]",
	               "Complex ops (transcendental unit): rcp div sqrt rsqrt exp2 log2; pow = log2+mul+exp2,\n"
	               "exp = mul+exp2, log = log2+mul; negation and abs are free source modifiers.\n"
	               "cost = simple * simple-cost + complex * complex-cost (the talk: many simple ops per\n"
	               "cycle, only one complex). --cost-model takes both weights from a named model:\n"
	               "ir, or aco-polaris10, aco-vega10, aco-navi21, aco-gfx1100 (least squares of AMD's\n"
	               "ACO instruction counts over the catalog, brdfkit gpucost --calibrate).\n"
	               "FILE.csv:MEMBER is a member of a front.csv of brdfkit search (MEMBER:A or MEMBER:B\n"
	               "of a split sum); the file part ends at the last \".csv:\".",
	               opts, 4, 1, 0, {0}};
	int rc = cli_parse_table(&cmd, &ops_table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, (int[]){model ? WEIGHTS_MODEL : WEIGHTS_OPTIONS})))
		return rc == 1 ? 0 : rc;
	if (model && cli_cost_model(&cmd, model, &cs, &cc))
		return 2;
	if (cli_form_positionals(&cmd, 0))
		return 2;
	if (cmd.npos != 1) {
		fprintf(stderr, "brdfkit ops: missing FORM (see brdfkit ops --help)\n");
		return 2;
	}
	form_arg fa;
	if ((rc = load_form("ops", cmd.pos[0], &fa)))
		return rc;
	/* no pN= here: a typed form's parameters are unknown, only its constants are checked */
	if ((rc = form_check_finite("ops", fa.named ? fa.label : "form", fa.f, fa.named ? fa.params : NULL))) {
		bk_form_free(fa.f);
		return rc;
	}
	bk_ops o;
	bk_form_count(fa.f, &o);
	bk_form_free(fa.f);
	double cost = bk_ops_cost(&o, cs, cc);
	if (csv)
		puts("class,count");
	for (int k = 1; k < BK_K_COUNT; k++)
		printf(csv ? "%s,%d\n" : "%-10s %d\n", bk_opclass_name((bk_opclass)k), o.n[k]);
	if (csv)
		printf("simple,%d\ncomplex,%d\ncost,%g\n", o.simple, o.complex, cost);
	else
		printf("%-10s %d\n%-10s %d\n%-10s %g   (simple x %g + complex x %g)\n", "simple", o.simple,
		       "complex", o.complex, "cost", cost, cs, cc);
	return 0;
}

/* The command line as a shell would need it back: arguments with anything
 * but [A-Za-z0-9_./=:,+-] in single quotes, so provenance can be pasted. */
static void shell_words(char *buf, size_t len, const char *head, int argc, char **argv)
{
	size_t k = (size_t)snprintf(buf, len, "%s", head);
	for (int i = 0; i < argc && k < len; i++) {
		const char *a = argv[i];
		int plain = *a != '\0' && strspn(a, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./=:,+-") == strlen(a);
		if (plain) {
			k += (size_t)snprintf(buf + k, len - k, " %s", a);
			continue;
		}
		k += (size_t)snprintf(buf + k, len - k, " '");
		for (; *a && k < len; a++)
			k += (size_t)(*a == '\'' ? snprintf(buf + k, len - k, "'\\''") : snprintf(buf + k, len - k, "%c", *a));
		if (k < len)
			k += (size_t)snprintf(buf + k, len - k, "'");
	}
}

/* C, GLSL and HLSL identifiers: [A-Za-z_][A-Za-z0-9_]*. */
/* codegen: --precision picks GLSL's qualifier or HLSL's and MSL's type; the
 * C output is float whatever it says. Index CODEGEN_MSL of the language
 * dimension is Metal, which is no bk_lang: SPIRV-Cross writes it
 * (analysis/msl.c). */
enum { CODEGEN_MSL = BK_LANG_HLSL + 1 };
static const cli_dim codegen_dims[] = {
	{"lang", {"c", "glsl", "hlsl", "msl", "latex", "sympy"},
	 {" with --lang c", " with --lang glsl", " with --lang hlsl", " with --lang msl", " with --lang latex",
	  " with --lang sympy"}},
};
static const cli_rule codegen_rules[] = {
	{"--precision", NULL, 0, 1u << BK_LANG_GLSL | 1u << BK_LANG_HLSL | 1u << CODEGEN_MSL,
	 "it picks a shader's float type: C is float only, LaTeX and SymPy have none", "half"},
	{"--lang", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--name", NULL, CLI_EVERYWHERE, 0, NULL, "f"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, "o.glsl"},
};
static const char *const codegen_setups[] = {"--lang c NoV",     "--lang glsl NoV",  "--lang hlsl NoV",
                                             "--lang msl NoV",   "--lang latex NoV", "--lang sympy NoV", NULL};
static const cli_table codegen_table = {codegen_dims, 1, codegen_rules,
                                        sizeof codegen_rules / sizeof codegen_rules[0], codegen_setups};

static int write_code(char *text, const char *out);

/* FILE.csv:NAME of a split-sum pair without a part: NAME_A, NAME_B and NAME
 * returning both as engines call it (bk_form_emit_pair), in the front's one
 * signature with named constants. -1 when the member is one form (the
 * one-form path takes it), else the exit status (a bad member: 2 after the
 * reader's line). */
static int codegen_pair(const cli_cmd *cmd, bk_lang L, int half, int li, bk_math_lang ml, const char *fname,
                        const char *out, const char *command)
{
	int math = li > CODEGEN_MSL;
	cli_member m;
	int rc = cli_member_load(cmd->pos[0], 1, &m);
	if (rc)
		return rc;
	if (!m.form_b) {
		cli_member_free(&m);
		return -1;
	}
	bk_form *f[2] = {m.f, m.f_b}; /* parsed as the file was read */
	m.f = m.f_b = NULL;
	if (cmd->npos > 1)
		rc = cli_bad("'%s': a member's parameters are baked in ('%s'): give MEMBER:A or MEMBER:B to change one",
		             cmd->pos[0], cmd->pos[1]);
	else if (li == CODEGEN_MSL) /* bk_msl_emit translates one function */
		rc = cli_bad("'%s' is a split-sum pair: give %s:A or %s:B for Metal", cmd->pos[0], cmd->pos[0], cmd->pos[0]);
	else if (math && ml == BK_MATH_SYMPY) /* one snippet binds one expr */
		rc = cli_bad("'%s' is a split-sum pair: give %s:A or %s:B for a SymPy snippet", cmd->pos[0], cmd->pos[0],
		             cmd->pos[0]);
	else if (!f[0] || !f[1])
		rc = cli_fail("codegen", "out of memory"); /* the reader parsed both */
	for (int k = 0; k < 2 && !rc; k++)
		rc = form_check_finite("codegen", cmd->pos[0], f[k], m.p);
	for (int k = 0; k < 2 && !rc && !math; k++) /* as one form: a formula has no precision */
		form_warn_precision("codegen", cmd->pos[0], f[k], m.p, half ? BK_F16 : BK_F32);
	if (!fname && m.fname[0] && bk_identifier(m.fname) && !bk_lang_reserved(L, m.fname))
		fname = m.fname;
	bk_emit_info info = {
		.name = fname,
		.source = m.source,
		.conventions = "r perceptual roughness, a = r^2; split sum: f0 A + B = integral of D V F NoL",
		.domain = m.domain,
		.error = m.errtext,
		.command = command,
	};
	bk_emit_style style = {m.signature, 1};
	char *text = NULL;
	if (!rc && math) { /* a formula each: NAME_A and NAME_B, as the code names them */
		char name[2][BK_NAME_MAX + 3];
		char *doc[2] = {NULL, NULL};
		for (int k = 0; k < 2; k++) {
			bk_emit_info part = info;
			snprintf(name[k], sizeof name[k], "%s_%c", fname ? fname : "brdfkit_form", "AB"[k]);
			part.name = name[k];
			doc[k] = bk_form_math_doc(f[k], ml, m.p, &part);
		}
		size_t n0 = doc[0] ? strlen(doc[0]) : 0, n1 = doc[1] ? strlen(doc[1]) : 0;
		if (doc[0] && doc[1] && (text = malloc(n0 + n1 + 2)))
			snprintf(text, n0 + n1 + 2, "%s\n%s", doc[0], doc[1]);
		free(doc[0]);
		free(doc[1]);
	} else if (!rc) {
		text = bk_form_emit_pair(f[0], f[1], L, half, m.p, &info, &style);
	}
	bk_form_free(f[0]);
	bk_form_free(f[1]);
	cli_member_free(&m);
	return rc ? rc : write_code(text, out);
}

int cmd_codegen(int argc, char **argv)
{
	char command_line[2048];
	const char *lang = NULL, *precision = "single", *fname = NULL, *out = NULL;
	cli_opt opts[] = {
		{.name = "--lang", .kind = CLI_STR, .metavar = "c|glsl|hlsl|msl|latex|sympy", .help = "target language (msl: Metal, by SPIRV-Cross from the GLSL's SPIR-V; latex: an equation; sympy: a Python snippet)", .dest = &lang, .required = 1},
		{.name = "--precision", .kind = CLI_STR, .metavar = "single|half|float16", .help = "single: GLSL highp / HLSL float / MSL float (default); half: GLSL mediump / HLSL min16float / MSL half; float16: GLSL float16_t / HLSL half (dxc -enable-16bit-types) / MSL half; half and float16 write constants as binary16 values; not with --lang c (C output is float)", .dest = &precision},
		{.name = "--name", .kind = CLI_STR, .metavar = "IDENT", .help = "function name (default: the catalog or member name, or brdfkit_form)", .dest = &fname},
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE", .help = "write there (atomically) instead of stdout", .dest = &out},
	};
	cli_cmd cmd = {"codegen", "Generates one function evaluating a form, parameters baked in as constants,\n"
	               "with a provenance comment (form, source, conventions, op counts).",
	               "--lang c|glsl|hlsl|msl|latex|sympy [--precision single|half|float16] 'FORM'|NAME|FILE.csv:MEMBER [p0=X ...]",
	               "Catalog entries use their published constants unless p0=... overrides them.\n"
	               "FILE.csv:MEMBER is a member of a front.csv of brdfkit search (MEMBER:A or MEMBER:B of\n"
	               "a split sum; the file part ends at the last \".csv:\"): its parameters are baked in\n"
	               "the same way, and the comment's source, fitted domain and fitted error come from the\n"
	               "file (its target line, the member's error with the objective and precision stated).\n"
	               "Every member of a front is written with one signature (the inputs its members read, r\n"
	               "for a: a = r*r computed first) and its constants named NAME_p0, ...; a split-sum member\n"
	               "without a part as NAME_A, NAME_B and NAME(NoV, r) returning both (vec2, float2; C: two\n"
	               "pointers), as engines call an environment BRDF.\n"
	               "One rule on the values (each input sampled at 0, 1e-3, 0.3, 0.7, 1): a form NaN or\n"
	               "infinite at every sample in double is refused (exit 2); one whose result the emitted\n"
	               "precision (single: C float, highp, HLSL float; half, float16: fp16) cannot hold at any\n"
	               "sample where it has a value (+inf, NaN, or not 0 but 0 or subnormal) is warned about\n"
	               "on stderr (exit 0), as is a constant the precision cannot hold.\n"
	               "latex writes an equation (the constants as the shaders hold them); sympy a Python\n"
	               "snippet defining the symbols, params (exact values), expr and fitted = expr.subs(params),\n"
	               "with brdfkit's meanings (pow is x**y for x > 0, mix(x, y, t) = x + (y - x)*t).",
	               opts, 4, 33, 0, {0}};
	int rc = cli_parse_table(&cmd, &codegen_table, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	static const char *const langs[] = {"c", "glsl", "hlsl", "msl", "latex", "sympy"};
	/* Metal's names are checked as GLSL's (its function is the GLSL's,
	 * translated) and Metal's own; LaTeX's and SymPy's as C's */
	static const bk_lang lang_of[] = {BK_LANG_C, BK_LANG_GLSL, BK_LANG_HLSL, BK_LANG_GLSL, BK_LANG_C, BK_LANG_C};
	int li = cli_choice("--lang", lang, langs, 6);
	if (li < 0)
		return 2;
	bk_lang L = lang_of[li];
	int math = li >= CODEGEN_MSL + 1; /* latex, sympy: brdf_math.h */
	bk_math_lang ml = li == CODEGEN_MSL + 1 ? BK_MATH_LATEX : BK_MATH_SYMPY;
	if ((rc = cli_applicable(&cmd, (int[]){li})))
		return rc;
	cli_prec prec = CLI_PREC_HALF;
	int half = BK_EMIT_F16; /* float16: explicit 16-bit types */
	if (strcmp(precision, "float16") &&
	    (rc = cli_precision(precision, CLI_PREC_BIT(CLI_PREC_SINGLE) | CLI_PREC_BIT(CLI_PREC_HALF), &prec)))
		return rc;
	if (strcmp(precision, "float16"))
		half = prec == CLI_PREC_HALF ? BK_EMIT_RELAXED : BK_EMIT_SINGLE;
	if (cmd.npos < 1) {
		fprintf(stderr, "brdfkit codegen: missing FORM (see brdfkit codegen --help)\n");
		return 2;
	}
	if (fname && !bk_identifier(fname)) {
		return cli_bad("--name: not an identifier: '%s'", fname);
	}
	if (fname && strlen(fname) > BK_NAME_MAX) {
		return cli_bad("--name: %zu characters, more than %d (C11 keeps %d significant in an internal name)",
		               strlen(fname), BK_NAME_MAX, BK_NAME_MAX);
	}
	if (fname && (bk_lang_reserved(L, fname) || (li == CODEGEN_MSL && bk_msl_reserved(fname)))) {
		return cli_bad("--name: '%s' is reserved in %s (a keyword, type, standard library function or macro, entry "
		               "point, reserved prefix, or a name the body uses)", fname, lang);
	}
	if (cli_form_positionals(&cmd, 0))
		return 2;
	shell_words(command_line, sizeof command_line, "brdfkit codegen", argc, argv);
	if (cli_member_split(cmd.pos[0]) && (rc = codegen_pair(&cmd, L, half, li, ml, fname, out,
	                                                             command_line)) != -1)
		return rc;
	form_arg fa;
	if ((rc = load_form("codegen", cmd.pos[0], &fa)))
		return rc;
	if ((rc = bind("codegen", cmd.pos + 1, cmd.npos - 1, &fa, NULL, NULL))) {
		bk_form_free(fa.f);
		return rc;
	}
	if (!fname && fa.fname[0] && bk_identifier(fa.fname) && !bk_lang_reserved(L, fa.fname) &&
	    !(li == CODEGEN_MSL && bk_msl_reserved(fa.fname)))
		fname = fa.fname;
	bk_emit_info info = {
		.name = fname,
		.source = fa.entry ? fa.entry->source : fa.named ? fa.source : "user form",
		.conventions = fa.entry ? fa.entry->convention
		                        : "r perceptual roughness, a = r^2; V includes 1/(4 NoL NoV); NoL not included",
		.domain = fa.domain[0] ? fa.domain : NULL,
		.error = fa.error[0] ? fa.error : NULL,
		.command = command_line,
	};
	/* a member: its front's one signature and its constants named, so that
	 * members swap at one call site */
	bk_emit_style style = {fa.member ? fa.signature : 0, fa.member};
	if ((rc = form_check_finite("codegen", fa.named ? fa.label : "form", fa.f, fa.params))) {
		bk_form_free(fa.f);
		return rc;
	}
	/* A clamp whose bounds are out of order is hi everywhere: spelled
	 * min(max()), defined; a warning like the precision's (form_check.h). */
	if (!math)
		form_warn_precision("codegen", fa.named ? fa.label : "form", fa.f, fa.params, half ? BK_F16 : BK_F32);
	char what[200];
	if (!math && bk_form_clamp_reversed(fa.f, fa.params, what, sizeof what) > 0)
		fprintf(stderr, "brdfkit codegen: warning: %s has its lower bound above its upper: it is the upper "
		        "bound everywhere (GLSL and HLSL leave clamp() undefined there; the code writes min(max()))\n",
		        what);
	char msl_err[600] = "out of memory";
	char *text = math ? bk_form_math_doc(fa.f, ml, fa.params, &info)
	             : li == CODEGEN_MSL ? bk_msl_emit(fa.f, half, fa.params, &info, &style, msl_err, sizeof msl_err)
	                                 : bk_form_emit_styled(fa.f, L, half, fa.params, &info, &style);
	if (!text && li == CODEGEN_MSL) {
		bk_form_free(fa.f);
		return cli_fail("codegen", "code generation failed (%s)", msl_err);
	}
	bk_form_free(fa.f);
	return write_code(text, out);
}

/* text (malloc'd, freed here; NULL: out of memory) to stdout or --out FILE. */
static int write_code(char *text, const char *out)
{
	int rc = 0;
	if (!text)
		return cli_fail("codegen", "code generation failed (out of memory)");
	if (!out) {
		fputs(text, stdout);
	} else {
		bk_out co;
		char err[512];
		if (bk_out_open_file(&co, out, err, sizeof err) == 0) {
			fputs(text, co.f);
			if (bk_out_commit(&co, err, sizeof err))
				rc = cli_fail("codegen", "%s", err);
		} else {
			rc = cli_fail("codegen", "%s", err);
		}
	}
	free(text);
	return rc;
}

static void params_text(const bk_catalog_entry *e, char *buf, size_t len)
{
	size_t k = 0;
	buf[0] = '\0';
	for (int i = 0; i < e->nparams && k < len; i++)
		k += (size_t)snprintf(buf + k, len - k, "%sp%d=%.9g", i ? ";" : "", i, e->defaults[i]);
}

static const char *const catalog_setups[] = {"", NULL};
static const cli_table catalog_table = {NULL, 0, NULL, 0, catalog_setups};

int cmd_catalog(int argc, char **argv)
{
	cli_cmd cmd = {"catalog", "Lists the published forms as CSV: name,target,form,parameters,source, then\n"
	               "form_b (B of a split-sum entry) and convention. Parameters are p0=...;p1=... with\n"
	               "the published constants.",
	               "", NULL, NULL, 0, 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &catalog_table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	puts("name,target,form,parameters,source,form_b,convention");
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		char params[BK_MAX_PARAMS * 24];
		params_text(e, params, sizeof params);
		const char *f[7] = {e->name, e->target, e->form, params, e->source, e->form_b ? e->form_b : "", e->convention};
		for (int k = 0; k < 7; k++) {
			if (k)
				putchar(',');
			bk_csv_field(stdout, f[k]);
		}
		putchar('\n');
	}
	return 0;
}
