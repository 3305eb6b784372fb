/*
 * cli.c — option tables, help and the one place errors are formatted, for the
 * brdfkit tool.
 */
#include "cli.h"
#include "clock.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *cur_cmd = "brdfkit";

void cli_set_name(const char *cmd) { cur_cmd = cmd; }

int cli_fail(const char *cmd, const char *fmt, ...)
{
	va_list ap;
	fprintf(stderr, "brdfkit %s: ", cmd ? cmd : cur_cmd);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	return 1;
}

static void range_text(const cli_opt *o, char *buf, size_t len)
{
	if (o->kind == CLI_INT)
		snprintf(buf, len, "[%.0f, %.0f]", o->lo, o->hi);
	else
		snprintf(buf, len, "%c%g, %g%c", o->lo_open ? '(' : '[', o->lo, o->hi,
		         o->hi_open ? ')' : ']');
}

void cli_help(const cli_cmd *cmd, FILE *out)
{
	fprintf(out, "usage: brdfkit %s %s\n\n%s\n\noptions:\n", cmd->name, cmd->usage,
	        cmd->summary);
	for (int i = 0; i < cmd->nopts; i++) {
		const cli_opt *o = &cmd->opts[i];
		char left[64], range[64] = "";
		snprintf(left, sizeof left, "%s%s%s", o->name, o->metavar ? " " : "",
		         o->metavar ? o->metavar : "");
		if (o->kind == CLI_NUM || o->kind == CLI_INT || o->kind == CLI_LIST) {
			char r[48];
			range_text(o, r, sizeof r);
			snprintf(range, sizeof range, " in %s", r);
		}
		fprintf(out, "  %-22s %s%s%s\n", left, o->help, range,
		        o->required ? " (required)" : "");
	}
	fprintf(out, "  %-22s %s\n", "--help", "this text");
	if (cmd->details)
		fprintf(out, "\n%s\n", cmd->details);
	if (strstr(cmd->usage, "FORM")) /* every command that takes one reads it through cli_form_arg */
		fprintf(out, "\nA FORM is formula text, @FILE (the file's text) or - (standard input); put --\n"
		             "before a form that starts with '-'. Numbers: decimal or scientific, finite.\n");
}

int cli_usage(const cli_cmd *cmd, const char *fmt, ...)
{
	va_list ap;
	fprintf(stderr, "brdfkit %s: ", cmd->name);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, " (see brdfkit %s --help)\n", cmd->name);
	return 2;
}

int cli_seen(const cli_cmd *cmd, const char *name)
{
	for (int k = 0; k < cmd->nopts; k++)
		if (strcmp(cmd->opts[k].name, name) == 0)
			return cmd->opts[k].seen;
	return 0;
}

int cli_number(const char *text, double *x)
{
	static const char digits[] = "0123456789";
	const char *s = text + (*text == '+' || *text == '-'), *mant = s;
	s += strspn(s, digits);
	if (*s == '.')
		s += 1 + strspn(s + 1, digits);
	size_t nmant = (size_t)(s - mant);
	if (nmant == 0 || (nmant == 1 && *mant == '.'))
		return -1;
	int nonzero = strcspn(mant, "123456789") < nmant;
	if (*s == 'e' || *s == 'E') {
		s += 1 + (s[1] == '+' || s[1] == '-');
		size_t e = strspn(s, digits);
		if (e == 0)
			return -1;
		s += e;
	}
	if (*s)
		return -1;
	errno = 0;
	double v = strtod(text, NULL);
	/* ERANGE is also how strtod reports a subnormal result, which is a number
	 * like any other; overflow to inf, and a nonzero text that underflows to
	 * zero, are not the value typed. */
	if (!isfinite(v) || (v == 0.0 && nonzero))
		return -1;
	*x = v;
	return 0;
}

/* Strict number: the whole text must be a finite number inside the range. */
static int parse_number(const cli_cmd *cmd, const cli_opt *o, const char *text,
                        double *out)
{
	char r[48];
	range_text(o, r, sizeof r);
	double x;
	if (cli_number(text, &x))
		return cli_usage(cmd, "%s: expected a finite number in %s, got '%s'",
		                   o->name, r, text);
	if (o->kind == CLI_INT && x != floor(x))
		return cli_usage(cmd, "%s: expected an integer in %s, got '%s'", o->name,
		                   r, text);
	int below = o->lo_open ? !(x > o->lo) : !(x >= o->lo);
	int above = o->hi_open ? !(x < o->hi) : !(x <= o->hi);
	if (below || above)
		return cli_usage(cmd, "%s: %s is out of range %s", o->name, text, r);
	*out = x;
	return 0;
}

/* Items between commas, each a number; an empty item (",0.5", "0.5,,1",
 * "0.5,") is a typing slip, not a value to skip. */
static int parse_list(const cli_cmd *cmd, const cli_opt *o, const char *text,
                      cli_list *l)
{
	if (!*text)
		return cli_usage(cmd, "%s: expected a comma-separated list of numbers, got ''", o->name);
	l->n = 0;
	for (const char *p = text;;) {
		const char *comma = strchr(p, ',');
		size_t n = comma ? (size_t)(comma - p) : strlen(p);
		if (n == 0)
			return cli_usage(cmd, "%s: empty item in the list '%s'", o->name, text);
		if (l->n == CLI_LIST_MAX)
			return cli_usage(cmd, "%s: more than %d values", o->name, CLI_LIST_MAX);
		char *item = strndup(p, n);
		if (!item)
			return cli_usage(cmd, "%s: out of memory", o->name);
		int rc = parse_number(cmd, o, item, &l->v[l->n++]);
		free(item);
		if (rc)
			return 2;
		if (!comma)
			return 0;
		p = comma + 1;
	}
}

static int set_value(const cli_cmd *cmd, cli_opt *o, const char *text)
{
	double x;
	switch (o->kind) {
	case CLI_NUM:
		return parse_number(cmd, o, text, o->dest);
	case CLI_INT:
		if (parse_number(cmd, o, text, &x))
			return 2;
		*(long *)o->dest = (long)x;
		return 0;
	case CLI_LIST:
		return parse_list(cmd, o, text, o->dest);
	case CLI_STR:
		if (!*text)
			return cli_usage(cmd, "%s: empty value", o->name);
		*(const char **)o->dest = text;
		return 0;
	case CLI_FLAG:
		*(int *)o->dest = 1;
		return 0;
	case CLI_FORM:
		if (!*text)
			return cli_usage(cmd, "%s: empty value", o->name);
		return cli_form_arg(text, o->dest);
	}
	return 2;
}

int cli_parse(cli_cmd *cmd, int argc, char **argv)
{
	cli_set_name(cmd->name);
	int options = 1; /* until "--" */
	for (int i = 0; i < argc; i++) {
		const char *arg = argv[i];
		if (options && strcmp(arg, "--") == 0) {
			options = 0;
			continue;
		}
		if (options && (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)) {
			cli_help(cmd, stdout);
			return 1;
		}
		if (!options || strncmp(arg, "--", 2) != 0) { /* a positional: a form, NAME=VALUE, ... */
			if (cmd->npos >= cmd->max_pos || cmd->npos == 32)
				return cli_usage(cmd, "unexpected argument '%s'", arg);
			cmd->pos[cmd->npos++] = argv[i];
			continue;
		}
		/* --name=value is accepted as well as --name value. */
		const char *eq = strchr(arg, '=');
		size_t nlen = eq ? (size_t)(eq - arg) : strlen(arg);
		cli_opt *o = NULL;
		for (int k = 0; k < cmd->nopts; k++)
			if (strlen(cmd->opts[k].name) == nlen &&
			    strncmp(cmd->opts[k].name, arg, nlen) == 0)
				o = &cmd->opts[k];
		if (!o)
			return cli_usage(cmd, "unknown option '%s'", arg);
		if (o->seen && o->seen >= (o->repeat > 1 ? o->repeat : 1))
			return o->repeat > 1 ? cli_usage(cmd, "%s given more than %d times", o->name, o->repeat)
			                     : cli_usage(cmd, "%s given twice", o->name);
		o->seen++;
		const char *val = NULL;
		if (o->kind == CLI_FLAG) {
			if (eq)
				return cli_usage(cmd, "%s takes no value", o->name);
		} else if (eq) {
			val = eq + 1;
		} else if (i + 1 < argc) {
			val = argv[++i];
		} else {
			return cli_usage(cmd, "%s needs a value (%s)", o->name, o->metavar);
		}
		cli_opt one = *o; /* a repeatable string or form: the next slot of its array */
		if (o->repeat > 1)
			one.dest = (const char **)o->dest + (o->seen - 1);
		if (set_value(cmd, &one, val))
			return 2;
	}
	for (int k = 0; k < cmd->nopts; k++)
		if (cmd->opts[k].required && !cmd->opts[k].seen)
			return cli_usage(cmd, "missing %s %s", cmd->opts[k].name,
			                   cmd->opts[k].metavar);
	return 0;
}

char *cli_read_file(const char *path, size_t *len)
{
	FILE *f = strcmp(path, "-") ? fopen(path, "rb") : stdin;
	if (!f)
		return NULL;
	size_t cap = 4096, n = 0;
	char *buf = malloc(cap);
	int err = buf ? 0 : ENOMEM;
	while (!err) {
		if (cap - n < 2) {
			char *b = realloc(buf, 2 * cap);
			if (!b) {
				err = ENOMEM;
				break;
			}
			buf = b;
			cap *= 2;
		}
		size_t k = fread(buf + n, 1, cap - n - 1, f);
		n += k;
		if (k == 0) {
			if (ferror(f))
				err = errno ? errno : EIO; /* a directory: EISDIR */
			break;
		}
	}
	if (f != stdin)
		fclose(f);
	if (err) {
		free(buf);
		errno = err;
		return NULL;
	}
	buf[n] = '\0';
	*len = n;
	return buf;
}

int cli_check_text(const char *buf, size_t len, char *why, size_t wlen)
{
	const unsigned char *s = (const unsigned char *)buf;
	for (size_t i = 0; i < len;) {
		unsigned c = s[i], cp, min;
		size_t n; /* continuation bytes */
		if (c == 0) {
			snprintf(why, wlen, "a NUL byte at offset %zu", i);
			return -1;
		}
		if (c < 0x80) {
			i++;
			continue;
		}
		/* RFC 3629: no overlong forms, no surrogates, nothing past U+10FFFF */
		if (c >= 0xc2 && c <= 0xdf)
			n = 1, min = 0x80;
		else if ((c & 0xf0) == 0xe0)
			n = 2, min = 0x800;
		else if (c >= 0xf0 && c <= 0xf4)
			n = 3, min = 0x10000;
		else
			goto bad;
		cp = c & (0x3fu >> n);
		for (size_t k = 1; k <= n; k++) {
			if (i + k >= len || (s[i + k] & 0xc0) != 0x80)
				goto bad;
			cp = cp << 6 | (s[i + k] & 0x3f);
		}
		if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
			goto bad;
		i += n + 1;
		continue;
	bad:
		snprintf(why, wlen, "invalid UTF-8 at offset %zu", i);
		return -1;
	}
	return 0;
}

/* What cli_form_arg read, freed at exit (the texts live as long as argv). */
static char **form_texts;
static size_t nform_texts;

static void free_form_texts(void)
{
	for (size_t i = 0; i < nform_texts; i++)
		free(form_texts[i]);
	free(form_texts);
}

int cli_form_arg(const char *arg, const char **text)
{
	if (arg[0] != '@' && strcmp(arg, "-") != 0) {
		*text = arg;
		return 0;
	}
	const char *path = arg[0] == '@' ? arg + 1 : "-";
	const char *label = arg[0] == '@' ? arg : "standard input";
	size_t len;
	char *buf = cli_read_file(path, &len), why[64];
	if (!buf) {
		cli_fail(NULL, "%s: cannot read: %s", label, strerror(errno));
		return 2;
	}
	if (cli_check_text(buf, len, why, sizeof why)) {
		cli_fail(NULL, "%s: not text (%s)", label, why);
		free(buf);
		return 2;
	}
	if (len && buf[len - 1] == '\n') /* as an editor saves it */
		buf[--len] = '\0';
	if (len && buf[len - 1] == '\r')
		buf[--len] = '\0';
	char **t = realloc(form_texts, (nform_texts + 1) * sizeof *t);
	if (!t) {
		free(buf);
		cli_fail(NULL, "%s: out of memory", label);
		return 2;
	}
	if (!form_texts)
		atexit(free_form_texts);
	form_texts = t;
	form_texts[nform_texts++] = buf;
	*text = buf;
	return 0;
}

int cli_form_positionals(cli_cmd *cmd, int first)
{
	for (int i = first; i < cmd->npos; i++) {
		const char *text;
		if (cli_form_arg(cmd->pos[i], &text))
			return 2;
		cmd->pos[i] = (char *)text;
	}
	return 0;
}

/* Off a terminal (logs) a counter cannot overwrite itself, so a stage gets a
 * line when it ends and, while it runs, one at each 10 % once it has run 1 s
 * and one every 10 s whatever: a quick stage still prints one line, an hour
 * of integrals says where it is. */
#define PROGRESS_QUIET_S 1.0
#define PROGRESS_EVERY_S 10.0
void cli_progress(void *label, int done, int total)
{
	static int tty = -1, last_done, last_tenth;
	static const void *stage;
	static double t_start, t_line;
	if (tty < 0)
		tty = isatty(fileno(stderr));
	if (!tty) {
		double now = bk_clock_now();
		if (label != stage || done < last_done) { /* a new stage */
			stage = label;
			t_start = t_line = now;
			last_tenth = 0;
		}
		int tenth = total > 0 ? (int)((long long)done * 10 / total) : 0;
		if (done == total)
			fprintf(stderr, "%s: %d/%d done\n", (const char *)label, done, total);
		else if ((tenth > last_tenth && now - t_start >= PROGRESS_QUIET_S) || now - t_line >= PROGRESS_EVERY_S) {
			fprintf(stderr, "%s: %d/%d (%d %%, %.0f s)\n", (const char *)label, done, total,
			        (int)((long long)done * 100 / total), now - t_start);
			t_line = now;
		}
		last_done = done;
		last_tenth = tenth;
		return;
	}
	fprintf(stderr, "\r%s: %d/%d", (const char *)label, done, total);
	if (done == total)
		fputc('\n', stderr);
	fflush(stderr);
}

int cli_scope_check(const cli_cmd *cmd, const cli_scope *t, size_t n, int kind, const char *kind_name)
{
	for (size_t k = 0; k < n; k++)
		if (cli_seen(cmd, t[k].opt) && !(t[k].targets >> kind & 1))
			return cli_usage(cmd, "%s has no effect on target %s (%s)", t[k].opt, kind_name, t[k].does);
	return 0;
}

int cli_cost_model(const cli_cmd *cmd, const char *name, double *simple, double *complex)
{
	const bk_cost_model *m = bk_cost_model_find(name);
	if (!m) {
		char list[256];
		size_t k = 0;
		list[0] = '\0';
		for (size_t i = 0; bk_cost_model_at(i) && k < sizeof list; i++)
			k += (size_t)snprintf(list + k, sizeof list - k, "%s%s", i ? ", " : "", bk_cost_model_at(i)->name);
		return cli_usage(cmd, "--cost-model: unknown model '%.60s' (known: %s)", name, list);
	}
	*simple = m->simple;
	*complex = m->complex;
	return 0;
}
