#!/bin/sh
# cli_tables2.sh — scene and report take no option without an effect (issue
# 21): both have an option-applicability table (every option of theirs acts in
# every context the arguments give: scene's --out is required and every run
# writes section.html), so the walk (tests/cli_opts.sh) covers them; and scene
# refuses --gpu on a run whose feature sets have no specular term (nothing to
# count: the V*F and env forms are what it compiles), a context only the scene
# files give. Each refusal has a control that is taken; the "everywhere"
# claims are checked in the files written.
# usage: sh tests/cli_tables2.sh path/to/brdfkit
set -u
BK=${1:?usage: sh tests/cli_tables2.sh path/to/brdfkit}
case $BK in /*) ;; *) BK=$(pwd)/$BK ;; esac
T=$(mktemp -d /tmp/bk_cli_tables2_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
tab=$(printf '\t')
cd "$T" || exit 1

# refused NAME TOKEN CMD...: exit 2, nothing on stdout, one line on stderr holding TOKEN.
refused() {
	name=$1 token=$2; shift 2
	"$@" >out 2>err
	rc=$?
	if [ $rc -eq 2 ] && [ ! -s out ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF -- "$token" err; then ok
	else bad "$name: rc $rc, stdout '$(head -c 200 out)', stderr '$(cat err)'"; fi
}

# ---- the tables: printed, and --check-options taken without doing the work ----
"$BK" help --applicability >tables 2>err || bad "help --applicability: $(cat err)"
for c in scene report; do
	grep -q "^table$tab$c\$" tables && ok || bad "$c: no option-applicability table"
done
# the files named do not exist: nothing is read, nothing written
"$BK" scene s.json --out o --gpu navi21 --check-options >out 2>err
[ $? -eq 0 ] && [ "$(cat out)" = "context${tab}scene" ] && [ ! -s err ] && [ ! -e o ] && ok ||
	bad "scene --check-options: stdout '$(cat out)', stderr '$(cat err)'"
"$BK" report --out p.html s.html --check-options >out 2>err
[ $? -eq 0 ] && [ "$(cat out)" = "context${tab}report" ] && [ ! -s err ] && [ ! -e p.html ] && ok ||
	bad "report --check-options: stdout '$(cat out)', stderr '$(cat err)'"

# ---- scene --gpu: nothing to count ---------------------------------------------
# "specular": false makes a material diffuse only: no V*F (punctual) and no env
# (IBL) term, whatever the lighting (analysis/scene.h); specular defaults to true
printf '{"materials": [{"name": "a", "specular": false}]}\n' >d.json
printf '{"materials": [{"name": "b", "specular": false}], "lighting": {"punctual": false}}\n' >e.json
printf '{"materials": [{"name": "m", "roughness": 0.5}]}\n' >s.json
MSG="brdfkit scene: --gpu has no effect: no feature set has a specular term"
refused "scene --gpu, diffuse only" "$MSG" "$BK" scene d.json --gpu navi21 --out o
refused "scene --gpu, diffuse only, IBL lighting" "$MSG" "$BK" scene e.json --gpu navi21,polaris10 --no-time --out o
refused "scene --gpu, two diffuse-only files" "$MSG" "$BK" scene d.json e.json --gpu navi21 --out o
# before the driver is looked for (a usage error, exit 2, not the driver's 1)
refused "scene --gpu, diffuse only, no driver" "$MSG" env VK_ICD_FILENAMES=/nonexistent "$BK" scene d.json --gpu navi21 --out o
[ ! -e o ] && ok || bad "a refused scene --gpu wrote o"
# controls: with a specular term anywhere in the run, --gpu is taken and goes
# on to look for the driver (absent here: exit 1, before any work)
for files in s.json "d.json s.json"; do
	env VK_ICD_FILENAMES=/nonexistent "$BK" scene $files --gpu navi21 --out o >out 2>err
	rc=$?
	[ $rc -eq 1 ] && [ "$(wc -l <err)" -eq 1 ] && grep -qF "brdfkit scene: --gpu: no Vulkan driver" err &&
		grep -qF "VK_ICD_FILENAMES=/nonexistent does not name" err &&
		ok || bad "scene $files --gpu (no driver): rc $rc, stderr '$(cat err)'"
done
[ ! -e o ] && ok || bad "scene --gpu without a driver wrote o"
# and without --gpu the diffuse-only scene runs
"$BK" scene d.json --no-time --out o >out 2>err && [ -s o/sets.csv ] && ok || bad "scene d.json: $(cat err)"

# ---- scene: --id and --link-prefix act in every run (section.html) ------------
# two files: DIR/d/ and DIR/e/, and the links are PREFIX + the file's folder
"$BK" scene d.json e.json --no-time --id s2 --link-prefix x/ --out two >out 2>err || bad "scene two files: $(cat err)"
[ "$(head -1 two/section.html)" = '<section id="s2">' ] && ok || bad "section.html opens '$(head -1 two/section.html)'"
grep -qF 'href="x/d/scene.csv"' two/section.html && grep -qF 'href="x/e/sets.csv"' two/section.html && ok ||
	bad "section.html links: $(grep -o 'href="[^"]*"' two/section.html | head -3 | tr '\n' ' ')"
# negative control of the link check: the one-file layout has no folder
"$BK" scene d.json --id s3 --link-prefix x/ --out one >out 2>err || bad "scene one file: $(cat err)"
grep -qF 'href="x/scene.csv"' one/section.html && ! grep -qF 'href="x/d/' one/section.html &&
	[ "$(head -1 one/section.html)" = '<section id="s3">' ] && ok || bad "one-file section.html"
# --no-time acts: timing.csv only without it
[ -s one/timing.csv ] && [ ! -e two/d/timing.csv ] && [ ! -e o/timing.csv ] && ok || bad "timing.csv and --no-time"
# scene's timing.csv opens with the provenance lines of every brdfkit CSV (analysis/prov.h)
sed -n 1p one/timing.csv | grep -q "^# brdfkit [0-9][0-9.]* scene specialisation timing: scene '" &&
	[ "$(sed -n 2p one/timing.csv)" = "# command: brdfkit scene d.json --id s3 --link-prefix x/ --out one" ] && ok ||
	bad "scene timing.csv provenance: $(head -2 one/timing.csv)"

# ---- report: its one option --------------------------------------------------
"$BK" report --out page.html one/section.html two/section.html >out 2>err && grep -q 'href="#s2"' page.html &&
	grep -q 'href="#s3"' page.html && ok || bad "report: $(cat err)"

echo "cli_tables2: $pass passed, $fail failed"
[ $fail -eq 0 ]
