#!/usr/bin/python3
"""bench_search_scipy.py — the SciPy side of build/bench_search (make bench).

usage: python3 analysis/bench/bench_search_scipy.py build/bench_search_problem.txt

The file holds the screening samples of vf2d (LoH r a f0 y w per line) and
candidates of a brdfkit search ("np form" per line, the formula language).
Each candidate is translated to a NumPy expression once (not timed: a
SciPy user would write it by hand) and fitted with
scipy.optimize.least_squares(method='lm') from all ones, the residuals
sqrt(w)(f - y) as brdfkit's, the Jacobian by 2-point finite differences
(a formula string has no analytic Jacobian in SciPy), ftol and xtol 1e-8
(brdfkit's screening asks 1e-6 of the bridge, which asks 1/100 of that) and
at most 20 iterations' worth of evaluations, as the screening fits (SCREEN_ITERATIONS,
fit/search/screen.c). Prints
"seconds_per_fit S" (the mean over the candidates) on stdout.
"""
import re
import sys
import time

import numpy as np
from scipy.optimize import least_squares


def translate(form):
    """The formula language to a Python expression over NumPy arrays."""
    t = form.replace("^", "**")
    t = re.sub(r"\bp(\d+)\b", r"p[\1]", t)
    return t


NS = {
    "sq": lambda x: x * x,
    "sqrt": np.sqrt,
    "rsqrt": lambda x: 1.0 / np.sqrt(x),
    "rcp": lambda x: 1.0 / x,
    "exp2": np.exp2,
    "log2": np.log2,
    "exp": np.exp,
    "log": np.log,
    "pow": np.power,
    "min": np.minimum,
    "max": np.maximum,
    "saturate": lambda x: np.clip(x, 0.0, 1.0),
    "clamp": np.clip,
    "mix": lambda a, b, t: a + (b - a) * t,
    "abs": np.abs,
}


def main():
    lines = open(sys.argv[1]).read().split("\n")
    n = int(lines[0])
    data = np.array([[float(v) for v in l.split()] for l in lines[1:1 + n]])
    env = dict(NS)
    env.update(LoH=data[:, 0], VoH=data[:, 0], r=data[:, 1], a=data[:, 2], f0=data[:, 3])
    y, sw = data[:, 4], np.sqrt(data[:, 5])
    cands = []
    for l in lines[1 + n:]:
        if not l.strip():
            continue
        k, form = l.split(" ", 1)
        cands.append((int(k), compile(translate(form), "<form>", "eval")))
    np.seterr(all="ignore")
    total = 0.0
    for k, code in cands:
        def res(p, code=code):
            env["p"] = p
            f = eval(code, env)
            r = sw * (f - y)
            return np.where(np.isfinite(r), r, 1e30)
        t0 = time.perf_counter()
        try:
            least_squares(res, np.ones(k), method="lm", ftol=1e-8, xtol=1e-8, gtol=1e-12,
                          max_nfev=20 * (k + 1))
        except Exception:
            pass
        total += time.perf_counter() - t0
    print("seconds_per_fit %.9g" % (total / max(1, len(cands))))


if __name__ == "__main__":
    main()
