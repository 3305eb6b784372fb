/*
 * expr.h — the search's candidates: small formula trees over the IR's own
 * opcode table (brdf/ir_ops.h, the single source of truth for names, arity
 * and cost), in prefix order so that a subtree is a contiguous run of nodes
 * and mutation and crossover are splices. A candidate is always printed to
 * the formula language and compiled by the IR (bk_form_parse): evaluation,
 * derivatives, op counts, stability and codegen stay one representation.
 *
 * Canonical form (bk_expr_canon) is what makes two spellings one candidate:
 * constants folded, subtrees that read no input collapsed to one parameter
 * (p0*p1, sqrt(p0), p0 + 2 are all "a constant to fit"), identities removed
 * (x*1, x + 0, --x, x - x, x/x, min(x, x), x - (-y)), literals a rounding
 * away from a simple value snapped to it (bk_expr_snap), operands of
 * commutative operations in a fixed order,
 * parameters renumbered p0, p1, ... in order of first appearance. The
 * canonical text is the candidate's identity: the cache hashes it, ties
 * between equally good candidates are broken on it.
 *
 * Start values: a PARAM node may carry the value its parameter had when its
 * tree was last fitted (the search writes a parent's fitted constants into
 * its nodes before mutating it), and canonicalisation and splicing carry it
 * along (a collapsed p0*p1 starts at their product, x - p becomes x + p
 * starting at -p, a literal made a parameter starts at the literal). A child
 * then starts its fit where its parent ended, as Operon and PySR do, instead
 * of from all ones, which for a grown form is often far from any good
 * minimum. The values never enter the canonical text, its order or its hash.
 */
#ifndef FIT_EXPR_H
#define FIT_EXPR_H

#include "brdf.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" { /* C linkage for a C++ program (tests/install.sh links one) */
#endif

/* Nodes of one candidate, at most (a candidate of the search is small: the
 * talk's V·F form is 9 nodes, Karis' env pair about 30). */
#define BK_EXPR_MAX 64

typedef struct bk_enode {
	int op;    /* a bk_op of brdf/ir.h: CONST, INPUT, PARAM or an operation;
	            * or BK_OP_COUNT + t: the registry term bk_term_at(t) */
	int slot;  /* INPUT: the bk_input; PARAM: the parameter index */
	double k;  /* CONST: the value; PARAM: where its fit starts, 0 for nowhere
	            * in particular (see "Start values" below) */
} bk_enode;

/* node[0] is the root; the operands of node i follow it in order, each a
 * whole subtree (prefix / Polish order). */
typedef struct bk_expr {
	int n;
	bk_enode node[BK_EXPR_MAX];
} bk_expr;

/* What a search may build from. ops: bit i set allows bk_op i (CONST, INPUT
 * and PARAM are leaves and always allowed); inputs: bit i allows bk_input i;
 * consts: the literals a leaf may be besides a parameter (e.g. 1, 2, 0.5). */
typedef struct bk_grammar {
	uint64_t ops;      /* bit op: operation op may appear (bk_grammar_default_ops, bk_grammar_parse_ops) */
	unsigned inputs;   /* bit i: input i (BK_IN_*) may appear as a leaf */
	double consts[8];  /* the constant leaves besides the parameters (1.0 in brdfkit search) */
	int nconsts;       /* how many of consts[] are used */
	int max_params; /* parameters in one candidate, <= BK_MAX_PARAMS */
	int max_size;   /* nodes, <= BK_EXPR_MAX */
} bk_grammar;

/* The default operation set of brdfkit search: + - * / sq sqrt rsqrt rcp
 * exp2 log2 min max saturate mix (sq is x*x: MUL with equal operands; the op
 * table has no SQ, so its bit in ops is bit 63, which no bk_op reaches; the
 * bit of MUL allows sq too). */
uint64_t bk_grammar_default_ops(void);
/* "+,-,*,/,sq,sqrt" -> the op bits; -1 with the bad name in err (also for
 * an empty item or an operation named twice). A
 * registry term of 1 to 3 arguments is allowed by its name ("F_schlick",
 * "D_ggx"): a node of op BK_OP_COUNT + t is bk_term_at(t), printed as the
 * call, which the IR inlines (its cost is its definition's, after folding
 * and sharing with the rest of the form); its bit in ops is its op. */
int bk_grammar_parse_ops(const char *list, uint64_t *ops, char *err, size_t errlen);
/* The grammar in words, for a certificate ("operations + - * / sq sqrt ...;
 * inputs LoH r a; literals 1; at most 4 parameters; no unary operation
 * directly over another"). Returns the length, or -1 if len is too small. */
int bk_grammar_describe(const bk_grammar *g, char *buf, size_t len);
/* 1 if op is one a tree may hold: an IR opcode, or a registry term of 1 to
 * 3 arguments (checkpoints are read through it). */
int bk_expr_op_valid(int op);
/* 0 if e is a tree the functions here may walk: 1 to BK_EXPR_MAX nodes,
 * every op valid, each node's operands whole subtrees that end exactly at
 * the last node, inputs below BK_IN_COUNT, parameters below BK_MAX_PARAMS,
 * literals and start values finite. Otherwise -1 and what is wrong in why
 * ("node 3: input 99 out of range"). What a checkpoint or a migrant holds is
 * checked with it before anything reads it. */
int bk_expr_valid(const bk_expr *e, char *why, size_t len);

/* Number of nodes of the subtree at node i (i itself included). */
int bk_expr_span(const bk_expr *e, int i);
/* Highest parameter index + 1. */
int bk_expr_nparams(const bk_expr *e);
/* Every parameter p_k of e renumbered p_(k + by): one tree's parameters after
 * another's, when two trees make one form. */
void bk_expr_shift_params(bk_expr *e, int by);
/* The grammar's size of e: one per node, except that sq(x) (MUL with two
 * equal operands) counts 1 + size(x), one operation as the grammar names it.
 * max_size and the sizes of bk_expr_enumerate are this measure. */
int bk_expr_size(const bk_expr *e);

/* A literal within BK_EXPR_SNAP_TOL (relative) of a non-zero multiple of
 * 1/BK_EXPR_SNAP_DENOM is that multiple: -0.4999999999999999 and
 * 2.0000000000000004 (a fold's or a parser's rounding) are -0.5 and 2, while
 * 0.49 and 0.1 stay (0.1 is 6.4/64, no multiple). 1e-12 is about 4,500
 * units in the last place of a value near 1: far above a fold's rounding,
 * far below any constant a person writes. */
#define BK_EXPR_SNAP_DENOM 64.0
#define BK_EXPR_SNAP_TOL 1e-12
double bk_expr_snap(double v);

/* Brings e to canonical form (see above). Returns 0, or -1 if the result
 * would not fit BK_EXPR_MAX (it never grows in practice). */
int bk_expr_canon(bk_expr *e);

/* The same, knowing which inputs (bits 1 << bk_input) the candidates may
 * read: where both r and a = r*r are among them, r*r is written a and
 * sqrt(a) is written r (r >= 0), so that one model has one spelling, the
 * cheaper one. The grammar's generators (enumeration, mutation, crossover,
 * neighbours) canonicalise with their grammar's inputs. */
int bk_expr_canon_in(bk_expr *e, unsigned inputs);

/* The formula-language text of e, parenthesised only where the language
 * needs it (a + (b + c) keeps its parentheses: it is not (a + b) + c in
 * floating point), MUL with equal operands as sq(x), literals with the
 * shortest of %.15g, %.16g, %.17g that reads back as the same double (0.1,
 * not 0.10000000000000001). Returns the length, or -1 if len is too small. */
int bk_expr_print(const bk_expr *e, char *buf, size_t len);

/* The tree of a compiled form (the IR's code expanded back into a tree:
 * MAD to a*b + c, shared subexpressions duplicated). Returns 0, or -1 when
 * the tree would exceed BK_EXPR_MAX nodes or the form uses an op the tree
 * cannot hold (e->n is then 0). The tree is not canonicalised: canon may
 * merge parameters (p0*p1 -> p0), so a catalog entry's defaults no longer
 * index it afterwards. */
int bk_expr_from_form(const bk_form *f, bk_expr *e);

/* 64-bit FNV-1a: of the canonical text (the cache key); of n bytes from h
 * (chained from BK_HASH_INIT: the search's options fingerprint). */
#define BK_HASH_INIT 14695981039346656037ull
uint64_t bk_expr_hash_text(const char *text);
uint64_t bk_hash_bytes(uint64_t h, const void *p, size_t n);

/* A set of 64-bit hashes (open addressing, doubling at half full; a hash of
 * 0 is stored as 1, 0 marking a free slot): the enumeration's and the
 * search's caches. Zero-initialise; h[0..cap) may be read (0: free). */
typedef struct bk_hashset {
	uint64_t *h;
	size_t cap, n;
} bk_hashset;
/* 1 if h was added, 0 if it was there, -1 when out of memory. */
int bk_hashset_add(bk_hashset *s, uint64_t h);
/* 1 if h is in the set. */
int bk_hashset_has(const bk_hashset *s, uint64_t h);
void bk_hashset_free(bk_hashset *s);

/* ---- generation ----------------------------------------------------------- */

/* Deterministic generator (splitmix64 seeding xoshiro256**): the same seed
 * gives the same stream on every machine. */
typedef struct bk_rng {
	uint64_t s[4];
} bk_rng;
void bk_rng_seed(bk_rng *r, uint64_t seed);
uint64_t bk_rng_next(bk_rng *r);
/* Uniform integer in [0, n), n >= 1 (unbiased: rejection). */
uint32_t bk_rng_below(bk_rng *r, uint32_t n);
/* Uniform double in [0, 1) with 53 random bits. */
double bk_rng_unit(bk_rng *r);

/* Every canonical candidate of exactly size nodes over the grammar, each
 * once, in a fixed order (bottom-up: built from the canonical candidates of
 * smaller sizes), canonical with the grammar's inputs (bk_expr_canon_in) and
 * without a unary operation directly over another (sqrt(rcp(x)),
 * log2(exp2(x)), sq(sqrt(x)): a nesting limit; at 5 nodes over NoV, r and a
 * they were over half the trees, and the search's enumeration budget ran out
 * in them before any binary or ternary tree of that size). fn returns
 * non-zero to stop. Returns the number of
 * candidates visited, or -1 (out of memory). */
typedef int (*bk_expr_visit)(void *ctx, const bk_expr *e);
long bk_expr_enumerate(const bk_grammar *g, int size, bk_expr_visit fn, void *ctx);

/* The raw trees of exactly size nodes over g (as ESR's tables count them):
 * every leaf (a parameter, each literal, each input) and every operation
 * (sq a unary one) at every node, before any canonical rule, nesting limit
 * or limit on parameters. A double: 2.3e8 trees of 8 nodes over five leaves. */
double bk_grammar_trees(const bk_grammar *g, int size);

/* The same trees drawn one at a time: every canonical candidate of size 1,
 * then of size 2, ... up to max_size (and the grammar's max_size), each in
 * bk_expr_enumerate's order. Nothing is built before it is drawn: memory
 * grows with the trees kept as operands of larger ones (those below the
 * last size: their nodes and a hash, about 30 + 16 x nodes bytes), never
 * with the sizes allowed; the trees of the last size are not kept, so they
 * cost nothing to draw. At most max_trees are kept: the enumeration ends
 * (cut) at the tree that would be one more. next returns the size of the
 * tree written to e, 0 after the last one, -1 when out of memory; count the
 * trees drawn; cut 1 when the limit ended it (the last size is then not
 * whole). */
typedef struct bk_expr_enum bk_expr_enum;
bk_expr_enum *bk_expr_enum_new(const bk_grammar *g, int max_size, long max_trees);
int bk_expr_enum_next(bk_expr_enum *E, bk_expr *e);
long bk_expr_enum_count(const bk_expr_enum *E);
int bk_expr_enum_cut(const bk_expr_enum *E);
void bk_expr_enum_free(bk_expr_enum *E);

/* One offspring of parent by one random mutation: replace a subtree by a
 * random small one, change an operation to another of the same arity,
 * replace a leaf, turn a literal into a parameter, wrap a subtree in a unary
 * operation, make a subtree an operand of a binary operation or of mix
 * beside random leaves or copies of the tree's own subtrees (x -> x op leaf,
 * y op x, mix(leaf, leaf', x)), or hoist an operand over its parent. The result is canonical
 * and within the grammar's limits. Returns 0, or -1 if no valid child was
 * found in a few tries (child is then a copy of parent). */
int bk_expr_mutate(const bk_grammar *g, bk_rng *r, const bk_expr *parent, bk_expr *child);
/* The neighbours of e by one free constant: p*x and p + x for every subtree
 * x of e (a fresh parameter p), canonical, within g, distinct, not e itself
 * (where x already has a free scale or offset canon folds p into it and the
 * child is e, left out). At most max written to out (2 x e->n suffice);
 * returns how many. A form one constant short of the target (p/(LoH^2 + a)
 * for p/(LoH^2 + p'*a)) is one of them: the search tries them for the best
 * of each cost level before random children (search.c). */
int bk_expr_neighbours(const bk_grammar *g, const bk_expr *e, bk_expr *out, int max);

/* The neighbours of e by a blend: mix(u, v, x) for every subtree x and every
 * ordered pair of distinct leaves u, v among the grammar's inputs, 1 and a
 * fresh parameter (f0 + (1 - f0)*x is mix(f0, 1, x); NoV*(1 - k) + k is
 * mix(NoV, 1, k)). Canonical, within g, distinct, not e; at most max. */
int bk_expr_mix_neighbours(const bk_grammar *g, const bk_expr *e, bk_expr *out, int max);

/* The neighbours of e by one input or a power, for each input of g in turn:
 * a parameter made affine in the input, p -> mix(p, p', in) (the constant
 * of a fit that depends on roughness: exp2(p*LoH) -> exp2(mix(p, p', LoH)*LoH),
 * Schlick's and Karis' forms); with the first input only, a subtree squared,
 * x -> sq(x) (powers: GGX's squared denominator, Schlick's (1 - x)^5); a
 * subtree times the input, x -> x*in (p/mix(a, p', NoV) -> NoV*p/...,
 * Smith's G1). Parameters are not squared or multiplied (canon folds them).
 * Canonical, within g, distinct, not e; at most max written to out
 * ((np + 2 n) x inputs suffice); returns how many. */
int bk_expr_input_neighbours(const bk_grammar *g, const bk_expr *e, bk_expr *out, int max);

/* Subtree crossover: a random subtree of a replaced by a random subtree of b.
 * Canonical, within limits; -1 as above. */
int bk_expr_crossover(const bk_grammar *g, bk_rng *r, const bk_expr *a, const bk_expr *b,
                      bk_expr *child);

#ifdef __cplusplus
}
#endif

#endif
