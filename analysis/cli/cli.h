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
/* CLI_LINK: a string that is a --link-prefix, checked as it is parsed
 * (bk_link_prefix_check, out.h: a relative path, no scheme or other host). */
typedef enum cli_kind { CLI_NUM, CLI_INT, CLI_STR, CLI_FLAG, CLI_LIST, CLI_FORM, CLI_LINK } cli_kind;

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
	/* CLI_STR: where the value is one of the space-separated words of
	 * then_values, the next argument (when it is no option) is the value of
	 * option then, as if given by name: "--target table FILE" is "--target
	 * table --target-file FILE". Not taken when then was given already. */
	const char *then, *then_values;
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
 * NAME=VALUE: bk_csvtab_number's (csvtab.h), which the CSV readers share.
 * Returns 0 with *x set, or -1. */
int cli_number(const char *text, double *x);

/* A FORM argument as text: "@FILE" is the whole file, "-" all of standard
 * input (one trailing newline dropped), anything else the argument itself.
 * *text is valid until exit. Returns 0, or 2 after an error naming the file
 * (cannot be read, or not text: a NUL byte or invalid UTF-8). */
int cli_form_arg(const char *arg, const char **text);

/* cli_form_arg on every positional from the first-th on, in place: for the
 * commands whose positionals are forms (or NAME=VALUE, which is never '-' or
 * starts with '@'). Returns 0 or 2 after an error. */
int cli_form_positionals(cli_cmd *cmd, int first);

/* Reads a file (path "-": standard input) into a malloc'd, NUL-terminated
 * buffer; *len excludes the NUL. At most max bytes: a longer input is refused
 * after reading max + 1 bytes (errno EFBIG), never read to its end, so
 * /dev/zero or a FIFO cannot fill the memory. Returns NULL with errno set. */
char *cli_read_max(const char *path, size_t max, size_t *len);
/* cli_read_max with CLI_READ_MAX: for files that are not forms (scenes and
 * report sections, kilobytes; 64 MiB bounds the memory and still reads a
 * binary given by mistake far enough to say it is not text). */
#define CLI_READ_MAX ((size_t)64 << 20)
char *cli_read_file(const char *path, size_t *len);

/* 0 if buf[0..len) is text: no NUL byte and valid UTF-8; otherwise -1 with
 * a reason ("a NUL byte at offset 12") in why. */
int cli_check_text(const char *buf, size_t len, char *why, size_t wlen);

/* "brdfkit CMD: message" on stderr, one line. Returns 1 (runtime failure) so a
 * command can `return cli_fail(...)`; usage errors return 2 from cli_parse. */
int cli_fail(const char *cmd, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
void cli_set_name(const char *cmd);
/* The command running, as cli_set_name set it (fit or search in fit_out.c). */
const char *cli_name(void);
/* --out FILE of a command that writes one file (out NULL: standard output)
 * checked before the work: bk_out_file_check's refusal through cli_fail (1),
 * else 0. */
int cli_out_file(const char *cmd, const char *out);
/* A usage error found after cli_parse (a value that conflicts with another,
 * an option with no effect in context): "brdfkit CMD: message (see brdfkit
 * CMD --help)" on stderr, one line. Returns 2. */
int cli_usage(const cli_cmd *cmd, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
/* cli_usage where the option table is not at hand: the command running
 * (cli_set_name) names itself. Every usage error ends with the "(see ...)"
 * suffix, so a script's user knows where the rules are. Returns 2. */
int cli_bad(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Whether option name (e.g. "--ior") was given. */
int cli_seen(const cli_cmd *cmd, const char *name);

/* A comma-separated list of words (--hold p0,p2; --chips navi21,vega10) into
 * items[0..n), pointers into a copy that lives until exit. An empty item
 * (",a", "a,,b", "a,") or an item given twice is a typing slip, not something
 * to skip or do twice: refused with one usage line naming opt. Returns n >= 1,
 * or -1 after the error. Number lists (CLI_LIST) follow the same rules. */
int cli_words(const cli_cmd *cmd, const char *opt, const char *text, const char **items, int max);

/* ---- option applicability -------------------------------------------------
 *
 * An option that acts only in some contexts (a target kind, a mode, another
 * option's presence) would be silently ignored in the others. Each command
 * states once, in a table, where each of its options acts, and calls
 * cli_applicable() once its context is known; an option given where it does
 * not act is refused with one uniform line:
 *
 *   brdfkit CMD: OPT has no effect WHERE (DOES) (see brdfkit CMD --help)
 *
 * The context is a few dimensions, each with one of a few values (fit: the
 * target kind; whether the form has parameters; whether --loss is robust). A
 * rule says that OPT (or OPT with one value, "--weight dnol") acts only where
 * dimension DIM has one of the values in the mask ACTS; an option acts where
 * all its rules hold. An option that acts everywhere has one rule with dim
 * CLI_EVERYWHERE, so that every option is named: cli_parse_table refuses to
 * run a command whose table misses an option (an internal error, exit 2).
 *
 * The walk. `brdfkit CMD --help-applicability` (hidden; `brdfkit help
 * --applicability` for every command) prints the table as tab-separated
 * lines, with SETUPS: argument lists that put the command in its contexts.
 * `brdfkit CMD SETUP --check-options` (hidden) parses, runs cli_applicable,
 * prints "context CMD DIM=VALUE ..." and exits 0 without doing the work.
 * tests/cli_opts.sh gives every option, in every setup that lacks it, and
 * checks it is refused (exit 2, one line naming it) where a rule says it does
 * not act and accepted where all its rules say it acts; a command printed
 * without a table, a dimension value no setup reaches (unless the table says
 * none can: cli_unreached), or a rule no setup refuses fails the walk.
 *
 * Every command has a table. To give a new command one:
 *   1. static const cli_dim dims[] = {{"target", {"vf2d", ...}, {" on target vf2d", ...}}, ...};
 *      static const cli_rule rules[] = {{"--nu", NULL, 0, ON(VF) | ON(SPEC), "it sets ...", "4"},
 *                                      {"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL}, ...};
 *      static const char *const setups[] = {"--target vf2d --out o", ..., NULL};
 *      static const cli_table table = {dims, 1, rules, n, setups};
 *   2. cli_parse(&cmd, ...) becomes cli_parse_table(&cmd, &table, ...);
 *   3. once the context is known, before any work (and before checks that
 *      need the work): int ctx[] = {kind}; if ((rc = cli_applicable(&cmd, ctx))) return rc;
 *      every path of the command reaches it (else --check-options would run
 *      the command: the walk sees no context line and fails);
 *   4. run sh tests/cli_opts.sh build/brdfkit.
 */
#define CLI_DIM_VALUES 12
#define CLI_EVERYWHERE (-1)

typedef struct cli_dim {
	const char *name;                  /* "target": a word, in context lines */
	const char *value[CLI_DIM_VALUES]; /* its values, words; NULL after the last */
	const char *where[CLI_DIM_VALUES]; /* per value, how a refusal names it, with its
	                                      leading space or colon (" on target vf2d",
	                                      ": the form has no parameters"); NULL:
	                                      " when NAME is VALUE" */
} cli_dim;
/* where[v] = cli_unreached: no setup can reach value v (search's islands:
 * mpirun alone makes them). The walk asks no setup to reach it, and does not
 * ask an option that acts there alone to be accepted elsewhere; a refusal
 * there reads " when NAME is VALUE". A pointer compared, never printed. */
extern const char cli_unreached[];

typedef struct cli_rule {
	const char *opt;     /* "--nu", as in the option table */
	const char *value;   /* NULL: whatever its value; else the rule is about
	                        this value only ("dnol"; CLI_STR/CLI_FORM options) */
	int dim;             /* index in the table's dims, or CLI_EVERYWHERE */
	unsigned acts;       /* bit v: the option acts where the dimension has value v */
	const char *does;    /* what the option does, in the refusal's parentheses, or NULL */
	const char *example; /* a value the walk gives it (NULL: a flag, a value rule,
	                        or an option every setup gives) */
} cli_rule;

typedef struct cli_table {
	const cli_dim *dims;
	int ndims;
	const cli_rule *rules;
	int nrules;
	const char *const *setups; /* NULL-terminated; words split at spaces, so no
	                              word holds one; every value of every dimension
	                              is reached by one */
} cli_table;

/* cli_parse for a command with an applicability table (kept until exit): also
 * answers --help-applicability and takes --check-options. 2 (an internal
 * error) if the table misses an option or names one the command lacks. */
int cli_parse_table(cli_cmd *cmd, const cli_table *t, int argc, char **argv);
/* ctx[d]: the value of dimension d in this run. Returns 0, or 2 after the
 * usage line for the first option (in table order) given where it does not
 * act. Under --check-options, prints the context line and exits 0 instead of
 * returning 0. */
int cli_applicable(const cli_cmd *cmd, const int *ctx);

/* --cost-model NAME: the named model's weights into *simple, *complex; 2
 * after a usage error listing the names. */
int cli_cost_model(const cli_cmd *cmd, const char *name, double *simple, double *complex);

/* Work that may run long or fill the memory, said before it starts (as
 * scene says its own estimate): nothing below CLI_SAY_S seconds and
 * CLI_SAY_BYTES; above, one line "brdfkit CMD: WHAT: about T, M of memory
 * (BASIS)", and past CLI_WARN_S or CLI_WARN_BYTES it is a warning, printed
 * under --quiet too, that ends "; Ctrl-C stops it". seconds or bytes 0:
 * not estimated. No size is refused: the options bound it, the line says
 * what it costs. */
#define CLI_SAY_S 60.0
#define CLI_WARN_S (30 * 60.0)
#define CLI_SAY_BYTES (1024.0 * 1024 * 1024)
#define CLI_WARN_BYTES (4 * CLI_SAY_BYTES)
void cli_estimate(const char *what, double seconds, double bytes, const char *basis);

/* Progress on stderr: a live counter on a terminal, one line per finished stage
 * otherwise (logs stay short). Nothing under --quiet. */
void cli_progress(void *label, int done, int total);

/* ---- shared conventions (issue 24) -------------------------------------------
 *
 * One name and one meaning per shared option: --precision double|single|half
 * (cli_precision); --fetch-cost K, a texture fetch priced as K simple ops
 * (compare, search; a scene file's alu_tex or costs.fetch); --threads, all
 * cores by default where the result does not depend on it (search), 1 where
 * it may (fit: Ceres sums per-thread shares); --out DIR, a directory replaced
 * whole, for commands that write several files, --out FILE, written
 * atomically instead of standard output, for those that write one.
 *
 * --quiet: every command takes it (the parser, not the option tables, so no
 * table names it): no progress lines on stderr; errors are still printed. */
int cli_quiet(void);
/* One progress line "brdfkit CMD: ..." on stderr, unless --quiet: the helper
 * every command's step lines go through (what, and how far). */
void cli_note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* The closest of names[0..n) to typed (optimal string alignment distance: an
 * insertion, a deletion, a substitution or a swap of neighbours each count
 * 1), if it is close enough to be a typing slip: one edit in a word of up
 * to 4 characters, two in a longer one, fewer than its length (after the
 * "--" options share); else NULL. */
const char *cli_suggest(const char *typed, const char *const *names, int n);

/* An enumerated value not among names[0..n): the one usage line
 * "brdfkit CMD: OPT: unknown value 'X'; did you mean 'Y'? (known: ...)"
 * (the suggestion only when cli_suggest finds one). Returns 2. */
int cli_unknown_value(const char *opt, const char *text, const char *const *names, int n);
/* The names --target takes (fit/target.h bk_target_parse), for the message. */
extern const char *const cli_targets[];
#define CLI_NTARGETS 11
/* text among names[0..n): its index; else -1 after cli_unknown_value. */
int cli_choice(const char *opt, const char *text, const char *const *names, int n);

/* LO:HI (--x-range, --r-range, --domain, the lut ranges): two cli_numbers
 * with min <= LO < HI <= max (-0 refused where min >= 0, as for options),
 * and wide enough to sample: HI - LO >= CLI_RANGE_MIN_REL * max(|LO|, |HI|)
 * (a range a few ulps wide is a point whose samples all round alike).
 * Returns 0 with *lo, *hi set, or 2 after one usage line naming opt. */
#define CLI_RANGE_MIN_REL 1e-6
int cli_range(const char *opt, const char *text, double min, double max, double *lo, double *hi);
/* Its width check alone, for a reader with its own syntax (--domain):
 * 0, or 2 after the usage line. */
int cli_range_width(const char *opt, const char *text, double lo, double hi);

/* Precision, one spelling for every command: double, single, half (and
 * render's both). Scene files keep GLSL's words (target.precision
 * "mediump" | "highp": a file format, what the shader declares). */
typedef enum cli_prec { CLI_PREC_DOUBLE, CLI_PREC_SINGLE, CLI_PREC_HALF, CLI_PREC_BOTH } cli_prec;
#define CLI_PREC_BIT(p) (1u << (p))
/* --precision TEXT, one of the precisions in the mask allowed; an old
 * spelling (fp16, f16, mediump, fp32, f32, highp, float, fp64, f64) is
 * refused with the one line that names the new one ("did you mean 'half'?").
 * Returns 0 with *out set, or 2 after the usage line. */
int cli_precision(const char *text, unsigned allowed, cli_prec *out);

#endif
