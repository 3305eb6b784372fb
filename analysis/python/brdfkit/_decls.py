"""The installed headers' declarations for cffi's cdef. Run as a program by
make install (python3 _decls.py INCLUDEDIR > _decls.h), so that an import
needs no C compiler; imported by _lib.py in the source tree."""
import os
import re
import subprocess
import sys
import tempfile

HEADERS = ["brdf.h", "brdf_ops.h", "solver.h", "target.h", "fit.h", "expr.h", "search.h", "catalog.h"]


def preprocess(includes):
    """The installed headers' declarations, preprocessed for cffi's cdef.
    cffi knows size_t, uint64_t and FILE itself, so the C library's headers are
    replaced by empty ones (-nostdinc): what is left is brdfkit's alone, the
    macros expanded (array sizes, enum values) and the comments gone; then
    (-dM) the headers' BK_ macros that are integers, as "#define NAME N"
    lines cffi's cdef reads as constants (lib.BK_FIT_DIGITS_SE)."""
    with tempfile.TemporaryDirectory() as d:
        for h in ("stddef.h", "stdint.h", "stdio.h"):
            open(os.path.join(d, h), "w").close()
        src = "".join("#include <brdfkit/%s>\n" % h for h in HEADERS)
        args = [os.environ.get("CC", "cc"), "-std=c11", "-E", "-P", "-nostdinc", "-I" + d]
        args += ["-I" + i for i in includes] + ["-"]
        decls = subprocess.run(args, input=src, capture_output=True, text=True, check=True).stdout
        macros = subprocess.run(args[:3] + ["-dM"] + args[3:], input=src, capture_output=True, text=True,
                                check=True).stdout
    ints = []
    for line in macros.splitlines():
        m = re.match(r"#define (BK_[A-Z0-9_]+) \(?(-?[0-9]+)[uU]?\)?$", line)
        if m:
            ints.append("#define %s %s" % (m.group(1), m.group(2)) if int(m.group(2)) >= 0 else
                        "static const int %s = %s;" % (m.group(1), m.group(2)))
    return decls + "\n" + "\n".join(sorted(ints)) + "\n"


if __name__ == "__main__":
    sys.stdout.write(preprocess(sys.argv[1:]))
