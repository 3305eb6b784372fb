/*
 * member.h — a member of a front.csv of brdfkit search named on the command
 * line as FILE.csv:NAME (a split-sum member's parts FILE.csv:NAME:A and :B):
 * the one reader of every command that takes a form (eval, ops, codegen,
 * stability, time, gpucost, render, fit's start point). The file part ends
 * at the last ".csv:", which no form holds (forms have no ':'; a path may).
 * The member's parameters come baked in, numbered as the file numbers them
 * (across A and B of a pair), with the front's provenance: its target (the
 * fitted domain), objective, precision and the member's error.
 */
#ifndef ANALYSIS_CLI_MEMBER_H
#define ANALYSIS_CLI_MEMBER_H

#include "brdf.h"

typedef struct cli_member {
	char name[96];             /* the name column */
	char *form, *form_b;       /* malloc'd; form_b: B of a pair read whole (else NULL) */
	bk_form *f, *f_b;          /* their forms, as the file's reading parsed them (owned): a
	                            * command takes these (and sets them NULL), not the texts again */
	int part;                  /* 'A' or 'B' when one part was named, else 0 */
	double p[BK_MAX_PARAMS];   /* p0..p(np-1), every one the file gives */
	int np;
	double cost, error;        /* the row's cost and error columns */
	char target[32];           /* the front's target: the "# target: " line's first word (vf2d, env, f, ...) */
	char fname[BK_NAME_MAX + 1]; /* NAME, NAME_A or NAME_B as a function name; "" when too long */
	/* The one signature of the front's members of its kind (one form, or
	 * split-sum pairs): bit i, bk_input i, every input any of them reads,
	 * a as r (the code computes a = r*r), so that a member's code swaps for
	 * another's at one call site (bk_emit_style). */
	unsigned signature;
	char source[600], domain[600], errtext[160]; /* provenance, as codegen states it */
} cli_member;

/* Where FILE.csv:NAME splits: the ':' after the last ".csv", or NULL when
 * arg names no member. */
const char *cli_member_split(const char *arg);

/* Reads the member arg names (cli_member_split(arg) not NULL). pair: a
 * split-sum member without a part is read whole (form and form_b), as
 * commands that take a pair do (render, stability, time, gpucost); else it
 * is refused ("write FILE.csv:NAME:A or ...:B"). 0, or 2 after one line on
 * stderr naming the bad input (a missing file, a file that is not a front,
 * no such member, an unknown part); 1 when out of memory. */
int cli_member_load(const char *arg, int pair, cli_member *m);
void cli_member_free(cli_member *m);

#endif
