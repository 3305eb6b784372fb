/*
 * cli.c — option tables, help and the one place errors are formatted, for the
 * brdfkit tool.
 */
#include "cli.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
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
#define usage_error cli_usage /* the parser's own name for it */

int cli_seen(const cli_cmd *cmd, const char *name)
{
	for (int k = 0; k < cmd->nopts; k++)
		if (strcmp(cmd->opts[k].name, name) == 0)
			return cmd->opts[k].seen;
	return 0;
}

/* Strict number: the whole text must be a finite number inside the range. */
static int parse_number(const cli_cmd *cmd, const cli_opt *o, const char *text,
                        double *out)
{
	char *end;
	char r[48];
	range_text(o, r, sizeof r);
	errno = 0;
	double x = strtod(text, &end);
	if (end == text || *end != '\0' || errno == ERANGE || !isfinite(x))
		return usage_error(cmd, "%s: expected a finite number in %s, got '%s'",
		                   o->name, r, text);
	if (o->kind == CLI_INT && x != floor(x))
		return usage_error(cmd, "%s: expected an integer in %s, got '%s'", o->name,
		                   r, text);
	int below = o->lo_open ? !(x > o->lo) : !(x >= o->lo);
	int above = o->hi_open ? !(x < o->hi) : !(x <= o->hi);
	if (below || above)
		return usage_error(cmd, "%s: %s is out of range %s", o->name, text, r);
	*out = x;
	return 0;
}

static int parse_list(const cli_cmd *cmd, const cli_opt *o, const char *text,
                      cli_list *l)
{
	char buf[4096];
	if (strlen(text) >= sizeof buf)
		return usage_error(cmd, "%s: list too long", o->name);
	strcpy(buf, text);
	l->n = 0;
	char *save = NULL;
	for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		if (l->n == CLI_LIST_MAX)
			return usage_error(cmd, "%s: more than %d values", o->name, CLI_LIST_MAX);
		if (parse_number(cmd, o, tok, &l->v[l->n++]))
			return 2;
	}
	if (l->n == 0)
		return usage_error(cmd, "%s: expected a comma-separated list of numbers, got '%s'",
		                   o->name, text);
	return 0;
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
			return usage_error(cmd, "%s: empty value", o->name);
		*(const char **)o->dest = text;
		return 0;
	case CLI_FLAG:
		*(int *)o->dest = 1;
		return 0;
	}
	return 2;
}

int cli_parse(cli_cmd *cmd, int argc, char **argv)
{
	cli_set_name(cmd->name);
	for (int i = 0; i < argc; i++) {
		const char *arg = argv[i];
		if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
			cli_help(cmd, stdout);
			return 1;
		}
		if (strncmp(arg, "--", 2) != 0) { /* a positional: a form, NAME=VALUE, ... */
			if (cmd->npos >= cmd->max_pos || cmd->npos == 32)
				return usage_error(cmd, "unexpected argument '%s'", arg);
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
			return usage_error(cmd, "unknown option '%s'", arg);
		if (o->seen)
			return usage_error(cmd, "%s given twice", o->name);
		o->seen = 1;
		const char *val = NULL;
		if (o->kind == CLI_FLAG) {
			if (eq)
				return usage_error(cmd, "%s takes no value", o->name);
		} else if (eq) {
			val = eq + 1;
		} else if (i + 1 < argc) {
			val = argv[++i];
		} else {
			return usage_error(cmd, "%s needs a value (%s)", o->name, o->metavar);
		}
		if (set_value(cmd, o, val))
			return 2;
	}
	for (int k = 0; k < cmd->nopts; k++)
		if (cmd->opts[k].required && !cmd->opts[k].seen)
			return usage_error(cmd, "missing %s %s", cmd->opts[k].name,
			                   cmd->opts[k].metavar);
	return 0;
}

void cli_progress(void *label, int done, int total)
{
	static int tty = -1;
	if (tty < 0)
		tty = isatty(fileno(stderr));
	if (!tty) { /* logs get one line per finished stage, not a counter */
		if (done == total)
			fprintf(stderr, "%s: %d/%d done\n", (const char *)label, done, total);
		return;
	}
	fprintf(stderr, "\r%s: %d/%d", (const char *)label, done, total);
	if (done == total)
		fputc('\n', stderr);
	fflush(stderr);
}
