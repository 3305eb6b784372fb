#!/usr/bin/python3
"""bench_fit_scipy.py — the SciPy side of build/bench_fit (make bench).

usage: /usr/bin/python3 analysis/bench/bench_fit_scipy.py build/bench_fit_NAME.bin [P0 P1 ...]

Driven by build/bench_fit over a pipe: after loading, checking the Jacobian
and one warm-up fit it prints "ready", answers each "run" line with the
seconds of one least_squares call, and at "end" (or end of input) prints its
summary. Run by hand (a terminal on stdin, or no P0...), it times the runs
itself and reports their median on stderr.

Fits the samples build/bench_fit writes with scipy.optimize.least_squares in
its best configuration for these problems: method 'lm' (MINPACK lmder), an
analytic Jacobian vectorised with NumPy, x_scale=1, the tolerances in the
file, from the start in the file. The residuals are sqrt(w)·(f - y), as
brdfkit's; the cost is least_squares' 1/2 Σ r², as Ceres'. Data-only
subexpressions are hoisted out of the residual (what a NumPy user would do):
vf2d's sqrt(w)·f0/(4 LoH²), env's Q shared by A and B (the two halves are the
same (NoV, r) cells, checked).

The analytic Jacobian is checked once against central differences at the
start and at the solution (assert), so that a wrong Jacobian cannot slip
into the comparison unnoticed. P0 P1 ...: brdfkit's solution, evaluated with
this residual as a check that both sides minimise the same function.

The summary is two lines: "cost nfev njev status cost_at_brdfkit_p
jacobian_check_error", then the solution.
"""
import sys
import time

import numpy as np
from scipy.optimize import least_squares

LN2 = float(np.log(2.0))


class Vf2d:
    """f = f0/(4 LoH² (r + p0)); df/dp0 = -f/(r + p0)."""

    def __init__(self, NoV, LoH, r, f0, y, sw):
        self.c = sw * f0 / (4.0 * LoH * LoH)
        self.r = r
        self.sy = sw * y
        self.J = np.empty((len(y), 1))

    def fun(self, p):
        return self.c / (self.r + p[0]) - self.sy

    def jac(self, p):
        d = self.r + p[0]
        self.J[:, 0] = -self.c / (d * d)
        return self.J


class EnvKaris:
    """Karis 2014 split sum, 11 parameters (fit/catalog.c, env_karis2014_split):
    T0 = p0 r + p4, T1 = p1 r + p5, E = exp2(p8 NoV), m = min(T0², E),
    Q = m T0 + T1, A = p9 Q + p2 r + p6, B = p10 Q + p3 r + p7.
    min() takes the branch the IR takes (brdf/ir_diff.c: T0² <= E -> T0²)."""

    def __init__(self, NoV, LoH, r, f0, y, sw, na):
        assert len(y) == 2 * na
        assert np.array_equal(NoV[:na], NoV[na:]) and np.array_equal(r[:na], r[na:])
        self.na = na
        self.NoV, self.r = NoV[:na].copy(), r[:na].copy()
        self.ln2NoV = LN2 * self.NoV
        self.swA, self.swB = sw[:na].copy(), sw[na:].copy()
        self.syA, self.syB = self.swA * y[:na], self.swB * y[na:]
        self.res = np.empty(2 * na)
        self.J = np.zeros((2 * na, 11))  # the structural zeros stay zero

    def _q(self, p):
        T0 = p[0] * self.r + p[4]
        T1 = p[1] * self.r + p[5]
        E = np.exp2(p[8] * self.NoV)
        S = T0 * T0
        lo = S <= E
        return T0, E, S, lo, np.where(lo, S, E) * T0 + T1

    def fun(self, p):
        Q = self._q(p)[4]
        na, r = self.na, self.r
        self.res[:na] = self.swA * (p[9] * Q + p[2] * r + p[6]) - self.syA
        self.res[na:] = self.swB * (p[10] * Q + p[3] * r + p[7]) - self.syB
        return self.res.copy()  # MINPACK may keep the previous vector

    def jac(self, p):
        T0, E, S, lo, Q = self._q(p)
        r, na, J = self.r, self.na, self.J
        dT0 = np.where(lo, 3.0 * S, E)                 # dQ/dT0
        d8 = np.where(lo, 0.0, self.ln2NoV * E * T0)   # dQ/dp8
        for rows, sw, k, lin_r, lin_1, own in ((slice(0, na), self.swA, p[9], 2, 6, 9),
                                               (slice(na, 2 * na), self.swB, p[10], 3, 7, 10)):
            ks = k * sw
            J[rows, 0] = ks * dT0 * r
            J[rows, 1] = ks * r
            J[rows, 4] = ks * dT0
            J[rows, 5] = ks
            J[rows, 8] = ks * d8
            J[rows, own] = sw * Q
            J[rows, lin_r] = sw * r
            J[rows, lin_1] = sw
        return J


def load(path):
    raw = np.fromfile(path, dtype='<f8')
    h = raw[:32]
    assert h[0] == 1.0, "not a bench_fit sample file (or not little-endian)"
    fmt, n, na, npar = int(h[1]), int(h[2]), int(h[3]), int(h[4])
    ftol, xtol, gtol, reps = float(h[5]), float(h[6]), float(h[7]), int(h[9])
    x0 = h[16:16 + npar].copy()
    cols = raw[32:].reshape(6, n)
    NoV, LoH, r, f0, y, sw = (np.ascontiguousarray(c) for c in cols)
    prob = Vf2d(NoV, LoH, r, f0, y, sw) if fmt == 0 else EnvKaris(NoV, LoH, r, f0, y, sw, na)
    return prob, x0, ftol, xtol, gtol, reps


def jacobian_error(prob, p):
    """Largest column-relative difference between the analytic Jacobian and
    central differences (a few samples may sit within h of min()'s kink: they
    move a column by O(h), far below the threshold)."""
    J = np.array(prob.jac(p))
    worst = 0.0
    for j in range(len(p)):
        h = 1e-6 * max(1.0, abs(p[j]))
        a, b = p.copy(), p.copy()
        a[j] += h
        b[j] -= h
        fd = (prob.fun(a) - prob.fun(b)) / (2 * h)
        worst = max(worst, np.linalg.norm(J[:, j] - fd) / max(np.linalg.norm(J[:, j]), 1e-300))
    return worst


def main():
    prob, x0, ftol, xtol, gtol, reps = load(sys.argv[1])
    p_bk = np.array([float(v) for v in sys.argv[2:]]) if len(sys.argv) > 2 else None
    err0 = jacobian_error(prob, x0)
    assert err0 < 1e-6, f"analytic Jacobian disagrees with central differences at the start: {err0:.3g}"

    def fit():
        return least_squares(prob.fun, x0, jac=prob.jac, method='lm', ftol=ftol, xtol=xtol, gtol=gtol,
                             x_scale=1.0)

    res = fit()  # warm-up, as the C side
    if sys.stdin.isatty() or len(sys.argv) < 3:  # by hand: time it here
        times = []
        for _ in range(reps):
            t = time.perf_counter()
            res = fit()
            times.append(time.perf_counter() - t)
        print(f"median of {reps}: {1e3 * sorted(times)[reps // 2]:.3f} ms, cost {res.cost:.17g}", file=sys.stderr)
    else:
        print("ready", flush=True)
        for line in sys.stdin:
            if line.strip() != "run":
                break
            t = time.perf_counter()
            res = fit()
            print(f"{time.perf_counter() - t:.9g}", flush=True)
    err1 = jacobian_error(prob, res.x)
    assert err1 < 1e-6, f"analytic Jacobian disagrees with central differences at the solution: {err1:.3g}"
    r_bk = prob.fun(p_bk) if p_bk is not None else np.array([np.nan])
    cost_bk = 0.5 * float(np.dot(r_bk, r_bk))
    njev = res.njev if res.njev is not None else -1
    print(f"{res.cost:.17g} {res.nfev} {njev} {res.status} {cost_bk:.17g} {max(err0, err1):.3g}")
    print(" ".join(f"{v:.17g}" for v in res.x), flush=True)


if __name__ == "__main__":
    main()
