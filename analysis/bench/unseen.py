#!/usr/bin/env python3
"""unseen.py -- the unseen suite of bench_recovery (issue 38): forms nobody chose.

The planted suite (planted.txt) was written by hand from the families the
search was tuned on; a rate measured on it says little about forms outside
them. This script draws forms at random from the default grammar, with a
generator of its own (not the search's mutation or enumeration, which would
favour what the search makes), and writes them in planted.txt's format:

    python3 analysis/bench/unseen.py [--seed N] > analysis/bench/unseen.txt
    build/bench_recovery --file analysis/bench/unseen.txt --beyond 100000

Each form: one to three inputs of NoV, LoH, NoH, r (with a = r*r) and f0, on
[0, 1]; a random tree of 5 to 11 nodes (the grammar's measure: sq(x) is
1 + size(x)) of the default grammar's operations, no unary operation directly
over another (as the grammar says); constants of 3 significant digits and
magnitude 10^U(-1.5, 1.2), a quarter of them negative, at most 4 of them.
A draw is kept when, on a grid of 11 points per input (endpoints included):
every value is finite with |v| <= 1e4 (no division by zero, no square root
or logarithm of a negative anywhere); every input and every constant changes
some value (relative 1e-4: no dead input, no constant folded away by a min
or max); and the form is not constant. The stream is Python's Mersenne
Twister from SEED, so the file is the same bytes on any machine (make test's
python.sh checks that the committed file is this script's output).

The suite was drawn once, committed, and measured after (git log): change
the search to do better on it and it is no longer unseen; draw a new one
with another SEED instead.
"""
import math
import random
import sys

SEED = 20261130
COUNT = 20
INPUTS = ["NoV", "LoH", "NoH", "r", "f0"]
UNARY = [("sq", 4), ("sqrt", 3), ("rcp", 3), ("exp2", 3), ("rsqrt", 1), ("log2", 1), ("saturate", 1)]
BINARY = [("+", 5), ("-", 4), ("*", 6), ("/", 4), ("min", 1), ("max", 1)]
GRID = [i / 10 for i in range(11)]


def weighted(rng, items):
    total = sum(w for _, w in items)
    x = rng.randrange(total)
    for name, w in items:
        if x < w:
            return name
        x -= w
    raise AssertionError


def constant(rng):
    """A literal of 3 significant digits, magnitude 10^U(-1.5, 1.2)."""
    v = float("%.3g" % 10 ** rng.uniform(-1.5, 1.2))
    return -v if rng.random() < 0.25 else v


def grow(rng, size, leaves, nconst):
    """A tree of exactly `size` nodes: (op, children) or ('leaf', text)."""
    if size == 1:
        if nconst[0] < 4 and rng.random() < 0.35:
            nconst[0] += 1
            return ("const", constant(rng))
        if rng.random() < 0.08:
            return ("one", 1.0)
        return ("in", rng.choice(leaves))
    kinds = []
    if size >= 2:
        kinds.append(("unary", 3))
    if size >= 3:
        kinds.append(("binary", 6))
    if size >= 4:
        kinds.append(("mix", 1))
    kind = weighted(rng, kinds)
    if kind == "unary":
        op = weighted(rng, UNARY)
        child = grow(rng, size - 1, leaves, nconst)
        if child is None or child[0] in [u for u, _ in UNARY]:
            return None  # no unary directly over another
        return (op, [child])
    if kind == "binary":
        k = rng.randrange(1, size - 1)
        a = grow(rng, k, leaves, nconst)
        b = grow(rng, size - 1 - k, leaves, nconst)
        return None if a is None or b is None else (weighted(rng, BINARY), [a, b])
    k = rng.randrange(1, size - 2)
    m = rng.randrange(1, size - 1 - k)
    parts = [grow(rng, k, leaves, nconst), grow(rng, m, leaves, nconst), grow(rng, size - 1 - k - m, leaves, nconst)]
    return None if None in parts else ("mix", parts)


def text(t):
    op, arg = t
    if op == "const" or op == "one":
        return "%.3g" % arg if op == "const" else "1"
    if op == "in":
        return arg
    if op in ("+", "-", "*", "/"):
        return "(%s %s %s)" % (text(arg[0]), op, text(arg[1]))
    return "%s(%s)" % (op, ", ".join(text(a) for a in arg))


def value(t, x, scale=None, live=None):
    """t at inputs x; scale: (constant index, factor) multiplies one constant;
    live: collects, for each min, max and saturate (by id), which way it went."""
    counter = [0]

    def ev(t):
        op, arg = t
        if op == "const":
            i = counter[0]
            counter[0] += 1
            return arg * (scale[1] if scale and scale[0] == i else 1.0)
        if op == "one":
            return 1.0
        if op == "in":
            return x[arg]
        v = [ev(a) for a in arg]
        if op == "sq":
            return v[0] * v[0]
        if op == "sqrt":
            return math.sqrt(v[0])
        if op == "rsqrt":
            return 1 / math.sqrt(v[0])
        if op == "rcp":
            return 1 / v[0]
        if op == "exp2":
            return 2.0 ** v[0]
        if op == "log2":
            return math.log2(v[0])
        if live is not None and op == "saturate":
            live.setdefault(id(t), set()).add(v[0] < 0 or v[0] > 1)
        if live is not None and op in ("min", "max") and v[0] != v[1]:  # a tie takes neither side
            live.setdefault(id(t), set()).add((v[0] < v[1]) == (op == "min"))
        if op == "saturate":
            return min(max(v[0], 0.0), 1.0)
        if op == "+":
            return v[0] + v[1]
        if op == "-":
            return v[0] - v[1]
        if op == "*":
            return v[0] * v[1]
        if op == "/":
            return v[0] / v[1]
        if op == "min":
            return min(v[0], v[1])
        if op == "max":
            return max(v[0], v[1])
        return v[0] + (v[1] - v[0]) * v[2]  # mix(a, b, t), as brdfkit's IR

    return ev(t)


def points(domain):
    pts = [{}]
    for name in domain:
        pts = [dict(p, **{name: g}) for p in pts for g in GRID]
    for p in pts:
        if "r" in p:
            p["a"] = p["r"] * p["r"]
    return pts


def values(t, pts, scale=None, live=None):
    out = []
    for p in pts:
        try:
            v = value(t, p, scale, live)
        except (ValueError, ZeroDivisionError, OverflowError):
            return None
        if not math.isfinite(v) or abs(v) > 1e4:
            return None
        out.append(v)
    return out


def leaves_used(t, acc):
    op, arg = t
    if op == "in":
        acc.add("r" if arg == "a" else arg)
    elif op not in ("const", "one"):
        for a in arg:
            leaves_used(a, acc)
    return acc


def changes(a, b):
    """Whether some value moved by more than 1e-4 relative."""
    scale = max(1.0, max(abs(v) for v in a))
    return any(abs(x - y) > 1e-4 * scale for x, y in zip(a, b))


def degenerate(t):
    """A part that a person would have written shorter: an operation over
    constants alone (exp2(1.12), sq(0.892)), over two equal operands (f0 + f0,
    mix(x, x, t)), or a product or quotient by 1."""
    op, arg = t
    if op in ("const", "one", "in"):
        return False
    if not leaves_used(t, set()):
        return True
    if len(arg) >= 2 and arg[0] == arg[1]:
        return True
    if op in ("*", "/") and ("one", 1.0) in arg:
        return True
    return any(degenerate(a) for a in arg)


def acceptable(t, domain, nconst):
    if degenerate(t) or leaves_used(t, set()) != set(domain):
        return False
    pts = points(domain)
    live = {}
    base = values(t, pts, live=live)
    if base is None or not changes(base, [base[0]] * len(base)):
        return False
    if any(len(ways) < 2 for ways in live.values()):
        return False  # a min or max that takes one side only, a saturate that never clamps
    for i in range(nconst):  # every constant matters
        moved = values(t, pts, (i, 1.01))
        if moved is None or not changes(base, moved):
            return False
    for name in domain:  # every input matters, the others held
        for p in pts:
            q = dict(p, **{name: 1.0 - p[name]})
            if "r" in q:
                q["a"] = q["r"] * q["r"]
            try:
                if abs(value(t, q) - value(t, p)) > 1e-4 * max(1.0, abs(value(t, p))):
                    break
            except (ValueError, ZeroDivisionError, OverflowError):
                return False
        else:
            return False
    return True


def main():
    seed = int(sys.argv[2]) if len(sys.argv) == 3 and sys.argv[1] == "--seed" else SEED
    rng = random.Random(seed)
    out = sys.stdout
    out.write("# unseen.txt -- the unseen suite of bench_recovery (issue 38), drawn by\n")
    out.write("# analysis/bench/unseen.py (SEED %d, %d forms): random trees of the default\n" % (seed, COUNT))
    out.write("# grammar, 5 to 11 nodes, kept when finite, non-constant and using every input\n")
    out.write("# and constant on [0, 1]. Written by the script, not by hand: do not edit.\n")
    out.write("# NAME | DOMAIN | FORM, as planted.txt.\n")
    kept = 0
    while kept < COUNT:
        ninputs = weighted(rng, [(1, 4), (2, 5), (3, 2)])
        domain = sorted(rng.sample(INPUTS, ninputs), key=INPUTS.index)
        leaves = domain + (["a"] if "r" in domain else [])
        size = rng.randrange(5, 12)
        nconst = [0]
        t = grow(rng, size, leaves, nconst)
        if t is None or not acceptable(t, domain, nconst[0]):
            continue
        kept += 1
        body = text(t)
        if t[0] in ("+", "-", "*", "/"):  # the outermost parentheses are not needed
            body = body[1:-1]
        out.write("u%02d | %s | %s\n" % (kept, ",".join("%s=0:1" % d for d in domain), body))


if __name__ == "__main__":
    main()
