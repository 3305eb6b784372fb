/*
 * cli.c — option tables, help and the one place errors are formatted, for the
 * brdfkit tool.
 */
#include "cli.h"
#include "clock.h"
#include "csvtab.h"
#include "out.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *cur_cmd = "brdfkit";
static const cli_table *cur_table; /* the running command's, set by cli_parse_table */
static int check_only;             /* --check-options: stop after cli_applicable */
static int quiet;                  /* --quiet: no progress lines */

/* Texts the parser hands out (forms read by cli_form_arg, cli_words' copies):
 * they live as long as argv, and are freed at exit. */
static char **kept;
static size_t nkept;

static void free_kept(void)
{
	for (size_t i = 0; i < nkept; i++)
		free(kept[i]);
	free(kept);
}

static int keep(char *text)
{
	char **t = realloc(kept, (nkept + 1) * sizeof *t);
	if (!t)
		return -1;
	if (!kept)
		atexit(free_kept);
	kept = t;
	kept[nkept++] = text;
	return 0;
}

void cli_set_name(const char *cmd) { cur_cmd = cmd; }
const char *cli_name(void) { return cur_cmd; }

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

int cli_out_file(const char *cmd, const char *out)
{
	char err[1200];
	return out && bk_out_file_check(out, err, sizeof err) ? cli_fail(cmd, "%s", err) : 0;
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
	fprintf(out, "  %-22s %s\n", "--quiet", "no progress lines on stderr (errors are still printed)");
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

int cli_bad(const char *fmt, ...)
{
	va_list ap;
	fprintf(stderr, "brdfkit %s: ", cur_cmd);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, " (see brdfkit %s --help)\n", cur_cmd);
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
	return bk_csvtab_number(text, x); /* one number syntax, options and files alike */
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
	/* -0 where no negative is allowed: a sign typed by mistake, or a value
	 * computed elsewhere that is not the one meant; it would print as -0 */
	int below = (o->lo_open ? !(x > o->lo) : !(x >= o->lo)) || (o->lo >= 0 && signbit(x));
	int above = o->hi_open ? !(x < o->hi) : !(x <= o->hi);
	if (below || above)
		return cli_usage(cmd, "%s: %s is out of range %s", o->name, text, r);
	*out = x;
	return 0;
}

/* Items between commas, each a number; an empty item (",0.5", "0.5,,1",
 * "0.5,") is a typing slip, not a value to skip, and a value given twice
 * ("0.5,0.5") one not to do twice. */
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
		int rc = parse_number(cmd, o, item, &l->v[l->n]);
		for (int k = 0; rc == 0 && k < l->n; k++)
			if (l->v[k] == l->v[l->n]) /* 0.5 and 5e-1 alike: a row or a weight twice */
				rc = cli_usage(cmd, "%s: '%s' given twice in the list '%.200s'", o->name, item, text);
		free(item);
		if (rc)
			return 2;
		l->n++;
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
	case CLI_LINK: { /* one rule for every section's links (out.h) */
		char err[160];
		if (!*text)
			return cli_usage(cmd, "%s: empty value", o->name);
		if (bk_link_prefix_check(text, err, sizeof err))
			return cli_usage(cmd, "%s", err);
		*(const char **)o->dest = text;
		return 0;
	}
	}
	return 2;
}

static void print_table(const cli_cmd *cmd, const cli_table *t);
static const cli_opt *find_opt(const cli_cmd *cmd, const char *name, size_t len);

/* Options that were renamed for one spelling across commands (issue 24): the
 * old name is refused with the new one, so a script fails once, loudly. */
static const struct {
	const char *old, *now;
} renamed[] = {
	{"--half", "--precision half"}, /* lut */
	{"--tier", "--fetch-cost"},     /* compare */
};

/* An option the table lacks: renamed, or a slip of one it has. */
static int unknown_option(const cli_cmd *cmd, const char *arg, size_t nlen)
{
	char typed[64];
	snprintf(typed, sizeof typed, "%.*s", (int)(nlen < 63 ? nlen : 63), arg);
	for (size_t k = 0; k < sizeof renamed / sizeof renamed[0]; k++)
		if (!strcmp(typed, renamed[k].old) && find_opt(cmd, renamed[k].now, strcspn(renamed[k].now, " ")))
			return cli_usage(cmd, "unknown option '%s'; did you mean '%s'?", typed, renamed[k].now);
	const char *names[128];
	int n = 0;
	for (int k = 0; k < cmd->nopts && n < 126; k++)
		names[n++] = cmd->opts[k].name;
	names[n++] = "--help";
	names[n++] = "--quiet";
	const char *near = cli_suggest(typed, names, n);
	if (near)
		return cli_usage(cmd, "unknown option '%s'; did you mean '%s'?", typed, near);
	return cli_usage(cmd, "unknown option '%s'", typed);
}

/* 1 if w is one of the space-separated words of list. */
static int word_in(const char *w, const char *list)
{
	size_t n = strlen(w);
	for (const char *p = list; p && *p;) {
		size_t k = strcspn(p, " ");
		if (k == n && !strncmp(p, w, n))
			return 1;
		p += k + (p[k] == ' ');
	}
	return 0;
}

static int parse(cli_cmd *cmd, int argc, char **argv)
{
	cli_set_name(cmd->name);
	check_only = 0;
	if (argc >= 1 && strcmp(argv[0], "--help-applicability") == 0) {
		if (cur_table)
			print_table(cmd, cur_table);
		else
			printf("none\t%s\n", cmd->name);
		return 1;
	}
	int options = 1, quiet_seen = 0; /* until "--" */
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
		if (options && strcmp(arg, "--quiet") == 0) { /* every command's: cli_quiet */
			if (quiet_seen++) /* as every other option given twice */
				return cli_usage(cmd, "--quiet given twice");
			quiet = 1;
			continue;
		}
		if (options && cur_table && strcmp(arg, "--check-options") == 0) { /* hidden: for the walk */
			check_only = 1;
			continue;
		}
		if (!options || strncmp(arg, "--", 2) != 0) { /* a positional: a form, NAME=VALUE, ... */
			if (cmd->max_pos > 1 && (cmd->npos >= cmd->max_pos || cmd->npos == 32))
				return cli_usage(cmd, "'%s': at most %d arguments", arg, cmd->max_pos < 32 ? cmd->max_pos : 32);
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
			return unknown_option(cmd, arg, nlen);
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
		if (o->then && i + 1 < argc && strncmp(argv[i + 1], "--", 2) != 0 && word_in(val, o->then_values)) {
			cli_opt *t = NULL;
			for (int k = 0; k < cmd->nopts; k++)
				if (!strcmp(cmd->opts[k].name, o->then))
					t = &cmd->opts[k];
			if (t && !t->seen) {
				t->seen++;
				if (set_value(cmd, t, argv[++i]))
					return 2;
			}
		}
	}
	for (int k = 0; k < cmd->nopts; k++)
		if (cmd->opts[k].required && !cmd->opts[k].seen)
			return cli_usage(cmd, "missing %s %s", cmd->opts[k].name,
			                   cmd->opts[k].metavar);
	return 0;
}

int cli_parse(cli_cmd *cmd, int argc, char **argv)
{
	cur_table = NULL; /* a command without a table (brdfkit help runs them all in one process) */
	return parse(cmd, argc, argv);
}

char *cli_read_max(const char *path, size_t max, size_t *len)
{
	FILE *f = strcmp(path, "-") ? fopen(path, "rb") : stdin;
	if (!f)
		return NULL;
	/* the buffer grows as the input does, to max + 1 bytes (the one more
	 * shows there is more, and nothing further is read) and the NUL */
	size_t want = max < (size_t)-2 ? max + 1 : max, cap = want < 4096 ? want + 1 : 4096, n = 0;
	char *buf = malloc(cap);
	int err = buf ? 0 : ENOMEM;
	while (!err && n < want) {
		if (n + 1 == cap) {
			size_t c = cap > (want + 1) / 2 ? want + 1 : 2 * cap;
			char *b = realloc(buf, c);
			if (!b) {
				err = ENOMEM;
				break;
			}
			buf = b;
			cap = c;
		}
		size_t k = fread(buf + n, 1, cap - n - 1, f);
		n += k;
		if (k == 0) {
			if (ferror(f))
				err = errno ? errno : EIO; /* a directory: EISDIR */
			break;
		}
	}
	if (!err && n > max)
		err = EFBIG;
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

char *cli_read_file(const char *path, size_t *len) { return cli_read_max(path, CLI_READ_MAX, len); }

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

/* A form file holds at most BK_FORM_MAX_LEN characters and the line end an
 * editor adds; a little more reaches the parser, which names the limit at
 * its column, and nothing past that is read. */
#define FORM_READ_MAX ((size_t)BK_FORM_MAX_LEN + 2)

int cli_form_arg(const char *arg, const char **text)
{
	if (arg[0] != '@' && strcmp(arg, "-") != 0) {
		*text = arg;
		return 0;
	}
	const char *path = arg[0] == '@' ? arg + 1 : "-";
	const char *label = arg[0] == '@' ? arg : "standard input";
	size_t len;
	char *buf = cli_read_max(path, FORM_READ_MAX, &len), why[64];
	if (!buf && errno == EFBIG) {
		cli_fail(NULL, "%s: longer than %zu bytes: a form is at most %d characters (not read further)", label,
		         FORM_READ_MAX, BK_FORM_MAX_LEN);
		return 2;
	}
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
	if (keep(buf)) {
		free(buf);
		cli_fail(NULL, "%s: out of memory", label);
		return 2;
	}
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
/* Stages that run at once (scene's feature sets on threads, each with its own
 * label; the caller serialises the calls) keep their own clocks, so one
 * stage's lines do not restart another's; the least recently used is reused. */
#define PROGRESS_STAGES 16
void cli_progress(void *label, int done, int total)
{
	static int tty = -1;
	static struct {
		const void *label;
		int last_done, last_tenth;
		double t_start, t_line;
		unsigned long used;
	} st[PROGRESS_STAGES];
	static unsigned long calls;
	if (quiet)
		return;
	if (tty < 0)
		tty = isatty(fileno(stderr));
	if (!tty) {
		double now = bk_clock_now();
		int k = 0;
		while (k < PROGRESS_STAGES && st[k].label != label)
			k++;
		if (k == PROGRESS_STAGES) /* a label not running: the oldest slot */
			for (int j = k = 0; j < PROGRESS_STAGES; j++)
				if (st[j].used < st[k].used)
					k = j;
		if (st[k].label != label || done < st[k].last_done) { /* a new stage */
			st[k].label = label;
			st[k].t_start = st[k].t_line = now;
			st[k].last_tenth = 0;
		}
		st[k].used = ++calls;
		int tenth = total > 0 ? (int)((long long)done * 10 / total) : 0;
		if (done == total)
			fprintf(stderr, "%s: %d/%d done\n", (const char *)label, done, total);
		else if ((tenth > st[k].last_tenth && now - st[k].t_start >= PROGRESS_QUIET_S) ||
		         now - st[k].t_line >= PROGRESS_EVERY_S) {
			fprintf(stderr, "%s: %d/%d (%d %%, %.0f s)\n", (const char *)label, done, total,
			        (int)((long long)done * 100 / total), now - st[k].t_start);
			st[k].t_line = now;
		}
		st[k].last_done = done;
		st[k].last_tenth = tenth;
		return;
	}
	fprintf(stderr, "\r%s: %d/%d", (const char *)label, done, total);
	if (done == total)
		fputc('\n', stderr);
	fflush(stderr);
}

int cli_cost_model(const cli_cmd *cmd, const char *name, double *simple, double *complex)
{
	const bk_cost_model *m = bk_cost_model_find(name);
	if (!m) {
		const char *names[32];
		int n = 0;
		for (size_t i = 0; bk_cost_model_at(i) && n < 32; i++)
			names[n++] = bk_cost_model_at(i)->name;
		(void)cmd;
		return cli_unknown_value("--cost-model", name, names, n);
	}
	*simple = m->simple;
	*complex = m->complex;
	return 0;
}

int cli_words(const cli_cmd *cmd, const char *opt, const char *text, const char **items, int max)
{
	char *copy = strdup(text);
	if (!copy || keep(copy)) {
		free(copy);
		cli_usage(cmd, "%s: out of memory", opt);
		return -1;
	}
	int n = 0;
	for (char *p = copy;;) {
		char *comma = strchr(p, ',');
		if (comma)
			*comma = '\0';
		if (!*p) {
			cli_usage(cmd, "%s: empty item in the list '%.200s'", opt, text);
			return -1;
		}
		for (int k = 0; k < n; k++)
			if (!strcmp(items[k], p)) {
				cli_usage(cmd, "%s: '%.60s' given twice in the list '%.200s'", opt, p, text);
				return -1;
			}
		if (n == max) {
			cli_usage(cmd, "%s: more than %d items", opt, max);
			return -1;
		}
		items[n++] = p;
		if (!comma)
			return n;
		p = comma + 1;
	}
}

/* ---- option applicability (cli.h) ----------------------------------------- */

const char cli_unreached[] = "";

/* The option named by name[0..len). */
static const cli_opt *find_opt(const cli_cmd *cmd, const char *name, size_t len)
{
	for (int k = 0; k < cmd->nopts; k++)
		if (strlen(cmd->opts[k].name) == len && !strncmp(cmd->opts[k].name, name, len))
			return &cmd->opts[k];
	return NULL;
}

static int nvalues(const cli_dim *d)
{
	int n = 0;
	while (n < CLI_DIM_VALUES && d->value[n])
		n++;
	return n;
}

/* Whether the rule's option was given (with its value, for a value rule). */
static int given(const cli_cmd *cmd, const cli_rule *r)
{
	const cli_opt *o = find_opt(cmd, r->opt, strlen(r->opt));
	if (!o || !o->seen)
		return 0;
	if (!r->value)
		return 1;
	for (int k = 0; k < o->seen; k++) /* a repeatable option: any of its values */
		if (((const char *const *)o->dest)[k] && !strcmp(((const char *const *)o->dest)[k], r->value))
			return 1;
	return 0;
}

/* What a table must hold for the walk to mean anything; a message naming the
 * first fault, or NULL. */
static const char *table_fault(const cli_cmd *cmd, const cli_table *t, char *buf, size_t len)
{
	for (int k = 0; k < t->nrules; k++) {
		const cli_rule *r = &t->rules[k];
		const cli_opt *o = find_opt(cmd, r->opt, strlen(r->opt));
		if (!o)
			snprintf(buf, len, "a rule names %s, which the command does not have", r->opt);
		else if (r->dim != CLI_EVERYWHERE && (r->dim < 0 || r->dim >= t->ndims))
			snprintf(buf, len, "a rule of %s names dimension %d of %d", r->opt, r->dim, t->ndims);
		else if (r->dim != CLI_EVERYWHERE && (!r->acts || r->acts >> nvalues(&t->dims[r->dim])))
			snprintf(buf, len, "a rule of %s acts on no value, or on values %s does not have", r->opt,
			         t->dims[r->dim].name);
		else if (r->value && o->kind != CLI_STR && o->kind != CLI_FORM && o->kind != CLI_LINK)
			snprintf(buf, len, "a value rule of %s, which takes no text", r->opt);
		else if (r->dim != CLI_EVERYWHERE && o->kind != CLI_FLAG && !r->value && !r->example)
			snprintf(buf, len, "the rule of %s on %s has no example value for the walk", r->opt,
			         t->dims[r->dim].name);
		else
			continue;
		return buf;
	}
	for (int i = 0; i < cmd->nopts; i++) {
		int ruled = 0;
		for (int k = 0; k < t->nrules && !ruled; k++)
			ruled = !strcmp(t->rules[k].opt, cmd->opts[i].name);
		if (!ruled) {
			snprintf(buf, len, "%s has no applicability rule (give it one: cli.h)", cmd->opts[i].name);
			return buf;
		}
	}
	return NULL;
}

/* --help-applicability: the table as tab-separated lines for the walk. */
static void print_table(const cli_cmd *cmd, const cli_table *t)
{
	printf("table\t%s\n", cmd->name);
	for (int i = 0; i < cmd->nopts; i++)
		printf("opt\t%s\t%s\t%s\n", cmd->name, cmd->opts[i].name, cmd->opts[i].kind == CLI_FLAG ? "flag" : "value");
	for (int d = 0; d < t->ndims; d++) {
		printf("dim\t%s\t%s\t", cmd->name, t->dims[d].name);
		for (int v = 0; v < nvalues(&t->dims[d]); v++)
			printf("%s%s", v ? "," : "", t->dims[d].value[v]);
		putchar('\t'); /* the values no setup can reach, or "-" */
		int first = 1;
		for (int v = 0; v < nvalues(&t->dims[d]); v++)
			if (t->dims[d].where[v] == cli_unreached) {
				printf("%s%s", first ? "" : ",", t->dims[d].value[v]);
				first = 0;
			}
		puts(first ? "-" : "");
	}
	for (int k = 0; k < t->nrules; k++) {
		const cli_rule *r = &t->rules[k];
		const char *ex = r->value ? r->value : r->example ? r->example : "-";
		printf("rule\t%s\t%s\t%s\t%s\t", cmd->name, r->opt, r->value ? r->value : "*", ex);
		if (r->dim == CLI_EVERYWHERE) {
			puts("*\t*");
			continue;
		}
		printf("%s\t", t->dims[r->dim].name);
		for (int v = 0, first = 1; v < nvalues(&t->dims[r->dim]); v++)
			if (r->acts >> v & 1) {
				printf("%s%s", first ? "" : ",", t->dims[r->dim].value[v]);
				first = 0;
			}
		putchar('\n');
	}
	for (int k = 0; t->setups && t->setups[k]; k++)
		printf("setup\t%s\t%s\n", cmd->name, t->setups[k]);
}

int cli_parse_table(cli_cmd *cmd, const cli_table *t, int argc, char **argv)
{
	char buf[200];
	const char *fault = table_fault(cmd, t, buf, sizeof buf);
	cur_table = t;
	if (fault) { /* a programming error, found on the first run of the command */
		fprintf(stderr, "brdfkit %s: internal error: %s\n", cmd->name, fault);
		return 2;
	}
	return parse(cmd, argc, argv);
}

int cli_applicable(const cli_cmd *cmd, const int *ctx)
{
	const cli_table *t = cur_table;
	if (!t) {
		fprintf(stderr, "brdfkit %s: internal error: cli_applicable without cli_parse_table\n", cmd->name);
		return 2;
	}
	for (int d = 0; d < t->ndims; d++)
		if (ctx[d] < 0 || ctx[d] >= nvalues(&t->dims[d])) {
			fprintf(stderr, "brdfkit %s: internal error: %s = %d is no value\n", cmd->name, t->dims[d].name, ctx[d]);
			return 2;
		}
	for (int k = 0; k < t->nrules; k++) {
		const cli_rule *r = &t->rules[k];
		if (r->dim == CLI_EVERYWHERE || (r->acts >> ctx[r->dim] & 1) || !given(cmd, r))
			continue;
		const cli_dim *d = &t->dims[r->dim];
		char where[160];
		if (d->where[ctx[r->dim]] && d->where[ctx[r->dim]] != cli_unreached)
			snprintf(where, sizeof where, "%s", d->where[ctx[r->dim]]);
		else
			snprintf(where, sizeof where, " when %s is %s", d->name, d->value[ctx[r->dim]]);
		return cli_usage(cmd, "%s%s%s has no effect%s%s%s%s", r->opt, r->value ? " " : "", r->value ? r->value : "",
		                 where, r->does ? " (" : "", r->does ? r->does : "", r->does ? ")" : "");
	}
	if (!check_only)
		return 0;
	printf("context\t%s", cmd->name);
	for (int d = 0; d < t->ndims; d++)
		printf("\t%s=%s", t->dims[d].name, t->dims[d].value[ctx[d]]);
	putchar('\n');
	fflush(stdout);
	exit(0); /* the walk asked for the check alone: nothing else runs, nothing is written */
}

/* ---- shared conventions (cli.h) ------------------------------------------- */

int cli_quiet(void) { return quiet; }

void cli_estimate(const char *what, double seconds, double bytes, const char *basis)
{
	int warn = seconds > CLI_WARN_S || bytes > CLI_WARN_BYTES;
	if ((seconds < CLI_SAY_S && bytes < CLI_SAY_BYTES) || (quiet && !warn))
		return;
	static const struct {
		double s;
		const char *unit;
	} units[] = {{365.25 * 86400, "years"}, {86400, "days"}, {3600, "h"}, {60, "min"}, {1, "s"}};
	char t[64] = "", m[48] = "";
	size_t u = 0;
	while (u + 1 < sizeof units / sizeof units[0] && seconds < 2 * units[u].s)
		u++;
	if (seconds > 0)
		snprintf(t, sizeof t, "about %.3g %s", seconds / units[u].s, units[u].unit);
	if (bytes > 0)
		snprintf(m, sizeof m, "%s%.1f GB of memory", *t ? ", " : "about ", bytes / 1e9);
	fprintf(stderr, "brdfkit %s: %s%s: %s%s (%s)%s\n", cur_cmd, warn ? "warning: " : "", what, t, m, basis,
	        warn ? "; Ctrl-C stops it" : "");
}

void cli_note(const char *fmt, ...)
{
	if (quiet)
		return;
	va_list ap;
	fprintf(stderr, "brdfkit %s: ", cur_cmd);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
}

/* Optimal string alignment distance (Damerau's four edits, no substring
 * edited twice), capped: words longer than 63 characters are never slips. */
static int osa(const char *a, const char *b)
{
	size_t m = strlen(a), n = strlen(b);
	if (m > 63 || n > 63)
		return 99;
	int d[64][64];
	for (size_t i = 0; i <= m; i++)
		d[i][0] = (int)i;
	for (size_t j = 0; j <= n; j++)
		d[0][j] = (int)j;
	for (size_t i = 1; i <= m; i++)
		for (size_t j = 1; j <= n; j++) {
			int c = a[i - 1] != b[j - 1];
			int v = d[i - 1][j] + 1;
			if (d[i][j - 1] + 1 < v)
				v = d[i][j - 1] + 1;
			if (d[i - 1][j - 1] + c < v)
				v = d[i - 1][j - 1] + c;
			if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < v)
				v = d[i - 2][j - 2] + 1;
			d[i][j] = v;
		}
	return d[m][n];
}

const char *cli_suggest(const char *typed, const char *const *names, int n)
{
	/* the "--" every option shares is no evidence of closeness */
	const char *t = strncmp(typed, "--", 2) ? typed : typed + 2;
	int len = (int)strlen(t), best = 99;
	const char *near = NULL;
	for (int i = 0; i < n; i++) {
		const char *c = strncmp(names[i], "--", 2) ? names[i] : names[i] + 2;
		int d = osa(t, c);
		if (d < best) { /* the first of equals: the table's order */
			best = d;
			near = names[i];
		}
	}
	/* a slip: one edit in a word of up to 4 letters ("mx" for "max"), two in a
	 * longer one, never the whole word ("x" is one edit from "d" and from "f"
	 * and means neither) */
	return near && best >= 1 && best <= (len <= 4 ? 1 : 2) && best < len ? near : NULL;
}

int cli_unknown_value(const char *opt, const char *text, const char *const *names, int n)
{
	char list[300] = "";
	for (int i = 0; i < n; i++)
		snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", names[i]);
	const char *near = cli_suggest(text, names, n);
	fprintf(stderr, "brdfkit %s: %s: unknown value '%.60s'", cur_cmd, opt, text);
	if (near)
		fprintf(stderr, "; did you mean '%s'?", near);
	fprintf(stderr, " (known: %s) (see brdfkit %s --help)\n", list, cur_cmd);
	return 2;
}

const char *const cli_targets[CLI_NTARGETS] = {"vf2d", "vf", "spec",  "env",   "d",   "f",
                                               "form", "ms", "sheen", "table", "merl"};

int cli_range_width(const char *opt, const char *text, double lo, double hi)
{
	double need = CLI_RANGE_MIN_REL * fmax(fabs(lo), fabs(hi));
	if (hi - lo < need)
		return cli_bad("%s: '%.100s' is too narrow to sample: HI - LO must be at least %g (1e-6 of the larger end)",
		               opt, text, need);
	return 0;
}

int cli_range(const char *opt, const char *text, double min, double max, double *lo, double *hi)
{
	const char *colon = strchr(text, ':');
	char lo_text[64] = "", where[80] = "";
	if (colon && (size_t)(colon - text) < sizeof lo_text)
		memcpy(lo_text, text, (size_t)(colon - text));
	if (min > -HUGE_VAL || max < HUGE_VAL)
		snprintf(where, sizeof where, " in [%g, %g]", min, max);
	double a, b;
	if (!colon || cli_number(lo_text, &a) || cli_number(colon + 1, &b) || !(a < b) || a < min || b > max ||
	    (min >= 0 && signbit(a)))
		return cli_bad("%s: expected LO:HI with LO < HI%s, got '%.100s'", opt, where, text);
	if (cli_range_width(opt, text, a, b))
		return 2;
	*lo = a;
	*hi = b;
	return 0;
}

int cli_choice(const char *opt, const char *text, const char *const *names, int n)
{
	for (int i = 0; i < n; i++)
		if (!strcmp(text, names[i]))
			return i;
	cli_unknown_value(opt, text, names, n);
	return -1;
}

int cli_precision(const char *text, unsigned allowed, cli_prec *out)
{
	static const char *const word[] = {"double", "single", "half", "both"};
	/* the spellings commands used before issue 24, and what each meant */
	static const struct {
		const char *old;
		cli_prec now;
	} alias[] = {{"fp64", CLI_PREC_DOUBLE}, {"f64", CLI_PREC_DOUBLE}, {"highp", CLI_PREC_SINGLE},
	             {"fp32", CLI_PREC_SINGLE}, {"f32", CLI_PREC_SINGLE}, {"float", CLI_PREC_SINGLE},
	             {"mediump", CLI_PREC_HALF}, {"fp16", CLI_PREC_HALF}, {"f16", CLI_PREC_HALF}};
	const char *names[4];
	int n = 0;
	for (int p = 0; p < 4; p++)
		if (allowed & CLI_PREC_BIT(p))
			names[n++] = word[p];
	for (int p = 0; p < 4; p++)
		if ((allowed & CLI_PREC_BIT(p)) && !strcmp(text, word[p])) {
			*out = (cli_prec)p;
			return 0;
		}
	for (size_t k = 0; k < sizeof alias / sizeof alias[0]; k++)
		if (!strcmp(text, alias[k].old) && (allowed & CLI_PREC_BIT(alias[k].now))) {
			fprintf(stderr, "brdfkit %s: --precision: unknown value '%s'; did you mean '%s'? (one spelling for "
			                "every command: double, single, half) (see brdfkit %s --help)\n",
			        cur_cmd, text, word[alias[k].now], cur_cmd);
			return 2;
		}
	return cli_unknown_value("--precision", text, names, n);
}
