#!/bin/sh
# python.sh — `import brdfkit` (analysis/python/brdfkit) over the libraries
# `make install` installed into a scratch PREFIX, with Debian's /usr/bin/python3
# (python3-cffi, python3-numpy, python3-pandas), against the command-line tool:
#   - Form.catalog("vf_talk_r").eval on a NumPy array, in f64, f32 and f16, is
#     `brdfkit eval vf_talk_r ...` at each point, to the digits it prints (f64
#     17, f32 9, f16 5: the same value once rounded to the CLI's digits and to
#     the precision), and f64 is the talk's f0/(4 LoH^2 (r + 0.5)) by hand;
#   - a front member (read_front, member) evaluated in f64 is `brdfkit eval
#     FRONT.csv:MEMBER` (results/search/vf2d/front.csv, committed); eval's
#     vs= (f16 against a target, each mad in the order farther from it) is
#     never nearer the target than plain f16 for a one-mad form, and differs
#     from it somewhere (the control); vs outside f16 is refused;
#   - fit() of p0 + p1 LoH + p2 LoH^2 to exp(-2 LoH) on [0, 1], and of the
#     catalog's vf_talk_r to the built-in vf2d target: rmse and constants are
#     brdfkit fit's, read from its metrics.csv and coefficients.csv by column
#     name (build/csvget);
#   - search() of a planted 0.45 LoH^2 + 0.2: run to its budget it finds the
#     plant (rmse below 1e-9); stopped by its stop callback after 200 fits it
#     returns early (evals below the budget), its progress callback heard; an
#     exception in either callback stops it and is raised, not swallowed;
#   - errors: a parse error and an unknown catalog name raise ValueError with
#     the library's message, the one the CLI prints;
#   - cffi's sizes and offsets of the structures the module fills or reads are
#     the C compiler's (a program of the installed headers prints them).
# - and first, without the module: analysis/bench/unseen.txt (bench_recovery's
#   unseen suite) is analysis/bench/unseen.py's output, byte for byte.
# Negative controls, each showing a check can fail: unseen.py at another seed
# draws another suite; the comparison rejects the
# f16 value of another point and a fit of another form; the layout check
# rejects one wrong offset; the search's
# early-stop check rejects the unstopped run; the import fails, naming them,
# from a prefix with the headers and no libraries (BRDFKIT_PREFIX).
# usage: sh tests/python.sh path/to/brdfkit
set -u
BK=${1:?usage: python.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$PWD/$BK ;; esac
ROOT=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d /tmp/bk_python_XXXXXX)
trap 'rm -rf "$T"' EXIT
CSVGET=$ROOT/build/csvget
. "$ROOT/tests/lib.sh"
PY=/usr/bin/python3
# bench_recovery's unseen suite is analysis/bench/unseen.py's output, byte for
# byte (drawn, not written by hand); control: another seed draws other forms
pre=0
$PY "$ROOT/analysis/bench/unseen.py" | cmp -s - "$ROOT/analysis/bench/unseen.txt" && pre=$((pre + 1)) ||
	{ echo "FAIL: analysis/bench/unseen.txt is not analysis/bench/unseen.py's output"; exit 1; }
$PY "$ROOT/analysis/bench/unseen.py" --seed 1 | cmp -s - "$ROOT/analysis/bench/unseen.txt" &&
	{ echo "FAIL: unseen.py --seed 1 drew the committed suite"; exit 1; } || pre=$((pre + 1))
if ! $PY -c 'import cffi, numpy, pandas' 2>/dev/null; then
	echo "python.sh: skipped: /usr/bin/python3 without cffi, numpy or pandas (apt-get install python3-cffi python3-numpy python3-pandas)"
	exit 0
fi
pass=$pre fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

U=$T/usr
(cd "$ROOT" && ${MAKE:-make} -s install PREFIX="$U" >"$T/install.log" 2>&1) || { cat "$T/install.log"; bad "make install PREFIX=$U"; }
export PYTHONPATH="$U/lib/python3/dist-packages"
[ -f "$PYTHONPATH/brdfkit/_decls.h" ] && [ -f "$PYTHONPATH/brdfkit/_config.py" ] && ok || bad "the module's installed files"

# the CLI's numbers
X="0.3 0.55 0.8 1"
for x in $X; do "$BK" eval --quiet vf_talk_r LoH=$x r=0.3 f0=0.04 >"$T/eval.$x" || bad "brdfkit eval at LoH=$x"; done
"$BK" eval --quiet "$ROOT/results/search/vf2d/front.csv:search_vf2d_6" LoH=0.6 r=0.3 f0=0.04 >"$T/member" ||
	bad "brdfkit eval of a front member"
"$BK" fit --quiet --target form --target-form 'exp(-2*LoH)' --domain LoH=0:1 --form 'p0 + p1*LoH + p2*LoH*LoH' \
	p0=1 p1=1 p2=1 --out "$T/fit" >/dev/null || bad "brdfkit fit"
for k in cost rmse max_abs; do csv_where "$T/fit/metrics.csv" constants fitted $k >"$T/fit.$k" || bad "metrics.csv $k"; done
for j in 0 1 2; do csv_where "$T/fit/coefficients.csv" parameter p$j value >"$T/fit.p$j" || bad "coefficients.csv p$j"; done
"$BK" fit --quiet --target vf2d --form vf_talk_r --out "$T/fitvf" >/dev/null || bad "brdfkit fit --target vf2d"
csv_where "$T/fitvf/metrics.csv" constants fitted rmse >"$T/fitvf.rmse" || bad "vf2d metrics.csv rmse"
csv_where "$T/fitvf/coefficients.csv" parameter p0 value >"$T/fitvf.p0" || bad "vf2d coefficients.csv p0"
"$BK" eval --quiet 'p0+' >/dev/null 2>"$T/parse.err"

# the C compiler's layout of the structures the module fills or reads, for
# cffi's own (ABI mode computes it; a mismatch would corrupt silently)
cat >"$T/layout.c" <<'C'
#include <brdfkit/catalog.h>
#include <brdfkit/search.h>
#include <stddef.h>
#include <stdio.h>
#define S(T) printf("sizeof %s %zu\n", #T, sizeof(T))
#define O(T, F) printf("offsetof %s %s %zu\n", #T, #F, offsetof(T, F))
int main(void)
{
	S(bk_form_error), S(bk_target_options), S(bk_samples), S(bk_fit_spec), S(bk_fit_result), S(bk_fit_metrics);
	S(bk_search_options), S(bk_search_callbacks), S(bk_cand), S(bk_grammar), S(bk_catalog_entry);
	O(bk_target_options, form_text), O(bk_target_options, dom_hi), O(bk_fit_spec, digits), O(bk_fit_result, fitted);
	O(bk_fit_result, message), O(bk_search_options, evals), O(bk_search_options, threads), O(bk_search_options, grammar);
	O(bk_cand, p), O(bk_cand, cost), O(bk_cand, err), O(bk_cand, found_at), O(bk_search_callbacks, progress_every);
	return 0;
}
C
cc -std=c11 -I"$U/include" "$T/layout.c" -o "$T/layout" && "$T/layout" >"$T/layout.txt" || bad "the layout program"
cat >"$T/layout.py" <<'PY'
import sys
from brdfkit import ffi
bad = 0
for line in open(sys.argv[1]):
    w = line.split()
    mine = ffi.sizeof(w[1]) if w[0] == "sizeof" else ffi.offsetof(w[1], w[2])
    if mine != int(w[-1]):
        print("%s: cffi %d, C %s" % (" ".join(w[:-1]), mine, w[-1]))
        bad = 1
sys.exit(bad)
PY
n=$(wc -l <"$T/layout.txt")
$PY "$T/layout.py" "$T/layout.txt" && [ "$n" -ge 20 ] && ok || bad "cffi's layouts are not the C compiler's ($n read)"
# negative control: the last offset with a digit put in front
sed '$s/ \([0-9]*\)$/ 1\1/' "$T/layout.txt" >"$T/layout.bad"
! $PY "$T/layout.py" "$T/layout.bad" >/dev/null && ok || bad "a wrong layout passed"

cat >"$T/check.py" <<'PY'
import os, sys
import numpy as np
import brdfkit

T, X = sys.argv[1], [float(x) for x in sys.argv[2].split()]
ROOT = sys.argv[3]
out = []
def check(name, cond, detail=""):
    out.append(("ok " if cond else "FAIL ") + name + ("" if cond else ": " + detail))

def cli(path):  # "f64 V\nf32 V\nf16 V" -> {precision: text}
    return dict(line.split() for line in open(path))

# same(prec, mine, text): my value, rounded to the precision, and to the digits
# the CLI printed, is the CLI's
def same(prec, mine, text):
    if prec == "f64":
        return float(text) == float(mine)
    t = np.float32 if prec == "f32" else np.float16
    digits = len(text.replace("-", "").replace(".", "").lstrip("0").split("e")[0])
    return t(float(text)) == t(mine) and float("%.*g" % (digits, t(mine))) == float(text)

f = brdfkit.Form.catalog("vf_talk_r")
check("catalog form", f.text == "f0/(4*LoH*LoH*(r + p0))" and f.params == [0.5], repr((f.text, f.params)))
x = np.array(X)
for prec in ("f64", "f32", "f16"):
    v = f.eval(LoH=x, r=0.3, f0=0.04, precision=prec)
    for i, xi in enumerate(X):
        c = cli(os.path.join(T, "eval.%g" % xi))[prec]
        check("eval %s LoH=%g" % (prec, xi), v.shape == x.shape and same(prec, v[i], c), "%r vs the CLI's %s" % (v[i], c))
# negative control: the f16 value of the next point is not this point's
c = cli(os.path.join(T, "eval.%g" % X[0]))["f16"]
check("control: another point's f16 differs", not same("f16", f.eval(LoH=X[1], r=0.3, f0=0.04, precision="f16"), c))
# by hand: the talk's printed form, f64 within an ulp or two
hand = 0.04 / (4 * x * x * (0.3 + 0.5))
check("eval f64 by hand", np.all(np.abs(f.eval(LoH=x, r=0.3, f0=0.04) - hand) <= 4e-16 * hand))
# half is not single: the f16 values are not the f64 ones rounded once
check("f16 rounds every operation", np.any(f.eval(LoH=x, r=0.3, f0=0.04, precision="f16") != hand.astype(np.float16)))

front = brdfkit.read_front(os.path.join(ROOT, "results/search/vf2d/front.csv"))
m = brdfkit.member(front, "search_vf2d_6")
c = cli(os.path.join(T, "member"))["f64"]
check("front member", same("f64", m.eval(LoH=0.6, r=0.3, f0=0.04), c), "%r vs %s" % (m.eval(LoH=0.6, r=0.3, f0=0.04), c))
check("front columns by name", {"name", "form", "cost", "max_abs"} <= set(front.columns) and front.attrs["comments"])
# f16 as a front scores it (vs=, bk_form_eval_half_vs): a mad in the order
# farther from the target, so with one mad never nearer it than bk_form_eval's
# order at any sample; the control: the two orders differ somewhere
xs = np.linspace(0.32, 1, 4001)
y = np.exp(-2 * xs)
g = brdfkit.Form("p0*LoH + p1")
plain = g.eval([-0.8642, 0.9876], LoH=xs, precision="f16")
worse = g.eval([-0.8642, 0.9876], LoH=xs, precision="f16", vs=y)
check("vs: never nearer the target", np.all(np.abs(worse - y) >= np.abs(plain - y)))
check("control: vs takes the other order somewhere", np.any(worse != plain))
try:
    g.eval([1, 0], LoH=xs, vs=y)
    check("vs in f64 refused", False, "no error")
except ValueError as e:
    check("vs in f64 refused", "only with precision f16" in str(e), str(e))

def near(a, text):  # the CLI prints 9 significant digits
    return abs(a - float(text)) <= 1e-8 * abs(float(text))
rd = lambda k: open(os.path.join(T, "fit." + k)).read().strip()
r = brdfkit.fit("p0 + p1*LoH + p2*LoH*LoH", "exp(-2*LoH)", {"LoH": (0, 1)})
check("fit converged", r.converged, r.message)
for k in ("cost", "rmse", "max_abs"):
    check("fit %s" % k, near(getattr(r, k), rd(k)), "%r vs %s" % (getattr(r, k), rd(k)))
for j in range(3):
    check("fit p%d" % j, float("%.5g" % r.params[j]) == float(rd("p%d" % j)), "%r vs %s" % (r.params[j], rd("p%d" % j)))
# a built-in target by name, the catalog's form from its published constant
rv = brdfkit.fit("vf_talk_r", "vf2d")
vf = lambda k: open(os.path.join(T, "fitvf." + k)).read().strip()
check("fit vf2d rmse", near(rv.rmse, vf("rmse")), "%r vs %s" % (rv.rmse, vf("rmse")))
check("fit vf2d p0", float("%.6g" % rv.params[0]) == float(vf("p0")), "%r vs %s" % (rv.params[0], vf("p0")))
r2 = brdfkit.fit("p0 + p1*LoH", "exp(-2*LoH)", {"LoH": (0, 1)})
check("control: another form's fit differs", not near(r2.rmse, rd("rmse")))

heard = []
full = brdfkit.search("0.45*LoH*LoH + 0.2", {"LoH": (0, 1)}, evals=600, max_params=2, max_size=9, threads=2)
best = full.iloc[-1]
check("search finds the plant", best["rmse"] < 1e-9 and full.attrs["evals"] >= 600, repr(best.to_dict()))
early = brdfkit.search("0.45*LoH*LoH + 0.2", {"LoH": (0, 1)}, evals=600, max_params=2, max_size=9, threads=2,
                       progress=heard.append, stop=lambda n: n >= 200)
stopped = lambda df: 200 <= df.attrs["evals"] < 600
check("search stopped by the callback", stopped(early) and heard, "%r %r" % (early.attrs, heard))
check("control: the unstopped run is not stopped", not stopped(full))
def boom(n):
    raise RuntimeError("boom")
for kw in ({"stop": boom}, {"progress": boom}):
    try:
        brdfkit.search("0.45*LoH*LoH + 0.2", {"LoH": (0, 1)}, evals=600, **kw)
        check("a callback's exception raised (%s)" % list(kw)[0], False, "swallowed")
    except RuntimeError:
        check("a callback's exception raised (%s)" % list(kw)[0], True)

def raises(fn, text):
    try:
        fn()
    except ValueError as e:
        return text in str(e)
    return False
check("unknown catalog name", raises(lambda: brdfkit.Form.catalog("zz_none"), "unknown catalog form 'zz_none'"))
err = open(os.path.join(T, "parse.err")).read().split("form:", 1)[-1].strip()
check("parse error as the CLI's", err and raises(lambda: brdfkit.Form("p0+"), err), err)
print("\n".join(out))
PY
$PY "$T/check.py" "$T" "$X" "$ROOT" >"$T/check.out" 2>&1 || bad "check.py: $(tail -5 "$T/check.out")"
while read -r w rest; do
	case $w in ok) ok ;; FAIL) bad "$rest" ;; esac
done <"$T/check.out"
[ "$(grep -c '^ok ' "$T/check.out")" -ge 20 ] && ok || bad "fewer than 20 checks ran: $(tail -3 "$T/check.out")"
# the import from BRDFKIT_PREFIX (declarations preprocessed from its headers);
# negative control: a prefix with the headers and no libraries fails, naming them
BRDFKIT_PREFIX="$U" $PY -c 'import brdfkit; print(brdfkit.Form.catalog("vf_talk_r").params)' >"$T/imp.out" 2>&1 &&
	[ "$(cat "$T/imp.out")" = "[0.5]" ] && ok || bad "import with BRDFKIT_PREFIX: $(tail -2 "$T/imp.out")"
mkdir -p "$T/empty/lib" && cp -R "$U/include" "$T/empty/"
! BRDFKIT_PREFIX="$T/empty" $PY -c 'import brdfkit' >"$T/imp.out" 2>&1 && grep -q "no libbrdf.so.\* in $T/empty/lib" "$T/imp.out" &&
	ok || bad "the import without libraries: $(tail -2 "$T/imp.out")"

echo "python: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
