#!/bin/sh
# cli_formula.sh — codegen --lang sympy and --lang latex (issue 40 item 4).
# The SymPy snippet is executed by Debian's python3 + sympy and evaluated at
# sample points in 30 digits: an evaluator independent of brdfkit's, held to
# brdfkit eval's f64 value (relative 1e-9: both are exact to ~1e-16, the slack
# is the points' decimal inputs through the forms' condition numbers). The
# forms cover every operation and catalog, front and user forms; the negative
# control perturbs each snippet by one part in 1e6 and must be caught. LaTeX
# is checked without a TeX engine: balanced braces and \left/\right, and a
# known form's exact text.
# usage: sh tests/cli_formula.sh path/to/brdfkit   (from the repository root)
set -u
BK=${1:?usage: sh tests/cli_formula.sh path/to/brdfkit}
T=$(mktemp -d /tmp/bk_cli_formula_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

if ! /usr/bin/python3 -c 'import sympy' 2>/dev/null; then
	echo "cli_formula: python3-sympy is missing (make deps installs it)" >&2
	exit 1
fi

# The checker, one python3 for every form (sympy's import is most of a
# start): each line of LIST is "N SNIPPET POINTS"; the snippet is executed in
# a scope of its own, `fitted` evaluated at each point (NAME=VALUE words of
# the inputs it reads) and compared with the expected value on the same line,
# then again scaled by 1 + 1e-6 (the control). Printed for each N: "N plain
# ok" or "N plain bad", then "N perturb ok" or "N perturb bad"; a failure's
# points and errors on lines "N plain:   ...".
cat >"$T/check.py" <<'EOF'
import sys
import traceback
import sympy as sp

def compare(n, mode, snippet, points):
    scope = {}
    exec(open(snippet).read(), scope)
    fitted = scope["fitted"]
    if mode == "perturb":
        fitted = fitted * (1 + sp.Rational(1, 10**6))
    names = {str(s): s for s in scope["inputs"]}
    bad = 0
    m = 0
    for line in open(points):
        words = line.split()
        if not words:
            continue
        want = float(words[0])
        subs = {names[k]: sp.Float(v, 30) for k, v in (w.split("=") for w in words[1:])}
        got = sp.N(fitted.subs(subs), 30)
        m += 1
        if not got.is_real or abs(float(got) - want) > 1e-9 * max(abs(want), 1e-12):
            print("%s %s:   at %s: sympy %s, brdfkit eval %r" % (n, mode, " ".join(words[1:]), got, want))
            bad += 1
    if m == 0:
        print("%s %s:   no point read" % (n, mode))
        return False
    return bad == 0

for line in open(sys.argv[1]):
    n, snippet, points = line.split()
    for mode in ("plain", "perturb"):
        try:
            good = compare(n, mode, snippet, points)
        except Exception:
            for t in traceback.format_exc().splitlines():
                print("%s %s:   %s" % (n, mode, t))
            good = False
        print("%s %s %s" % (n, mode, "ok" if good else "bad"))
EOF

# points FORM SNIPPET: "f64 NAME=VALUE..." lines of brdfkit eval at three
# points, over the inputs the snippet declares (a = r*r where both are read).
points() {
	_in=$(sed -n "s/^inputs = sp.symbols('\(.*\)', real=True, seq=True)$/\1/p" "$2")
	for _pt in "NoV=0.6 NoL=0.55 NoH=0.8 LoH=0.7 r=0.5 a=0.25 f0=0.04" \
	           "NoV=0.25 NoL=0.9 NoH=0.95 LoH=0.45 r=0.3 a=0.09 f0=0.5" \
	           "NoV=0.9 NoL=0.35 NoH=0.6 LoH=0.95 r=0.8 a=0.64 f0=0.9"; do
		_args=""
		for _w in $_pt; do
			case " $_in " in *" ${_w%%=*} "*) _args="$_args $_w" ;; esac
		done
		# shellcheck disable=SC2086 # NAME=VALUE words, no blanks
		_v=$("$BK" eval "$1" $_args | sed -n 's/^f64 //p')
		[ -n "$_v" ] || return 1
		echo "$_v$_args"
	done
}

# Forms: catalog entries (mix, exp2, pow, exp, log2, saturate, clamp, max,
# min, negative literals), front members pasted by name, and a user form with
# the operations left (rsqrt rcp sqrt log abs neg, clamp on parameters).
USER='rsqrt(NoV + p0) - rcp(LoH)*sqrt(r) + log(1 + abs(-NoV*p1)) - -LoH + clamp(NoV, p0, 0.8) + exp(-r)*pow(f0, 0.5)'
n=0
: >"$T/list"
for form in vf_talk_r v_hammon f_schlick_sg f_schlick_unreal_gated env_ross env_karis2014 env_lazarov2013 \
            env_materialx:A env_materialx:B dvf_unity_urp_half \
            results/search/vf2d/front.csv:search_vf2d_6 results/search/env/front.csv:search_env_3:A \
            "$USER"; do
	n=$((n + 1))
	printf '%s\n' "$form" >"$T/form$n"
	extra=""
	[ "$form" = "$USER" ] && extra="p0=0.1 p1=2"
	# shellcheck disable=SC2086 # parameter words, no blanks
	if ! "$BK" codegen --lang sympy "$form" $extra >"$T/f$n.py" 2>"$T/err"; then
		bad "codegen --lang sympy '$form' failed: $(cat "$T/err")"
		continue
	fi
	if [ -n "$extra" ]; then
		# shellcheck disable=SC2086
		points "$(printf '%s' "$form" | sed 's/p0/0.1/g; s/p1/2/g')" "$T/f$n.py" >"$T/p$n" || { bad "brdfkit eval '$form'"; continue; }
	else
		points "$form" "$T/f$n.py" >"$T/p$n" || { bad "brdfkit eval '$form'"; continue; }
	fi
	echo "$n $T/f$n.py $T/p$n" >>"$T/list"
done
/usr/bin/python3 "$T/check.py" "$T/list" >"$T/verdicts" 2>&1 || { bad "the sympy checker stopped:"; cat "$T/verdicts"; }
while read -r n _; do
	form=$(cat "$T/form$n")
	if grep -qx "$n plain ok" "$T/verdicts"; then ok; else bad "sympy != eval for '$form':"; grep "^$n plain:" "$T/verdicts"; fi
	# negative control: the same snippet off by one part in a million is caught
	if grep -qx "$n perturb bad" "$T/verdicts"; then ok; else bad "control: a perturbed '$form' passed the comparison"; fi
done <"$T/list"

# The snippet keeps the parameters symbolic and binds them in params: the
# expression of vf_talk_r is f0/(4 LoH^2 (r + p0)) with p0 = 0.5 (the catalog's).
"$BK" codegen --lang sympy vf_talk_r >"$T/v.py"
if /usr/bin/python3 - "$T/v.py" <<'EOF'
import sys
import sympy as sp
s = {}
exec(open(sys.argv[1]).read(), s)
LoH, r, f0, p0 = sp.symbols('LoH r f0 p0', real=True)
want = f0 / (4 * LoH**2 * (r + p0))
assert sp.simplify(s["expr"] - want) == 0, s["expr"]
assert s["params"] == {p0: sp.Float('0.5', 17)}, s["params"]
# control: a different form is told apart by the same comparison
assert sp.simplify(s["expr"] - f0 / (4 * LoH**2 * (r + 2 * p0))) != 0
EOF
then ok; else bad "vf_talk_r's sympy expression is not f0/(4 LoH^2 (r + p0))"; fi

# A form that reads no input still gives a snippet that runs (sympy.symbols
# refuses an empty name list): p0 + 1 at p0 = 2 is 3; the control, p0 = 2.5,
# is not.
for v in 2:ok 2.5:control; do
	"$BK" codegen --lang sympy 'p0 + 1' "p0=${v%:*}" >"$T/c.py"
	if /usr/bin/python3 -c "import sys; s = {}; exec(open(sys.argv[1]).read(), s); sys.exit(0 if s['fitted'] == 3 and s['inputs'] == () else 1)" "$T/c.py" 2>"$T/err"; then
		[ "${v#*:}" = ok ] && ok || bad "control: p0 = 2.5 gave 3"
	else
		[ "${v#*:}" = control ] && ok || bad "the snippet of a form without inputs: $(tail -1 "$T/err")"
	fi
done

# ---- LaTeX ------------------------------------------------------------------

# balanced FILE: braces (not \{ \}) and \left/\right pair up, never below 0.
balanced() {
	awk '{ s = s $0 "\n" } END {
		gsub(/\\[{}]/, "", s)
		d = 0; for (i = 1; i <= length(s); i++) { c = substr(s, i, 1)
			if (c == "{") d++; else if (c == "}") { d--; if (d < 0) exit 1 } }
		l = gsub(/\\left/, "", s); r = gsub(/\\right/, "", s)
		exit !(d == 0 && l == r) }' "$1"
}

for form in vf_talk_r v_hammon env_ross env_lazarov2013 dvf_unity_urp_half "$USER"; do
	extra=""
	[ "$form" = "$USER" ] && extra="p0=0.1 p1=2"
	# shellcheck disable=SC2086
	"$BK" codegen --lang latex "$form" $extra >"$T/l.tex" 2>"$T/err" || { bad "codegen --lang latex '$form': $(cat "$T/err")"; continue; }
	if balanced "$T/l.tex" && grep -q '^\\begin{equation}$' "$T/l.tex" && grep -q '^\\end{equation}$' "$T/l.tex"; then
		ok
	else
		bad "latex of '$form' is not a balanced equation"
	fi
done
# control: the same check refuses a brace and a \right dropped
sed '0,/}/s/}//' "$T/l.tex" >"$T/l1.tex"
if balanced "$T/l1.tex"; then bad "control: a dropped brace passed"; else ok; fi
sed '0,/\\right/s/\\right//' "$T/l.tex" >"$T/l2.tex"
if balanced "$T/l2.tex"; then bad "control: a dropped \\right passed"; else ok; fi

# A known form's exact equation (the name's '_' escaped, f0 as f_0, the
# constants as the shaders hold them, x + (-k) as x - k, numbers first in a
# product, the terms in the IR's canonical order); the control is a
# different constant.
"$BK" codegen --lang latex --name my_f 'f0/(LoH*LoH*(r + p0)) + sqrt(NoV)*2 + exp2(-NoV) - 0.25' p0=0.5 >"$T/k.tex"
want='\mathrm{my\_f}\left(\mathrm{NoV}, \mathrm{LoH}, r, f_0\right) = 2 \cdot \sqrt{\mathrm{NoV}} + \frac{f_0}{\mathrm{LoH}^{2} \cdot \left(r + 0.5\right)} + 2^{-\mathrm{NoV}} - 0.25'
got=$(grep '^\\mathrm' "$T/k.tex")
if [ "$got" = "$want" ]; then ok; else bad "latex of a known form:"; printf '  got  %s\n  want %s\n' "$got" "$want"; fi
"$BK" codegen --lang latex --name my_f 'f0/(LoH*LoH*(r + p0)) + sqrt(NoV)*2 + exp2(-NoV) - 0.25' p0=0.6 >"$T/k2.tex"
if [ "$(grep '^\\mathrm' "$T/k2.tex")" = "$want" ]; then bad "control: p0 = 0.6 gave p0 = 0.5's text"; else ok; fi
# the symbolic form in the header's comment (p_0 for the constant), beside
# the equation's fitted value; the control: the same form with 0.5 written in
# has no constant to name, so no such line
"$BK" codegen --lang latex vf_talk_r >"$T/s.tex"
"$BK" codegen --lang latex 'f0/(4*LoH*LoH*(r + 0.5))' >"$T/s0.tex"
sym='% \frac{f_0}{4 \cdot \mathrm{LoH}^{2} \cdot \left(r + p_{0}\right)}'
if grep -qxF "$sym" "$T/s.tex"; then ok; else bad "latex: no symbolic comment line '$sym'"; fi
if grep -qxF "$sym" "$T/s0.tex"; then bad "control: a form without parameters has the symbolic line"; else ok; fi
if grep '^\\mathrm' "$T/s.tex" | grep -qF 'p_{0}'; then bad "the equation holds p_0, not 0.5"; else ok; fi
# comments only: nothing a user wrote reaches the equation but the escaped name
"$BK" codegen --lang latex 'NoV + 1' >"$T/c.tex"
if [ "$(grep -vc '^%' "$T/c.tex")" -eq 3 ]; then ok; else bad "latex: lines outside comments besides the equation"; fi
# --precision is about shaders; refused with latex and sympy
if "$BK" codegen --lang latex --precision half NoV >/dev/null 2>"$T/err"; then bad "--precision half accepted with latex"; else ok; fi

echo "cli_formula: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
