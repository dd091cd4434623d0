"""The two compiled extensions and what every module of the binding shares:
loading, the struct layouts as numpy dtypes, SI <-> build-format
conversions, status codes and the exception."""
import glob
import importlib
import json
import os
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

ARITHS = ("float", "fixed")
_MODULES = {"float": "_grip_f32", "fixed": "_grip_q16"}

# grip_status_t (grip_types.h)
OK = 0
WARN_CLAMPED = 1
ERR_NULL = -1
ERR_PARAM = -2
ERR_INPUT = -3
ERR_STATE = -4
ERR_DOMAIN = -5
STATUS_NAMES = {OK: "GRIP_OK", WARN_CLAMPED: "GRIP_WARN_CLAMPED", ERR_NULL: "GRIP_ERR_NULL",
                ERR_PARAM: "GRIP_ERR_PARAM", ERR_INPUT: "GRIP_ERR_INPUT", ERR_STATE: "GRIP_ERR_STATE",
                ERR_DOMAIN: "GRIP_ERR_DOMAIN"}

SCALE = {"QS": 1.0 / 65536.0, "QL": 1.0 / 256.0}


class GripError(Exception):
    """A call of the library failed, or a value cannot be given to it.

    status: the grip_status_t (int) or None when the library was not called;
    status_name: "GRIP_ERR_PARAM", ...; param: the parameter, key or input
    concerned, when known; where: the function or object; detail: text."""

    def __init__(self, status, where, detail=None, param=None, arith=None):
        self.status = None if status is None else int(status)
        self.status_name = STATUS_NAMES.get(self.status, f"status {self.status}") if status is not None else None
        self.where = where
        self.detail = detail
        self.param = param
        self.arith = arith
        parts = [where + (f" ({arith})" if arith else "")]
        if status is not None:
            parts.append(f"{self.status_name} ({status_str(self.status)})")
        if param is not None:
            parts.append(str(param))
        if detail:
            parts.append(detail)
        super().__init__(": ".join(parts))


def status_str(status):
    """grip_status_str of the library (the same text in both builds)."""
    be = backend("float")
    return be.ffi.string(be.lib.grip_status_str(int(status))).decode()


def status_name(status):
    return STATUS_NAMES.get(int(status), f"status {int(status)}")


def check_arith(arith):
    if arith not in ARITHS:
        raise ValueError(f"arith must be 'float' or 'fixed', not {arith!r}")
    return arith


def _import_ext(name):
    """grip.<name>; when this grip package has no compiled extension (a
    source folder shadowing an installed copy), another grip folder on
    sys.path that has it."""
    pkg = sys.modules["grip"]
    try:
        return importlib.import_module("grip." + name)
    except ImportError as first:
        here = os.path.dirname(os.path.abspath(__file__))
        for p in sys.path:
            d = os.path.join(os.path.abspath(p or "."), "grip")
            if d == here or d in pkg.__path__:
                continue
            if glob.glob(os.path.join(d, name + ".*so")) + glob.glob(os.path.join(d, name + ".*pyd")):
                pkg.__path__.append(d)
                return importlib.import_module("grip." + name)
        raise ImportError(
            f"the C extension grip.{name} is not built ({first}); install the tools: "
            "`make setup` (editable, in .venv) or `pip install ./tools` from the top of the clone") from None


class Backend:
    """One compiled extension: ffi, lib, and what Python needs to know
    about its number format and structs."""

    def __init__(self, arith):
        mod = _import_ext(_MODULES[arith])
        self.arith = arith
        self.ffi = mod.ffi
        self.lib = mod.lib
        if self.ffi.string(self.lib.grip_py_info(0)).decode() != arith:
            raise ImportError(f"grip.{_MODULES[arith]} is not the {arith} build")
        self.fixed = arith == "fixed"
        self.real = np.dtype(np.int32 if self.fixed else np.float32)
        self.version = self.ffi.string(self.lib.grip_py_info(1)).decode()
        self.structs = json.loads(self.ffi.string(self.lib.grip_py_info(2)).decode())
        self.build = json.loads(self.ffi.string(self.lib.grip_py_info(3)).decode())
        self._dtypes = {}
        self.path = getattr(mod, "__file__", None)
        self.stale = _stale(self.build, self.path)
        if self.stale:
            import warnings
            warnings.warn(f"grip.{_MODULES[arith]} is older than {self.stale}: it is not the C code of the clone "
                          "any more; compile it again (`make setup`, or `pip install ./tools`)", stacklevel=3)
        self.n_inputs = int(self.lib.GRIP_IN_COUNT)
        self.input_names = tuple(self.ffi.string(self.lib.grip_input_name(i)).decode()
                                 for i in range(self.n_inputs))
        self.input_ql = np.array([self.lib.grip_input_is_ql(i) for i in range(self.n_inputs)], np.uint8)

    # ---- struct layouts
    def fields(self, struct):
        """[(name, ctype, dims, fmt, unit)] of a public struct, from its header."""
        return [tuple(f) for f in self.structs[struct]]

    def fmt(self, struct, field):
        for f in self.structs[struct]:
            if f[0] == field:
                return f[3]
        raise KeyError(field)

    def dtype(self, struct):
        """The struct as a numpy structured dtype (offsets from the compiler)."""
        dt = self._dtypes.get(struct)
        if dt is not None:
            return dt
        base = {"grip_real_t": self.real, "int32_t": np.int32, "uint32_t": np.uint32, "uint8_t": np.uint8,
                "int64_t": np.int64}
        names, formats, offsets = [], [], []
        for name, ctype, dims, _fmt, _unit in self.fields(struct):
            if ctype not in base:
                continue
            names.append(name)
            formats.append((base[ctype], tuple(dims)) if dims else base[ctype])
            offsets.append(self.ffi.offsetof(struct, name))
        dt = np.dtype({"names": names, "formats": formats, "offsets": offsets,
                       "itemsize": self.ffi.sizeof(struct)})
        self._dtypes[struct] = dt
        return dt

    def ptr(self, ctype, arr):
        """A C pointer to the data of a C-contiguous numpy array (no copy)."""
        if arr.size == 0:
            return self.ffi.NULL
        return self.ffi.cast(ctype + " *", self.ffi.from_buffer(arr, require_writable=False))

    # ---- numbers
    def to_si(self, q, fmt):
        """grip_real_t array -> float64 SI (exact)."""
        q = np.asarray(q)
        if self.fixed:
            return q.astype(np.float64) * SCALE[fmt]
        return q.astype(np.float64)

    def param_real(self, si, fmt, where, name):
        """One parameter SI -> grip_real_t as GRIP_QS()/GRIP_QL() would
        convert it; GripError (GRIP_ERR_PARAM, naming it) when the build
        cannot hold it."""
        out = self.ffi.new("grip_real_t *")
        try:
            v = float(si)
        except (TypeError, ValueError):
            raise GripError(ERR_PARAM, where, f"{si!r} is not a number", param=name, arith=self.arith) from None
        if self.lib.grip_py_param(v, 1 if fmt == "QL" else 0, out) != 0:
            what = {"QS": "QS = Q15.16", "QL": "QL = Q23.8"}[fmt] if self.fixed else "single precision"
            raise GripError(ERR_PARAM, where, f"{v!r} is not representable in {what}", param=name,
                            arith=self.arith)
        return out[0]

    def inputs_real(self, si, ql):
        """SI array -> (grip_real_t array, status array) with grip_convert.h;
        ql: 0/1 per element (broadcast)."""
        si = np.ascontiguousarray(si, dtype=np.float64)
        ql = np.ascontiguousarray(np.broadcast_to(np.asarray(ql, np.uint8), si.shape))
        out = np.zeros(si.shape, self.real)
        st = np.zeros(si.shape, np.int32)
        self.lib.grip_py_to_real(si.size, self.ptr("double", si), self.ptr("uint8_t", ql),
                                 self.ptr("grip_real_t", out), self.ptr("int32_t", st))
        return out, st

    def struct_to_dict(self, struct, arr, skip=()):
        """Every field of a structured array, grip_real_t fields in SI."""
        out = {}
        for name, ctype, _dims, fmt, _unit in self.fields(struct):
            if name in skip or name not in arr.dtype.names:
                continue
            if ctype == "grip_real_t":
                out[name] = self.to_si(arr[name], fmt)
            else:
                out[name] = np.array(arr[name])
        return out


def _stale(build, path):
    """A C source or header of the clone the extension was compiled from
    that is newer than the extension, or None."""
    repo = build.get("repository")
    if not repo or not path or not os.path.isdir(repo):
        return None
    try:
        t = os.path.getmtime(path)
        files = [os.path.join(repo, f) for f in build.get("lib_sources", []) + build.get("port_sources", [])]
        for d in ("include/grip", "lib/*", "port/linux"):
            files += glob.glob(os.path.join(repo, d, "*.h"))
        for f in files:
            if os.path.getmtime(f) > t:
                return os.path.relpath(f, repo)
    except OSError:
        return None
    return None


_BACKENDS = {}


def backend(arith):
    check_arith(arith)
    be = _BACKENDS.get(arith)
    if be is None:
        be = _BACKENDS[arith] = Backend(arith)
    return be


def build_info(arith="float"):
    """How the extension of `arith` was built: compiler, its version, the
    flags of the library objects (the Makefile's) and of the host readers,
    the sources, the clone it was built from."""
    return dict(backend(arith).build)


# ---- arrays of points ---------------------------------------------------

def broadcast_inputs(arrays):
    """float64 inputs broadcast together: (shape, [(buffer, stride)]) where a
    single value is passed with stride 0 (no copy per point)."""
    arrays = [np.asarray(a, dtype=np.float64) for a in arrays]
    shape = np.broadcast_shapes(*[a.shape for a in arrays])
    out = []
    for a in arrays:
        if a.size == 1:
            out.append((np.ascontiguousarray(a.reshape(1)), 0))
        elif a.shape == shape:
            out.append((np.ascontiguousarray(a).reshape(-1), 1))
        else:
            out.append((np.ascontiguousarray(np.broadcast_to(a, shape)).reshape(-1), 1))
    return shape, out


def run_chunks(n, threads, fn):
    """fn(start, stop) over [0, n) in `threads` pieces; cffi releases the
    GIL during each C call, so the pieces run in parallel."""
    if threads is None or threads == 0:
        threads = os.cpu_count() or 1
    threads = max(1, min(int(threads), n // 4096 or 1))
    if threads == 1:
        return [fn(0, n)]
    bounds = [(n * i) // threads for i in range(threads + 1)]
    with ThreadPoolExecutor(max_workers=threads) as pool:
        return list(pool.map(lambda i: fn(bounds[i], bounds[i + 1]), range(threads)))


def raise_first_error(status, where, arith, describe):
    bad = np.flatnonzero(np.asarray(status).reshape(-1) < 0)
    if bad.size:
        k = int(bad[0])
        st = int(np.asarray(status).reshape(-1)[k])
        raise GripError(st, where, f"{bad.size} of {np.asarray(status).size} points failed; first: {describe(k)}",
                        arith=arith)


# ---- configuration structs from dicts ---------------------------------------

def set_fields(be, struct, ptr, values, where, skip=(), names_for_arrays=None):
    """Writes {field: SI value} into a configuration struct, field by field:
    grip_real_t fields converted as GRIP_QS()/GRIP_QL() of the field's
    header format, integer fields as integers; array fields take a sequence,
    or a {name: value} dict when names_for_arrays (a tuple of element names)
    is given. GripError naming the key for an unknown key or a value the
    build cannot hold."""
    fields = {f[0]: f for f in be.fields(struct) if f[0] not in skip}
    for key, v in values.items():
        f = fields.get(key)
        if f is None:
            raise GripError(ERR_PARAM, where, "unknown configuration key; known: " + ", ".join(fields),
                            param=key, arith=be.arith)
        _name, ctype, dims, fmt, _unit = f
        if dims:
            cur = getattr(ptr, key)
            if isinstance(v, dict):
                if names_for_arrays is None:
                    raise GripError(ERR_PARAM, where, "give a sequence", param=key, arith=be.arith)
                items = []
                for nm, x in v.items():
                    if nm not in names_for_arrays[:dims[0]]:
                        raise GripError(ERR_PARAM, where, f"no element {nm!r}; elements: "
                                        + ", ".join(names_for_arrays[:dims[0]]), param=key, arith=be.arith)
                    items.append((names_for_arrays.index(nm), x))
            else:
                seq = list(v)
                if len(seq) != dims[0]:
                    raise GripError(ERR_PARAM, where, f"needs {dims[0]} values, not {len(seq)}", param=key,
                                    arith=be.arith)
                items = list(enumerate(seq))
            for i, x in items:
                cur[i] = _one(be, ctype, fmt, x, where, f"{key}[{i}]")
        else:
            setattr(ptr, key, _one(be, ctype, fmt, v, where, key))


def _one(be, ctype, fmt, v, where, name):
    if ctype == "grip_real_t":
        return be.param_real(v, fmt, where, name)
    try:
        iv = int(v)
    except (TypeError, ValueError):
        raise GripError(ERR_PARAM, where, f"{v!r} is not an integer", param=name, arith=be.arith) from None
    if iv != v:
        raise GripError(ERR_PARAM, where, f"{v!r} is not an integer", param=name, arith=be.arith)
    lo, hi = {"uint32_t": (0, 2 ** 32 - 1), "int32_t": (-2 ** 31, 2 ** 31 - 1), "uint8_t": (0, 255)}[ctype]
    if not lo <= iv <= hi:
        raise GripError(ERR_PARAM, where, f"{iv} is outside {ctype}", param=name, arith=be.arith)
    return iv


def get_fields(be, struct, ptr, skip=()):
    """{field: SI value (arrays as lists)} of a configuration struct."""
    out = {}
    for name, ctype, dims, fmt, _unit in be.fields(struct):
        if name in skip:
            continue
        v = getattr(ptr, name)
        if dims:
            v = [v[i] for i in range(dims[0])]
        if ctype == "grip_real_t":
            out[name] = (be.to_si(np.array(v, be.real), fmt).tolist())
        else:
            out[name] = list(v) if dims else int(v)
    return out


def culprits(try_init, overrides):
    """The keys of `overrides` that the init rejects: each one without
    which (the default in its place) try_init(values) passes."""
    bad = []
    for k in overrides:
        rest = {kk: vv for kk, vv in overrides.items() if kk != k}
        try:
            if try_init(rest) == OK:
                bad.append(k)
        except GripError:
            continue
    return bad


def culprit_text(bad, ranges):
    if bad:
        return ("the configuration is rejected; it passes with "
                + ("this value" if len(bad) == 1 else "each of these values")
                + f" at its default (valid ranges: {ranges})")
    return f"the configuration is rejected (valid ranges: {ranges})"
