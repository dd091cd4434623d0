"""grip-replay's replay of a log file, run in this process.

    res = grip.replay.run(["-e", tir, "--vehicle", "rav4", "log.candump"], arith="fixed")
    res.status        grip-replay's exit status (0 ok, 2 usage, 3 table, 4 input)
    res.text          what grip-replay prints on stderr (messages, summary)
    res.columns       {column: array}, one row per estimator step

The arguments are grip-replay's (docs/can.md) for a candump log or a
`--csv` file with `-e TIR`; no `-i`, `-o` or `--dump`. The C code is the
program's own (port/linux/replay_core.c: signal table, sample loop, CSV
reader and its input rules, vehicle presets and file, estimator), compiled
into the extension with the library, so a log gives here what the program
gives. The columns are those of grip-replay's output as
grip_tools.fleet.backend.parse_output reads them: t_s, step, in_<input>
(NaN = empty cell) and in_<input>_fault (str) for each input the output
writes, est_status, est_valid, est_flags (int64) and the estimator's
outputs. Every number is the double that reading the program's text gives
(the C side formats each value as the program prints it and reads it
back), so the columns equal the program's bit for bit.

Memory: 8 bytes per column and step (a 60 s log at 100 Hz with 9 inputs:
about 2 MB), at most max_steps steps (more: status EXIT_OUTPUT with a
message). The replay's line buffers are static: calls are serialised by a
lock (the C call itself runs without the GIL).
"""
import threading

import numpy as np

from grip import _core

EXIT_OUTPUT = 5
DEFAULT_MAX_STEPS = 1 << 21   # 5.8 h at 100 Hz; about 0.5 GB of rows at 9 inputs
# the estimator's real-valued columns after est_flags (replay_core.h,
# replay_est_values), in output order
EST_REALS = ("vx", "beta", "yaw_rate", "yaw_rate_ref", "delta", "mu", "mu_conf", "fy_front", "fy_rear",
             "util_front", "util_rear", "fy_margin_front", "yaw_rate_bias", "ay_model", "beta_sd", "mu_sd")
EST_INTS = ("est_status", "est_valid", "est_flags")

_LOCK = threading.Lock()
_FAULTS = {}


class Result:
    def __init__(self, status, text, columns, capped):
        self.status = status
        self.text = text
        self.columns = columns
        self.capped = capped


def available(arith="float"):
    """None when the extension of `arith` has the replay, else why not."""
    try:
        be = _core.backend(arith)
    except (ImportError, OSError) as e:
        return f"the grip binding does not import ({e})"
    if not hasattr(be.lib, "grip_py_replay_run"):
        return "the grip binding was built without the replay (compile it again: `make setup`)"
    if be.stale:
        return f"the grip binding is older than {be.stale} (compile it again: `make setup`)"
    if int(be.lib.GRIP_PY_REPLAY_EST_REALS) != len(EST_REALS):
        return "the grip binding's replay has other estimator columns than grip.replay"
    return None


def _fault_names(be):
    names = _FAULTS.get(be.arith)
    if names is None:
        names = _FAULTS[be.arith] = np.array(
            [be.ffi.string(be.lib.grip_sig_fault_str(i)).decode() for i in range(16)], dtype=object)
    return names


def run(args, arith="float", max_steps=DEFAULT_MAX_STEPS):
    """grip-replay ARGS in this process (see the module's text)."""
    be = _core.backend(arith)
    ffi, lib = be.ffi, be.lib
    keep = [ffi.new("char[]", b"grip-replay")] + [ffi.new("char[]", str(a).encode()) for a in args]
    argv = ffi.new("char *[]", keep)
    out = ffi.new("grip_py_replay_out *")
    with _LOCK:
        status = lib.grip_py_replay_run(len(keep), argv, int(max_steps), out)
    try:
        if status < 0:
            raise MemoryError("grip.replay: no memory for the message stream")
        text = ffi.string(out.text, out.text_len).decode("utf-8", "replace") if out.text != ffi.NULL else ""
        n, ncol = int(out.n), int(out.ncol)
        written = [i for i in range(be.n_inputs) if out.write_input[i]]
        if ncol == 0:
            ncol = 2 + 2 * len(written) + len(EST_INTS) + len(EST_REALS)
        if ncol != 2 + 2 * len(written) + len(EST_INTS) + len(EST_REALS):
            raise RuntimeError(f"grip.replay: {ncol} columns per step from C, expected "
                               f"{2 + 2 * len(written) + len(EST_INTS) + len(EST_REALS)}")
        if n:
            rows = np.frombuffer(ffi.buffer(out.rows, n * ncol * 8), dtype=np.float64).reshape(n, ncol)
        else:
            rows = np.zeros((0, ncol))
        faults = _fault_names(be)
        cols = {"t_s": rows[:, 0].copy(), "step": rows[:, 1].astype(np.int64)}
        c = 2
        for i in written:
            name = be.input_names[i]
            cols[f"in_{name}"] = rows[:, c].copy()
            cols[f"in_{name}_fault"] = faults[rows[:, c + 1].astype(np.int64)]
            c += 2
        for name in EST_INTS:
            cols[name] = rows[:, c].astype(np.int64)
            c += 1
        for name in EST_REALS:
            cols[name] = rows[:, c].copy()
            c += 1
        capped = bool(out.capped)
    finally:
        lib.grip_py_replay_free(out)
    if capped and status == 0:
        status = EXIT_OUTPUT
        text += f"grip-replay: more than {int(max_steps)} steps: the in-process replay keeps at most that many\n"
    return Result(int(status), text, cols, capped)
