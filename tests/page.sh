#!/bin/sh
# page.sh — the report page renders: headless Chromium loads it, its inline
# <svg> plots and its <img> pictures are in the DOM after load, every picture
# is a file beside the page that Chromium actually decoded (naturalWidth > 0),
# nothing is fetched from elsewhere, and a screenshot of it is not blank.
# usage: sh tests/page.sh [page.html]   (default results/index.html)
# env: CHROMIUM (default chromium, Debian package chromium), PAGE_MIN_SVG and
#      PAGE_MIN_IMG (default 1: the report has at least one of each).
# The loaded check runs on a copy of the page in a temporary folder, with a
# <base> pointing back at the page's folder and a small script that writes
# each image's naturalWidth into the DOM; the page itself is only read.
set -u
PAGE=${1:-results/index.html}
CHROMIUM=${CHROMIUM:-chromium}
MIN_SVG=${PAGE_MIN_SVG:-1}
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

tags "$PAGE" img | attr src >"$T/srcs"
nimg=$(grep -c '' "$T/srcs")
nsvg=$(tr '\n\r' '  ' <"$PAGE" | grep -o '<svg[[:space:]>]' | grep -c '')
if [ "$nimg" -ge "$MIN_IMG" ]; then ok; else bad "$nimg <img> in $PAGE, expected at least $MIN_IMG"; fi
if [ "$nsvg" -ge "$MIN_SVG" ]; then ok; else bad "$nsvg <svg> in $PAGE, expected at least $MIN_SVG"; fi

while IFS= read -r src; do
	case $src in
	'') bad "an <img> without src" ;;
	data:*) ok ;;
	*://* | //*) bad "img $src: not beside the page (remote)" ;;
	/*) bad "img $src: absolute path, the page would not move with its folder" ;;
	*)
		file=${src%%[?#]*}
		if [ -f "$DIR/$file" ] && [ -s "$DIR/$file" ]; then ok; else bad "img $src: no file $DIR/$file"; fi
		;;
	esac
done <"$T/srcs"

# Scripts, styles and frames from elsewhere would make the page depend on a
# network; links (<a href>) to sources are fine.
remote=$( (tags "$PAGE" script; tags "$PAGE" link; tags "$PAGE" iframe; tags "$PAGE" source) |
	grep -E "(src|href)=[\"'](https?:)?//" | head -3)
if [ -z "$remote" ]; then ok; else bad "remote resources: $remote"; fi

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
	out.push('PAGECHECK-DONE');
	var pre = document.createElement('pre');
	pre.id = 'pagecheck';
	pre.textContent = '\n' + out.join('\n') + '\n';
	document.body.appendChild(pre);
});
</script>
EOF
# <base> first thing in <head> (or the document) so relative src resolve to the page's
# folder; the probe last, after everything it looks at.
base="<base href=\"file://$(printf '%s' "$DIR" | sed 's/ /%20/g')/\">"
if grep -qiE '<head([[:space:]][^>]*)?>' "$PAGE"; then
	esc=$(printf '%s' "$base" | sed 's/[&|\\]/\\&/g')
	sed "0,/<[hH][eE][aA][dD]\([[:space:]][^>]*\)\{0,1\}>/s||&$esc|" "$PAGE" >"$T/copy.html"
else
	{ echo "$base"; cat "$PAGE"; } >"$T/copy.html"
fi
cat "$T/probe.html" >>"$T/copy.html"

chromium_run --dump-dom "file://$T/copy.html" >"$T/dom.html"
grep '^PAGECHECK-' "$T/dom.html" >"$T/probe.txt"
if grep -q '^PAGECHECK-DONE' "$T/probe.txt"; then ok; else
	bad "chromium did not load the page (see below)"
	tail -5 "$T/chromium.log"
	finish
fi

dom_img=$(grep -c '^PAGECHECK-IMG' "$T/probe.txt")
dom_svg=$(grep -c '^PAGECHECK-SVG' "$T/probe.txt")
if [ "$dom_img" -eq "$nimg" ]; then ok; else bad "$dom_img images in the DOM, $nimg in the page"; fi
if [ "$dom_svg" -eq "$nsvg" ]; then ok; else bad "$dom_svg svg in the DOM, $nsvg in the page"; fi
while read -r tag width src; do
	[ -n "$tag" ] || continue
	if [ "$width" -gt 0 ]; then ok; else bad "img $src: not loaded by chromium (naturalWidth 0)"; fi
done <<EOF
$(grep '^PAGECHECK-IMG' "$T/probe.txt")
EOF
while read -r tag size; do
	[ -n "$tag" ] || continue
	case $size in
	0x* | *x0) bad "an svg renders at $size" ;;
	*) ok ;;
	esac
done <<EOF
$(grep '^PAGECHECK-SVG' "$T/probe.txt")
EOF

# ---- a screenshot of the page itself: not blank ------------------------------------

# Its PNG must be clearly larger than one of an empty page taken the same way
# (a blank 1200x1600 compresses to about 9 KB with Chromium 156): the measure
# where python3 is missing, and a check that the screenshot was written at all.
echo '<!DOCTYPE html><html><body></body></html>' >"$T/empty.html"
chromium_run --window-size=1200,1600 --screenshot="$T/empty.png" "file://$T/empty.html" >/dev/null
chromium_run --window-size=1200,1600 --screenshot="$T/shot.png" "file://$DIR/$NAME" >/dev/null
size=$(wc -c <"$T/shot.png" 2>/dev/null || echo 0)
empty=$(wc -c <"$T/empty.png" 2>/dev/null || echo 0)
if [ "$size" -gt $((empty + empty / 4 + 1000)) ]; then ok; else
	bad "screenshot $size bytes, an empty page's $empty: blank or missing"
fi
# Count its colours (stdlib only: zlib and the PNG filters), where python3 is.
if command -v python3 >/dev/null 2>&1; then
	colours=$(python3 - "$T/shot.png" <<'EOF'
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
)
	if [ "${colours:-0}" -ge 8 ] 2>/dev/null; then ok; else bad "screenshot has ${colours:-no} colours: blank"; fi
fi

finish
