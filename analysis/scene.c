/*
 * scene.c — a scene file read with jansson and checked key by key, and the
 * plan: what each material needs, and the feature sets that share a shader.
 * The format is documented in scene.h; every rule here is a line there.
 */
#include "scene.h"

#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- errors: "PATH: detail", the first one wins ------------------------------ */

typedef struct reader {
	char *err;
	size_t errlen;
	int failed;
} reader;

static int fail(reader *R, const char *path, const char *fmt, ...)
{
	if (R->failed++)
		return -1;
	int k = snprintf(R->err, R->errlen, "%s: ", path);
	if (k < 0 || (size_t)k >= R->errlen)
		return -1;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(R->err + k, R->errlen - (size_t)k, fmt, ap);
	va_end(ap);
	return -1;
}

/* A JSON value's kind in words, for "expected a number, got a string". */
static const char *kind(const json_t *v)
{
	switch (json_typeof(v)) {
	case JSON_OBJECT: return "an object";
	case JSON_ARRAY: return "a list";
	case JSON_STRING: return "a string";
	case JSON_INTEGER:
	case JSON_REAL: return "a number";
	case JSON_TRUE:
	case JSON_FALSE: return "a boolean";
	default: return "null";
	}
}

static void join(char *out, size_t len, const char *path, const char *key)
{
	snprintf(out, len, "%s%s%s", path, *path ? "." : "", key);
}

/* Every key of obj is one of allowed (NULL-terminated). */
static int only_keys(reader *R, const json_t *obj, const char *path, const char *const *allowed)
{
	const char *key;
	json_t *v;
	json_object_foreach((json_t *)obj, key, v) {
		int ok = 0;
		for (const char *const *a = allowed; *a && !ok; a++)
			ok = !strcmp(key, *a);
		if (!ok) {
			char list[256] = "";
			for (const char *const *a = allowed; *a; a++)
				snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", a == allowed ? "" : ", ", *a);
			return fail(R, *path ? path : "scene", "unknown key '%s' (known: %s)", key, list);
		}
	}
	return 0;
}

static int object(reader *R, const json_t *v, const char *path)
{
	return json_is_object(v) ? 0 : fail(R, path, "expected an object, got %s", kind(v));
}

static int boolean(reader *R, const json_t *obj, const char *key, const char *path, int *out)
{
	json_t *v = json_object_get(obj, key);
	if (!v)
		return 0;
	char p[256];
	join(p, sizeof p, path, key);
	if (!json_is_boolean(v))
		return fail(R, p, "expected true or false, got %s", kind(v));
	*out = json_is_true(v);
	return 0;
}

static int number(reader *R, const json_t *v, const char *path, double lo, double hi, double *out)
{
	if (!json_is_number(v))
		return fail(R, path, "expected a number, got %s", kind(v));
	double x = json_number_value(v); /* never -0: numbers_exact refused it */
	if (!(x >= lo && x <= hi))
		return fail(R, path, "%g is outside [%g, %g]", x, lo, hi);
	*out = x;
	return 0;
}

/* A range of more than one value is wide enough to sample, as the command
 * line's (cli_range: CLI_RANGE_MIN_REL of the larger end): [0.5, 0.5 + 1e-16]
 * is one value written as a range. Returns 0 or -1. */
static int narrow(reader *R, const char *path, double lo, double hi)
{
	double need = 1e-6 * fmax(fabs(lo), fabs(hi));
	if (lo < hi && hi - lo < need)
		return fail(R, path, "[%.17g, %.17g] is too narrow to sample: max - min must be at least %g (1e-6 of the "
		            "larger end), or give one number", lo, hi, need);
	return 0;
}

/* A value in [lo, hi] given as a number, a list of numbers (its hull) or
 * {"min", "max"}; a string is one of names[] (values in nlo[], nhi[]). */
static int range(reader *R, const json_t *v, const char *path, double lo, double hi, const char *const *names,
                 const double *nlo, const double *nhi, double *rlo, double *rhi)
{
	char p[256];
	if (json_is_number(v)) {
		if (number(R, v, path, lo, hi, rlo))
			return -1;
		*rhi = *rlo;
		return 0;
	}
	if (json_is_string(v)) {
		const char *s = json_string_value(v);
		char list[128] = "";
		for (int i = 0; names[i]; i++) {
			if (!strcmp(s, names[i])) {
				*rlo = nlo[i];
				*rhi = nhi[i];
				return 0;
			}
			snprintf(list + strlen(list), sizeof list - strlen(list), "%s'%s'", i ? ", " : "", names[i]);
		}
		return fail(R, path, "unknown value '%s' (known: a number, a list, {\"min\", \"max\"}, %s)", s, list);
	}
	if (json_is_array(v)) {
		if (!json_array_size(v))
			return fail(R, path, "the list is empty");
		*rlo = HUGE_VAL;
		*rhi = -HUGE_VAL;
		size_t i;
		json_t *e;
		json_array_foreach(v, i, e) {
			double x;
			snprintf(p, sizeof p, "%s[%zu]", path, i);
			if (number(R, e, p, lo, hi, &x))
				return -1;
			*rlo = fmin(*rlo, x);
			*rhi = fmax(*rhi, x);
		}
		return narrow(R, path, *rlo, *rhi);
	}
	if (json_is_object(v)) {
		static const char *const keys[] = {"min", "max", NULL};
		if (only_keys(R, v, path, keys))
			return -1;
		for (int k = 0; k < 2; k++) {
			json_t *e = json_object_get(v, keys[k]);
			join(p, sizeof p, path, keys[k]);
			if (!e)
				return fail(R, p, "missing (a range needs \"min\" and \"max\")");
			if (number(R, e, p, lo, hi, k ? rhi : rlo))
				return -1;
		}
		if (*rlo > *rhi)
			return fail(R, path, "min %g is above max %g", *rlo, *rhi);
		return narrow(R, path, *rlo, *rhi);
	}
	return fail(R, path, "expected a number, a list or {\"min\", \"max\"}, got %s", kind(v));
}

/* A name goes into reports, tables and comments: no line break, tab or
 * escape sequence in it (the writers escape them too, scene_write.c). */
static int control_char(const char *s)
{
	for (; *s; s++)
		if ((unsigned char)*s < 0x20 || *s == 0x7f)
			return 1;
	return 0;
}

/* ---- the sections -------------------------------------------------------------- */

static int material(reader *R, const json_t *v, const char *path, bk_scene_material *m)
{
	static const char *const keys[] = {"name", "roughness", "f0", "specular", "multiscatter", "cloth", NULL};
	static const char *const rnames[] = {"texture", NULL};
	static const double rlo[] = {0}, rhi[] = {1};
	static const char *const fnames[] = {"dielectric", "metal", "texture", NULL};
	static const double flo[] = {BK_SCENE_DIELECTRIC_F0, BK_SCENE_METAL_F0_LO, BK_SCENE_TEXTURE_F0_LO};
	static const double fhi[] = {BK_SCENE_DIELECTRIC_F0, 1, 1};
	char p[256];
	if (object(R, v, path) || only_keys(R, v, path, keys))
		return -1;
	json_t *name = json_object_get(v, "name");
	join(p, sizeof p, path, "name");
	if (!name)
		return fail(R, p, "missing (every material has a name)");
	if (!json_is_string(name))
		return fail(R, p, "expected a string, got %s", kind(name));
	const char *s = json_string_value(name);
	if (!*s || strlen(s) >= sizeof m->name)
		return fail(R, p, "'%s' must have 1 to %zu characters", s, sizeof m->name - 1);
	if (control_char(s))
		return fail(R, p, "a control character in the name");
	strcpy(m->name, s);
	m->r_lo = 0;
	m->r_hi = 1;
	m->f0_lo = m->f0_hi = BK_SCENE_DIELECTRIC_F0;
	m->specular = 1;
	json_t *e;
	if ((e = json_object_get(v, "roughness"))) {
		join(p, sizeof p, path, "roughness");
		if (range(R, e, p, 0, 1, rnames, rlo, rhi, &m->r_lo, &m->r_hi))
			return -1;
	}
	if ((e = json_object_get(v, "f0"))) {
		join(p, sizeof p, path, "f0");
		if (range(R, e, p, 0, 1, fnames, flo, fhi, &m->f0_lo, &m->f0_hi))
			return -1;
	}
	return boolean(R, v, "specular", path, &m->specular) || boolean(R, v, "multiscatter", path, &m->multiscatter) ||
	       boolean(R, v, "cloth", path, &m->cloth) ? -1 : 0;
}

static int materials(reader *R, const json_t *v, bk_scene *sc)
{
	if (!v)
		return fail(R, "materials", "missing (a scene lists its materials)");
	if (!json_is_array(v))
		return fail(R, "materials", "expected a list, got %s", kind(v));
	size_t n = json_array_size(v);
	if (!n)
		return fail(R, "materials", "the list is empty");
	if (n > BK_SCENE_MAX_MATERIALS)
		return fail(R, "materials", "%zu materials, at most %d", n, BK_SCENE_MAX_MATERIALS);
	for (size_t i = 0; i < n; i++) {
		char p[64];
		snprintf(p, sizeof p, "materials[%zu]", i);
		if (material(R, json_array_get(v, i), p, &sc->mat[i]))
			return -1;
		for (size_t j = 0; j < i; j++)
			if (!strcmp(sc->mat[j].name, sc->mat[i].name))
				return fail(R, p, "name '%s' is also materials[%zu]'s", sc->mat[i].name, j);
		sc->nmat++;
	}
	return 0;
}

static int lighting(reader *R, const json_t *v, bk_scene *sc)
{
	static const char *const keys[] = {"punctual", "ibl", "diffuse", "multiscatter", NULL};
	if (!v)
		return 0;
	if (object(R, v, "lighting") || only_keys(R, v, "lighting", keys))
		return -1;
	if (boolean(R, v, "punctual", "lighting", &sc->punctual) || boolean(R, v, "ibl", "lighting", &sc->ibl) ||
	    boolean(R, v, "diffuse", "lighting", &sc->diffuse) || boolean(R, v, "multiscatter", "lighting", &sc->multiscatter))
		return -1;
	if (!sc->punctual && !sc->ibl)
		return fail(R, "lighting", "neither punctual lights nor image-based lighting: nothing lights the scene");
	return 0;
}

static int geometry(reader *R, const json_t *v, bk_scene *sc)
{
	static const char *const keys[] = {"nov", NULL};
	static const char *const none[] = {NULL};
	if (!v)
		return 0;
	if (object(R, v, "geometry") || only_keys(R, v, "geometry", keys))
		return -1;
	json_t *e = json_object_get(v, "nov");
	if (e && range(R, e, "geometry.nov", 0, 1, none, NULL, NULL, &sc->nov_lo, &sc->nov_hi))
		return -1;
	if (sc->nov_hi - sc->nov_lo < 0.01)
		return fail(R, "geometry.nov", "[%g, %g] is narrower than 0.01: give the range the geometry produces",
		            sc->nov_lo, sc->nov_hi);
	return 0;
}

static int budget(reader *R, const json_t *v, bk_scene *sc)
{
	static const char *const keys[] = {"vf", "env", "ms", "sheen", NULL};
	if (json_is_string(v)) {
		const char *s = json_string_value(v);
		if (strcmp(s, "generic") && strcmp(s, "at-generic-cost"))
			return fail(R, "target.error",
			            "unknown value '%s' (known: a number, {\"vf\", \"env\"}, 'generic', 'at-generic-cost')", s);
		sc->budget_vf = sc->budget_env = strcmp(s, "generic") ? BK_SCENE_BUDGET_AT_COST : BK_SCENE_BUDGET_GENERIC;
		sc->budget_ms = sc->budget_sheen = sc->budget_vf;
		return 0;
	}
	if (json_is_number(v)) {
		if (number(R, v, "target.error", 1e-6, 1, &sc->budget_vf))
			return -1;
		sc->budget_env = sc->budget_ms = sc->budget_sheen = sc->budget_vf;
		return 0;
	}
	if (!json_is_object(v))
		return fail(R, "target.error", "expected a number, 'generic', 'at-generic-cost' or {\"vf\", \"env\"}, got %s",
		            kind(v));
	if (only_keys(R, v, "target.error", keys))
		return -1;
	json_t *e;
	if ((e = json_object_get(v, "vf")) && number(R, e, "target.error.vf", 1e-6, 1, &sc->budget_vf))
		return -1;
	if ((e = json_object_get(v, "env")) && number(R, e, "target.error.env", 1e-6, 1, &sc->budget_env))
		return -1;
	if ((e = json_object_get(v, "ms")) && number(R, e, "target.error.ms", 1e-6, 1, &sc->budget_ms))
		return -1;
	if ((e = json_object_get(v, "sheen")) && number(R, e, "target.error.sheen", 1e-6, 1, &sc->budget_sheen))
		return -1;
	return 0;
}

static int costs(reader *R, const json_t *v, bk_scene *sc)
{
	static const char *const keys[] = {"simple", "complex", "fetch", NULL};
	double *dest[] = {&sc->simple_cost, &sc->complex_cost, &sc->fetch_cost};
	if (object(R, v, "target.costs") || only_keys(R, v, "target.costs", keys))
		return -1;
	for (int k = 0; k < 3; k++) {
		char p[64];
		json_t *e = json_object_get(v, keys[k]);
		join(p, sizeof p, "target.costs", keys[k]);
		if (!e)
			return fail(R, p, "missing (explicit costs give simple, complex and fetch)");
		if (number(R, e, p, 0, 1e4, dest[k]))
			return -1;
	}
	if (!(sc->simple_cost > 0))
		return fail(R, "target.costs.simple", "must be above 0");
	return 0;
}

static int target(reader *R, const json_t *v, bk_scene *sc)
{
	static const char *const keys[] = {"precision", "alu_tex", "costs", "lut", "languages", "error", NULL};
	if (!v)
		return 0;
	if (object(R, v, "target") || only_keys(R, v, "target", keys))
		return -1;
	json_t *e;
	if ((e = json_object_get(v, "precision"))) {
		const char *s = json_is_string(e) ? json_string_value(e) : NULL;
		if (!s)
			return fail(R, "target.precision", "expected a string, got %s", kind(e));
		if (strcmp(s, "mediump") && strcmp(s, "highp"))
			return fail(R, "target.precision", "unknown value '%s' (known: 'mediump', 'highp')", s);
		sc->half = !strcmp(s, "mediump");
	}
	if (boolean(R, v, "lut", "target", &sc->lut))
		return -1;
	json_t *tex = json_object_get(v, "alu_tex"), *c = json_object_get(v, "costs");
	if (tex && c)
		return fail(R, "target", "'alu_tex' and 'costs' both given: give one (alu_tex N is costs simple 1, complex 4, fetch N)");
	if (tex) {
		if (!json_is_integer(tex))
			return fail(R, "target.alu_tex", "expected 16, 32, 48 or 64, got %s", kind(tex));
		json_int_t t = json_integer_value(tex);
		if (t != 16 && t != 32 && t != 48 && t != 64)
			return fail(R, "target.alu_tex", "%lld is not a tier of the talk's table (16, 32, 48, 64)", (long long)t);
		sc->alu_tex = (int)t;
		sc->fetch_cost = (double)t;
	}
	if (c) {
		sc->alu_tex = 0;
		if (costs(R, c, sc))
			return -1;
	}
	if ((e = json_object_get(v, "languages"))) {
		static const char *const langs[BK_SCENE_LANGS] = {"glsl", "hlsl", "c", "msl"};
		if (!json_is_array(e))
			return fail(R, "target.languages", "expected a list, got %s", kind(e));
		if (!json_array_size(e))
			return fail(R, "target.languages", "the list is empty");
		sc->languages = 0;
		size_t i;
		json_t *l;
		json_array_foreach(e, i, l) {
			char p[64];
			snprintf(p, sizeof p, "target.languages[%zu]", i);
			const char *s = json_is_string(l) ? json_string_value(l) : NULL;
			int k = 0;
			while (s && k < BK_SCENE_LANGS && strcmp(s, langs[k]))
				k++;
			if (!s || k == BK_SCENE_LANGS)
				return s ? fail(R, p, "unknown language '%s' (known: 'glsl', 'hlsl', 'c', 'msl')", s)
				         : fail(R, p, "expected a string, got %s", kind(l));
			for (size_t j = 0; j < i; j++)
				if (!strcmp(s, json_string_value(json_array_get(e, j))))
					return fail(R, p, "'%s' is also target.languages[%zu]", s, j);
			sc->languages |= 1u << k;
		}
	}
	if ((e = json_object_get(v, "error")) && budget(R, e, sc))
		return -1;
	return 0;
}

/* The length of the JSON number at s (valid JSON: jansson read it). */
static size_t number_len(const char *s, const char *end)
{
	size_t n = 0;
	while (s + n < end && strchr("+-0123456789.eE", s[n]))
		n++;
	return n;
}

/* Every number of the (valid) JSON text is the value it spells: jansson
 * reads 1e-999 as 0 without a word, the command line refuses it
 * (cli_number), and so does a scene. A negative zero is refused too: every
 * number a scene takes is 0 or above, as an option whose range excludes
 * negatives refuses -0 (cli.c). The check is on the text, outside
 * strings, with the line and column an editor shows. Returns 0 or -1. */
static int numbers_exact(const char *text, size_t len, char *err, size_t errlen)
{
	const char *end = text + len;
	int line = 1, col = 1, in_string = 0;
	for (const char *s = text; s < end; s++) {
		if (in_string) {
			if (*s == '\\')
				s++, col++;
			else if (*s == '"')
				in_string = 0;
		} else if (*s == '"') {
			in_string = 1;
		} else if (*s == '-' || (*s >= '0' && *s <= '9')) {
			size_t n = number_len(s, end), mant = strcspn(s, "eE");
			char *tok = strndup(s, n);
			if (!tok) {
				snprintf(err, errlen, "out of memory");
				return -1;
			}
			int nonzero = strcspn(tok, "123456789") < (mant < n ? mant : n);
			double x = strtod(tok, NULL);
			if (x == 0 && *tok == '-') { /* a sign typed by mistake, or a value computed elsewhere */
				snprintf(err, errlen, "line %d, column %d: %.40s%s is negative zero (every number of a scene is 0 or "
				                      "above: write 0)", line, col, tok, n > 40 ? "..." : "");
				free(tok);
				return -1;
			}
			if (x == 0 && nonzero) {
				snprintf(err, errlen, "line %d, column %d: %.40s%s is not 0 but underflows to it (brdfkit reads "
				                      "numbers from about 4.9e-324 up, and 0)", line, col, tok, n > 40 ? "..." : "");
				free(tok);
				return -1;
			}
			free(tok);
			s += n - 1;
			col += (int)n - 1;
		}
		if (*s == '\n')
			line++, col = 0;
		if (((unsigned char)*s & 0xc0) != 0x80) /* a column per character, not per byte */
			col++;
	}
	return 0;
}

/* A budget given per term ({"vf", "env"}) for a term no material of the
 * scene needs would change nothing, silently: refused, saying why the term
 * is absent. (A single number is every term's budget: nothing to check.) */
static int term_budgets(reader *R, const json_t *v, const bk_scene *sc)
{
	int vf = 0, env = 0, spec = 0, ms = 0, sheen = 0;
	for (int m = 0; m < sc->nmat; m++) {
		bk_scene_needs n;
		bk_scene_material_needs(sc, m, &n);
		vf |= n.vf;
		env |= n.env;
		ms |= n.ms;
		sheen |= n.sheen;
		spec |= sc->mat[m].specular;
	}
	if (json_is_object(v) && json_object_get(v, "ms") && !ms)
		return fail(R, "target.error.ms", "has no effect %s", !spec ? "when no material is specular"
		                                                             : "when no specular material asks for \"multiscatter\"");
	if (json_is_object(v) && json_object_get(v, "sheen") && !sheen)
		return fail(R, "target.error.sheen", "has no effect when no material asks for \"cloth\"");
	if (json_is_object(v) && json_object_get(v, "vf") && !vf)
		return fail(R, "target.error.vf", "has no effect %s", !spec ? "when no material is specular"
		                                                             : "without punctual lights (lighting.punctual is false)");
	if (json_is_object(v) && json_object_get(v, "env") && !env)
		return fail(R, "target.error.env", "has no effect %s", !spec ? "when no material is specular"
		                                                              : "without image-based lighting (lighting.ibl is false)");
	return 0;
}

int bk_scene_parse(const char *text, size_t len, bk_scene *sc, char *err, size_t errlen)
{
	reader R = {err, errlen, 0};
	memset(sc, 0, sizeof *sc);
	snprintf(sc->name, sizeof sc->name, "scene");
	sc->punctual = sc->ibl = sc->diffuse = 1;
	sc->nov_lo = 0;
	sc->nov_hi = 1;
	sc->alu_tex = 32;
	sc->simple_cost = 1;
	sc->complex_cost = 4;
	sc->fetch_cost = 32;
	sc->lut = 1;
	sc->languages = BK_SCENE_GLSL | BK_SCENE_HLSL | BK_SCENE_C;
	sc->budget_vf = sc->budget_env = BK_SCENE_BUDGET_GENERIC;
	sc->budget_ms = sc->budget_sheen = BK_SCENE_BUDGET_GENERIC;

	if (len >= 3 && !memcmp(text, "\xef\xbb\xbf", 3)) {
		snprintf(err, errlen, "line 1, column 1: the file starts with a UTF-8 byte-order mark (JSON has none: save it "
		                      "as UTF-8 without one)");
		return -1;
	}
	json_error_t je;
	json_t *root = json_loadb(text, len, JSON_REJECT_DUPLICATES, &je);
	if (!root) {
		snprintf(err, errlen, "line %d, column %d: %s", je.line, je.column, je.text);
		return -1;
	}
	if (numbers_exact(text, len, err, errlen)) {
		json_decref(root);
		return -1;
	}
	static const char *const keys[] = {"scene", "materials", "lighting", "geometry", "target", NULL};
	if (object(&R, root, "scene") || only_keys(&R, root, "", keys))
		goto done;
	json_t *e = json_object_get(root, "scene");
	if (e) {
		if (!json_is_string(e))
			fail(&R, "scene", "expected a string, got %s", kind(e));
		else if (!*json_string_value(e) || strlen(json_string_value(e)) >= sizeof sc->name)
			fail(&R, "scene", "the name must have 1 to %zu characters", sizeof sc->name - 1);
		else if (control_char(json_string_value(e)))
			fail(&R, "scene", "a control character in the name");
		else
			strcpy(sc->name, json_string_value(e));
	}
	if (R.failed || materials(&R, json_object_get(root, "materials"), sc) ||
	    lighting(&R, json_object_get(root, "lighting"), sc) || geometry(&R, json_object_get(root, "geometry"), sc) ||
	    target(&R, json_object_get(root, "target"), sc))
		goto done;
	/* conflicts between sections */
	if (term_budgets(&R, json_object_get(json_object_get(root, "target"), "error"), sc))
		goto done;
	for (int m = 0; m < sc->nmat && !R.failed; m++)
		if (sc->mat[m].multiscatter && !sc->mat[m].specular) { /* it would change nothing, silently */
			char p[64];
			snprintf(p, sizeof p, "materials[%d].multiscatter", m);
			fail(&R, p, "true has no effect: material '%s' is not specular (\"specular\": false)", sc->mat[m].name);
		}
	for (int m = 0; m < sc->nmat && !R.failed; m++)
		if (!sc->mat[m].specular && !sc->mat[m].cloth && !sc->diffuse) {
			char p[64];
			snprintf(p, sizeof p, "materials[%d].specular", m);
			fail(&R, p, "false, and lighting.diffuse is false: material '%s' would not be shaded at all",
			     sc->mat[m].name);
		}
done:
	json_decref(root);
	return R.failed ? -1 : 0;
}

/* ---- the plan ---------------------------------------------------------------- */

void bk_scene_material_needs(const bk_scene *sc, int m, bk_scene_needs *n)
{
	const bk_scene_material *M = &sc->mat[m];
	memset(n, 0, sizeof *n);
	n->vf = M->specular && sc->punctual;
	n->env = M->specular && sc->ibl;
	n->diffuse = sc->diffuse;
	n->fixed_f0 = (n->vf || n->env) && M->f0_lo == M->f0_hi; /* f0 means nothing to a diffuse-only set */
	n->f0 = n->fixed_f0 ? M->f0_lo : NAN;
	/* E is read wherever the GGX lobe is shaded, punctual or IBL alike
	 * (Filament scales both by its energy compensation) */
	n->ms = (n->vf || n->env) && (M->multiscatter || sc->multiscatter);
	n->cloth = M->cloth && sc->punctual;
	/* the sheen albedo: the IBL's cloth channel, and what scales the layer
	 * below (specular or diffuse) under any light */
	n->sheen = M->cloth && (sc->ibl || M->specular || sc->diffuse);
}

static int same_needs(const bk_scene_needs *a, const bk_scene_needs *b)
{
	return a->vf == b->vf && a->env == b->env && a->diffuse == b->diffuse && a->fixed_f0 == b->fixed_f0 &&
	       (!a->fixed_f0 || a->f0 == b->f0) && a->ms == b->ms && a->cloth == b->cloth && a->sheen == b->sheen;
}

/* sets[k].name made unlike every earlier set's: "_2", "_3", ... added. A
 * name from needs ends in a word or three digits, never in "_" and one or
 * two digits, so an added suffix meets no other set's name. */
static void unique_name(bk_scene_set *sets, int k)
{
	char base[BK_SCENE_NAME_MAX];
	snprintf(base, sizeof base, "%s", sets[k].name);
	for (int suffix = 2;; suffix++) {
		int clash = 0;
		for (int j = 0; j < k && !clash; j++)
			clash = !strcmp(sets[j].name, sets[k].name);
		if (!clash)
			return;
		snprintf(sets[k].name, sizeof sets[k].name, "%.50s_%d", base, suffix);
	}
}

int bk_scene_plan(const bk_scene *sc, bk_scene_set *sets)
{
	int nset = 0;
	for (int m = 0; m < sc->nmat; m++) {
		bk_scene_needs n;
		bk_scene_material_needs(sc, m, &n);
		const bk_scene_material *M = &sc->mat[m];
		int k = 0;
		while (k < nset && !same_needs(&sets[k].needs, &n))
			k++;
		bk_scene_set *S = &sets[k];
		if (k == nset) {
			memset(S, 0, sizeof *S);
			S->needs = n;
			S->r_lo = M->r_lo;
			S->r_hi = M->r_hi;
			S->f0_lo = M->f0_lo;
			S->f0_hi = M->f0_hi;
			/* a name from the needs, parts joined by '_': a C/GLSL/HLSL identifier prefix */
			/* ms and cloth only where asked: the other sets keep their names */
			const char *part[6] = {n.vf ? "spec" : NULL, n.env ? "ibl" : NULL, n.ms ? "ms" : NULL,
			                       n.cloth || n.sheen ? "cloth" : NULL, n.diffuse ? "diffuse" : NULL,
			                       n.vf || n.env ? (n.fixed_f0 ? "f0" : "anyf0") : NULL};
			for (int p = 0; p < 6; p++)
				if (part[p])
					snprintf(S->name + strlen(S->name), sizeof S->name - strlen(S->name), "%s%s",
					         S->name[0] ? "_" : "", part[p]);
			if (n.fixed_f0)
				snprintf(S->name + strlen(S->name), sizeof S->name - strlen(S->name), "_%03ld",
				         lround(n.f0 * 1000));
			unique_name(sets, nset);
			nset++;
		}
		S->r_lo = fmin(S->r_lo, M->r_lo);
		S->r_hi = fmax(S->r_hi, M->r_hi);
		S->f0_lo = fmin(S->f0_lo, M->f0_lo);
		S->f0_hi = fmax(S->f0_hi, M->f0_hi);
		S->mat[S->nmat++] = m;
	}
	return nset;
}
