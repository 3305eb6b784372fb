"""Forms on NumPy arrays, fits, searches and fronts: thin wrappers over the C
API (brdf.h, fit.h, search.h, catalog.h); each raises ValueError with the
library's own message where the library refuses."""
import numpy as np

from ._lib import ffi, lib

INPUTS = ["NoV", "NoL", "NoH", "LoH", "r", "a", "f0"]  # brdf.h's bk_input order
PRECISIONS = {"f64": lib.BK_F64, "f32": lib.BK_F32, "f16": lib.BK_F16}


def _s(text):
    return ffi.new("char[]", text.encode())


def _input(name):
    if name not in INPUTS:
        raise ValueError("unknown input '%s' (inputs: %s)" % (name, " ".join(INPUTS)))
    return INPUTS.index(name)


class Form:
    """A parsed form: Form("f0/(4*LoH*LoH*(r + p0))"), or Form.catalog(NAME)
    with the published constants in .params."""

    def __init__(self, text, params=None, _ptr=None):
        if _ptr is None:
            err = ffi.new("bk_form_error *")
            _ptr = lib.bk_form_parse(text.encode(), err)
            if _ptr == ffi.NULL:
                raise ValueError("form:1:%d: %s" % (err.column, ffi.string(err.message).decode()))
        self._f = ffi.gc(_ptr, lib.bk_form_free)
        self.text = ffi.string(lib.bk_form_text(self._f)).decode()
        self.nparams = lib.bk_form_nparams(self._f)
        bits = lib.bk_form_inputs(self._f)
        self.inputs = [n for i, n in enumerate(INPUTS) if bits >> i & 1]
        self.params = list(params) if params is not None else None

    @classmethod
    def catalog(cls, name):
        """A published form by its catalog name (bk_catalog_form): A of a split sum."""
        err = ffi.new("bk_form_error *")
        p = ffi.new("double[]", lib.BK_MAX_PARAMS)
        f = lib.bk_catalog_form(name.encode(), p, err)
        if f == ffi.NULL:
            raise ValueError(ffi.string(err.message).decode())
        form = cls(None, _ptr=f)
        form.params = [p[k] for k in range(form.nparams)]
        form.name = name
        return form

    def eval(self, params=None, precision="f64", vs=None, **inputs):
        """The form's values where the inputs (scalars or arrays, broadcast
        together) are, in precision f64, f32 or f16 (every operation rounded,
        as bk_form_eval): a float64 array of their shape. a defaults to r*r
        when r is given, as brdfkit eval does. With vs (f16 only: values of
        a target, broadcast with the inputs), each mad and mix in the order
        farther from vs, as bk_form_eval_half_vs: the values whose error
        against vs is the one a front's f16_max_abs states, whichever order
        a driver takes."""
        if precision not in PRECISIONS:
            raise ValueError("precision '%s': f64, f32 or f16" % precision)
        if vs is not None and precision != "f16":
            raise ValueError("vs: only with precision f16 (the order of a mad matters in half alone)")
        if "r" in inputs and "a" not in inputs:
            r = np.asarray(inputs["r"], dtype=np.float64)
            inputs["a"] = r * r
        for n in inputs:
            _input(n)
        missing = [n for n in self.inputs if n not in inputs]
        if missing:
            raise ValueError("form %s reads %s: not given" % (self.text, ", ".join(missing)))
        given = [np.asarray(inputs[n], dtype=np.float64) for n in self.inputs]
        if vs is not None:  # broadcast with the inputs (a form may read none of the arrays)
            given.append(np.asarray(vs, dtype=np.float64))
        arrays = np.broadcast_arrays(*given) if given else []
        shape = arrays[0].shape if arrays else ()
        cols = {n: np.ascontiguousarray(a).ravel() for n, a in zip(self.inputs, arrays)}
        size = int(np.prod(shape)) if shape else 1
        p = params if params is not None else (self.params or [])
        if len(p) < self.nparams:
            raise ValueError("form %s has %d parameters, %d given" % (self.text, self.nparams, len(p)))
        pc = ffi.new("double[]", max(len(p), 1))
        for k, v in enumerate(p):
            pc[k] = float(v)
        inp = ffi.new("double *[]", len(INPUTS))
        for n, c in cols.items():
            inp[INPUTS.index(n)] = ffi.cast("double *", ffi.from_buffer(c))
        out = np.empty(size, dtype=np.float64)
        if vs is not None:
            y = np.ascontiguousarray(arrays[-1]).ravel()
            rc = lib.bk_form_eval_half_vs(self._f, size, inp, pc, ffi.cast("double *", ffi.from_buffer(y)),
                                          ffi.cast("double *", ffi.from_buffer(out)))
        else:
            rc = lib.bk_form_eval(self._f, PRECISIONS[precision], size, inp, pc,
                                  ffi.cast("double *", ffi.from_buffer(out)))
        if rc:
            raise ValueError("bk_form_eval failed on %s" % self.text)
        return out.reshape(shape)


def member(df, name, part="form"):
    """The form of front member NAME of a front DataFrame (read_front), its
    fitted constants from the parameters column (p0=...;p1=...)."""
    row = df[df["name"] == name]
    if len(row) != 1:
        raise ValueError("no member '%s' in the front" % name)
    row = row.iloc[0]
    params = {}
    text = row["parameters"] if isinstance(row["parameters"], str) else ""
    for kv in filter(None, text.split(";")):
        k, v = kv.split("=")
        params[int(k.strip()[1:])] = float(v)
    f = Form(row[part])
    f.params = [params.get(k, 0.0) for k in range(max([f.nparams] + [k + 1 for k in params]))]
    f.name = name
    return f


class FitResult:
    """A fit's constants (params, standard errors se), its metrics on the
    target's samples (rmse, max_abs, max_rel) and whether it converged."""

    def __init__(self, res, np_, rc):
        self.params = [res.p[k] for k in range(np_)]
        self.se = [res.se[k] for k in range(np_)]
        self.rmse = res.fitted.rmse
        self.weighted_rmse = res.fitted.weighted_rmse
        self.max_abs = res.fitted.max_abs
        self.max_rel = res.fitted.max_rel
        self.cost = res.fitted.cost
        self.converged = rc == 0
        self.message = ffi.string(res.message).decode()

    def __repr__(self):
        return "FitResult(params=%r, rmse=%.6g, max_abs=%.6g)" % (self.params, self.rmse, self.max_abs)


class _Target:
    """A target's samples (bk_target_build), kept alive with the strings they
    were made from: a built-in target by name with its defaults (domain None:
    "vf2d", "vf", "spec", "d", "f", "ms", "sheen"), or an expression of the
    inputs on domain ({input: (lo, hi)}, the first varying fastest: kind
    form)."""

    def __init__(self, target, domain, nx=0):
        o = ffi.new("bk_target_options *")
        if domain is None:
            kind = ffi.new("bk_target_kind *")
            if lib.bk_target_parse(target.encode(), kind) or kind[0] == lib.BK_TARGET_FORM:
                raise ValueError("target '%s': a built-in target's name, or an expression with a domain" % target)
            lib.bk_target_defaults(kind[0], o)
        else:
            lib.bk_target_defaults(lib.BK_TARGET_FORM, o)
            self._text = _s(target)
            o.form_text = self._text
            o.ndomain = len(domain)
            for i, (n, (lo, hi)) in enumerate(domain.items()):
                o.dom_in[i], o.dom_lo[i], o.dom_hi[i] = _input(n), lo, hi
        if nx:
            o.nx = nx
        err = ffi.new("char[]", 512)
        self.samples = ffi.new("bk_samples *")
        if lib.bk_target_build(o, self.samples, ffi.NULL, ffi.NULL, err, 512):
            raise ValueError(ffi.string(err).decode())
        self.samples = ffi.gc(self.samples, lib.bk_samples_free)


def fit(form, target, domain=None, start=None, starts=4, seed=1, nx=0):
    """Fits form (text, Form, or a catalog name, whose published constants
    start it) to a target: a built-in one by name ("vf2d", ...; domain None)
    as `brdfkit fit --target vf2d --form ...` does, or the expression target on
    domain ({input: (lo, hi)}) as `brdfkit fit --target form --target-form
    TARGET --domain ...` does; starts deterministic starts, constants rounded
    to the digits their standard errors justify (the CLI's defaults)."""
    f = form if isinstance(form, Form) else (Form.catalog(form) if form.isidentifier() and "_" in form and
                                              lib.bk_catalog_find(form.encode()) != ffi.NULL else Form(form))
    t = _Target(target, domain, nx)
    sp = ffi.new("bk_fit_spec *")
    lib.bk_fit_defaults(sp)
    sp.s = t.samples
    sp.form[0] = f._f
    sp.np = f.nparams
    st = start if start is not None else (f.params or [1.0] * f.nparams)
    for k in range(f.nparams):
        sp.start[k] = st[k]
    sp.starts = starts
    sp.seed = seed
    sp.digits = lib.BK_FIT_DIGITS_SE
    res = ffi.new("bk_fit_result *")
    rc = lib.bk_fit_run(sp, res)
    if rc < 0:
        raise ValueError(ffi.string(res.message).decode())
    return FitResult(res, f.nparams, rc)


def search(target_form, domain, evals=600, inputs=None, ops=None, max_params=2, max_size=9, threads=1,
           seed=1, progress=None, stop=None, progress_every=100, nx=0):
    """A search (bk_search_drive) for target_form on domain: trees of ops
    (a comma list as brdfkit search --ops takes, default its default) over the
    inputs (default: the domain's), at most max_params parameters and max_size
    nodes, evals candidate fits. progress(evals) is called every
    progress_every fits; stop(evals) after each step, a true value stops the
    search (its front so far is returned). Returns the front, least cost
    first, as a pandas DataFrame (form, parameters, cost, error, rmse,
    max_abs, found_at)."""
    import pandas

    t = _Target(target_form, domain, nx)
    o = ffi.new("bk_search_options *")
    lib.bk_search_defaults(o)
    o.screen = t.samples
    o.shape = lib.BK_SHAPE_PLAIN
    g = o.grammar
    g.ops = lib.bk_grammar_default_ops()
    if ops is not None:
        err = ffi.new("char[]", 256)
        bits = ffi.new("uint64_t *")
        if lib.bk_grammar_parse_ops(ops.encode(), bits, err, 256):
            raise ValueError(ffi.string(err).decode())
        g.ops = bits[0]
    g.inputs = 0
    for n in inputs or list(domain):
        g.inputs |= 1 << _input(n)
    g.nconsts, g.consts[0] = 1, 1.0
    g.max_params, g.max_size = max_params, max_size
    o.evals, o.threads, o.seed = evals, threads, seed
    err = ffi.new("char[]", 512)
    s = lib.bk_search_new(o, err, 512)
    if s == ffi.NULL:
        raise ValueError(ffi.string(err).decode())
    s = ffi.gc(s, lib.bk_search_free)

    # an exception in a callback stops the search and is raised again here
    # (C cannot unwind through bk_search_drive): never swallowed
    raised = []

    def keep(exc, value, tb):  # void progress: returns None
        raised.append(value)

    @ffi.callback("int(void *, const bk_search *)", onerror=lambda *e: keep(*e) or 1)
    def on_stop(ctx, sp):
        return 1 if raised or (stop and stop(lib.bk_search_evals(sp))) else 0

    @ffi.callback("void(void *, const bk_search *)", onerror=keep)
    def on_progress(ctx, sp):
        if progress and not raised:
            progress(lib.bk_search_evals(sp))

    cb = ffi.new("bk_search_callbacks *")
    cb.progress, cb.stop, cb.progress_every = on_progress, on_stop, progress_every
    rc = lib.bk_search_drive(s, cb, err, 512)
    if raised:
        raise raised[0]
    if rc < 0:
        raise ValueError(ffi.string(err).decode())
    idx = ffi.new("size_t[]", 4096)
    n = lib.bk_search_front(s, idx, 4096)
    rows = []
    for i in range(n):
        c = lib.bk_search_at(s, idx[i])
        rows.append({"form": ffi.string(c.text).decode(),
                     "parameters": ";".join("p%d=%.17g" % (k, c.p[k]) for k in range(c.np)),
                     "cost": c.cost, "error": c.err, "rmse": c.rmse, "max_abs": c.max_abs, "found_at": c.found_at})
    df = pandas.DataFrame(rows, columns=["form", "parameters", "cost", "error", "rmse", "max_abs", "found_at"])
    df.attrs["evals"] = lib.bk_search_evals(s)
    return df


def read_front(path):
    """A front.csv of brdfkit search as a DataFrame, read by column names;
    its leading '#' lines (the command, the target, the certificate) in
    df.attrs["comments"]."""
    import io
    import pandas

    lines = open(path, encoding="utf-8").read().splitlines(True)
    k = 0
    while k < len(lines) and lines[k].startswith("#"):
        k += 1
    df = pandas.read_csv(io.StringIO("".join(lines[k:])))
    df.attrs["comments"] = [ln[1:].strip() for ln in lines[:k]]
    return df
