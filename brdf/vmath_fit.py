#!/usr/bin/env python3
"""vmath_fit.py — the minimax coefficients of brdf/vmath.c, fitted here.

    python3 brdf/vmath_fit.py      (needs mpmath; prints the C constants)

A plain Remez exchange in 60-digit arithmetic (mpmath), weighted so that the
error minimised is the RELATIVE error of what vmath.c computes:

  exp2: 2^r ~ 1 + r*q(r) on |r| <= 1/2 (r = x - round(x)); q of degree NE-1
        fits g(r) = (2^r - 1)/r with weight |r|/2^r, so the constant term of
        the whole polynomial is exactly 1 (exp2 of an integer is exact).
  log2: log2(m) = s*Q(s^2), s = (m - 1)/(m + 1), m in [sqrt(1/2), sqrt(2));
        Q of degree NL-1 in z = s^2 fits (2/ln 2) atanh(sqrt z)/sqrt z with
        weight 1/Q itself (log2(1) = 0 exactly: s = 0).

The coefficients are then rounded to double and the error measured again
with the rounded ones (what the C uses); both figures are printed.
"""
import mpmath as mp

mp.mp.dps = 60
NE = 8  # exp2: q of degree 7, p = 1 + r*q of degree 8
NL = 6  # log2: Q of degree 5 in s^2 (s^11)


def remez(f, w, a, b, n, iters=30, grid=6000):
    """Coefficients c[0..n-1] of the polynomial of degree n-1 minimising
    max |w(x) (sum c_j x^j - f(x))| on [a, b], and that maximum."""
    m = n + 1  # reference points
    # start: Chebyshev extrema, nudged off 0 (where the exp2 weight vanishes)
    ref = [(a + b) / 2 + (b - a) / 2 * mp.cos(mp.pi * (m - 1 - i) / (m - 1)) for i in range(m)]
    ref = [x + mp.mpf('1e-3') if abs(x) < mp.mpf('1e-6') else x for x in ref]
    xs = [a + (b - a) * mp.mpf(i) / grid for i in range(grid + 1)]
    for _ in range(iters):
        A = mp.matrix(m, m)
        rhs = mp.matrix(m, 1)
        for i, x in enumerate(ref):
            wx = w(x)
            for j in range(n):
                A[i, j] = wx * x ** j
            A[i, n] = (-1) ** i
            rhs[i] = wx * f(x)
        sol = mp.lu_solve(A, rhs)
        c = [sol[j] for j in range(n)]
        err = lambda x: w(x) * (mp.polyval(c[::-1], x) - f(x))
        es = [err(x) for x in xs]
        # one extremum per run of equal sign, the largest of each run
        runs, cur = [], None
        for x, e in zip(xs, es):
            s = e > 0
            if cur is None or s != cur[0]:
                runs.append([s, x, e])
                cur = runs[-1]
            elif abs(e) > abs(cur[2]):
                cur[1], cur[2] = x, e
        runs = [r for r in runs if abs(r[2]) > 0]
        # keep the m consecutive runs with the largest smallest extremum
        if len(runs) >= m:
            best = max(range(len(runs) - m + 1), key=lambda s: min(abs(r[2]) for r in runs[s:s + m]))
            ref = [r[1] for r in runs[best:best + m]]
    return c, max(abs(e) for e in es)


def exp2_fit():
    f = lambda r: (mp.power(2, r) - 1) / r if r != 0 else mp.log(2)
    w = lambda r: abs(r) / mp.power(2, r)
    return remez(f, w, mp.mpf(-0.5), mp.mpf(0.5), NE)


# the largest s^2 of m in [0x3f3504f3 as a float, twice that): above
# ((sqrt(2) - 1)/(sqrt(2) + 1))^2 by a margin
ZMAX = mp.mpf('0.02944')


def log2_fit():
    def Q(z):
        if z == 0:
            return 2 / mp.log(2)
        s = mp.sqrt(z)
        return 2 * mp.atanh(s) / s / mp.log(2)
    return remez(Q, lambda z: 1 / Q(z), mp.mpf(0), ZMAX, NL)


def rounded_error(c, f, w, a, b, grid=20000):
    cd = [mp.mpf(float(x)) for x in c]
    return max(abs(w(x) * (mp.polyval(cd[::-1], x) - f(x)))
               for x in (a + (b - a) * mp.mpf(i) / grid for i in range(grid + 1)))


def main():
    c, e = exp2_fit()
    f = lambda r: (mp.power(2, r) - 1) / r if r != 0 else mp.log(2)
    w = lambda r: abs(r) / mp.power(2, r)
    er = rounded_error(c, f, w, mp.mpf(-0.5), mp.mpf(0.5))
    print('/* exp2: 2^r = 1 + r*q(r), |r| <= 1/2; relative error %.3g (2^%.1f), %.3g with the doubles */'
          % (float(e), float(mp.log(e, 2)), float(er)))
    for j, x in enumerate(c):
        print('#define E%d %s' % (j, float(x).hex()))
    c, e = log2_fit()
    Q = lambda z: 2 * mp.atanh(mp.sqrt(z)) / mp.sqrt(z) / mp.log(2) if z != 0 else 2 / mp.log(2)
    er = rounded_error(c, Q, lambda z: 1 / Q(z), mp.mpf(0), ZMAX)
    print('/* log2: log2(m) = s*Q(s^2), s^2 <= %s; relative error %.3g (2^%.1f), %.3g with the doubles */'
          % (mp.nstr(ZMAX, 6), float(e), float(mp.log(e, 2)), float(er)))
    for j, x in enumerate(c):
        print('#define L%d %s' % (j, float(x).hex()))


if __name__ == '__main__':
    main()
