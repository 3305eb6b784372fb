/*
 * cli.h — the command-line tool's shared parts: table-driven option parsing
 * (help text and validation come from the same table), the one place where
 * errors are formatted, and atomic output files.
 */
#ifndef ANALYSIS_CLI_H
#define ANALYSIS_CLI_H

#include <stdio.h>

#define CLI_LIST_MAX 64

typedef enum cli_kind { CLI_NUM, CLI_INT, CLI_STR, CLI_FLAG, CLI_LIST } cli_kind;

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
	int seen;         /* set by the parser */
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

/* Parses argv (after the subcommand) into the option table. Returns 0, 1 when
 * --help was printed (exit 0), or 2 after printing an error (usage error). */
int cli_parse(cli_cmd *cmd, int argc, char **argv);
void cli_help(const cli_cmd *cmd, FILE *out);

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

/* Progress on stderr: a live counter on a terminal, one line per finished stage
 * otherwise (logs stay short). */
void cli_progress(void *label, int done, int total);

#endif
