/*
 * cli.h — the command-line tool's shared parts: table-driven option parsing
 * (help text and validation come from the same table), the one place where
 * errors are formatted, and atomic output files.
 */
#ifndef ANALYSIS_CLI_H
#define ANALYSIS_CLI_H

#include "brdf.h"

#include <stdio.h>

#define CLI_LIST_MAX 64

/* CLI_FORM: a string that is a form, read through cli_form_arg (@FILE, -). */
typedef enum cli_kind { CLI_NUM, CLI_INT, CLI_STR, CLI_FLAG, CLI_LIST, CLI_FORM } cli_kind;

typedef struct cli_list {
	int n;
	double v[CLI_LIST_MAX];
} cli_list;

/* One option. Numbers are checked against [lo, hi], each end open when its flag
 * is set; range is how --help and errors spell that interval. */
typedef struct cli_opt {
	const char *name; /* "--nov" */
	cli_kind kind;
	const char *metavar;
	const char *help;
	void *dest;       /* double*, long*, const char**, int* (flag), cli_list* */
	double lo, hi;
	int lo_open, hi_open;
	int required;
	int repeat;       /* CLI_STR, CLI_FORM: may be given this many times, into
	                     dest[0..repeat) (const char *[repeat]); 0 or 1: once */
	int seen;         /* set by the parser: how many times given */
} cli_opt;

typedef struct cli_cmd {
	const char *name;
	const char *summary;
	const char *usage;  /* after "brdfkit NAME " */
	const char *details;/* paragraph printed after the options, may be NULL */
	cli_opt *opts;
	int nopts;
	int max_pos;        /* positional arguments allowed (0: none) */
	int npos;           /* set by the parser */
	char *pos[32];
} cli_cmd;

/* Parses argv (after the subcommand) into the option table; "--" ends the
 * options (what follows is positional, so a form may start with '-'). Returns
 * 0, 1 when --help was printed (exit 0), or 2 after printing an error (usage
 * error). */
int cli_parse(cli_cmd *cmd, int argc, char **argv);
void cli_help(const cli_cmd *cmd, FILE *out);

/* The one number syntax of the tool, for option values, list items and
 * NAME=VALUE: [+-] digits ['.' [digits]] | [+-] '.' digits, then an optional
 * exponent [eE][+-]digits; nothing before or after. Not hex, inf or nan
 * (which strtod alone would take). Subnormal values are accepted; a value
 * that overflows double is not. Returns 0 with *x set, or -1. */
int cli_number(const char *text, double *x);

/* A FORM argument as text: "@FILE" is the whole file, "-" all of standard
 * input (one trailing newline dropped), anything else the argument itself.
 * *text is valid until exit. Returns 0, or 2 after an error naming the file
 * (cannot be read, or not text: a NUL byte or invalid UTF-8). */
int cli_form_arg(const char *arg, const char **text);

/* Reads a whole file (path "-": standard input) into a malloc'd, NUL-
 * terminated buffer; *len excludes the NUL. Returns NULL with errno set. */
/* cli_form_arg on every positional from the first-th on, in place: for the
 * commands whose positionals are forms (or NAME=VALUE, which is never '-' or
 * starts with '@'). Returns 0 or 2 after an error. */
int cli_form_positionals(cli_cmd *cmd, int first);

char *cli_read_file(const char *path, size_t *len);

/* 0 if buf[0..len) is text: no NUL byte and valid UTF-8; otherwise -1 with
 * a reason ("a NUL byte at offset 12") in why. */
int cli_check_text(const char *buf, size_t len, char *why, size_t wlen);

/* "brdfkit CMD: message" on stderr, one line. Returns 1 (runtime failure) so a
 * command can `return cli_fail(...)`; usage errors return 2 from cli_parse. */
int cli_fail(const char *cmd, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
void cli_set_name(const char *cmd);
/* A usage error found after cli_parse (a value that conflicts with another,
 * an option with no effect in context): "brdfkit CMD: message (see brdfkit
 * CMD --help)" on stderr, one line. Returns 2. */
int cli_usage(const cli_cmd *cmd, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
/* Whether option name (e.g. "--ior") was given. */
int cli_seen(const cli_cmd *cmd, const char *name);

/* An option that acts on some targets only (bit k of targets: target kind k;
 * does: what it does, for the message). Given for another target it would be
 * ignored, so cli_scope_check refuses it: returns 2 after a usage error naming
 * the option and the target, or 0. */
typedef struct cli_scope {
	const char *opt;
	unsigned targets;
	const char *does;
} cli_scope;
int cli_scope_check(const cli_cmd *cmd, const cli_scope *t, size_t n, int kind, const char *kind_name);

/* --cost-model NAME: the named model's weights into *simple, *complex; 2
 * after a usage error listing the names. */
int cli_cost_model(const cli_cmd *cmd, const char *name, double *simple, double *complex);

/* Progress on stderr: a live counter on a terminal, one line per finished stage
 * otherwise (logs stay short). */
void cli_progress(void *label, int done, int total);

#endif
