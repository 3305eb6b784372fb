"""Loads the libraries and declares their API to cffi (ABI mode: no compiler
at import where `make install` put the preprocessed declarations beside this
file as _decls.h; in the source tree they are made from the headers with cc -E).
"""
import os
import tempfile

import cffi

from ._decls import HEADERS, preprocess

HERE = os.path.dirname(os.path.abspath(__file__))
TREE = os.path.normpath(os.path.join(HERE, "..", "..", ".."))  # analysis/python/brdfkit -> the tree


def locate():
    """(libdir, declarations text) of the libraries to load."""
    prefix = os.environ.get("BRDFKIT_PREFIX")
    if not prefix:
        try:
            from ._config import PREFIX as prefix  # written by make install
        except ImportError:
            prefix = None
    if prefix:
        decls = os.path.join(HERE, "_decls.h")
        if os.environ.get("BRDFKIT_PREFIX") or not os.path.exists(decls):
            return os.path.join(prefix, "lib"), preprocess([os.path.join(prefix, "include")])
        return os.path.join(prefix, "lib"), open(decls).read()
    # the source tree: the headers where they are written, under the names
    # they are installed with (a scratch include/brdfkit/ of symlinks)
    build = os.path.join(TREE, "build")
    with tempfile.TemporaryDirectory() as d:
        os.mkdir(os.path.join(d, "brdfkit"))
        for h in HEADERS + ["ir_ops.h"]:
            src = os.path.join(TREE, "brdf" if h in ("brdf.h", "brdf_ops.h", "ir_ops.h") else "fit", h)
            os.symlink(src, os.path.join(d, "brdfkit", h))
        return build, preprocess([d])


def load():
    libdir, decls = locate()
    f = cffi.FFI()
    f.cdef(decls)
    names = sorted(os.listdir(libdir)) if os.path.isdir(libdir) else []

    def one(stem):
        # the file (libX.so.MAJOR.MINOR.PATCH), which the tree's build/ has alone
        cands = [n for n in names if n.startswith(stem + ".so.") and n.count(".") == 4]
        if not cands:
            raise OSError("brdfkit: no %s.so.* in %s (make install, or set BRDFKIT_PREFIX)" % (stem, libdir))
        # RTLD_GLOBAL: libbrdfkit-fit's NEEDED libbrdf.so.MAJOR is then found
        # by its soname among the loaded objects, wherever the directory is
        return f.dlopen(os.path.join(libdir, cands[-1]), f.RTLD_NOW | f.RTLD_GLOBAL)

    one("libbrdf")
    return f, one("libbrdfkit-fit"), libdir


ffi, lib, LIBDIR = load()
