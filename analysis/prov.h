/*
 * prov.h — the provenance header of every CSV brdfkit writes: its first
 * line "# brdfkit VERSION WHAT", then "# command: ..." and, where a target
 * was sampled, "# target: ...". Written here only, so that every table
 * states the same things in the same words, and readers (frontcsv.c's
 * "# brdfkit " and "# target: ", out.c's signed single files; csvtab.c and
 * tests/tools/csvget.c skip the '#' lines before the column names) can rely
 * on them.
 *
 * A comment line must stay one line: a line break in any text continues it
 * on a new "# " line, a carriage return is dropped, and every other control
 * character becomes a space (a raw one would start a row of data, or hide
 * the line, in a reader that splits on them).
 */
#ifndef ANALYSIS_PROV_H
#define ANALYSIS_PROV_H

#include <stdio.h>

/* "# brdfkit VERSION " + the printf text + "\n": the first line. */
void bk_prov_title(FILE *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* "# command: COMMAND\n" (an empty command for NULL). */
void bk_prov_command(FILE *f, const char *command);
/* "# target: DESCRIPTION\n". */
void bk_prov_target(FILE *f, const char *description);
/* The three in that order, the target's line left out when target is NULL:
 * the header of fit's, search's and compare's tables. */
void bk_prov_header(FILE *f, const char *command, const char *target, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

#endif
