"""grip fleet run: the C estimator over many logs, one Dask task per log.

    grip fleet run SOURCE... --out DIR [--arith float|fixed|both] [--steps]
                   [--backend binding|subprocess]
                   [--scheduler tcp://HOST:8786 | --workers N]

SOURCE: a folder, a glob or a manifest (grip_tools/fleet/manifest.py).
Per log: decode (candump logs through the signal table; estimator-input
CSV; Parquet) and estimate with grip-replay's C code of each arithmetic
asked for (--backend: in the worker's process through the grip binding,
the default when it imports, or the grip-replay program as a subprocess;
both give the same rows bit for bit, fleet/backend.py), then the log's
summary (fleet/summary.py): validity shares per bit and
flag, mu and beta statistics, model-misfit share, the replay's decode and
timing counters, residuals, est_eval's accuracy metrics where the log has
a truth, the measured-data loop's attribution of the residual.

Results (fleet/store.py): DIR/logs.parquet (one row per log and
arithmetic), DIR/bands.parquet (residual moments per speed band),
DIR/steps/ (per-step outputs, --steps), DIR/run.json.

A rerun skips every log whose rows exist with the same input hash (the
bytes of the log, its truth, tire, vehicle file and signal table, and the
settings) and the same grip version (grip_tools.__version__ and the
backend's identity: the sha256 of the grip binding's extension, or of the
grip-replay program, of each arithmetic; rows of one backend are not
reused by the other). A log that fails becomes an error row
(status 'error', stage and message) and the run goes on; a worker that dies
has its tasks run again elsewhere (Dask).
"""
import argparse
import math
import os
import resource
import sys
import time
import traceback


from grip_tools import __version__
from grip_tools.errors import UsageError
from grip_tools.fleet import backend as B, cluster, manifest, store, summary
from grip_tools.paths import REPO_ROOT

ARITHS = ("float", "fixed")
DEFAULT_BINS = {a: os.path.join(REPO_ROOT, "build", f"{a}-gcc", "bin", "grip-replay") for a in ARITHS}


def default_tir():
    from grip_tools.golden import est as golden_est
    return golden_est.tire_path()


def log_schema():
    """The fixed columns of logs.parquet (manifest columns follow them)."""
    import pyarrow as pa
    s, f64, i64, b = pa.string(), pa.float64(), pa.int64(), pa.bool_()
    fields = [("log_id", s), ("arith", s), ("status", s), ("stage", s), ("error", s), ("path", s), ("format", s),
              ("vehicle", s), ("preset", s), ("surface", s), ("manoeuvre", s), ("has_truth", b),
              ("input_hash", s), ("grip_version", s), ("replay_id", s), ("backend", s), ("wall_s", f64),
              ("cpu_s", f64), ("rss_peak_mb", f64)]
    fields += [(n, i64) for n in B.COUNTER_NAMES]
    for n in summary.summary_columns():
        fields.append((n, i64 if n in ("steps", "est_status_errors") else f64))
    fields += [(f"acc_{k}", i64 if k in ("rows", "valid_rows") else f64) for k in summary.ACC_KEYS]
    fields += [("dev_beta_max_rad", f64), ("dev_mu_max", f64), ("fixed_float_ratio", f64),
               ("fixed_float_ratio_metric", s)]
    fields += [("attr_n", i64), ("attr_chosen", s), ("attr_chosen_score", f64), ("attr_accepted", s),
               ("attr_scores", s), ("attr_params", s), ("attr_note", s)]
    return pa.schema([pa.field(n, t) for n, t in fields])


# ---------------------------------------------------------------------------
# The task (runs on a worker; must not raise: every failure is a row)

_BIN_IDS = {}
_BACKENDS = {}
BACKENDS = ("binding", "subprocess")


def _cpu():
    """CPU seconds of this process and its finished children (grip-replay)."""
    a, b = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return a.ru_utime + a.ru_stime + b.ru_utime + b.ru_stime


def _binary_id(path):
    if path not in _BIN_IDS:
        _BIN_IDS[path] = B.file_sha256(path)
    return _BIN_IDS[path]


def _base_row(spec, arith, opts):
    row = {"log_id": spec["log_id"], "arith": arith, "path": spec["path"], "format": spec["format"],
           "vehicle": spec["vehicle"], "preset": spec["preset"], "surface": spec["surface"],
           "manoeuvre": spec["manoeuvre"], "has_truth": bool(spec["truth"]),
           "grip_version": opts["grip_version"], "replay_id": opts["replay_ids"][arith],
           "backend": opts["backend"]}
    for k, v in spec["meta"].items():
        row[k if k not in row else f"meta_{k}"] = v
    return row


def _error(row, stage, msg):
    row.update(status="error", stage=stage, error=str(msg)[:2000])
    return row


def make_backend(arith, opts):
    """The replay backend of an arithmetic (one per process and setting)."""
    key = (opts["backend"], arith, opts["bins"].get(arith))
    be = _BACKENDS.get(key)
    if be is None:
        if opts["backend"] == B.BindingReplay.name:
            be = B.BindingReplay(arith, opts.get("max_steps"))
        else:
            be = B.SubprocessReplay(opts["bins"][arith])
        _BACKENDS[key] = be
    return be


def _check_backend(arith, opts):
    """The backend on this worker is the client's (same program or
    extension bytes), else a ReplayError."""
    if opts["backend"] == B.BindingReplay.name:
        try:
            ident = make_backend(arith, opts).identity()
        except ImportError as e:
            raise B.ReplayError(f"the grip binding ({arith}) does not work on this worker: {e}", "estimate")
        if ident != opts["replay_ids"][arith]:
            raise B.ReplayError(f"the grip binding ({arith}) on this worker differs from the client's", "estimate")
    elif opts["bins"].get(arith) and _binary_id(opts["bins"][arith]) != opts["replay_ids"][arith]:
        raise B.ReplayError(f"grip-replay ({arith}) on this worker differs from the client's "
                            f"({opts['bins'][arith]})", "estimate")


def read_parquet_inputs(path):
    import pyarrow.parquet as pq
    t = pq.read_table(path)
    if "t_s" not in t.column_names:
        raise B.ReplayError(f"{path}: no t_s column (estimator-input Parquet: t_s, wheel_speed_fl, ...)")
    cols = {n: t.column(n).to_numpy(zero_copy_only=False).astype(float)
            for n in ["t_s"] + [n for n in B.CSV_INPUTS if n in t.column_names]}
    return cols


def process_log(spec, opts):
    """One log, every arithmetic asked for. Returns {'log_id', 'skipped',
    'rows': [logs rows], 'bands': [bands rows]}."""
    t0 = time.perf_counter()
    cpu0 = _cpu()
    ariths = opts["ariths"]
    rows = {a: _base_row(spec, a, opts) for a in ariths}
    out = {"log_id": spec["log_id"], "skipped": False, "rows": [], "bands": []}
    try:
        h = manifest.input_hash(manifest.LogSpec(**{k: v for k, v in spec.items() if not k.startswith("_")}),
                                opts["hash_options"])
    except OSError as e:
        h = None
        for a in ariths:
            _error(rows[a], "read", f"{e.filename or spec['path']}: {e.strerror or e}")
    for a in ariths:
        rows[a]["input_hash"] = h
    prev = spec.get("_previous") or {}
    if h is not None and not opts.get("force") and all(
            a in prev and prev[a][0] in ("ok", "error") and prev[a][1:] == (h, opts["grip_version"],
                                                                           opts["replay_ids"][a])
            for a in ariths):
        out["skipped"] = True
        return out
    if h is not None:
        _run_ariths(spec, opts, rows, out)
    wall, cpu = time.perf_counter() - t0, _cpu() - cpu0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    for a in ariths:
        rows[a].update(wall_s=wall / len(ariths), cpu_s=cpu / len(ariths), rss_peak_mb=rss)
        out["rows"].append(rows[a])
    return out


def _run_ariths(spec, opts, rows, out):
    job = B.ReplayJob(kind=spec["format"], tir=spec["tir"], path=spec["path"], preset=spec["preset"],
                      vehicle_file=spec["vehicle_file"], table=spec["table"], step_ms=spec["step_ms"],
                      skip_bad=opts["skip_bad"], timeout_s=opts["timeout"])
    cols, accs, tr = {}, {}, None
    for a in opts["ariths"]:
        row = rows[a]
        stage = "decode"
        try:
            _check_backend(a, opts)
            if spec["format"] == "parquet":
                job.kind, job.path, job.columns = "columns", None, read_parquet_inputs(spec["path"])
            res = make_backend(a, opts).run(job)
            c = res.columns
            if len(c["t_s"]) == 0:
                raise B.ReplayError("the log gave no estimator step", "decode")
            stage = "summary"
            row.update({n: res.counters.get(n) for n in B.COUNTER_NAMES})
            row.update(summary.summarize(c))
            truth = None
            if spec["truth"]:
                stage = "evaluate"
                acc = summary.accuracy(spec["truth"], c)
                row.update(acc)
                accs[a] = acc
                tr = tr if tr is not None else summary.read_truth(spec["truth"])
                truth = summary.truth_on_grid(tr, c["t_s"])
            if opts["attribution"]:
                stage = "attribution"
                row.update(summary.attribution(c))
            stage = "bands"
            for b in summary.bands(c, summary.residuals(c, truth)):
                out["bands"].append(dict(log_id=spec["log_id"], arith=a, input_hash=row["input_hash"],
                                         replay_id=row["replay_id"], **b))
            if opts["steps_dir"]:
                stage = "steps"
                store.write_steps(opts["steps_dir"], spec["log_id"], a, summary.step_table(c))
            row.update(status="ok", stage=None, error=None)
            cols[a] = c
        except B.ReplayError as e:
            _error(row, e.stage, e)
        except Exception as e:  # noqa: BLE001 - a failing log is a row, not a failed run
            tb = traceback.extract_tb(e.__traceback__)[-1]
            _error(row, stage, f"{type(e).__name__}: {e} ({os.path.basename(tb.filename)}:{tb.lineno})")
    if "float" in cols and "fixed" in cols:
        rows["fixed"].update(summary.fixed_vs_float(cols["float"], cols["fixed"], accs.get("float"),
                                                    accs.get("fixed")))


def task_failed_rows(spec, opts, exc):
    """Error rows for a task Dask gave up on (e.g. its worker died more often
    than distributed.scheduler.allowed-failures)."""
    rows = []
    for a in opts["ariths"]:
        r = _base_row(spec, a, opts)
        r["input_hash"] = None
        rows.append(_error(r, "task", f"{type(exc).__name__}: {exc}"))
    return rows


# ---------------------------------------------------------------------------

def parse_args(argv):
    ap = argparse.ArgumentParser(prog="grip fleet run", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sources", nargs="+", help="folders, globs, files or manifests (manifest.csv)")
    ap.add_argument("--out", "-o", required=True, help="results folder (created; a rerun resumes)")
    ap.add_argument("--arith", default="float", choices=("float", "fixed", "both"))
    ap.add_argument("--backend", choices=BACKENDS, default=None,
                    help="how the C code runs: 'binding' (in the worker's process, through the grip binding; "
                         "the default when it imports) or 'subprocess' (one grip-replay process per log)")
    ap.add_argument("--replay-bin", action="append", default=[], metavar="ARITH=PATH",
                    help="--backend subprocess: grip-replay of an arithmetic "
                         "(default build/<arith>-gcc/bin/grip-replay)")
    ap.add_argument("--tir", default=None, help="tire of the estimator (default PacejkaBook_Defaults.tir)")
    ap.add_argument("--preset", default="generic", choices=manifest.PRESETS,
                    help="grip-replay --vehicle where the manifest gives none")
    ap.add_argument("--vehicle-file", default=None, help="grip-replay --vehicle-file where the manifest gives none")
    ap.add_argument("--table", default=None, help="signal table (text) of candump logs (default: built-in rav4)")
    ap.add_argument("--step-ms", type=float, default=10.0)
    ap.add_argument("--steps", action="store_true", help="also write the per-step table (DIR/steps/)")
    ap.add_argument("--no-attribution", action="store_true", help="skip the residual attribution per log")
    ap.add_argument("--skip-bad", action="store_true", help="candump: skip malformed lines (counted)")
    ap.add_argument("--timeout", type=float, default=600.0,
                    help="--backend subprocess: per log and arithmetic [s]")
    ap.add_argument("--max-steps", type=int, default=None,
                    help="--backend binding: most estimator steps kept per log (default 2097152; more: an "
                         "error row)")
    ap.add_argument("--retries", type=int, default=2, help="Dask retries of a task that raised")
    ap.add_argument("--force", action="store_true", help="recompute every log")
    ap.add_argument("--flush", type=int, default=200, help="journal the rows every N logs")
    cluster.add_arguments(ap)
    return ap.parse_args(argv)


def check_args(a):
    """What the whole run cannot go with, refused before any log is read
    (UsageError, exit 2): a step or count out of range, a --timeout where it
    has no effect, and a tire, vehicle file or signal table that cannot be
    opened (a .tir that is read but refused: its DataError, exit 3)."""
    if not (math.isfinite(a.step_ms) and 0.5 <= a.step_ms <= 20.0):
        raise UsageError(f"--step-ms {a.step_ms!r}: the estimator runs at 50 - 2000 Hz, a step in [0.5, 20] ms")
    if not (math.isfinite(a.timeout) and a.timeout > 0.0):
        raise UsageError(f"--timeout {a.timeout!r}: give seconds > 0")
    if a.retries < 0:
        raise UsageError(f"--retries {a.retries}: give a count >= 0")
    if a.flush < 1:
        raise UsageError(f"--flush {a.flush}: give a number of logs >= 1")
    for opt, path in (("--tir", a.tir), ("--vehicle-file", a.vehicle_file), ("--table", a.table)):
        if path is not None and not os.path.isfile(path):
            raise UsageError(f"{opt} {path}: cannot open (no such file)")
    if a.tir is not None:
        from grip_tools.reference import tir as tir_ref
        tir_ref.load_params(a.tir)          # a refused file: its DataError names file, line and field


def options(a):
    ariths = list(ARITHS) if a.arith == "both" else [a.arith]
    bins = dict(DEFAULT_BINS)
    for s in a.replay_bin:
        k, _, v = s.partition("=")
        if k not in ARITHS or not v:
            raise UsageError(f"--replay-bin {s}: give float=PATH or fixed=PATH")
        bins[k] = os.path.abspath(v)
    bins = {k: bins[k] for k in ariths}
    if getattr(a, "max_steps", None) is not None and a.max_steps < 1:
        raise UsageError(f"--max-steps {a.max_steps}: give a number of steps >= 1")
    backend = getattr(a, "backend", None)
    if backend is None:
        why = B.binding_available(ariths)
        backend = "subprocess" if why else "binding"
        if why:
            print(f"grip fleet run: {why}; running grip-replay as a subprocess per log", file=sys.stderr)
    elif backend == "binding":
        why = B.binding_available(ariths)
        if why:
            raise UsageError(f"--backend binding: {why}")
    if backend == "binding":
        ids = {k: B.BindingReplay(k).identity() for k in ariths}
        backend_name, bins = B.BindingReplay.name, {}
    else:
        for k, v in bins.items():
            if not os.path.exists(v):
                raise UsageError(f"{v}: not built (make ARITH={k} progs)")
        ids = {k: B.file_sha256(v) for k, v in bins.items()}
        backend_name = B.SubprocessReplay.name
    steps_dir = os.path.join(os.path.abspath(a.out), store.STEPS) if a.steps else None
    return {"ariths": ariths, "bins": bins, "replay_ids": ids, "max_steps": getattr(a, "max_steps", None),
            "grip_version": __version__, "backend": backend_name, "steps_dir": steps_dir,
            "attribution": not a.no_attribution, "skip_bad": a.skip_bad, "timeout": a.timeout,
            "force": a.force,
            "hash_options": {"summary_version": summary.SUMMARY_VERSION, "steps": bool(a.steps), "attribution": not a.no_attribution,
                             "skip_bad": bool(a.skip_bad)}}


def _extension_path(arith):
    from grip import _core
    return _core.backend(arith).path


def run_fleet(a, specs=None, client=None, on_result=None):
    """Runs the fleet; returns the run info dict (also DIR/run.json)."""
    t_start = time.time()
    check_args(a)
    defaults = {"tir": os.path.abspath(a.tir) if a.tir else default_tir(), "preset": a.preset,
                "vehicle_file": os.path.abspath(a.vehicle_file) if a.vehicle_file else None,
                "table": os.path.abspath(a.table) if a.table else None, "step_ms": a.step_ms}
    if specs is None:
        specs = manifest.discover(a.sources, defaults)
    if not specs:
        raise UsageError("no logs found in " + " ".join(a.sources))
    opts = options(a)
    res = store.Results(a.out)
    prev = res.previous()
    schema = log_schema()
    tasks = []
    for s in specs:
        d = s.to_dict()
        d["_previous"] = prev.get(s.log_id)
        tasks.append(d)
    own = client is None
    if own:
        client = cluster.open_client(a)
    t_ready = time.time()
    t_results = []
    prog = cluster.Progress(len(tasks), enabled=not a.no_progress)
    counts = {"computed": 0, "skipped": 0, "error_rows": 0, "cpu_s": 0.0}
    pend_rows, pend_bands = [], []

    def take(r):
        t_results.append(time.time())
        if r["skipped"]:
            counts["skipped"] += 1
        else:
            counts["computed"] += 1
        errs = sum(1 for row in r["rows"] if row.get("status") == "error")
        counts["cpu_s"] += sum(row.get("cpu_s") or 0.0 for row in r["rows"])
        counts["error_rows"] += errs
        pend_rows.extend(r["rows"])
        pend_bands.extend(r["bands"])
        prog.update(1, errors=errs, skipped=int(r["skipped"]))
        if on_result:
            on_result(r)
        if len(pend_rows) >= a.flush * len(opts["ariths"]):
            res.append_journal(pend_rows, pend_bands, schema)
            pend_rows.clear()
            pend_bands.clear()

    try:
        if isinstance(client, cluster.Serial):
            for d in tasks:
                take(process_log(d, opts))
        else:
            from dask.distributed import as_completed
            opts_f = client.scatter(opts, broadcast=True)
            futs = client.map(process_log, tasks, [opts_f] * len(tasks), pure=False, retries=a.retries,
                              key=[f"grip-fleet-{d['log_id']}-{os.urandom(4).hex()}" for d in tasks])
            by_key = {f.key: d for f, d in zip(futs, tasks)}
            for f in as_completed(futs):
                # result(), not the status: a future whose result lived on a
                # worker that died after as_completed yielded it is lost and
                # computed again (result() waits for that); only a task Dask
                # gave up on raises here
                try:
                    r = f.result()
                except (KeyboardInterrupt, SystemExit):
                    raise
                except BaseException as exc:    # the task's error, KilledWorker, a cancellation
                    d = by_key[f.key]
                    r = {"log_id": d["log_id"], "skipped": False, "bands": [],
                         "rows": task_failed_rows(d, opts, exc)}
                f.release()
                take(r)
    finally:
        # also when interrupted: what finished is kept for the next run
        res.append_journal(pend_rows, pend_bands, schema)
        if own:
            cluster.close_client(client)
    logs = res.compact([s.log_id for s in specs], schema)
    status = logs.column("status").to_pylist() if logs is not None else []
    info = {"grip_version": __version__, "backend": opts["backend"],
            # per arithmetic: the program or the extension that ran, its sha256
            # (the identity is "binding:" + sha256 for the extension)
            "replay": {k: ({"binary": opts["bins"][k], "sha256": opts["replay_ids"][k]} if opts["bins"] else
                           {"extension": _extension_path(k), "sha256": opts["replay_ids"][k].split(":")[-1]})
                       for k in opts["ariths"]},
            "sources": [os.path.abspath(s) for s in a.sources], "options": opts["hash_options"],
            "logs": len(specs), "computed": counts["computed"], "skipped": counts["skipped"],
            "rows": len(status), "error_rows": status.count("error"),
            "wall_s": round(time.time() - t_start, 3),
            # where the time went: discovery and the cluster's start, first and
            # last result (the steady rate is between them), the tables' compaction
            "ready_s": round(t_ready - t_start, 3),
            "first_result_s": round(t_results[0] - t_start, 3) if t_results else None,
            "last_result_s": round(t_results[-1] - t_start, 3) if t_results else None,
            "steady_logs_per_s": (round((len(t_results) - 1) / (t_results[-1] - t_results[0]), 3)
                                  if len(t_results) > 1 and t_results[-1] > t_results[0] else None),
            "task_cpu_s": round(counts["cpu_s"], 3),
            "workers": getattr(client, "n_workers", None), "scheduler": a.scheduler or ("local" if a.workers != 0 else "none"),
            "started": time.strftime("%Y-%m-%dT%H:%M:%S", time.localtime(t_start))}
    res.write_run(info)
    return info


def main(argv=None):
    a = parse_args(argv)
    info = run_fleet(a)
    print(f"grip fleet run: {info['logs']} logs: {info['computed']} computed, {info['skipped']} unchanged; "
          f"{info['rows']} rows, {info['error_rows']} errors; {info['wall_s']:.1f} s -> {a.out}",
          file=sys.stderr)
    return 0
