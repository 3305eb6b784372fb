/*
 * search_setup.h — brdfkit search's options turned into a run (cmd_search.c):
 * the parsed command line (search_cli), the run's state (job), and the
 * set-up that checks the options and fills the search's: objective,
 * precision, weights, grammar, shape and constraints; the inputs; the seeds
 * (the catalog's, fit/search/seeds.h, or --start's, each checked as fit
 * checks a form). Errors are the CLI's one line (cli.h): each function
 * returns 0, or the exit status after the message (2 usage, 1 failure).
 */
#ifndef CLI_SEARCH_SETUP_H
#define CLI_SEARCH_SETUP_H

#include "cli.h"
#include "fitargs.h"
#include "frontcsv.h"
#include "gpucost.h"
#include "search.h"
#include "search/seeds.h"
#include "search_ck.h"
#include "search_front.h"

#define MAX_SEEDS BK_SEEDS_MAX
#define MAX_FRONT BK_SFRONT_MAX
#define MAX_START_FRONTS 8 /* --start-front (and --start-forms) given this many times at most */

typedef struct search_cli {
	fitargs t; /* the target options, as fit reads them */
	const char *out, *prefix, *inputs, *ops, *objective, *precision, *weights, *cost_model, *gpu, *env_form, *checkpoint, *resume;
	const char *start[MAX_SEEDS];
	int nstart;
	const char *start_front[MAX_START_FRONTS]; /* --start-front FILE, each time given */
	int nstart_front;
	const char *start_forms[MAX_START_FRONTS]; /* --start-forms FILE, each time given */
	int nstart_forms;
	const char *vs_front; /* --vs-front FILE */
	long evals, seed, threads, max_params, max_size, enum_size, enum_max, every, generation, migrate, migrants;
	double seconds, max_cost, fetch_cost;
	int relative, no_constraints, merge_fronts, inherit, split_fits;
} search_cli;

typedef struct job {
	search_cli *a;
	const cli_cmd *cmd;
	bk_target_kind kind;
	bk_target_options to, to_screen;
	bk_samples s, screen;
	bk_search_options so;
	bk_search *S;
	bk_sfront F;
	ck_islands ck; /* the checkpoint files' options */
	char command[2048];
	double seconds;
	long start_evals;  /* fits done before this process started (a resume): not counted in fits/s */
	int interrupted;
	long total_evals;  /* over all islands */
	const char *chip[BK_GPUCOST_MAX_CHIPS]; /* --gpu */
	int nchips;
	char chipbuf[512], driver[256];
	bk_frontcsv start_fc[MAX_START_FRONTS]; /* --start-front's rows: the seeds point at their texts */
	bk_frontcsv forms_fc[MAX_START_FRONTS]; /* --start-forms' rows, likewise */
	bk_frontcsv vs_fc;    /* --vs-front's rows */
	int ncatalog;         /* seeds before those: published (or --start), exempt from the constraints */
	bk_search_cert cert;  /* how far the run is complete, all islands together */
	int islands;          /* MPI ranks as islands (each its own search); not with --split-fits */
	bk_search_split split; /* --split-fits: the ranks' share of each step's fits */
} job;

/* --env-form f0 (or mix): env candidates are one form in f0. */
int search_env_in_f0(const job *J);
/* --env-form mix: that, seeded by the halves' compositions (fit/search/halves.h). */
int search_env_halves(const job *J);
/* The search's options from the command line (islands: the budget and the
 * enumeration shared out, each island its seed; --split-fits: one search,
 * each rank fitting its share of every step). */
int search_setup(job *J);
/* The inputs a candidate may read: --inputs, or what the target provides. */
int search_setup_inputs(job *J);
/* The seeds: the catalog's (no --start) or --start's, then --start-front's
 * members (after them, not exempt from the constraints, no catalog rows),
 * into sd and J->so. */
int search_setup_seeds(job *J, bk_seeds *sd);
/* A --start form NaN or infinite on s at its start is refused, as fit refuses it. */
int search_check_starts(const job *J, const bk_seeds *sd, const bk_samples *s);

/* Where the options act (cli.h's table: each option against the run's
 * target, candidates, checkpoint, enumeration, weights and processes). */
extern const cli_table search_table;
/* The run's context in the table's dimensions, then cli_applicable. */
int search_check_applicable(const job *J);

#endif
