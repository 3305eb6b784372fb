/*
 * fitargs.h — the target options of brdfkit fit, which search takes too
 * (search_cli's t): the parsed options (fitargs), their applicability
 * dimension (the target kind), and the set-up of a bk_target_options from
 * them. A module of the command-line tool, shared by cmd_fit.c and
 * cmd_search.c so that neither calls the other's internals. Errors are the
 * CLI's one line (cli.h): 2 after a usage error, 1 after a failure.
 */
#ifndef ANALYSIS_CLI_FITARGS_H
#define ANALYSIS_CLI_FITARGS_H

#include "cli.h"
#include "fit.h"

/* The target kind as a dimension of an applicability table (cli.h): value k
 * is bk_target_kind k. */
#define FITARGS_TARGET_DIM                                                                                    \
	{"target",                                                                                        \
	 {"vf2d", "vf", "spec", "env", "d", "f", "form", "ms", "sheen", "table", "merl"},                  \
	 {" on target vf2d", " on target vf", " on target spec", " on target env", " on target d",        \
	  " on target f", " on target form", " on target ms", " on target sheen", " on target table",    \
	  " on target merl"}}
_Static_assert(BK_TARGET_COUNT == 11, "FITARGS_TARGET_DIM names every target kind in order");
#define FITARGS_ON(k) (1u << BK_TARGET_##k)
#define FITARGS_ALL ((1u << BK_TARGET_COUNT) - 1)
#define FITARGS_FILE (FITARGS_ON(TABLE) | FITARGS_ON(MERL)) /* the targets whose samples a file gives */
/* The rules of the options a file target takes or makes pointless, as fit
 * and search both state them (cli_rule rows of dimension dim). */
#define FITARGS_FILE_RULES(dim)                                                                              \
	{"--target-file", NULL, dim, FITARGS_FILE, "it gives the file of targets table and merl", "t.csv"},         \
	{"--channel", NULL, dim, FITARGS_FILE, "it chooses the channel of targets table (EXR) and merl", "R"},       \
	{"--nx", NULL, dim, FITARGS_ALL & ~FITARGS_FILE, "the file gives the samples of targets table and merl", "8"}, \
	{"--nr", NULL, dim, FITARGS_ALL & ~FITARGS_FILE, "the file gives the samples of targets table and merl", "8"}, \
	{"--r-range", NULL, dim, FITARGS_ALL & ~FITARGS_FILE, "the file gives the samples of targets table and merl", \
	 "0:0.5"},                                                                                               \
	{"--x-range", NULL, dim, FITARGS_ALL & ~FITARGS_FILE, "the file gives the samples of targets table and merl", \
	 "0:0.5"}

typedef struct fitargs {
	const char *target, *form, *form_a, *form_b, *out, *weight, *loss, *tr, *objective, *digits;
	const char *r_range, *x_range, *bounds, *talk, *smith, *hold, *target_form, *domain;
	const char *target_file, *channel; /* table, merl */
	cli_list f0;
	long nx, nr, nu, nphi, starts, seed, max_iter, threads;
	double loss_scale, ior, k;
	int relative;
} fitargs;

/* fit and search: the memory and time of the target's samples, said before
 * they are built when that is much (cli_estimate): about 168 bytes and 15 us
 * a sample for the reference, the fits and the refit (measured: search on
 * vf2d at --nx 512 --nr 512, and 2.8 GB at 4096 x 4096). */
void fitargs_say_size(const bk_target_options *to);
/* --domain NAME=LO:HI[,...] into to's domain; 2 after a usage error. */
int fitargs_domain(const cli_cmd *cmd, const char *text, bk_target_options *to);
/* Defaults of kind, then the target options of a; 2 after an error. */
int fitargs_setup_target(const fitargs *a, bk_target_kind kind, bk_target_options *to);
/* table, merl: reads --target-file into *t (zeroed for other targets); 0 or an exit status. */
int fitargs_read_file(const cli_cmd *cmd, const fitargs *a, bk_target_kind kind, bk_samples *t);

#endif
