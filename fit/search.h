/*
 * search.h — the search for closed forms: candidates generated over the
 * formula IR (fit/expr.h), each fitted on a screening sample with the fast
 * solver, kept in an archive of the best per cost level, the Pareto front of
 * error against GPU cost read off it.
 *
 * How a run goes (fit/search/, driver.c and the parts it wires): a
 * schedule of stages, each a list of generators sharing a step's batch
 * (bk_search_generator below); by default three stages:
 *   1. `seeds`: the seeds (catalog entries of the target, --start forms) are
 *      fitted first, so the front starts at the published state of the art;
 *   2. `enumeration`: every canonical candidate up to enum_size nodes,
 *      bottom-up;
 *   3. `neighbours` + `semantic` + `children` (evolution), generations of
 *      `generation` candidates: first (not for pairs; at most half a
 *      generation) the neighbours of each cost level's best by one free
 *      constant (p*x, p + x) and of each front level's best by one input or
 *      a power (mix(p, p', in), x*in, sq(x)) and by a blend (mix(u, v, x)):
 *      expr.h, issue 22; then (not for pairs; up to `semantic` more of the
 *      generation) each front level's best with one subtree replaced by
 *      the small tree nearest the values the target wants of it
 *      (search/semantic.h); then archive members' children by mutation and
 *      crossover filling the rest, until the budget of fits (evals) is spent
 *      or a generation comes out empty.
 * A candidate is fitted once: the cache holds the hash of each canonical
 * text. Fits of one generation run on threads; their results are merged in
 * candidate order, so the same seed and budget give the same archive for any
 * thread count. The archive is MAP-Elites over cost: for each integer cost
 * level the `per_level` best candidates (error, then canonical text), one per
 * error (an equal error at a cost level is mostly one model spelled twice), which
 * keeps cheap and expensive forms alive together instead of collapsing onto
 * the currently best trade-off.
 *
 * Errors are compared at a stated resolution (BK_SEARCH_ERR_BITS significant
 * bits) and ties broken by text: no selection hinges on the last bit of a
 * libm result, so the front does not depend on the CPU (FMA or not).
 */
#ifndef FIT_SEARCH_H
#define FIT_SEARCH_H

#include "expr.h"
#include "fit.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" { /* C linkage for a C++ program (tests/install.sh links one) */
#endif

/* Errors are rounded to this many significant bits before any comparison. */
#define BK_SEARCH_ERR_BITS 20

/* The enumeration is drawn tree by tree as the search consumes it (expr.h,
 * bk_expr_enum): a run with --enum-size 9 and a budget of 300 fits builds the
 * few hundred trees it fits, not the hundreds of millions up to 9 nodes (the
 * default grammar over LoH, r and a has 1.37 million canonical trees up to 7
 * nodes, bench_enum). It ends once this many trees are kept as operands of
 * larger ones (those below the last size, 30 + 16 bytes a node each: 157 to
 * 159 MB measured for 1,048,576 trees of the default grammar over 2 to 4
 * inputs, so about 2.5 GB at this limit; certifying 8 nodes over three inputs
 * keeps the 1.37 million, 9 nodes about 14 million). Past it the search goes
 * on by evolution, and the certificate stops at the last size drawn whole. */
#define BK_SEARCH_ENUM_TREES (1L << 24)
/* The trees of the last size are not kept (expr.h): drawing them costs
 * about 1 us each and no memory. A run draws at most this many in all (a
 * few minutes of drawing; the default grammar over three inputs has about
 * 1.25 million trees of 7 nodes, over one input about a million of 8). */
#define BK_SEARCH_ENUM_DRAWN (1L << 28)

/* env's constraints A, B >= 0 and A + B <= 1 hold to half an 8-bit unorm step:
 * less is invisible in an 8-bit render target, and an exact zero slack rejects
 * nearly every affine form (the exact A + B reaches 1 at r = 0, NoV = 1, and
 * Karis' published fit itself dips below 0). */
#define BK_SEARCH_ENV_SLACK (0.5 / 255)

/* The part of a generation the `semantic` generator fills by default
 * (bk_search_options.semantic; search/semantic.h): a quarter, after the
 * neighbours' half, before the children. Measured with bench_recovery,
 * planted suite, seeds 1-9: 448 of 459 runs at 100,000 fits and 403 at
 * 20,000 (none: 443 and 401); its five hardest forms 38 of 45 at 100,000
 * (none: 29); catalog 126 of 144 runs (none: 125); unseen suite, seeds 1-3:
 * 57 and 58 of 60 at 20,000 and 100,000 (none: 52 and 57). A first version
 * at 0.125 recovered 437 planted runs at 100,000, at 0.25 449. */
#define BK_SEARCH_SEMANTIC 0.25

typedef enum bk_objective { BK_OBJ_RMSE, BK_OBJ_MAX, BK_OBJ_ALBEDO } bk_objective;

/* How a candidate's trees become the form that is fitted. */
typedef enum bk_shape {
	BK_SHAPE_PLAIN, /* the tree is the form */
	BK_SHAPE_F0,    /* the talk's scalar pipeline: f0*(g), specColor applied at the end */
	BK_SHAPE_PAIR   /* env split sum: trees A and B, parameters of B after A's; or one
	                   tree s shared by both (tree[1] empty), A = p*s + p'*r + p'',
	                   B likewise with its own three (Karis' structure, s paid once) */
} bk_shape;

/* The ranks of one search that split its fits (bk_search_options.split)
 * and its enumeration's fingerprints: the same search as one process, byte
 * for byte, on any number of them (against islands, which each run a search
 * of their own). share is collective: every rank calls it at the same
 * points, in the same order (once a step for its fits, once a window of the
 * enumeration's trees looked at ahead), with n records of recsize bytes,
 * having written those of index i with i % size == rank; it fills in the
 * others from the ranks that wrote them. Returns 0, or -1 on every rank
 * (then the step fails). */
typedef struct bk_search_split {
	int rank, size;
	int (*share)(void *ctx, void *rec, size_t recsize, size_t n);
	void *ctx;
} bk_search_split;

typedef struct bk_search_options {
	const bk_samples *screen; /* the screening samples (target.h, bk_target_build) */
	bk_shape shape;           /* how trees become the fitted form */
	bk_grammar grammar;       /* the operations, inputs, constants and sizes of the trees
	                             (expr.h) */
	bk_objective objective;   /* what err is: rmse, max |error|, or the albedo's max error */
	int relative;             /* residuals (f - y)/|y| */
	bk_precision precision;   /* the candidate's error is that of its evaluation in this */
	double max_cost;          /* candidates above are not fitted (HUGE_VAL: none) */
	double simple_cost, complex_cost; /* a candidate's cost: simple ops (add, mul, ...)
	                             and complex ones (rcp, sqrt, exp2, ...) weighted by these
	                             (brdf.h: BK_COST_SIMPLE, BK_COST_COMPLEX) */
	int scale;                /* linear scaling: each tree g fitted as p*g (search/generate.c, scaled) */
	int nonneg;               /* reject a candidate negative anywhere on the samples */
	int env_bound;            /* pair: reject unless A, B >= 0 and A + B <= 1 */
	long evals;               /* budget: candidate fits; the search stops after the
	                             generation that reaches it (whole generations, so
	                             that a resumed run makes the same batches) */
	unsigned long seed;
	int threads;              /* >= 1 */
	int enum_size;            /* exhaustive up to this many nodes */
	long enum_max;            /* ... but at most this many fits of them */
	int generation;           /* children per generation */
	int per_level;            /* archive entries per integer cost level */
	int starts;               /* screening starts per candidate (1..4): ones, 0.1,
	                             then random (search/starts.h), each only where the
	                             one before did not converge */
	int inherit;              /* children start from their parents' fitted constants
	                             (expr.h, "Start values"), then from the default
	                             starts; 0: from the default starts alone */
	const char *const *seeds; /* forms fitted first (pair: "A" then "B" in seeds_b) */
	const char *const *seeds_b;
	/* their forms when the caller has parsed them (bk_seeds_apply): [k]
	 * bk_form_parse(seeds[k]) (of seeds_b[k]), copied and not parsed again;
	 * NULL, or a form whose text is not seeds[k]'s: the text is parsed here */
	const bk_form *const *seed_forms;
	const bk_form *const *seed_forms_b;
	const char *const *seed_names; /* their names in outputs (catalog names, "start 1", ...) */
	const double (*seed_p)[BK_MAX_PARAMS]; /* their starting constants (published), or NULL */
	int nseeds;
	int exempt_seeds;         /* the first exempt_seeds seeds (published forms) are kept
	                             whatever the constraints say; those after are held to
	                             them as generated forms are (default: all seeds exempt) */
	int island, islands;      /* this search is island `island` of `islands` (an
	                             MPI rank of a run): it enumerates only its share
	                             of the trees (every islands-th, from island) */
	/* ranks that split each step's fits (NULL: this process fits them all):
	 * every rank runs the same search, fits the candidates of the batch
	 * whose index is rank mod size, and the results are shared before the
	 * merge, so each holds what one process would (bk_search_split) */
	const struct bk_search_split *split;
	double semantic;          /* the part of a generation the `semantic` generator may fill
	                             after the neighbours (semantic backpropagation into a
	                             library of small trees: search/semantic.h), in [0, 0.5];
	                             0: none (not for pairs) */
} bk_search_options;

/* Sets the defaults of everything but screen, shape and grammar. */
void bk_search_defaults(bk_search_options *o);

typedef enum bk_cand_status {
	BK_CAND_OK,        /* fitted, finite, within the constraints */
	BK_CAND_NONFINITE, /* not finite somewhere the target is */
	BK_CAND_CONSTRAINT,/* negative, or env A, B outside [0, 1] */
	BK_CAND_FAILED     /* the fit failed */
} bk_cand_status;

typedef struct bk_cand {
	char *text;               /* the whole form as fitted (shape applied); A for a pair */
	char *text_b;             /* B for a pair, else NULL */
	bk_form *form;            /* its IR (owned), parsed once where the candidate is made (cand.h,
	                             bk_cand_parse): the one tree's, or a pair's A; */
	bk_form *form_b;          /* a pair's B; */
	bk_form *form_pair;       /* and a pair's f0*(A) + (B), its cost's. The screening fit reads
	                             them; the archive keeps them while no other candidate has both
	                             less error and no more cost, or no more error and less cost,
	                             so that a front member's reach the front's refit (NULL: freed,
	                             or a candidate read back, whose text is parsed where read) */
	const char *seed_name;    /* a seed's name, else NULL */
	bk_enode *tree;           /* the search trees (before the shape), packed: tree 0's ntree[0]
	                             nodes, then tree 1's ntree[1] (a pair's B, else none); owned.
	                             Two bk_expr are 2 kB, a candidate's trees ~100 bytes, and the
	                             archive keeps every candidate; bk_cand_trees copies them out) */
	int ntree[2];
	int np;                   /* its parameters p0..p(np-1) */
	double p[BK_MAX_PARAMS];  /* their fitted values */
	bk_ops ops;               /* its operation counts (brdf.h) */
	double cost;              /* the weighted count the front is on (simple_cost, complex_cost) */
	bk_cand_status status;
	double err;               /* the objective, rounded to BK_SEARCH_ERR_BITS; +inf unless OK */
	double rmse, max_abs, albedo_max_abs; /* on the screening samples, in the search precision */
	long found_at;            /* 1-based number of the fit, on its island */
	int island;               /* the island that fitted it (0 without islands) */
	int starts_run, start_won; /* the screening starts its fit ran and the one whose
	                             constants it kept (0: the first; a seed's
	                             published start is 0 too); a measurement, not
	                             kept in checkpoints (0 there) */
} bk_cand;

typedef struct bk_search bk_search;

/* 1 if the options are usable; otherwise 0 and a one-line reason in why
 * naming the option at fault ("starts: must be in 1..4, got 7"). */
int bk_search_options_valid(const bk_search_options *o, char *why, size_t len);

/* Checks the options (bk_search_options_valid: the message names the option)
 * and fits nothing yet. NULL with a message on a bad option. */
bk_search *bk_search_new(const bk_search_options *o, char *err, size_t errlen);
void bk_search_free(bk_search *s);

/* ---- the schedule: the generators that make the candidates ----------------
 *
 * A step's batch is made by the generators of the schedule's current stage,
 * in order, each filling the batch up to its share of it; the stage is over
 * after the batch in which every one of its generators said it was over,
 * and the search is over after its last stage. A program adds its own
 * generator (bk_search_schedule_add) before the search is stepped or
 * loaded; a checkpoint names the current stage and each generator, with
 * the state its save wrote, so that a search with another schedule refuses
 * it. A generator's make offers trees (bk_search_offer): each is made a
 * candidate as the built-in generators' are (canonical, scaled, shaped,
 * fitted once: the cache), and fitted in the same step. */

/* The batch a generator fills (its room: bk_search_sink_room). */
typedef struct bk_search_sink bk_search_sink;

typedef struct bk_search_generator {
	const char *name; /* 1 to 31 of [a-z0-9_-], not "done", distinct within a schedule:
	                     how checkpoints name it (copied) */
	size_t room;      /* the batch its stage needs at the least (0: a generation) */
	/* Offers the next candidates (bk_search_offer) while the sink has room.
	 * 1 when it is over (its stage ends after the batch in which every one of
	 * its generators said so), 0 when it has more, -1 on an error (out of
	 * memory: the step fails). */
	int (*make)(void *state, bk_search *s, bk_search_sink *sink);
	/* Its state in a checkpoint, as whole lines of text (NULL: none). 0, or -1. */
	int (*save)(const void *state, const bk_search *s, FILE *f);
	/* Reads back what save wrote and checks it (NULL: none). when: < 0 its
	 * stage is still to come, 0 it is the current one, > 0 it is over (make
	 * is not called again). 0, or -1 with what is wrong in err. */
	int (*load)(void *state, bk_search *s, int when, FILE *f, char *err, size_t errlen);
	void (*free)(void *state); /* called with state by bk_search_free (NULL: nothing to free) */
	void *state;
} bk_search_generator;

/* Adds g to the schedule of s (made by bk_search_new, not stepped or loaded
 * yet). join 0: a stage of g alone before stage `stage` (0 to the number
 * of stages: the default schedule has 0 seeds, 1 enumeration, 2 neighbours
 * + children; 3 appends); join 1: g joins stage `stage` after its
 * generators. share (0, 1]: g fills the batch up to that part of it
 * (counted from the batch's start, at least one candidate); 1: whatever the
 * generators before it left. On 0 s owns g->state (g->free); on -1 (what is
 * wrong in err) the caller keeps it. */
int bk_search_schedule_add(bk_search *s, int stage, int join, double share, const bk_search_generator *g, char *err,
                           size_t errlen);

/* How many more candidates the sink takes in this generator's share. */
size_t bk_search_sink_room(const bk_search_sink *k);

/* Offers the candidate of trees t (t[1] the second tree of a pair, empty: a
 * shared feature; ignored unless a pair), canonicalised here, with start its
 * first fit's starting constants (as many as it has parameters; NULL: the
 * default starts). 1 taken (it is fitted in this step), 0 not taken (not a
 * valid tree, seen before, over a limit, or no room), -1 out of memory. */
int bk_search_offer(bk_search_sink *k, const bk_expr t[2], const double *start);

/* Fits the next batch (a generation, or part of the seeds and enumeration).
 * Returns 1 while budget remains, 0 when the budget is spent or nothing new
 * can be generated, -1 on an error (message). */
int bk_search_step(bk_search *s, char *err, size_t errlen);

/* What a program hears from a running search, and how it stops one. Every
 * member may be zero (BK_SEARCH_CALLBACKS_INIT): then the search runs to its
 * budget in silence.
 *   progress  called after a step once progress_every fits (0: every step)
 *             have been made since it was last called, and once more when
 *             the run ends (budget spent, nothing left, or stopped), so the
 *             last call sees the final state;
 *   stop      asked after every step (whole steps: a stopped search is a
 *             consistent state, bk_search_save can write it); non-zero stops.
 * Both run on the caller's thread, between steps, never during the fits. */
typedef struct bk_search_callbacks {
	void (*progress)(void *ctx, const bk_search *s);
	int (*stop)(void *ctx, const bk_search *s);
	void *ctx;
	long progress_every;
} bk_search_callbacks;
#define BK_SEARCH_CALLBACKS_INIT {NULL, NULL, NULL, 0}

/* The one loop that drives a search: steps until the budget is spent, the
 * search has nothing new to generate, or cb->stop says so (cb may be NULL).
 * Returns 0 when the budget is spent or nothing is left, 1 when stopped, -1
 * on an error (message). */
int bk_search_drive(bk_search *s, const bk_search_callbacks *cb, char *err, size_t errlen);

/* The same loop with one callback, after_step (may be NULL), called after
 * every step as cb->stop: non-zero stops. */
typedef int (*bk_search_after_step)(void *ctx, const bk_search *s);
int bk_search_run(bk_search *s, bk_search_after_step after_step, void *ctx, char *err, size_t errlen);

long bk_search_evals(const bk_search *s);

/* How far a search is complete: every candidate the enumeration makes from
 * the trees of up to complete_size nodes (bk_expr_size; a tree as the
 * enumeration builds it, before its scale, search/generate.c) was fitted
 * with up to `starts` screening starts, or is a twin of one fitted at no
 * greater cost (the same values at 64 probes at four parameter vectors:
 * search/unique.h), or was fitted before (a seed), or is outside the
 * limits: costlier than max_cost, more parameters than the grammar allows.
 * The grammar is the options' (operations, inputs, literals, parameters),
 * without a unary operation directly over another (expr.h,
 * bk_expr_enumerate). So no form of the grammar up to complete_size nodes
 * and cost max_cost does better than the front, as far as a screening fit
 * finds each model's best constants. 0: nothing is complete (a size-1 tree
 * is a leaf). The counts are of this island's share, by tree size: the
 * enumeration's candidates drawn, left out as twins, and fitted. */
typedef struct bk_search_cert {
	int complete_size;
	double max_cost;
	int starts;
	int island, islands;
	long drawn[BK_EXPR_MAX + 1], twins[BK_EXPR_MAX + 1], fitted[BK_EXPR_MAX + 1];
	double dedup_seconds; /* CPU time the fingerprints took in this process (a measurement: varies) */
} bk_search_cert;
void bk_search_certificate(const bk_search *s, bk_search_cert *c);

/* The twin test under audit (build/bench_enum --audit): fn, when not NULL,
 * is called for each candidate the enumeration makes that parses, with its
 * texts (b NULL but for a pair), its fingerprint and whether it was left
 * out as a twin of a model fitted before (non-zero) or fitted; ctx is
 * passed on. The calls come from the thread that steps the search, in
 * candidate order. Set before the first step. */
typedef void (*bk_search_twin_fn)(void *ctx, const char *a, const char *b, uint64_t fp, int twin);
void bk_search_on_twin(bk_search *s, bk_search_twin_fn fn, void *ctx);

/* The fingerprint's probes: how many parameter vectors it evaluates at
 * (the first max copied into theta), and in *probes and *stride (either
 * may be NULL) its screening samples, sample i stride mod n for i < probes. */
int bk_search_twin_probes(const bk_search *s, double (*theta)[BK_MAX_PARAMS], int max, size_t *probes,
                          size_t *stride);

/* The certificate in words, one line (front.csv's '# certificate:' line,
 * section.html, the report): "every unique form of the grammar up to N
 * nodes [and cost <= K] was fitted, with up to S screening starts each (...);
 * grammar: ..." or "none: ...". g: the search's grammar. The length, or -1
 * when len was too small (cut). */
int bk_search_cert_text(const bk_search_cert *c, const bk_grammar *g, char *buf, size_t len);

/* The run in one paragraph, for a log or a notebook: fits, unique forms and
 * twins, how far it is complete and what that means, the screening front's
 * ends. The length, or -1 when len was too small (cut). */
int bk_search_brief(const bk_search *s, char *buf, size_t len);

/* The distinct candidates fitted so far, in the order they were found. */
size_t bk_search_count(const bk_search *s);
const bk_cand *bk_search_at(const bk_search *s, size_t i);
/* Which of the options' seeds (bk_search_options.seeds) c was made from:
 * its index, or -1 for a generated candidate. */
int bk_search_seed_index(const bk_search *s, const bk_cand *c);
/* c's search trees copied out of its packed nodes (bk_cand.tree), t[1].n = 0
 * where it has one tree (every shape but a pair). */
void bk_cand_trees(const bk_cand *c, bk_expr t[2]);
/* The Pareto front of (cost, err) over the candidates with status OK, by
 * increasing cost: indices into bk_search_at. Returns how many (<= max). */
size_t bk_search_front(const bk_search *s, size_t *idx, size_t max);

/* Checkpoint: the state after the last completed step, as text. A search
 * loaded from it (made by bk_search_new with the same options) continues
 * exactly as the one that saved it. The options' fingerprint is recorded and
 * checked. Return 0, or -1 with a message. */
int bk_search_save(const bk_search *s, FILE *f);
/* Reads the rest of f into s, a search just made (nothing stepped). The
 * checkpoint's checksum (its last line) and every field are checked against
 * what a search with these options can hold before any is used; a budget
 * (o.evals) below both the fits it holds and the budget of the run that
 * wrote it is refused (the result would hold more fits than asked for). On
 * -1 (what is wrong in err), s holds a part: free it. */
int bk_search_load(bk_search *s, FILE *f, char *err, size_t errlen);

/* Islands (an island model across processes: analysis/cli/islands.h).
 * export writes the candidates idx[0..n) as text; import reads such a text
 * from another island of the same run (the options but seed and island
 * checked, each candidate as a checkpoint's is) and adds the candidates this
 * one has not fitted or received, as they were fitted there: they join the
 * archive and become parents, and cost no fit. *added: how many were new.
 * Return 0, or -1 (message). */
int bk_search_export(const bk_search *s, const size_t *idx, size_t n, FILE *f);
int bk_search_import(bk_search *s, FILE *f, size_t *added, char *err, size_t errlen);

/* The objective of o for values v on samples s with metrics m
 * (bk_samples_metrics of v): rmse (of the relative residuals with
 * o->relative), max (relative with o->relative) or the albedo's max error.
 * v may be NULL where the metrics suffice (NaN for the relative rmse).
 * +inf when the values are not finite at some sample (m->nonfinite). */
double bk_search_error(const bk_search_options *o, const bk_samples *s, const double *v, const bk_fit_metrics *m);

/* Round an error to BK_SEARCH_ERR_BITS significant bits (nan, inf kept). */
double bk_search_round_err(double e);

#ifdef __cplusplus
}
#endif

#endif
