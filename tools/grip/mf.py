"""Magic Formula (lib/mf, grip_mf.h) on numpy arrays.

    params = grip.mf.load("tests/data/mfeval-tir/PacejkaBook_Defaults.tir")
    r = grip.mf.evaluate(params, kappa, alpha, gamma, fz, arith="fixed")
    r["fx"], r["fy"], r["mz"], r["status"]

evaluate() calls grip_mf_eval (or grip_mf_eval_pure) of the compiled
library once per point, in a C loop: Python works once per array.
"""
import math

import numpy as np

from grip import _core
from grip._core import GripError, backend, check_arith

_INPUTS = ("kappa", "alpha", "gamma", "fz", "p", "vx")


class Params:
    """A Magic Formula parameter set, loaded once.

    values: {field: SI value} of every coefficient of GRIP_MF_COEFFICIENTS
    (lower-case .tir keys: "fnomin", "pcy1", ...); fittyp, tyreside (+1
    LEFT, -1 RIGHT: the side the file was fitted for), options (bit set of
    GRIP_MF_OPT_*), path. The C struct of each arithmetic is filled on first
    use (struct(arith)), field by field, and checked with
    grip_mf_check_params."""

    def __init__(self, values, fittyp, tyreside=1, options=0, path=None):
        self.values = {k: float(v) for k, v in values.items()}
        self.fittyp = int(fittyp)
        self.tyreside = int(tyreside)
        self.options = int(options)
        self.path = path
        self._structs = {}

    def __repr__(self):
        return (f"grip.mf.Params({self.path or '<values>'}, FITTYP {self.fittyp}, "
                f"TYRESIDE {'RIGHT' if self.tyreside < 0 else 'LEFT'}, options 0x{self.options:x})")

    def replace(self, **changes):
        """A copy with some coefficients (SI), or fittyp / tyreside /
        options, changed."""
        values = dict(self.values)
        head = {"fittyp": self.fittyp, "tyreside": self.tyreside, "options": self.options}
        for k, v in changes.items():
            if k in head:
                head[k] = v
            elif k.lower() in values:
                values[k.lower()] = v
            else:
                raise GripError(_core.ERR_PARAM, "grip.mf.Params.replace", "no such coefficient", param=k)
        return Params(values, path=self.path, **head)

    def struct(self, arith="float"):
        """The grip_mf_params of this arithmetic (cffi pointer; keep the
        Params alive while the library uses it)."""
        check_arith(arith)
        p = self._structs.get(arith)
        if p is None:
            p = self._structs[arith] = _fill(self, backend(arith))
        return p

    def stored(self, arith="float"):
        """{KEY: SI value} as the arithmetic stores it (each coefficient
        read back from the C struct)."""
        be = backend(arith)
        p = self.struct(arith)
        return {key: be.lib.grip_py_mf_get(p, i) for i, (_f, key, *_rest) in enumerate(coefficients(arith))}


def coefficients(arith="float"):
    """[(field, KEY, SECTION, fmt, default, required)] of the compiled
    GRIP_MF_COEFFICIENTS (grip_mf_coefs.h)."""
    be = backend(arith)
    ffi, lib = be.ffi, be.lib
    f, k, s = ffi.new("const char **"), ffi.new("const char **"), ffi.new("const char **")
    ql, d, r = ffi.new("int *"), ffi.new("double *"), ffi.new("int *")
    out = []
    for i in range(lib.grip_py_mf_ncoef()):
        lib.grip_py_mf_coef(i, f, k, s, ql, d, r)
        out.append((ffi.string(f[0]).decode(), ffi.string(k[0]).decode(), ffi.string(s[0]).decode(),
                    "QL" if ql[0] else "QS", d[0], bool(r[0])))
    return out


def _fill(params, be):
    coefs = coefficients(be.arith)
    missing = [c[0] for c in coefs if c[0] not in params.values]
    if missing:
        raise GripError(_core.ERR_PARAM, "grip.mf", "coefficients missing from the parameter set",
                        param=", ".join(missing), arith=be.arith)
    v = np.array([params.values[c[0]] for c in coefs], np.float64)
    p = be.ffi.new("grip_mf_params *")
    rc = be.lib.grip_py_mf_fill(p, params.fittyp, params.tyreside, params.options & 0xFFFFFFFF,
                                be.ptr("double", v), len(coefs))
    if rc != 0:
        c = coefs[-1 - rc]
        what = {"QS": "QS = Q15.16", "QL": "QL = Q23.8"}[c[3]] if be.fixed else "single precision"
        raise GripError(_core.ERR_PARAM, "grip.mf", f"value {v[-1 - rc]!r} (SI) is not representable in {what}",
                        param=c[1], arith=be.arith)
    st = be.lib.grip_mf_check_params(p)
    if st != _core.OK:
        raise GripError(st, "grip_mf_check_params", f"{params.path or 'parameter set'}: the library rejects it",
                        arith=be.arith)
    return p


def options_bits(side=None, sae=False, kappa_braking=False, book=False, mirror=False):
    """GRIP_MF_OPT_* bits (grip_mf.h) of the keyword options."""
    lib = backend("float").lib
    bits = 0
    if side not in (None, "left", "right"):
        raise ValueError(f"side must be 'fitted', 'left' or 'right', not {side!r}")
    if side == "right":
        bits |= lib.GRIP_MF_OPT_RIGHT_SIDE
    if sae:
        bits |= lib.GRIP_MF_OPT_SAE
    if kappa_braking:
        bits |= lib.GRIP_MF_OPT_KAPPA_BRAKE
    if book:
        bits |= lib.GRIP_MF_OPT_BOOK
    if mirror:
        bits |= lib.GRIP_MF_OPT_MIRROR
    return int(bits)


def _tools_reader():
    """grip_tools.reference.tir when it can run (a clone: it reads the
    coefficient list from include/grip/grip_mf_coefs.h), else None."""
    try:
        from grip_tools.reference import tir
    except (ImportError, OSError):
        return None
    import os
    return tir if os.path.exists(tir.COEFS_HEADER) else None


def load(tir_path, side=None, sae=False, kappa_braking=False, book=False, mirror=False, reader=None):
    """Reads a .tir file once: a Params for evaluate() and the estimator.

    side: where the tyre is mounted: "fitted" (default: on the side the
    file's TYRESIDE names, never mirrored, as grip-tire and every grip tool
    evaluate a .tir), "left" or "right" (the library mirrors a file fitted
    for the other side, as `grip-tire --side`). sae, kappa_braking, book, mirror: the other
    GRIP_MF_OPT_* options (grip_mf.h).
    reader: "tools" (grip_tools.reference.tir, the default in a clone),
    "c" (port/linux/tir_reader.c, grip-tire's reader, compiled into the
    extension: the fallback when grip_tools cannot read its header), or None
    (the first that works). Errors name file, line and key."""
    def mounted(tyreside):
        s = side if side in ("left", "right") else ("right" if int(tyreside) == -1 else "left")
        if side not in (None, "fitted", "left", "right"):
            raise ValueError(f"side must be 'fitted', 'left' or 'right', not {side!r}")
        return options_bits(s, sae, kappa_braking, book, mirror)
    tir = _tools_reader() if reader in (None, "tools") else None
    if reader == "tools" and tir is None:
        raise ImportError("grip_tools.reference.tir is not usable here (run from a clone with `make setup`)")
    if tir is not None:
        t = tir.read_tir(tir_path)
        d = t.params()
        values = {c.field: d[c.field] for c in tir.coefficients()}
        return Params(values, d["fittyp"], d["tyreside"], mounted(d["tyreside"]), path=tir_path)
    if reader not in (None, "c"):
        raise ValueError(f"reader must be 'tools', 'c' or None, not {reader!r}")
    return _load_c(tir_path, mounted)


def _load_c(tir_path, mounted):
    be = backend("float")
    coefs = coefficients("float")
    v = np.zeros(len(coefs), np.float64)
    fittyp, tyreside = be.ffi.new("int32_t *"), be.ffi.new("int32_t *")
    err = be.ffi.new("char[1024]")
    if be.lib.grip_py_tir_parse(str(tir_path).encode(), be.ffi.from_buffer("double[]", v), len(coefs),
                                fittyp, tyreside, err, 1024) != 0:
        raise GripError(None, "grip.mf.load", be.ffi.string(err).decode(errors="replace"))
    values = {c[0]: float(x) for c, x in zip(coefs, v)}
    return Params(values, fittyp[0], tyreside[0], mounted(tyreside[0]), path=tir_path)


def evaluate(params, kappa, alpha, gamma, fz, p=None, vx=None, arith="float", pure=False, raw=False,
             threads=1, errors="return", lanes=False):
    """Forces and moment of the Magic Formula at every point.

    kappa [-], alpha [rad], gamma [rad], fz [N], p [Pa] (None: 0, i.e.
    INFLPRES, or NOMPRES when INFLPRES = 0), vx [m/s] (None: LONGVL of the
    set): numpy arrays or numbers, broadcast together, SI, ISO-W axes (or as
    the set's options say). Each point is converted to the build's number
    format (grip_convert.h: float, or QS/QL rounded half away from zero) and
    passed to grip_mf_eval (pure=True: grip_mf_eval_pure).

    Returns {"fx", "fy", "mz": float64 [N, N m] (raw=True: the build's
    grip_real_t, float32 or Q23.8 int32), "status": int32 grip_status_t}
    in the broadcast shape. A point the build cannot hold (non-finite; fixed:
    beyond the Q range) is not evaluated: status GRIP_ERR_INPUT, zero
    outputs (as grip-tire). errors="raise": a GripError for the first point
    with status < 0. threads: pieces evaluated in parallel (0: one per CPU);
    results do not depend on it.

    lanes=True: the set is prepared once (grip_mf_prepare) and the points
    go through grip_mf_eval_prepared_lanes (pure: _pure_prepared_lanes),
    eight side by side in SIMD instructions where the build has them (the
    float build on x86-64 or Arm with NEON; docs/python-binding.md section
    5): the same statuses, the outputs within 2e-5 Fz (Mz: Fz R0) of the
    default path's - grip's float kernels instead of libm - and so no
    longer bit for bit grip-tire's; about 2.5x the points per second. The
    fixed build has no lane form: the same results either way."""
    check_arith(arith)
    if not isinstance(params, Params):
        raise TypeError("params must be a grip.mf.Params (grip.mf.load)")
    if errors not in ("return", "raise"):
        raise ValueError("errors must be 'return' or 'raise'")
    be = backend(arith)
    cp = params.struct(arith)
    if p is None:
        p = 0.0
    if vx is None:
        vx = params.values["longvl"]
    shape, ins = _core.broadcast_inputs([kappa, alpha, gamma, fz, p, vx])
    n = int(math.prod(shape))
    fx = np.empty(n, be.real)
    fy = np.empty(n, be.real)
    mz = np.empty(n, be.real)
    status = np.empty(n, np.int32)
    ffi, lib = be.ffi, be.lib

    def piece(a, b):
        args = []
        for buf, stride in ins:
            args += [ffi.from_buffer("double[]", buf if stride == 0 else buf[a:b]), stride]
        return lib.grip_py_mf_eval(cp, 1 if pure else 0, 1 if lanes else 0, b - a, *args,
                                   ffi.from_buffer("grip_real_t[]", fx[a:b]),
                                   ffi.from_buffer("grip_real_t[]", fy[a:b]),
                                   ffi.from_buffer("grip_real_t[]", mz[a:b]),
                                   ffi.from_buffer("int32_t[]", status[a:b]))

    if n:
        _core.run_chunks(n, threads, piece)
    if errors == "raise":
        fn = ("grip_mf_eval_pure_prepared_lanes" if pure else "grip_mf_eval_prepared_lanes") if lanes else \
            ("grip_mf_eval_pure" if pure else "grip_mf_eval")
        _core.raise_first_error(status, fn, arith,
                                lambda k: ", ".join(f"{nm}={float(buf[k * s])!r}"
                                                    for nm, (buf, s) in zip(_INPUTS, ins)))
    if raw:
        out = {"fx": fx, "fy": fy, "mz": mz}
    else:
        out = {"fx": be.to_si(fx, "QL"), "fy": be.to_si(fy, "QL"), "mz": be.to_si(mz, "QL")}
    out["status"] = status
    return {k: v.reshape(shape) for k, v in out.items()}
