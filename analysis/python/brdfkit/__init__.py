"""brdfkit from Python: the installed libraries (libbrdf, libbrdfkit-fit) through
cffi in ABI mode, over the installed headers' own declarations.

    import brdfkit
    f = brdfkit.Form.catalog("vf_talk_r")           # a published form, its constants
    v = f.eval(LoH=x, r=0.3, f0=0.04, precision="f16")
    res = brdfkit.fit("p0 + p1*LoH", "exp(-2*LoH)", {"LoH": (0, 1)})  # or fit("vf_talk_r", "vf2d")
    front = brdfkit.search("0.45*LoH*LoH + 0.2", {"LoH": (0, 1)}, evals=600, stop=lambda n: n >= 300)
    df = brdfkit.read_front("results/search/vf2d/front.csv")

Where the libraries are (_lib.locate): $BRDFKIT_PREFIX, else the prefix
`make install` wrote into _config.py, else this source tree's build/ (the
in-tree use of notebooks_data/figures.ipynb and tests/python.sh).
Nothing here is computed in Python: values, fits and searches are the C
library's, the command-line tool's own (tests/python.sh compares them).
"""
from ._lib import ffi, lib
from .api import Form, FitResult, fit, search, read_front, member

__all__ = ["ffi", "lib", "Form", "FitResult", "fit", "search", "read_front", "member"]
