"""The brush-model family (lib/brush, grip_brush.h) on numpy arrays:
fiala, brush, sakai, neofiala.

    tyre = grip.brush.load("my_tyre.params")          # model = neofiala ...
    tyre = grip.brush.params("fiala", ky=60000.0, mu=0.9)
    r = grip.brush.evaluate(tyre, kappa, alpha, gamma, fz, vx, arith="fixed")
    r["fx"], r["fy"], r["mz"], r["rh"], r["status"]

Inputs and outputs in ISO-W axes as `grip-tire --model NAME` (no SAE or
kappa-braking conversion here). Neo-FIALA is prepared once per set
(grip_neofiala_prepare) and evaluated with grip_neofiala_eval_model, as
grip-tire does (bit for bit the results of grip_neofiala_eval).
"""
import math

import numpy as np

from grip import _core
from grip._core import GripError, backend, check_arith

MODELS = ("fiala", "brush", "sakai", "neofiala")
_KIND = {"fiala": 1, "brush": 2, "sakai": 3, "neofiala": 4}   # port/linux/brush_params.h
_STRUCT = {m: f"grip_{m}_params" for m in MODELS}
_INPUTS = ("kappa", "alpha", "gamma", "fz", "vx")


def fields(model, arith="float"):
    """[(name, fmt, scale, unit)] of the model's C parameter struct, from
    its header: fmt "QS", "QL" or "int"; scale: SI value x scale = struct
    value (1000 for the fields the struct keeps per kN)."""
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}, not {model!r}")
    out = []
    for name, ctype, _dims, fmt, unit in backend(arith).fields(_STRUCT[model]):
        out.append((name, fmt if ctype == "grip_real_t" else "int", 1000.0 if "kN" in unit else 1.0, unit))
    return out


def _defaults(model):
    """The documented defaults (grip_tools.reference.brush dataclasses, the
    defaults the parameter files and grip-tire use)."""
    try:
        from grip_tools.reference import brush as ref
    except (ImportError, OSError):
        return None
    from dataclasses import asdict
    return {k: float(v) for k, v in asdict(ref.MODELS[model]()).items()}


class Params:
    """A brush-family parameter set: model, values {field: SI value}
    (per-kN fields in SI, i.e. per N, as the parameter files), path."""

    def __init__(self, model, values, path=None):
        if model not in MODELS:
            raise ValueError(f"model must be one of {', '.join(MODELS)}, not {model!r}")
        self.model = model
        self.values = {k: float(v) for k, v in values.items()}
        self.path = path
        self._structs = {}
        self._c_text = None

    def __repr__(self):
        return f"grip.brush.Params({self.model}, {self.path or '<values>'})"

    def struct(self, arith="float"):
        """(kind, cffi pointer): the checked parameter struct, or for
        neofiala the prepared grip_neofiala_model."""
        check_arith(arith)
        s = self._structs.get(arith)
        if s is None:
            s = self._structs[arith] = self._fill(backend(arith))
        return s

    def _fill(self, be):
        if self._c_text is not None:
            return self._fill_c(be)
        names = [f[0] for f in fields(self.model, be.arith)]
        unknown = sorted(set(self.values) - set(names))
        if unknown:
            raise GripError(_core.ERR_PARAM, f"grip.brush ({self.model})", "unknown parameter; known: "
                            + ", ".join(names), param=", ".join(unknown), arith=be.arith)
        missing = [n for n in names if n not in self.values]
        if missing:
            raise GripError(_core.ERR_PARAM, f"grip.brush ({self.model})", "missing parameter",
                            param=", ".join(missing), arith=be.arith)
        p = be.ffi.new(_STRUCT[self.model] + " *")
        for name, fmt, scale, _unit in fields(self.model, be.arith):
            v = self.values[name]
            if fmt == "int":
                if v != int(v) or abs(v) > 1000:
                    raise GripError(_core.ERR_PARAM, f"grip.brush ({self.model})", f"{v!r} is not an integer",
                                    param=name, arith=be.arith)
                setattr(p, name, int(v))
            else:
                setattr(p, name, be.param_real(v * scale, fmt, f"grip.brush ({self.model})", name))
        return self._checked(be, p, lambda: _culprits(self.model, self.values, be))

    def _fill_c(self, be):
        p = be.ffi.new(_STRUCT[self.model] + " *")
        _c_parse(be, self._c_text, self.path or "<values>", p, be.ffi.sizeof(_STRUCT[self.model]))
        return self._checked(be, p, lambda: [])

    def _checked(self, be, p, culprits):
        check = getattr(be.lib, f"grip_{self.model}_check_params")
        st = check(p)
        if st != _core.OK:
            bad = culprits()
            raise GripError(st, f"grip_{self.model}_check_params",
                            _core.culprit_text(bad, "docs/brush-models.md, \"Valid range\""),
                            param=", ".join(f"{k} = {self.values[k]!r}" for k in bad) or None, arith=be.arith)
        if self.model == "neofiala":
            m = be.ffi.new("grip_neofiala_model *")
            st = be.lib.grip_neofiala_prepare(p, m)
            if st != _core.OK:
                raise GripError(st, "grip_neofiala_prepare", arith=be.arith)
            return (_KIND["neofiala"], m, p)
        return (_KIND[self.model], p)

    def stored(self, arith="float"):
        """{field: SI value} as the arithmetic stores it."""
        be = backend(arith)
        s = self.struct(arith)
        p = s[2] if self.model == "neofiala" else s[1]
        out = {}
        for name, fmt, scale, _unit in fields(self.model, arith):
            v = getattr(p, name)
            out[name] = float(v) if fmt == "int" else float(be.to_si(np.array(v, be.real), fmt)) / scale
        return out


def _culprits(model, values, be):
    """The values the library's check rejects: each one that, put back to
    its documented default, lets the set pass."""
    d = _defaults(model)
    if d is None:
        return []
    overrides = {k: v for k, v in values.items() if k in d and d[k] != v}

    def try_check(rest):
        trial = Params(model, {**d, **rest})
        try:
            trial.struct(be.arith)
        except GripError as e:
            return e.status
        return _core.OK

    return _core.culprits(try_check, overrides)


def params(model, **values):
    """A parameter set from keyword values (SI); the others take the
    documented defaults (docs/brush-models.md)."""
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}, not {model!r}")
    d = _defaults(model)
    if d is None:
        # no grip_tools (installed outside a clone): grip-tire's reader
        # knows the defaults; give it the values as a parameter file
        lines = [f"model = {model}"] + [f"{k} = {float(v)!r}" for k, v in values.items()]
        return _from_text("\n".join(lines) + "\n", "<values>")
    return Params(model, {**d, **values})


def load(path, reader=None):
    """Reads a brush-model parameter file (`model = NAME`, `key = value`
    lines, SI; docs/brush-models.md). reader: "tools"
    (grip_tools.reference.brush), "c" (port/linux/brush_params.c,
    grip-tire's reader), None: the first that works."""
    if reader in (None, "tools"):
        try:
            from grip_tools.reference import brush as ref
        except (ImportError, OSError):
            if reader == "tools":
                raise
            ref = None
        if ref is not None:
            from dataclasses import asdict
            model, p = ref.read_params(path)
            return Params(model, asdict(p), path=path)
    if reader not in (None, "c", "tools"):
        raise ValueError(f"reader must be 'tools', 'c' or None, not {reader!r}")
    with open(path, "rb") as f:
        text = f.read().decode("utf-8", errors="replace")
    return _from_text(text, path)


def _c_parse(be, text, name, out, size):
    kind = be.ffi.new("int *")
    err = be.ffi.new("char[1024]")
    if be.lib.grip_py_brush_parse(text.encode(), str(name).encode(), kind, out, size, err, 1024) != 0:
        raise GripError(None, "grip.brush", be.ffi.string(err).decode(errors="replace"), arith=be.arith)
    return MODELS[kind[0] - 1]


def _from_text(text, name):
    """A set parsed by grip-tire's reader (port/linux/brush_params.c),
    compiled into each extension: every arithmetic fills its struct from
    the text exactly as grip-tire does. values: as the float build stores
    them."""
    be = backend("float")
    buf = be.ffi.new("char[]", 4096)
    model = _c_parse(be, text, name, buf, 4096)
    p = Params(model, {}, path=name if name != "<values>" else None)
    p._c_text = text
    p.values = p.stored("float")
    return p


def evaluate(params, kappa, alpha, gamma, fz, vx=0.0, arith="float", raw=False, threads=1, errors="return"):
    """Forces, moment and adhesion fraction of a brush-family model.

    kappa [-], alpha [rad], gamma [rad], fz [N], vx [m/s] (sliding speed;
    0: none): arrays or numbers, broadcast, ISO-W. Inputs a model does not
    use are ignored (fiala: kappa, gamma, vx; brush: alpha, gamma; sakai:
    gamma, vx). Returns {"fx", "fy", "mz" (float64 SI; raw: grip_real_t),
    "rh" (adhesion fraction, QS), "status"}; a point the build cannot hold
    gets GRIP_ERR_INPUT and zeros (rh 0), as in evaluate() of grip.mf."""
    check_arith(arith)
    if not isinstance(params, Params):
        raise TypeError("params must be a grip.brush.Params (grip.brush.load / grip.brush.params)")
    if errors not in ("return", "raise"):
        raise ValueError("errors must be 'return' or 'raise'")
    be = backend(arith)
    s = params.struct(arith)
    kind, cp = s[0], s[1]
    shape, ins = _core.broadcast_inputs([kappa, alpha, gamma, fz, vx])
    n = int(math.prod(shape))
    out = {k: np.empty(n, be.real) for k in ("fx", "fy", "mz", "rh")}
    status = np.empty(n, np.int32)
    ffi, lib = be.ffi, be.lib

    def piece(a, b):
        args = []
        for buf, stride in ins:
            args += [ffi.from_buffer("double[]", buf if stride == 0 else buf[a:b]), stride]
        return lib.grip_py_brush_eval(kind, cp, b - a, *args,
                                      *[ffi.from_buffer("grip_real_t[]", out[k][a:b])
                                        for k in ("fx", "fy", "mz", "rh")],
                                      ffi.from_buffer("int32_t[]", status[a:b]))

    if n:
        _core.run_chunks(n, threads, piece)
    if errors == "raise":
        _core.raise_first_error(status, f"grip_{params.model}_eval", arith,
                                lambda k: ", ".join(f"{nm}={float(buf[k * st])!r}"
                                                    for nm, (buf, st) in zip(_INPUTS, ins)))
    if not raw:
        out = {k: be.to_si(v, "QS" if k == "rh" else "QL") for k, v in out.items()}
    out["status"] = status
    return {k: v.reshape(shape) for k, v in out.items()}
