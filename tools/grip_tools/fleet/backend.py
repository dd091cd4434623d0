"""How the fleet runs the C estimator on one log: the replay adapter.

A backend turns one log (a candump file, an estimator-input CSV, or the
input columns already in memory) into the estimator's per-step outputs and
the replay's counters. The fleet code only calls `Backend.run(job)` and
`Backend.identity()`. Two backends run the same C code on the same
arguments:

    BindingReplay(arith)       grip-replay's replay (port/linux/replay_core.c)
                               inside this process, through the grip binding
                               (grip.replay): no process start, no text
                               output parsed; the default
    SubprocessReplay(binary)   the grip-replay program, one process per log
                               (stdout CSV parsed, stderr summary)

Both return the same ReplayResult, bit for bit (the binding gives each
number as the double that reading the program's text gives;
tests/python/fleet/test_fleet.py compares the two on every kind of log),
with the same error message for a log that fails.

    ReplayJob     what to run: source kind and path (or columns), .tir,
                  vehicle preset and vehicle file, signal table, step
    ReplayResult  columns (name -> numpy array), counters (dict), text
"""
import hashlib
import io
import os
import re
import subprocess
import tempfile
from dataclasses import dataclass, field

import numpy as np

# estimator input columns of grip-replay --csv (est_eval.IN_COLS plus the
# optional brake torques it also reads)
CSV_INPUTS = ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle",
              "yaw_rate", "ax", "ay", "vehicle_speed", "brake_pressure_fl", "brake_pressure_fr",
              "brake_pressure_rl", "brake_pressure_rr", "brake_torque_fl", "brake_torque_fr",
              "brake_torque_rl", "brake_torque_rr", "rear_steer_angle")
# the estimator's output columns (grip-replay -e, after the inputs)
EST_COLS = ("est_status", "est_valid", "est_flags", "vx", "beta", "yaw_rate", "yaw_rate_ref", "delta", "mu",
            "mu_conf", "fy_front", "fy_rear", "util_front", "util_rear", "fy_margin_front", "yaw_rate_bias",
            "ay_model", "beta_sd", "mu_sd")
INT_COLS = ("step", "est_status", "est_valid", "est_flags")


class ReplayError(Exception):
    """The log could not be replayed; the message says why (grip-replay's
    own last line when it has one). stage: 'decode' (the log or its
    inputs) or 'estimate'."""

    def __init__(self, msg, stage="decode"):
        super().__init__(msg)
        self.stage = stage


@dataclass
class ReplayJob:
    kind: str                      # 'csv' | 'candump' | 'columns'
    tir: str
    path: str = None               # csv / candump
    columns: dict = None           # kind 'columns': t_s and CSV_INPUTS names -> arrays (NaN = not valid)
    preset: str = "generic"        # grip-replay --vehicle
    vehicle_file: str = None
    table: str = None              # candump: signal table (text form); None = built-in rav4
    step_ms: float = 10.0
    skip_bad: bool = False
    timeout_s: float = 600.0


@dataclass
class ReplayResult:
    columns: dict                  # t_s, step, in_<input>, in_<input>_fault, EST_COLS
    counters: dict = field(default_factory=dict)
    text: str = ""                 # the replay's summary (stderr)


def file_sha256(path, bufsize=1 << 20):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        while True:
            b = f.read(bufsize)
            if not b:
                break
            h.update(b)
    return h.hexdigest()


def write_columns_csv(path, cols):
    """Input columns (t_s + CSV_INPUTS names; NaN = not valid) as a
    grip-replay --csv file; floats as repr, so they read back exactly."""
    names = ["t_s"] + [n for n in CSV_INPUTS if n in cols]
    arrs = [np.asarray(cols[n], dtype=float) for n in names]
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        for k in range(len(arrs[0])):
            f.write(",".join("" if x != x else repr(float(x)) for x in (a[k] for a in arrs)) + "\n")


def parse_output(text):
    """grip-replay's output CSV (with -e) -> columns. Input columns before
    est_status become in_<name> / in_<name>_fault (the estimator has a
    yaw_rate column of its own); numbers as float64 (empty = NaN), the
    integer columns as int64, faults as str."""
    import pyarrow as pa
    import pyarrow.csv as pcsv
    nl = text.find("\n")
    if nl < 0 or not text[:nl].strip():
        raise ReplayError("grip-replay wrote no output rows", "estimate")
    header = text[:nl].strip().split(",")
    if "est_status" not in header:
        raise ReplayError("grip-replay output has no estimator columns (est_status)", "estimate")
    k_est = header.index("est_status")
    names = []
    for i, n in enumerate(header):
        if i >= k_est or n in ("t_s", "step"):
            names.append(n)
            continue
        # grip-replay -e names a measured input that the estimator also
        # outputs <name>_in (yaw_rate_in, yaw_rate_in_fault): in_<name> here
        if n.endswith("_in_fault"):
            n = n[:-len("_in_fault")] + "_fault"
        elif n.endswith("_in"):
            n = n[:-len("_in")]
        names.append(f"in_{n}")
    types = {}
    for n in names:
        if n.endswith("_fault"):
            types[n] = pa.string()
        elif n in INT_COLS:
            types[n] = pa.int64()
        else:
            types[n] = pa.float64()
    body = text[nl + 1:].encode()
    if not body.strip():
        return {n: np.zeros(0, dtype=np.int64 if n in INT_COLS else (object if n.endswith("_fault") else float))
                for n in names}
    # one thread: a Dask worker is one core's worth of work
    tab = pcsv.read_csv(io.BytesIO(body), read_options=pcsv.ReadOptions(column_names=names, use_threads=False),
                        convert_options=pcsv.ConvertOptions(column_types=types, strings_can_be_null=False))
    out = {}
    for n in names:
        c = tab.column(n)
        if n.endswith("_fault"):
            out[n] = np.asarray(c.to_pylist(), dtype=object)
        elif n in INT_COLS:
            out[n] = c.to_numpy().astype(np.int64)
        else:
            out[n] = c.to_numpy(zero_copy_only=False).astype(float)
    return out


_COUNTERS = [
    (re.compile(r"frames\s+(\d+) read.*?(\d+) decoded, (\d+) other ids, (\d+) error frames, (\d+) remote"),
     ("frames_read", "frames_decoded", "frames_other_ids", "error_frames", "remote_frames")),
    (re.compile(r"decode errors\s+(\d+) \(dlc (\d+), checksum (\d+), counter frozen (\d+), out of range (\d+), "
                r"sender fault (\d+)\), counter skips (\d+)"),
     ("decode_errors", "dlc_errors", "checksum_errors", "counter_frozen", "out_of_range", "sender_faults",
      "counter_skips")),
    (re.compile(r"timing\s+(\d+) reordered, (\d+) late, (\d+) too old, (\d+) timestamp jumps"),
     ("reordered", "late", "too_old", "timestamp_jumps")),
    (re.compile(r"drops\s+(\d+)"), ("drops",)),
    (re.compile(r"(\d+) rows, (\d+) with a time step off by"), ("csv_rows", "rows_off_step")),
    (re.compile(r"estimator\s+(\d+) steps, (\d+) errors"), ("est_steps", "est_errors")),
    (re.compile(r"(\d+) malformed lines skipped"), ("lines_skipped",)),
]
COUNTER_NAMES = tuple(n for _, names in _COUNTERS for n in names)


def parse_summary(text):
    """The replay's summary lines (stderr) -> counters; a counter the
    summary does not print (e.g. frame counts of a CSV replay) is absent."""
    out = {}
    for rx, names in _COUNTERS:
        m = rx.search(text)
        if m:
            out.update({n: int(v) for n, v in zip(names, m.groups())})
    return out


_SUMMARY_HEAD = re.compile(r"^grip-replay: .*(\(CSV input\), step|, table .*, step .* stale after)")


def error_line(stderr):
    """grip-replay's error message: its last 'grip-replay: ' line that is not
    the summary's heading (the summary follows the error)."""
    lines = [ln.strip() for ln in stderr.splitlines() if ln.startswith("grip-replay: ")]
    lines = [ln for ln in lines if not _SUMMARY_HEAD.match(ln)]
    if lines:
        return lines[-1]
    rest = [ln.strip() for ln in stderr.splitlines() if ln.strip()]
    return rest[-1] if rest else ""


class Backend:
    """Interface: identity() and run(job)."""
    name = "?"

    def identity(self):
        raise NotImplementedError

    def run(self, job):
        raise NotImplementedError


def replay_args(job, src):
    """grip-replay's arguments (without the program) for a job whose log
    is the file src."""
    a = ["-e", job.tir, "--vehicle", job.preset, "--step-ms", repr(float(job.step_ms))]
    if job.vehicle_file:
        a += ["--vehicle-file", job.vehicle_file]
    if job.kind == "candump":
        if job.table:
            a += ["-t", job.table]
        if job.skip_bad:
            a += ["--skip-bad"]
        a += [src]
    else:
        a += ["--csv", src]
    return a


def replay_error(status, stderr, job, src):
    """The ReplayError of a replay that ended with a non-zero status."""
    msg = error_line(stderr) or f"exit status {status}"
    if msg.startswith("grip-replay: "):
        msg = msg[len("grip-replay: "):]
    if src != job.path and job.path is None:
        msg = msg.replace(src, "<columns>")
    return ReplayError(f"grip-replay exit {status}: {msg}", "decode" if status in (3, 4) else "estimate")


class _Source:
    """The job's log as a file: its path, or a temporary grip-replay --csv
    file of its columns (kind 'columns')."""

    def __init__(self, job):
        self.job = job
        self.dir = None

    def __enter__(self):
        if self.job.kind != "columns":
            return self.job.path
        self.dir = tempfile.TemporaryDirectory(prefix="grip-fleet-")
        src = os.path.join(self.dir.name, "inputs.csv")
        write_columns_csv(src, self.job.columns)
        return src

    def __exit__(self, *exc):
        if self.dir is not None:
            self.dir.cleanup()


class BindingReplay(Backend):
    """grip-replay's replay in this process (grip.replay, one arithmetic).
    No timeout (the C loop cannot be stopped halfway; its time is bounded
    by the log's length); the rows are capped at max_steps instead."""
    name = "binding"

    def __init__(self, arith, max_steps=None):
        import grip.replay
        why = grip.replay.available(arith)
        if why:
            raise ImportError(why)
        self.arith = arith
        self.max_steps = max_steps or grip.replay.DEFAULT_MAX_STEPS
        self._id = None

    def identity(self):
        """'binding:' + sha256 of the compiled extension: any rebuild that
        changes the code changes it, and rows made by the grip-replay
        program (whose identity is its own file's sha256) are not taken
        for this backend's (see docs/fleet.md, "Backends")."""
        if self._id is None:
            from grip import _core
            self._id = "binding:" + file_sha256(_core.backend(self.arith).path)
        return self._id

    def run(self, job):
        import grip.replay
        with _Source(job) as src:
            res = grip.replay.run(replay_args(job, src), self.arith, self.max_steps)
            if res.status != 0:
                raise replay_error(res.status, res.text, job, src)
        return ReplayResult(res.columns, parse_summary(res.text), res.text)


def binding_available(ariths):
    """None when BindingReplay works for every arithmetic, else why not."""
    try:
        import grip.replay
    except ImportError as e:
        return f"the grip binding does not import ({e})"
    for a in ariths:
        why = grip.replay.available(a)
        if why:
            return why
    return None


class SubprocessReplay(Backend):
    """The C estimator as the grip-replay program (one process per log)."""
    name = "grip-replay"

    def __init__(self, binary):
        self.binary = os.path.abspath(binary)
        self._id = None

    def identity(self):
        """sha256 of the program file: any rebuild that changes the code
        changes it."""
        if self._id is None:
            self._id = file_sha256(self.binary)
        return self._id

    def args(self, job, src):
        return [self.binary] + replay_args(job, src)

    def run(self, job):
        if not os.path.exists(self.binary):
            raise ReplayError(f"{self.binary}: not built", "estimate")
        with _Source(job) as src:
            args = self.args(job, src)
            try:
                p = subprocess.run(args, capture_output=True, text=True, timeout=job.timeout_s)
            except subprocess.TimeoutExpired:
                raise ReplayError(f"grip-replay did not finish within {job.timeout_s:g} s", "estimate")
            if p.returncode != 0:
                raise replay_error(p.returncode, p.stderr, job, src)
        return ReplayResult(parse_output(p.stdout), parse_summary(p.stderr), p.stderr)
