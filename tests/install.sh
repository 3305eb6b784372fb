#!/bin/sh
# install.sh — `make install` honours PREFIX and DESTDIR, and an installed
# libbrdf is usable through its pkg-config file: a program built with
# `pkg-config --cflags --libs brdfkit` prints GGX D at a = 1, which is 1/π.
set -u
T=$(mktemp -d /tmp/bk_install_XXXXXX)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

${MAKE:-make} -s install PREFIX=/opt/bk DESTDIR="$T/stage" >/dev/null || bad "make install"
for f in lib/libbrdf.a include/brdf.h lib/pkgconfig/brdfkit.pc bin/brdfkit bin/brdfkit-mpi; do
	[ -f "$T/stage/opt/bk/$f" ] && ok || bad "missing $f under DESTDIR/PREFIX"
done
grep -q '^prefix=/opt/bk$' "$T/stage/opt/bk/lib/pkgconfig/brdfkit.pc" && ok || bad "pc prefix"

${MAKE:-make} -s install PREFIX="$T/usr" >/dev/null || bad "make install PREFIX"
cat >"$T/use.c" <<'C'
#include <brdf.h>
#include <stdio.h>
int main(void) { printf("%.15f\n", bk_D_ggx(0.3, 1.0) * BK_PI); return 0; }
C
flags=$(PKG_CONFIG_PATH="$T/usr/lib/pkgconfig" pkg-config --static --cflags --libs brdfkit) || bad "pkg-config"
cc -std=c11 "$T/use.c" $flags -o "$T/use" && [ "$("$T/use")" = "1.000000000000000" ] && ok || bad "linking the installed library"
"$T/usr/bin/brdfkit" --version | grep -q '^brdfkit ' && ok || bad "installed tool"

echo "install: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
