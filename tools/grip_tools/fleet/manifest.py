"""Which logs a fleet run covers: a folder, a glob or a manifest.

A manifest is a CSV (or Parquet) table, one row per log. Columns (only
`path` is required; paths relative to the manifest's folder):

  path          the log: an estimator-input CSV (grip-replay --csv), a
                candump -l log (.log, .candump, .asc-free text) or a Parquet
                file with the estimator-input columns (t_s, wheel_speed_fl, ...)
  log_id        unique name (default: path without extension, '/' -> '__')
  format        csv | candump | parquet (default: from the extension)
  truth         a truth.csv of the same run (grip simulate's columns):
                accuracy metrics are computed where given
  vehicle       label the analysis pools by (default: the preset)
  preset        grip-replay --vehicle (rav4 | av21 | generic; default --preset)
  vehicle_file  grip-replay --vehicle-file (key = value lines)
  tir           the tire (.tir) of the estimator (default --tir)
  table         candump: signal table, text form (default --table or the built-in rav4)
  step_ms       estimator step (default --step-ms)
  surface, manoeuvre   labels the analysis and report group by
  any other column     carried into the results as it is (e.g. the
                simulator's injected sensor offsets)

A folder: its manifest.csv if it has one; else every *.csv, *.log,
*.candump and *.parquet file below it (truth.csv, *.truth.csv and
manifest files excepted; a truth.csv beside an inputs file is its truth).
A glob: the files it matches, the same way.
"""
import glob
import hashlib
import os
import re
from dataclasses import dataclass, field

from grip_tools.errors import DataError, UsageError

FORMATS = ("csv", "candump", "parquet")
EXT_FORMAT = {".csv": "csv", ".log": "candump", ".candump": "candump", ".parquet": "parquet"}
KNOWN = ("path", "log_id", "format", "truth", "vehicle", "preset", "vehicle_file", "tir", "table", "step_ms",
         "surface", "manoeuvre")
PRESETS = ("rav4", "av21", "generic")


@dataclass
class LogSpec:
    log_id: str
    path: str
    format: str
    tir: str
    preset: str = "generic"
    vehicle: str = None
    vehicle_file: str = None
    table: str = None
    truth: str = None
    step_ms: float = 10.0
    surface: str = None
    manoeuvre: str = None
    meta: dict = field(default_factory=dict)

    def files(self):
        """Every file the result depends on (the input hash covers their bytes)."""
        return [p for p in (self.path, self.truth, self.vehicle_file, self.table, self.tir) if p]

    def to_dict(self):
        return dict(self.__dict__)


def safe_id(s):
    """A log id usable as a folder name (the per-step table's partition)."""
    s = re.sub(r"[^A-Za-z0-9._-]+", "_", s.replace(os.sep, "__").replace("/", "__")).strip("._")
    return s or "log"


def input_hash(spec, options):
    """sha256 over the bytes of every file the log's result depends on, the
    spec's settings and the run options that change results."""
    from grip_tools.fleet.backend import file_sha256
    h = hashlib.sha256()
    for p in spec.files():
        h.update(os.path.basename(p).encode() + b"\0")
        h.update(file_sha256(p).encode() if os.path.exists(p) else b"missing")
    settings = {k: v for k, v in spec.to_dict().items() if k not in ("path", "truth", "vehicle_file", "table", "tir")}
    h.update(repr(sorted(settings.items())).encode())
    h.update(repr(sorted(options.items())).encode())
    return h.hexdigest()


def _fmt(path, given=None):
    if given:
        if given not in FORMATS:
            raise DataError(path, None, "format", f"unknown format '{given}' (one of {', '.join(FORMATS)})")
        return given
    return EXT_FORMAT.get(os.path.splitext(path)[1].lower(), "candump")


def _excluded(path):
    b = os.path.basename(path).lower()
    return b in ("truth.csv", "manifest.csv", "manifest.parquet") or b.endswith(".truth.csv")


def _truth_beside(path):
    stem = os.path.splitext(path)[0]
    for cand in (stem + ".truth.csv", os.path.join(os.path.dirname(path), "truth.csv")):
        if os.path.exists(cand) and cand != path:
            return cand
    return None


def _default_id(path, root):
    rel = os.path.relpath(path, root)
    stem = os.path.splitext(rel)[0]
    # a folder per log holding inputs.csv: the folder names the log
    if os.path.basename(stem) in ("inputs", "can", "sensors") and os.path.dirname(stem):
        stem = os.path.dirname(stem)
    return safe_id(stem)


def read_manifest(path, defaults):
    """LogSpecs of a manifest file (CSV or Parquet)."""
    import pandas as pd
    if path.endswith(".parquet"):
        df = pd.read_parquet(path)
    else:
        df = pd.read_csv(path, comment="#", dtype_backend="numpy_nullable")
    if "path" not in df.columns:
        raise DataError(path, 1, None, "a manifest needs a 'path' column")
    root = os.path.dirname(os.path.abspath(path))
    specs = []
    for i, row in enumerate(df.to_dict("records")):
        row = {k: (None if _isna(v) else v) for k, v in row.items()}
        if not row.get("path"):
            raise DataError(path, i + 2, "path", "empty")
        try:
            specs.append(_spec(row, root, defaults))
        except DataError as e:
            raise DataError(path, i + 2, e.field, e.message) from None
        except ValueError as e:              # e.g. step_ms not a number
            raise DataError(path, i + 2, None, str(e)) from None
    return specs


def _isna(v):
    try:
        import pandas as pd
        return v is None or v is pd.NA or (isinstance(v, float) and v != v)
    except TypeError:
        return False


def _abs(p, root):
    return None if p is None else (p if os.path.isabs(p) else os.path.normpath(os.path.join(root, str(p))))


def _spec(row, root, defaults):
    path = _abs(str(row["path"]), root)
    preset = row.get("preset") or defaults.get("preset") or "generic"
    return LogSpec(
        log_id=safe_id(str(row["log_id"])) if row.get("log_id") else _default_id(path, root),
        path=path, format=_fmt(path, row.get("format")),
        tir=_abs(row.get("tir"), root) or defaults["tir"],
        preset=str(preset), vehicle=str(row.get("vehicle") or preset),
        vehicle_file=_abs(row.get("vehicle_file"), root) or defaults.get("vehicle_file"),
        table=_abs(row.get("table"), root) or defaults.get("table"),
        truth=_abs(row.get("truth"), root),
        step_ms=float(row.get("step_ms") or defaults.get("step_ms") or 10.0),
        surface=None if row.get("surface") is None else str(row["surface"]),
        manoeuvre=None if row.get("manoeuvre") is None else str(row["manoeuvre"]),
        meta={k: (v.item() if hasattr(v, "item") else v) for k, v in row.items() if k not in KNOWN})


def discover(sources, defaults):
    """LogSpecs of the given sources (folders, globs, files, manifests), in
    a stable order (sorted by log id); duplicate ids are an error."""
    specs = []
    for src in sources:
        if os.path.isdir(src):
            for m in ("manifest.csv", "manifest.parquet"):
                if os.path.exists(os.path.join(src, m)):
                    specs += read_manifest(os.path.join(src, m), defaults)
                    break
            else:
                files = sorted(p for ext in EXT_FORMAT
                               for p in glob.glob(os.path.join(src, "**", "*" + ext), recursive=True))
                specs += _from_files([p for p in files if not _excluded(p)], src, defaults)
        elif os.path.basename(src).startswith("manifest") or src.endswith((".manifest.csv", ".manifest")):
            specs += read_manifest(src, defaults)
        else:
            if not glob.has_magic(src) and not os.path.exists(src):
                raise UsageError(f"{src}: no such file or folder")
            files = sorted(glob.glob(src, recursive=True)) if glob.has_magic(src) else [src]
            if not files:
                raise UsageError(f"{src}: matches no file")
            root = os.path.commonpath([os.path.dirname(os.path.abspath(p)) for p in files])
            specs += _from_files([p for p in files if not _excluded(p)], root, defaults)
    seen = {}
    for s in specs:
        if s.log_id in seen:
            raise UsageError(f"two logs have the id '{s.log_id}': {seen[s.log_id]} and {s.path} "
                             "(give log_id in a manifest)")
        seen[s.log_id] = s.path
    return sorted(specs, key=lambda s: s.log_id)


def _from_files(files, root, defaults):
    root = os.path.abspath(root)
    out = []
    for p in files:
        p = os.path.abspath(p)
        out.append(_spec({"path": p, "truth": _truth_beside(p)}, root, defaults))
    return out
