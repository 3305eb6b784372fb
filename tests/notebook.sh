#!/bin/sh
# notebook.sh — notebooks_data/ as a notebook user sees it (issue 24).
#
#   sh tests/notebook.sh [DIR]      (DIR: notebooks_data)
#
# 1. Every DIR/*.csv loads with plain pandas.read_csv(path) (no comment=), its
#    columns are exactly those its section of DIR/README.md lists (the backticked
#    names in the first cell of the section's table rows; CHIP stands for a chip
#    name), the file is named in the README, and NAME.meta.txt beside it holds
#    "source: results/..." and then comment lines only (notebooks_data/copy.sh).
#    Negative controls: a copy with a comment line, with a renamed column, and
#    with an extra undocumented file must each fail the same check.
# 2. Where Debian's jupyter-nbconvert, python3-ipykernel, python3-pandas and
#    python3-matplotlib are installed (make test installs them), DIR/figures.ipynb
#    runs to completion in a scratch copy (headless), every cell tagged "figure"
#    shows an image and is followed by its caption (a markdown cell starting
#    "**Figure"), and the committed notebook holds no outputs. Elsewhere one line
#    says that part was skipped. Figure 5 drives the library through `import
#    brdfkit` (analysis/python, BRDFKIT_PYTHON; build/'s shared libraries) and
#    asserts that its errors are the CSV's.
set -eu
DIR=${1:-notebooks_data}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "notebook.sh: FAIL: $*" >&2; exit 1; }

# the interpreter: Debian's (where python3-pandas installs), else the first python3
PY=""
for p in /usr/bin/python3 python3; do
	if command -v "$p" >/dev/null 2>&1 && "$p" -c 'import pandas' 2>/dev/null; then PY=$p; break; fi
done
[ -n "$PY" ] || { echo "notebook.sh: skipped: no python3 with pandas (apt-get install python3-pandas)"; exit 0; }

cat >"$T/check.py" <<'EOF'
# check.py DIR: the CSVs of DIR against DIR/README.md (see tests/notebook.sh)
import fnmatch, glob, os, re, sys
import pandas

d = sys.argv[1]
readme = open(os.path.join(d, "README.md"), encoding="utf-8").read()
sections = []  # (globs, exact names, patterns)
for block in re.split(r"^## ", readme, flags=re.M)[1:]:
    head, _, body = block.partition("\n")
    globs = re.findall(r"`([^`]+\.csv)`", head)
    if not globs:
        continue
    cols = []
    for line in body.splitlines():
        if line.startswith("|"):
            cols += re.findall(r"`([^`]+)`", line.split("|")[1])
    exact = [c for c in cols if "CHIP" not in c]
    pats = [re.compile("^" + re.escape(c).replace("CHIP", "[a-z0-9]+") + "$") for c in cols if "CHIP" in c]
    sections.append((globs, exact, pats))
if not sections:
    sys.exit("no documented sections in README.md")
named = set(re.findall(r"`([A-Za-z0-9_.-]+\.csv)`", readme))
bad = []
csvs = sorted(glob.glob(os.path.join(d, "*.csv")))
if not csvs:
    sys.exit("%s: no CSV" % d)
for path in csvs:
    f = os.path.basename(path)
    secs = [s for s in sections if any(fnmatch.fnmatchcase(f, g) for g in s[0])]
    if len(secs) != 1:
        bad.append("%s: matches %d README sections, not 1" % (f, len(secs)))
        continue
    if f not in named:
        bad.append("%s: not named in README.md" % f)
    try:
        df = pandas.read_csv(path)
    except Exception as e:  # the check itself: what plain read_csv says
        bad.append("%s: pandas.read_csv: %s" % (f, str(e).strip().splitlines()[0]))
        continue
    _, exact, pats = secs[0]
    cols = list(df.columns)
    if any(str(c).startswith("#") for c in cols):
        bad.append("%s: a comment line read as the header" % f)
        continue
    for c in cols:
        if c not in exact and not any(p.match(c) for p in pats):
            bad.append("%s: column %r is not documented" % (f, c))
    for c in exact:
        if c not in cols:
            bad.append("%s: documented column %r is missing" % (f, c))
    for p in pats:
        if not any(p.match(c) for c in cols):
            bad.append("%s: no column matches %s" % (f, p.pattern))
    meta = path[:-len(".csv")] + ".meta.txt"
    if not os.path.exists(meta):
        bad.append("%s: no %s" % (f, os.path.basename(meta)))
        continue
    lines = open(meta, encoding="utf-8").read().splitlines()
    if not lines or not lines[0].startswith("source: results/"):
        bad.append("%s: its first line is not 'source: results/...'" % os.path.basename(meta))
    elif lines[1:] != ["(no comment lines)"] and not all(l.startswith("#") for l in lines[1:]):
        bad.append("%s: a line that is no comment line" % os.path.basename(meta))
for meta in glob.glob(os.path.join(d, "*.meta.txt")):
    if not os.path.exists(meta[:-len(".meta.txt")] + ".csv"):
        bad.append("%s: no CSV beside it" % os.path.basename(meta))
for b in bad:
    print(b)
if bad:
    sys.exit(1)
print("%d CSV files: plain pandas.read_csv, columns as documented, sidecars" % len(csvs))
EOF

"$PY" "$T/check.py" "$DIR" || fail "$DIR does not pass (above)"

# negative controls: each copy must fail, for the planted reason
mk() { rm -rf "$T/bad"; mkdir "$T/bad"; cp "$DIR"/*.csv "$DIR"/*.meta.txt "$DIR/README.md" "$T/bad/"; }
refuse() {  # refuse WHAT MESSAGE
	if "$PY" "$T/check.py" "$T/bad" >"$T/out" 2>&1; then fail "negative control passed: $1"; fi
	grep -q "$2" "$T/out" || { cat "$T/out" >&2; fail "negative control failed for another reason: $1"; }
}
mk; { echo "# brdfkit: a comment line"; cat "$DIR/albedo.csv"; } >"$T/bad/albedo.csv"
refuse "a comment line" "albedo.csv: a comment line read as the header"
# the file as brdfkit wrote it into results/, its comment lines in place (where results/ is)
src=$(sed -n '1s/^source: //p' "$DIR/search_vs_double_vf2d_half.meta.txt")
if [ -f "$src" ]; then
	mk; cp "$src" "$T/bad/search_vs_double_vf2d_half.csv"
	refuse "results/' own file" "search_vs_double_vf2d_half.csv: pandas.read_csv: Error tokenizing data"
fi
mk; sed '1s/half_error/half_err/' "$DIR/search_vs_double_vf2d_half.csv" >"$T/bad/search_vs_double_vf2d_half.csv"
refuse "a renamed column" "column 'half_err' is not documented"
mk; cp "$DIR/albedo.csv" "$T/bad/undocumented.csv"; cp "$DIR/albedo.meta.txt" "$T/bad/undocumented.meta.txt"
refuse "an undocumented file" "undocumented.csv: matches 0 README sections"

# the rule (notebooks_data/copy.sh) on planted files, against hand-written results
C="${0%/*}/../notebooks_data/copy.sh"
mkdir "$T/cp" "$T/cp/out"
printf '# one: the command\n# two, with a comma\nx,y\n1,2\n' >"$T/cp/a.csv"
printf 'x\n3\n' >"$T/cp/b.csv"
printf '%s a\n%s b\n' "$T/cp/a.csv" "$T/cp/b.csv" | sh "$C" "$T/cp/out" >/dev/null || fail "copy.sh refused two good files"
[ "$(cat "$T/cp/out/a.csv")" = "$(printf 'x,y\n1,2')" ] || fail "copy.sh: a.csv: $(cat "$T/cp/out/a.csv")"
[ "$(cat "$T/cp/out/a.meta.txt")" = "$(printf 'source: %s\n# one: the command\n# two, with a comma' "$T/cp/a.csv")" ] || fail "copy.sh: a.meta.txt"
[ "$(cat "$T/cp/out/b.meta.txt")" = "$(printf 'source: %s\n(no comment lines)' "$T/cp/b.csv")" ] || fail "copy.sh: b.meta.txt"
# whole or nothing: a missing source, or a comment line after the header, leaves the folder as it was
printf '# late\n' >>"$T/cp/b.csv"
for list in "$T/cp/a.csv a|$T/cp/missing.csv m" "$T/cp/a.csv c|$T/cp/b.csv b"; do
	echo "$list" | tr '|' '\n' | sh "$C" "$T/cp/out" 2>"$T/out" && fail "copy.sh accepted: $list"
	# (a hidden scratch folder left behind would show in the first pattern)
	got=$(cd "$T/cp/out" && printf '%s ' .[!.]* *)
	[ "$got" = ".[!.]* a.csv a.meta.txt b.csv b.meta.txt " ] || fail "copy.sh changed the folder on a refusal: $got"
	[ "$(cat "$T/cp/out/a.csv")" = "$(printf 'x,y\n1,2')" ] || fail "copy.sh changed a.csv on a refusal"
done
grep -q "a comment line after the header" "$T/out" || fail "copy.sh refused the late comment for another reason: $(cat "$T/out")"

# each file with its sidecar gives its results/ source back byte for byte (where results/ is)
same_as_source() {  # same_as_source META SOURCE
	{ grep '^#' "$1" || true; cat "${1%.meta.txt}.csv"; } | cmp -s - "$2"
}
n=0
for m in "$DIR"/*.meta.txt; do
	src=$(sed -n '1s/^source: //p' "$m")
	[ -f "$src" ] || continue
	same_as_source "$m" "$src" || fail "${m%.meta.txt}.csv and its .meta.txt are not $src (run make notebooks-data)"
	n=$((n + 1))
	if [ $n -eq 1 ]; then  # negative control: a data row too many
		mkdir "$T/src"; cp "$m" "$T/src/x.meta.txt"; { cat "${m%.meta.txt}.csv"; echo "1"; } >"$T/src/x.csv"
		! same_as_source "$T/src/x.meta.txt" "$src" || fail "a changed sidecar still gives $src back"
	fi
done
echo "notebook.sh: $n files and their .meta.txt give their results/ source back"

# 2. the notebook
nb="$DIR/figures.ipynb"
[ -f "$nb" ] || fail "$nb: missing"
if ! command -v jupyter-nbconvert >/dev/null 2>&1 || ! /usr/bin/python3 -c 'import pandas, matplotlib, ipykernel' 2>/dev/null; then
	echo "notebook.sh: skipped executing $nb: jupyter-nbconvert, python3-ipykernel, python3-pandas or python3-matplotlib not installed"
	echo "notebook.sh: ok"
	exit 0
fi
cat >"$T/figs.py" <<'EOF'
# figs.py NOTEBOOK [executed]: figure cells with their captions (and images, when executed)
import json, sys
nb = json.load(open(sys.argv[1], encoding="utf-8"))
executed = len(sys.argv) > 2
cells, bad, n = nb["cells"], [], 0
for i, c in enumerate(cells):
    if c["cell_type"] != "code":
        continue
    if not executed and (c.get("outputs") or c.get("execution_count") is not None):
        bad.append("cell %d: committed with outputs" % i)
    for o in c.get("outputs", []):
        if o.get("output_type") == "error":
            bad.append("cell %d: %s" % (i, o.get("ename")))
    if "figure" not in c.get("metadata", {}).get("tags", []):
        continue
    n += 1
    nxt = cells[i + 1] if i + 1 < len(cells) else None
    if not nxt or nxt["cell_type"] != "markdown" or not "".join(nxt["source"]).startswith("**Figure"):
        bad.append("cell %d: no caption cell after it" % i)
    if executed and not any("image/png" in o.get("data", {}) for o in c.get("outputs", [])):
        bad.append("cell %d: no image" % i)
if n < 4:
    bad.append("%d figure cells, fewer than 4" % n)
for b in bad:
    print(b)
if bad:
    sys.exit(1)
if executed:
    print("%d figures" % n)
EOF
"$PY" "$T/figs.py" "$nb" || fail "$nb (above)"
mkdir "$T/nb"
cp "$DIR"/*.csv "$DIR"/*.meta.txt "$nb" "$T/nb/"
start=$(date +%s)
# figure 5 imports brdfkit from this tree (analysis/python, over build/'s libraries)
PYMOD=$(cd "${0%/*}/../analysis/python" && pwd)
( cd "$T/nb" && BRDFKIT_PYTHON="$PYMOD" MPLBACKEND=Agg MPLCONFIGDIR="$T/mpl" PYDEVD_DISABLE_FILE_VALIDATION=1 \
	jupyter-nbconvert --to notebook --execute --ExecutePreprocessor.timeout=120 \
	--output executed.ipynb figures.ipynb >"$T/nbconvert.log" 2>&1 ) || { cat "$T/nbconvert.log" >&2; fail "$nb does not run"; }
secs=$(($(date +%s) - start))
"$PY" "$T/figs.py" "$T/nb/executed.ipynb" executed >"$T/figs" || { cat "$T/figs" >&2; fail "$nb executed (above)"; }
# negative control: the executed notebook with one figure's outputs taken away
"$PY" -c 'import json, sys
nb = json.load(open(sys.argv[1]))
c = [c for c in nb["cells"] if "figure" in c["metadata"].get("tags", [])][-1]
c["outputs"] = []
json.dump(nb, open(sys.argv[2], "w"))' "$T/nb/executed.ipynb" "$T/nb/stripped.ipynb"
if "$PY" "$T/figs.py" "$T/nb/stripped.ipynb" executed >"$T/out"; then fail "a figure cell without an image passed"; fi
grep -q "no image" "$T/out" || fail "the stripped figure was refused for another reason"
echo "notebook.sh: $nb executed in ${secs} s, $(cat "$T/figs") with images and captions"
echo "notebook.sh: ok"
