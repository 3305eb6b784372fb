#!/bin/sh
# page.sh — the report page renders: headless Chromium loads it, its inline
# <svg> plots and its <img> pictures are in the DOM after load, every picture
# is a file beside the page that Chromium actually decoded (naturalWidth > 0),
# nothing is fetched from elsewhere, and a screenshot of it is not blank.
# usage: sh tests/page.sh [page.html]   (default results/index.html)
# env: CHROMIUM (default chromium, Debian package chromium), PAGE_MIN_SVG and
#      PAGE_MIN_IMG (defaults 0 and 1: the figures are pictures, <img>).
# The loaded check runs on a copy of the page in a temporary folder, with a
# <base> pointing back at the page's folder and a small script that writes
# each image's naturalWidth into the DOM; the page itself is only read.
# Every check is a function, run once more on a page it must refuse (its
# negative control): a page with a missing and an undecodable image and a
# 0x0 plot, one loading a remote script, and an empty page. Issue 24's checks
# (every picture in a <figure> with a caption, tables over 6 rows folded in
# <details>, the summary table and Figure 1 on the first screen of a 1280x800
# window) are refused on a doctored copy of the page. Issue 40's: every
# <math> of the page renders as MathML (a box, fractions stacked) and the first
# finding is on the first screen; refused on the page with spans for <math>
# and on the doctored copy; at 1280 and
# 1900 px wide every table and the render table's difference column lie inside
# the window, and Figure 1's tick labels show at >= 9 CSS px (the PNG's drawn
# size, its img's data-tick-px, times displayed width / natural width); refused
# on a copy with the page's style of before and Figure 1 at half the width.
set -u
PAGE=${1:-results/index.html}
CHROMIUM=${CHROMIUM:-chromium}
MIN_SVG=${PAGE_MIN_SVG:-0} # the figures are cairo SVG/PNG pictures (<img>, analysis/plot.h): no inline <svg> is required
MIN_IMG=${PAGE_MIN_IMG:-1}
pass=0 fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
finish() {
	echo "page: $pass passed, $fail failed"
	[ "$fail" -eq 0 ]
	exit
}

if [ ! -f "$PAGE" ]; then
	bad "no page at $PAGE"
	finish
fi
if ! command -v "$CHROMIUM" >/dev/null 2>&1; then
	bad "$CHROMIUM not found (Debian: apt-get install chromium)"
	finish
fi

T=$(mktemp -d /tmp/bk_page_XXXXXX)
trap 'rm -rf "$T"' EXIT
DIR=$(cd "$(dirname "$PAGE")" && pwd)
NAME=$(basename "$PAGE")

# One Chromium run, as root in a sandbox-less container: the flags the
# machines' notes give (no background networking: this machine has no network
# and Chromium would otherwise retry Google's hosts), a fresh profile each
# time, a time limit so a hung renderer fails the test instead of the build.
chromium_run() {
	rm -rf "$T/profile"
	timeout 90 "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
		--disable-background-networking --disable-component-update --disable-sync \
		--user-data-dir="$T/profile" --hide-scrollbars --run-all-compositor-stages-before-draw \
		--virtual-time-budget=5000 "$@" 2>>"$T/chromium.log"
}

# The page's tags on one line each ("<img ...>"), newlines inside tags folded.
tags() { tr '\n\r' '  ' <"$1" | grep -oiE "<$2([[:space:]][^>]*)?>"; }
# The value of attribute $1 in each tag on stdin ("" when a tag has none).
attr() {
	sed -n "s/.*[[:space:]]$1=\"\([^\"]*\)\".*/\1/p; t; s/.*[[:space:]]$1='\([^']*\)'.*/\1/p; t; s/.*//p"
}

# ---- the page as written: pictures are files beside it, nothing remote ----------

# counts_ok PAGE: at least MIN_IMG <img> and MIN_SVG <svg> (sets nimg, nsvg)
counts_ok() {
	nimg=$(tags "$1" img | grep -c '')
	nsvg=$(tr '\n\r' '  ' <"$1" | grep -o '<svg[[:space:]>]' | grep -c '')
	[ "$nimg" -ge "$MIN_IMG" ] || { echo "$nimg <img> in $1, expected at least $MIN_IMG"; return 1; }
	[ "$nsvg" -ge "$MIN_SVG" ] || { echo "$nsvg <svg> in $1, expected at least $MIN_SVG"; return 1; }
}
# imgs_beside PAGE: every <img> src is a data: URL or a non-empty file in the
# page's folder, relative (the page moves with its folder); prints each that is not
imgs_beside() {
	d=$(cd "$(dirname "$1")" && pwd) rc=0
	tags "$1" img | attr src >"$T/srcs"
	while IFS= read -r src; do
		case $src in
		'') echo "an <img> without src"; rc=1 ;;
		data:*) ;;
		*://* | //*) echo "img $src: not beside the page (remote)"; rc=1 ;;
		/*) echo "img $src: absolute path, the page would not move with its folder"; rc=1 ;;
		*)
			file=${src%%[?#]*}
			[ -f "$d/$file" ] && [ -s "$d/$file" ] || { echo "img $src: no file $d/$file"; rc=1; }
			;;
		esac
	done <"$T/srcs"
	return $rc
}
# no_remote PAGE: no script, style, frame or source from elsewhere (the page
# must not depend on a network; links <a href> to sources are fine)
no_remote() {
	remote=$( (tags "$1" script; tags "$1" link; tags "$1" iframe; tags "$1" source) |
		grep -E "(src|href)=[\"'](https?:)?//" | head -3)
	[ -z "$remote" ] || { echo "remote resources: $remote"; return 1; }
}
# check NAME FUNCTION ARGS...: count FUNCTION's verdict, its words in the failure
check() {
	_n=$1; shift
	if "$@" >"$T/why" 2>&1; then ok; else bad "$_n: $(cat "$T/why")"; fi
}
# expect_fail NAME FUNCTION ARGS...: the negative control: FUNCTION must refuse ARGS
expect_fail() {
	_n=$1; shift
	if "$@" >/dev/null 2>&1; then bad "control $_n: the check passed on a page it must refuse"; else ok; fi
}

check "counts" counts_ok "$PAGE"
page_img=$nimg page_svg=$nsvg
check "pictures beside the page" imgs_beside "$PAGE"
check "nothing remote" no_remote "$PAGE"

# the controls' pages: broken pictures and a 0x0 plot; a remote script; empty
mkdir "$T/ctl"
printf 'not a PNG\n' >"$T/ctl/text.png"
cat >"$T/ctl/broken.html" <<'EOF'
<!DOCTYPE html><html><head><title>control</title></head><body>
<img src="missing.png"> <img src="text.png">
<svg width="0" height="0"></svg>
</body></html>
EOF
printf '%s\n' '<!DOCTYPE html><html><head><script src="https://example.invalid/x.js"></script></head><body></body></html>' \
	>"$T/ctl/remote.html"
echo '<!DOCTYPE html><html><body></body></html>' >"$T/empty.html"
expect_fail "counts" counts_ok "$T/empty.html"
expect_fail "pictures beside the page" imgs_beside "$T/ctl/broken.html"
expect_fail "nothing remote" no_remote "$T/ctl/remote.html"

# ---- loaded: a copy with <base> and a probe script -------------------------------

# Written into the DOM after load: one line per image (naturalWidth, src) and per
# svg (rendered width x height), then PAGECHECK-DONE so a half-run probe shows.
cat >"$T/probe.html" <<'EOF'
<script>
window.addEventListener('load', function () {
	var out = [];
	for (var i = 0; i < document.images.length; i++) {
		var im = document.images[i];
		out.push('PAGECHECK-IMG ' + (im.complete ? im.naturalWidth : 0) + ' ' + im.getAttribute('src'));
	}
	var svgs = document.querySelectorAll('svg');
	for (var j = 0; j < svgs.length; j++) {
		var r = svgs[j].getBoundingClientRect();
		out.push('PAGECHECK-SVG ' + Math.round(r.width) + 'x' + Math.round(r.height));
	}
	// captions: every picture and every plot (an outer <svg>) sits in a
	// <figure> whose <figcaption> says something
	var pics = document.querySelectorAll('img, svg');
	for (var k = 0; k < pics.length; k++) {
		var el = pics[k];
		if (el.tagName.toLowerCase() === 'svg' && el.parentElement && el.parentElement.closest('svg'))
			continue;
		var fig = el.closest('figure'), cap = fig ? fig.querySelector('figcaption') : null;
		if (!cap || !cap.textContent.trim())
			out.push('PAGECHECK-NOCAP ' + (el.getAttribute('src') || 'an inline svg'));
	}
	// folded: a table of more than 6 rows sits in a <details>, the summary aside
	var tables = document.querySelectorAll('table');
	for (var t = 0; t < tables.length; t++)
		if (tables[t].id !== 'summary' && tables[t].rows.length > 6 && !tables[t].closest('details')) {
			var sec = tables[t].closest('section');
			out.push('PAGECHECK-UNFOLDED ' + tables[t].rows.length + ' rows in ' + (sec ? sec.id : 'the page'));
		}
	// the first screen: where the summary table and Figure 1 are, and the window
	var box = function (id) {
		var e = document.getElementById(id);
		if (!e) return 'none';
		var r = e.getBoundingClientRect();
		return Math.round(r.top + window.scrollY) + ' ' + Math.round(r.bottom + window.scrollY);
	};
	// formulas (issue 40): each <math> a MathML element with a box, each
	// fraction laid out stacked (numerator above denominator), as Chromium
	// renders MathML Core and no HTML fallback would
	var ms = document.querySelectorAll('math');
	for (var m = 0; m < ms.length; m++) {
		var mr = ms[m].getBoundingClientRect();
		out.push('PAGECHECK-MATH ' + (ms[m].namespaceURI === 'http://www.w3.org/1998/Math/MathML' ? 'mathml' : 'other') +
			' ' + Math.round(mr.width) + ' ' + Math.round(mr.height));
	}
	var fr = document.querySelectorAll('mfrac');
	for (var q = 0; q < fr.length; q++) {
		var kids = fr[q].children;
		var stacked = kids.length === 2 && kids[0].getBoundingClientRect().bottom <= kids[1].getBoundingClientRect().top + 1 &&
			kids[0].getBoundingClientRect().height > 0;
		out.push('PAGECHECK-MFRAC ' + (stacked ? 'stacked' : 'flat'));
	}
	out.push('PAGECHECK-FINDING ' + box('first-finding'));
	// issue 40: tables inside the window (a table in a closed fold has no box),
	// the render table's third column (difference) too, and Figure 1's ticks
	var vw = document.documentElement.clientWidth;
	var all = document.querySelectorAll('table');
	for (var w = 0; w < all.length; w++) {
		var rb = all[w].getBoundingClientRect(), sw = all[w].closest('section');
		if (rb.width > 0 && (rb.left < -0.5 || rb.right > vw + 0.5))
			out.push('PAGECHECK-WIDE ' + Math.round(rb.left) + ' ' + Math.round(rb.right) + ' of ' + vw + ' in ' + (sw ? sw.id : 'the page'));
	}
	var diff = document.querySelectorAll('#render td, #render th'), dr = -1;
	for (var q = 0; q < diff.length; q++)
		if (diff[q].cellIndex === 2 && diff[q].colSpan === 1)
			dr = Math.max(dr, diff[q].getBoundingClientRect().right);
	if (document.getElementById('render'))
		out.push('PAGECHECK-DIFFCOL ' + Math.round(dr) + ' ' + vw);
	var mi = document.querySelector('#main-figure img');
	if (mi)
		out.push('PAGECHECK-TICK ' + (mi.getAttribute('data-tick-px') || 'none') + ' ' + mi.naturalWidth + ' ' +
			mi.getBoundingClientRect().width.toFixed(1));
	out.push('PAGECHECK-WINDOW ' + window.innerWidth + ' ' + window.innerHeight);
	out.push('PAGECHECK-SUMMARY ' + box('summary'));
	out.push('PAGECHECK-FIGURE ' + box('main-figure'));
	out.push('PAGECHECK-DONE');
	var pre = document.createElement('pre');
	pre.id = 'pagecheck';
	pre.textContent = '\n' + out.join('\n') + '\n';
	document.body.appendChild(pre);
});
</script>
EOF
# probe PAGE OUT [DIR] [WIDTH]: load a copy of PAGE in chromium, in a 1280x800
# window (a laptop's first screen; WIDTH x 800 when given), its probe's lines into OUT. <base> first thing in
# <head> (or the document) so relative src resolve to the page's folder (or
# DIR, for a doctored copy kept elsewhere); the probe last, after everything
# it looks at.
probe() {
	d=$(cd "${3:-$(dirname "$1")}" && pwd)
	base="<base href=\"file://$(printf '%s' "$d" | sed 's/ /%20/g')/\">"
	if grep -qiE '<head([[:space:]][^>]*)?>' "$1"; then
		esc=$(printf '%s' "$base" | sed 's/[&|\\]/\\&/g')
		sed "0,/<[hH][eE][aA][dD]\([[:space:]][^>]*\)\{0,1\}>/s||&$esc|" "$1" >"$T/copy.html"
	else
		{ echo "$base"; cat "$1"; } >"$T/copy.html"
	fi
	cat "$T/probe.html" >>"$T/copy.html"
	chromium_run --window-size="${4:-1280}",800 --dump-dom "file://$T/copy.html" >"$T/dom.html"
	grep '^PAGECHECK-' "$T/dom.html" >"$2"
}
# loaded_ok PROBE NIMG NSVG: the probe ran, the DOM holds the page's NIMG
# images and NSVG plots, chromium decoded every image (naturalWidth > 0) and
# every plot renders at a size; prints what is not so
loaded_ok() {
	grep -q '^PAGECHECK-DONE' "$1" || { echo "chromium did not load the page: $(tail -5 "$T/chromium.log")"; return 1; }
	rc=0
	dom_img=$(grep -c '^PAGECHECK-IMG' "$1")
	dom_svg=$(grep -c '^PAGECHECK-SVG' "$1")
	[ "$dom_img" -eq "$2" ] || { echo "$dom_img images in the DOM, $2 in the page"; rc=1; }
	[ "$dom_svg" -eq "$3" ] || { echo "$dom_svg svg in the DOM, $3 in the page"; rc=1; }
	grep '^PAGECHECK-IMG' "$1" >"$T/imgs"
	while read -r tag width src; do
		[ "$width" -gt 0 ] 2>/dev/null || { echo "img $src: not loaded by chromium (naturalWidth $width)"; rc=1; }
	done <"$T/imgs"
	grep '^PAGECHECK-SVG' "$1" >"$T/svgs"
	while read -r tag size; do
		case $size in
		[1-9]*x[1-9]*) ;;
		*) echo "an svg renders at $size"; rc=1 ;;
		esac
	done <"$T/svgs"
	return $rc
}

probe "$PAGE" "$T/probe.txt"
check "loaded in chromium" loaded_ok "$T/probe.txt" "$page_img" "$page_svg"
# control: two images chromium cannot decode (a missing file, a text file)
# and a 0x0 plot; told the counts the page has, as the page's own check is
probe "$T/ctl/broken.html" "$T/probe_ctl.txt"
expect_fail "loaded in chromium" loaded_ok "$T/probe_ctl.txt" 2 1
grep -q '^PAGECHECK-DONE' "$T/probe_ctl.txt" && ok || bad "control page not loaded: the control proves nothing"

# ---- captions, folds and the first screen (issue 24) ---------------------------------

# captioned PROBE: every picture and plot on the page in a <figure> with a
# <figcaption> (what is plotted, axes, units, the data file)
captioned() {
	grep -q '^PAGECHECK-DONE' "$1" || { echo "no probe output"; return 1; }
	! grep '^PAGECHECK-NOCAP' "$1" | head -5 | sed 's/^PAGECHECK-NOCAP /no caption: /' | grep .
}
# folded PROBE: no table of more than 6 rows outside a <details> but the summary
folded() {
	grep -q '^PAGECHECK-DONE' "$1" || { echo "no probe output"; return 1; }
	! grep '^PAGECHECK-UNFOLDED' "$1" | head -5 | sed 's/^PAGECHECK-UNFOLDED /not folded: /' | grep .
}
# first_screen PROBE: in a 1280x800 window the summary table is whole on the
# first screen and Figure 1 begins at least 100 px above its bottom edge. The
# screen is the page's viewport as Chromium reports it (its headless dump
# gives a 1280x800 window about 657 px of page, less its frame): the bound is
# that height, checked to be a laptop's screen (600 to 800 px).
first_screen() {
	set -- $(sed -n 's/^PAGECHECK-WINDOW //p' "$1") $(sed -n 's/^PAGECHECK-SUMMARY //p' "$1") \
		$(sed -n 's/^PAGECHECK-FIGURE //p' "$1")
	[ "$#" -eq 6 ] || { echo "the page has no summary table (id summary) or no Figure 1 (id main-figure): $*"; return 1; }
	[ "$1" -eq 1280 ] && [ "$2" -ge 600 ] && [ "$2" -le 800 ] ||
		{ echo "viewport $1x$2, not a 1280x800 window's: the check would measure another screen"; return 1; }
	[ "$3" -ge 0 ] && [ "$4" -le "$2" ] || { echo "the summary table spans y $3 to $4, not within the first $2 px"; return 1; }
	[ "$5" -le $(($2 - 100)) ] || { echo "Figure 1 starts at y $5, below the first screen's last 100 px"; return 1; }
}
check "every picture captioned" captioned "$T/probe.txt"
check "long tables folded" folded "$T/probe.txt"
check "the first screen: summary and Figure 1" first_screen "$T/probe.txt"
# the controls: one doctored copy of the page, beside it so its pictures
# resolve: its first caption made a <span>, its first fold a <div>, and 900 px
# of nothing before the summary; each check must refuse it
sed -e '0,/<figcaption>/s//<span>/' -e '0,/<details class="fold">/s//<div>/' \
	-e '0,/<body>/s//<body><div style="height:900px"><\/div>/' "$PAGE" >"$T/doctored.html"
probe "$T/doctored.html" "$T/probe_doc.txt" "$DIR"
grep -q '^PAGECHECK-DONE' "$T/probe_doc.txt" && ok || bad "doctored page not loaded: its controls prove nothing"
expect_fail "every picture captioned" captioned "$T/probe_doc.txt"
expect_fail "long tables folded" folded "$T/probe_doc.txt"
expect_fail "the first screen: summary and Figure 1" first_screen "$T/probe_doc.txt"

# ---- formulas and findings (issue 40) ------------------------------------------------

# formulas PROBE NMATH: the page's NMATH <math> elements (counted in its
# source) are all in the DOM as MathML with a non-empty box, it has at least
# one fraction and every fraction renders stacked, and the first finding
# (Figure 1's target, with its formula) is on the first screen
formulas() {
	grep -q '^PAGECHECK-DONE' "$1" || { echo "no probe output"; return 1; }
	[ "$2" -gt 0 ] || { echo "the page has no formula (<math>)"; return 1; }
	n=$(grep -c '^PAGECHECK-MATH mathml [1-9][0-9]* [1-9]' "$1")
	[ "$n" -eq "$2" ] || { echo "$n of $2 formulas in the DOM as MathML with a box"; return 1; }
	grep -q '^PAGECHECK-MFRAC stacked' "$1" || { echo "no fraction rendered stacked"; return 1; }
	! grep -q '^PAGECHECK-MFRAC flat' "$1" || { echo "$(grep -c '^PAGECHECK-MFRAC flat' "$1") fractions not stacked"; return 1; }
	set -- $(sed -n 's/^PAGECHECK-WINDOW //p' "$1") $(sed -n 's/^PAGECHECK-FINDING //p' "$1")
	[ "$#" -eq 4 ] || { echo "no first finding (id first-finding)"; return 1; }
	[ "$3" -ge 0 ] && [ "$4" -le "$2" ] || { echo "the first finding spans y $3 to $4, not within the first $2 px"; return 1; }
}
nmath=$(tr '\n' ' ' <"$PAGE" | grep -o '<math>' | wc -l)
check "formulas rendered, the first finding on the first screen" formulas "$T/probe.txt" "$nmath"
# controls: the same page with its formulas made HTML spans (no MathML, so
# nothing stacks) must be refused, and so must the doctored copy above
# (its first finding pushed 900 px down)
sed -e 's/<math>/<span>/g; s/<\/math>/<\/span>/g' "$PAGE" >"$T/nomath.html"
probe "$T/nomath.html" "$T/probe_nomath.txt" "$DIR"
grep -q '^PAGECHECK-DONE' "$T/probe_nomath.txt" && ok || bad "the page without MathML not loaded: its control proves nothing"
expect_fail "formulas rendered" formulas "$T/probe_nomath.txt" "$nmath"
expect_fail "the first finding on the first screen" formulas "$T/probe_doc.txt" "$nmath"

# one_finding_per_row PAGE: as many findings (<p class="finding"
# id="finding-TARGET">) as the summary table has targets (its rows that open
# with a linked <th>), each target's id once
one_finding_per_row() {
	rows=$(sed -n '/<table id="summary"/,/<\/table>/p' "$1" | grep -o '<tr><th><a href=' | wc -l)
	found=$(grep -o '<p class="finding" id="finding-[^"]*"' "$1" | sort -u | wc -l)
	all=$(grep -o '<p class="finding" id="finding-[^"]*"' "$1" | wc -l)
	[ "$rows" -gt 0 ] || { echo "no summary row"; return 1; }
	[ "$found" -eq "$rows" ] && [ "$all" -eq "$rows" ] || { echo "$all findings ($found ids) for $rows summary rows"; return 1; }
}
check "a finding per summary row" one_finding_per_row "$PAGE"
# control: the page with its second finding dropped
awk '/<p class="finding" id="finding-/ && ++n == 2 { next } { print }' "$PAGE" >"$T/onefewer.html"
expect_fail "a finding per summary row" one_finding_per_row "$T/onefewer.html"
# ---- issue 40: tables inside the window, Figure 1's ticks readable ---------------------

# fits PROBE: no table past the window's edges, and the render table's difference
# column (when the page has the render section) inside it
fits() {
	grep -q '^PAGECHECK-DONE' "$1" || { echo "no probe output"; return 1; }
	! grep '^PAGECHECK-WIDE' "$1" | head -3 | sed 's/^PAGECHECK-WIDE /a table spans x /' | grep . || return 1
	set -- $(sed -n 's/^PAGECHECK-DIFFCOL //p' "$1")
	[ "$#" -eq 0 ] && return 0
	[ "$1" -gt 0 ] && [ "$1" -le "$2" ] || { echo "the render table's difference column ends at x $1, the window at $2"; return 1; }
}
# ticks_readable PROBE: Figure 1's tick labels at >= 9 CSS px as displayed: the
# PNG's tick font in its pixels times displayed width / natural width
ticks_readable() {
	set -- $(sed -n 's/^PAGECHECK-TICK //p' "$1")
	[ "$#" -eq 3 ] && [ "$1" != none ] || { echo "no Figure 1 with data-tick-px: $*"; return 1; }
	awk -v t="$1" -v n="$2" -v w="$3" 'BEGIN {
		if (!(n > 0)) { print "Figure 1 not decoded"; exit 1 }
		px = t * w / n
		if (px < 9) { printf "Figure 1 tick labels at %.2f CSS px (%s px drawn, %s of %s px shown): under 9\n", px, t, w, n; exit 1 } }'
}
check "tables inside a 1280 px window" fits "$T/probe.txt"
check "Figure 1 tick labels >= 9 px at 1280" ticks_readable "$T/probe.txt"
probe "$PAGE" "$T/probe_1900.txt" "$DIR" 1900
check "tables inside a 1900 px window" fits "$T/probe_1900.txt"
# the controls: the page without the rules for the render table and long headers (the
# style of before) and Figure 1 at 40 % of the width; both checks must refuse it
sed -e 's/figure\.main>a{flex:0 0 [0-9]*%}/figure.main>a{flex:0 0 40%}/' -e 's/#render table{[^}]*}//' \
	-e 's/#render img{[^}]*}//' -e 's/td code,th code,th{overflow-wrap:anywhere}//' "$PAGE" >"$T/old_style.html"
probe "$T/old_style.html" "$T/probe_old.txt" "$DIR"
grep -q '^PAGECHECK-DONE' "$T/probe_old.txt" && ok || bad "old-style page not loaded: its controls prove nothing"
expect_fail "tables inside a 1280 px window" fits "$T/probe_old.txt"
expect_fail "Figure 1 tick labels >= 9 px at 1280" ticks_readable "$T/probe_old.txt"

# ---- a screenshot of the page itself: not blank ------------------------------------

# Its PNG must be clearly larger than one of an empty page taken the same way
# (a blank 1200x1600 compresses to about 9 KB with Chromium 156): the measure
# where python3 is missing, and a check that the screenshot was written at all.
# Where python3 is, it must also hold at least 8 colours.
colours() {
	python3 - "$1" <<'EOF'
import struct, sys, zlib
data = open(sys.argv[1], 'rb').read()
pos, idat, w, h, bpp = 8, b'', 0, 0, 0
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
        bpp = {2: 3, 6: 4, 0: 1, 4: 2}[ctype] * depth // 8
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
raw, stride, prev, seen = zlib.decompress(idat), w * bpp, bytearray(w * bpp), set()
for y in range(h):
    f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b, c = prev[i], prev[i - bpp] if i >= bpp else 0
        if f == 1: line[i] = (line[i] + a) & 255
        elif f == 2: line[i] = (line[i] + b) & 255
        elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    if y % 8 == 0:
        for x in range(0, stride, bpp * 4):
            seen.add(bytes(line[x:x + bpp]))
    prev = line
print(len(seen))
EOF
}
# not_blank SHOT EMPTY: the screenshot SHOT is not blank, against EMPTY's
not_blank() {
	size=$(wc -c <"$1" 2>/dev/null || echo 0)
	empty=$(wc -c <"$2" 2>/dev/null || echo 0)
	[ "$empty" -gt 0 ] || { echo "no screenshot of the empty page"; return 1; }
	[ "$size" -gt $((empty + empty / 4 + 1000)) ] || { echo "screenshot $size bytes, an empty page's $empty: blank or missing"; return 1; }
	if command -v python3 >/dev/null 2>&1; then
		n=$(colours "$1")
		[ "${n:-0}" -ge 8 ] 2>/dev/null || { echo "screenshot has ${n:-no} colours: blank"; return 1; }
	fi
}
chromium_run --window-size=1200,1600 --screenshot="$T/empty.png" "file://$T/empty.html" >/dev/null
chromium_run --window-size=1200,1600 --screenshot="$T/shot.png" "file://$DIR/$NAME" >/dev/null
check "screenshot" not_blank "$T/shot.png" "$T/empty.png"
# control: the empty page's own screenshot is blank
expect_fail "screenshot" not_blank "$T/empty.png" "$T/empty.png"
# and the colour count alone calls it blank (the measure the size cannot give)
if command -v python3 >/dev/null 2>&1; then
	[ "$(colours "$T/empty.png")" -lt 8 ] 2>/dev/null && ok || bad "control colours: the empty page has $(colours "$T/empty.png") colours"
fi

finish
