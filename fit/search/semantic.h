/*
 * semantic.h — the `semantic` generator (internal to the search): semantic
 * backpropagation (Pawlak, Wieloch & Krawiec, "Semantic Backpropagation for
 * Designing Search Operators in Genetic Programming", IEEE TEVC 19(3),
 * 2015). For the best of each front level it asks, subtree by subtree, what
 * values that subtree would have to take for the whole form to equal the
 * target, at the fitted constants: the target's values are carried from the
 * root down the path to the subtree by inverting each operation on it, the
 * other operands held at their values (where an operation cannot be
 * inverted at a sample, as max under its other side or sqrt of a negative,
 * that sample is left free). The subtree is then replaced by the tree of a
 * library (every parameter-free tree of the grammar up to SEM_LIB_SIZE
 * nodes) whose values, scaled and offset, come nearest to those wanted,
 * written p + p'*g and fitted from the constants the inversion gave; or by
 * two of them, p + p'*g + p''*h, where together they leave less than half
 * of what the nearest one alone leaves (a subtree p2 sq(x) + p3 x is no one
 * library tree scaled). A walk's offers go out the best explained first
 * (the least share of the wanted values' variance left), not root first:
 * a generation's share is small, and the sites nearest the root took it
 * all before.
 *
 * Why: in the recovery suite's missed runs the right structure is one
 * subtree away from a level's best (GGX's a/sq(mix(1, a, sq(NoH))) from a
 * best with mix(p, a, mix(r, p', NoH)) in it), and no mutation draws that
 * subtree at that place but by luck. Deterministic (no random draws), not
 * for pairs (as the neighbours), each best walked once.
 */
#ifndef FIT_SEARCH_SEMANTIC_H
#define FIT_SEARCH_SEMANTIC_H

#include "search/search_int.h"

/* The generator; its state (the library, the bests walked) is made by
 * bk_sem_generator and freed by the search (g->free). NULL when out of
 * memory. */
int bk_sem_generator(bk_search_generator *g);

#endif
