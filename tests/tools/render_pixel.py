#!/usr/bin/env python3
"""render_pixel.py — one pixel of `brdfkit render --term env` rebuilt from the
numbers brdfkit-render(1) states ("The scene, every number") alone, for
tests/cli_render_scene.sh: an independent implementation in Python (no code
of brdfkit's), with the candidate env_karis2014_split written from Karis'
published constants (B. Karis 2014, "Physically Based Shading on Mobile":
c0 = (-1, -0.0275, -0.572, 0.022), c1 = (1, 0.0425, 1.04, -0.04)), so that no
DFG integral is needed.

usage: render_pixel.py PAGE.scd W R1,R2,... X Y [NAME=VALUE ...]

Prints "R G B" of the candidate f32 image's pixel (X, Y), y down, to 9
digits. Every number of the recipe is in SCENE below with the text that
states it in PAGE: a number the page does not state (whitespace and line
breaks aside) exits 2 naming it. NAME=VALUE replaces one number (the test's
negative controls: a wrong number in the recipe must change the pixel).
"""
import math
import re
import struct
import sys

# name: (value, the words of the page that state it)
SCENE = {
    "albedo": ((0.30, 0.04, 0.03), "albedo (0.30, 0.04, 0.03)"),
    "f0_dielectric": (0.04, "f0 = 0.04 in each channel"),
    "f0_gold": ((1.00, 0.71, 0.29), "f0 = (1.00, 0.71, 0.29)"),
    "cam": (4.0, "C = (0, 0, 4)"),
    "radius": (0.45, "ρ = 0.45 c"),
    "light": ((0.5, 0.6, 0.62), "L = n(0.5, 0.6, 0.62)"),
    "E": ((3.0, 2.9, 2.7), "E = (3.0, 2.9, 2.7)"),
    "nov_min": (0.001, "NoV = max(N·V, 0.001)"),
    "blend": (0.05, "smoothstep(−0.05, 0.05, y(d))"),
    "glow": (8.0, "8 exp(200 (d·L − 1)) sun"),
    "glow_sharp": (200.0, "8 exp(200 (d·L − 1)) sun"),
    "patch": (4.0, "4 exp(40 (d·P − 1))"),
    "patch_sharp": (40.0, "4 exp(40 (d·P − 1))"),
    "ground": ((0.20, 0.16, 0.12), "ground = (0.20, 0.16, 0.12)"),
    "horizon": ((0.90, 0.85, 0.80), "horizon = (0.90, 0.85, 0.80)"),
    "zenith": ((0.20, 0.35, 0.80), "zenith = (0.20, 0.35, 0.80)"),
    "sun": ((1, 0.95, 0.85), "sun = (1, 0.95, 0.85)"),
    "P": ((-0.6, 0.4, 0.7), "P = n(−0.6, 0.4, 0.7)"),
    "frame_z": (0.9, "or (1, 0, 0) where |z(n)| > 0.9"),
    "grid_u": (24, "i = 0..23"),
    "grid_phi": (48, "j = 0..47"),
}


def f32(x):
    """x rounded to float, as the render stores each input."""
    return struct.unpack("f", struct.pack("f", x))[0]


def norm(v):
    length = math.sqrt(sum(c * c for c in v))
    return [c / length for c in v]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def main(argv):
    if len(argv) < 6:
        sys.stderr.write(__doc__)
        return 2
    page = " ".join(open(argv[1], encoding="utf-8").read().split())
    k = dict((n, v[0]) for n, v in SCENE.items())
    for n, (_, words) in SCENE.items():
        if " ".join(words.split()) not in page:
            sys.stderr.write("render_pixel: %s: the page does not state %s ('%s')\n" % (argv[1], n, words))
            return 2
    for a in argv[6:]:
        n, _, v = a.partition("=")
        if n not in k:
            sys.stderr.write("render_pixel: no number '%s'\n" % n)
            return 2
        k[n] = tuple(float(x) for x in v.split(",")) if "," in v else float(v)
    width, rough = int(argv[2]), [float(r) for r in argv[3].split(",")]
    x, y = int(argv[4]), int(argv[5])
    cell = width // len(rough)
    row, col = y // cell, x // cell
    r = rough[col]
    a = r * r

    L = norm(k["light"])
    P = norm(k["P"])

    def sky(d):
        s = math.sqrt(max(d[1], 0))
        tau = min(max((d[1] + k["blend"]) / (2 * k["blend"]), 0), 1)
        t = tau * tau * (3 - 2 * tau)
        glow = k["glow"] * math.exp(k["glow_sharp"] * (dot(d, L) - 1))
        patch = k["patch"] * math.exp(k["patch_sharp"] * (dot(d, P) - 1))
        out = []
        for c in range(3):
            sk = k["horizon"][c] + (k["zenith"][c] - k["horizon"][c]) * s
            out.append(k["ground"][c] + (sk - k["ground"][c]) * t + glow * k["sun"][c] + patch)
        return out

    def frame(n):
        up = [1, 0, 0] if abs(n[2]) > k["frame_z"] else [0, 0, 1]
        t1 = norm(cross(up, n))
        return t1, cross(n, t1)

    gu, gp = int(k["grid_u"]), int(k["grid_phi"])

    def prefilter(R):
        t1, t2 = frame(R)
        acc, wsum = [0.0, 0.0, 0.0], 0.0
        for i in range(gu):
            for j in range(gp):
                u1, u2 = (i + 0.5) / gu, (j + 0.5) / gp
                cos2 = (1 - u1) / (1 + (a * a - 1) * u1)
                ct, st, phi = math.sqrt(cos2), math.sqrt(max(0, 1 - cos2)), 2 * math.pi * u2
                h = [st * math.cos(phi) * t1[q] + st * math.sin(phi) * t2[q] + ct * R[q] for q in range(3)]
                rh = dot(R, h)
                l = [2 * rh * h[q] - R[q] for q in range(3)]
                w = dot(R, l)
                if w <= 0:
                    continue
                c = sky(l)
                acc = [acc[q] + w * c[q] for q in range(3)]
                wsum += w
        return [c / wsum for c in acc]

    def irradiance(N):
        t1, t2 = frame(N)
        acc = [0.0, 0.0, 0.0]
        for i in range(gu):
            for j in range(gp):
                u, phi = (i + 0.5) / gu, 2 * math.pi * (j + 0.5) / gp
                s = math.sqrt(u)
                d = [s * math.cos(phi) * t1[q] + s * math.sin(phi) * t2[q] + math.sqrt(1 - u) * N[q] for q in range(3)]
                c = sky(d)
                acc = [acc[q] + c[q] for q in range(3)]
        return [c / (gu * gp) for c in acc]

    cam = k["cam"]
    rad = k["radius"] * cell
    u = (x + 0.5 - (col + 0.5) * cell) / rad
    v = -(y + 0.5 - (row + 0.5) * cell) / rad
    t = 1 / math.sqrt(cam * cam - 1)
    D = norm([u * t, v * t, -1])
    C = [0, 0, cam]
    b = dot(C, D)
    disc = b * b - (cam * cam - 1)
    if disc <= 0:
        sys.stderr.write("render_pixel: (%d, %d) is background\n" % (x, y))
        return 2
    hit = -b - math.sqrt(disc)
    N = norm([C[q] + hit * D[q] for q in range(3)])
    V = [-c for c in D]
    H = norm([L[q] + V[q] for q in range(3)])
    nov = dot(N, V)
    R = [2 * nov * N[q] - V[q] for q in range(3)]
    nov = max(nov, k["nov_min"])
    nol, noh, loh = max(dot(N, L), 0), max(dot(N, H), 0), dot(L, H)
    pref = prefilter(R)
    irr = irradiance(N) if row == 0 else None
    f0s = [k["f0_dielectric"]] * 3 if row == 0 else list(k["f0_gold"])
    out = []
    for c in range(3):
        # every input as the render stores it: rounded to float
        NoV, NoL, NoH, LoH, rr, aa, f0 = (f32(z) for z in (nov, nol, noh, loh, r, a, f0s[c]))
        E, pr = f32(k["E"][c]), f32(pref[c])
        diff = f32(k["albedo"][c] * (k["E"][c] * nol / math.pi + irr[c])) if row == 0 else 0.0
        spec = 0.0
        if NoL > 0:
            Dg = aa * aa / (math.pi * (NoH * NoH * (aa * aa - 1) + 1) ** 2)
            Vs = 0.5 / (NoL * math.sqrt(NoV * NoV * (1 - aa * aa) + aa * aa) +
                        NoV * math.sqrt(NoL * NoL * (1 - aa * aa) + aa * aa))
            F = f0 + (1 - f0) * (1 - LoH) ** 5
            spec = Dg * Vs * F * NoL * E
        # Karis' EnvBRDFApprox, split: A and B from the published constants
        c0, c1 = (-1, -0.0275, -0.572, 0.022), (1, 0.0425, 1.04, -0.04)
        q = [rr * c0[i] + c1[i] for i in range(4)]
        a004 = min(q[0] * q[0], 2 ** (-9.28 * NoV)) * q[0] + q[1]
        A, B = -1.04 * a004 + q[2], 1.04 * a004 + q[3]
        out.append(f32((spec + pr * (f0 * A + B)) + diff))
    print("%.9g %.9g %.9g" % tuple(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
