"""One log's summary: from the estimator's per-step outputs to one row of
the fleet's logs table, the residual moments of the bands table and the
per-step table.

Accuracy against a truth (a simulator run's truth.csv) is est_eval's own
`evaluate` (the metrics of `grip est-eval`), and the attribution of the
residual is the measured-data loop's `attribution.analyse`, both called,
not repeated.
"""
import io
import json
import math
import os
import shutil
import tempfile

import numpy as np

from grip_tools.reference import est as est_ref

DEG = 180.0 / math.pi
# bumped whenever a summary column's meaning or computation changes: part of
# every log's input hash, so a rerun recomputes rather than keeping old rows
SUMMARY_VERSION = 1
MOVING_MS = 5.0                 # "moving": the estimate's vx above 5 m/s (est_eval's threshold)

VALID_BITS = (("vx", est_ref.V_VX), ("beta", est_ref.V_BETA), ("yaw", est_ref.V_YAW),
              ("yaw_ref", est_ref.V_YAW_REF), ("fz", est_ref.V_FZ), ("axle", est_ref.V_AXLE),
              ("mu", est_ref.V_MU), ("steer", est_ref.V_STEER), ("margin", est_ref.V_MARGIN))
FLAG_BITS = (("standstill", est_ref.F_STANDSTILL), ("reversing", est_ref.F_REVERSING),
             ("low_speed", est_ref.F_LOW_SPEED), ("no_wheels", est_ref.F_NO_WHEELS),
             ("no_steer", est_ref.F_NO_STEER), ("no_yaw", est_ref.F_NO_YAW), ("no_ay", est_ref.F_NO_AY),
             ("no_ax", est_ref.F_NO_AX), ("saturated", est_ref.F_SATURATED),
             ("steer_limit", est_ref.F_STEER_LIMIT), ("wheel_lock", est_ref.F_WHEEL_LOCK),
             ("wheel_spin", est_ref.F_WHEEL_SPIN), ("excited", est_ref.F_EXCITED),
             ("tire_error", est_ref.F_TIRE_ERROR), ("reset", est_ref.F_RESET),
             ("model_misfit", est_ref.F_MODEL_MISFIT))
CORE_INPUTS = ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle",
               "yaw_rate", "ax", "ay", "vehicle_speed")
# est_eval.evaluate's keys (a fixed schema: absent = null)
ACC_KEYS = ("rows", "valid_rows", "beta_rms_deg", "beta_max_deg", "beta_true_max_deg",
            "fy_front_peak_N", "fy_front_rms_pct", "fy_front_rms_N", "fy_rear_peak_N", "fy_rear_rms_pct",
            "fy_rear_rms_N", "mu_true_end", "mu_est_end",
            "mu_t0", "mu_err_1s", "mu_conf_1s", "mu_within_0p1_pct",
            "mu_t0_lim", "mu_err_1s_lim", "mu_conf_1s_lim", "mu_within_0p1_pct_lim")
# speed bands of the pooled residuals [km/h] (the estimate's |vx|)
BAND_EDGES_KMH = (0.0, 20.0, 40.0, 70.0, 100.0, math.inf)
BAND_NAMES = ("0-20", "20-40", "40-70", "70-100", "100+")
# per-step quantities whose moments go to the bands table
RESIDUALS = (("yaw_resid", "rad/s", "measured yaw rate - the estimator's bicycle reference (yaw_rate_ref)"),
             ("ay_resid", "m/s^2", "measured ay - the estimator's model ay (sum Fy / m)"),
             ("beta_err_deg", "deg", "estimated - true sideslip (truth only)"),
             ("mu_err", "-", "estimated - true road friction scale while mu is valid (truth only)"))
STEP_FLOAT32 = ("vx", "beta", "yaw_rate", "yaw_rate_ref", "delta", "mu", "mu_conf", "fy_front", "fy_rear",
                "util_front", "util_rear", "fy_margin_front", "yaw_rate_bias", "ay_model")
STEP_INPUTS = CORE_INPUTS + ("brake_pressure_fl", "brake_pressure_fr", "brake_pressure_rl", "brake_pressure_rr")
ATTR_MIN_SAMPLES = 200


def _f(x):
    """A float for a Parquet cell: None for NaN / missing."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def _share(mask, n):
    return float(np.count_nonzero(mask)) / n if n else None


def _stats(prefix, x, scale=1.0):
    x = np.asarray(x, float)
    x = x[np.isfinite(x)] * scale
    keys = ("mean", "std", "min", "p05", "p50", "p95", "max")
    if len(x) == 0:
        return {f"{prefix}_{k}": None for k in keys}
    p05, p50, p95 = np.percentile(x, [5.0, 50.0, 95.0])
    return {f"{prefix}_mean": float(np.mean(x)), f"{prefix}_std": float(np.std(x)),
            f"{prefix}_min": float(np.min(x)), f"{prefix}_p05": float(p05), f"{prefix}_p50": float(p50),
            f"{prefix}_p95": float(p95), f"{prefix}_max": float(np.max(x))}


def summary_columns():
    """Names (in order) of the summary fields summarize() returns."""
    cols = ["steps", "duration_s", "moving_share"]
    cols += [f"valid_{n}_share" for n, _ in VALID_BITS]
    cols += [f"flag_{n}_share" for n, _ in FLAG_BITS]
    cols += [f"input_{n}_valid_share" for n in CORE_INPUTS]
    for p in ("mu", "beta_deg"):
        cols += [f"{p}_{k}" for k in ("mean", "std", "min", "p05", "p50", "p95", "max")]
    cols += ["mu_end", "mu_conf_mean", "mu_conf_max", "mu_conf_end", "yaw_rate_bias_end",
             "yaw_resid_mean", "yaw_resid_rms", "ay_resid_mean", "ay_resid_rms", "est_status_errors"]
    return cols


def summarize(c):
    """Shares and statistics of one replay's columns (backend.parse_output)."""
    n = len(c["t_s"])
    valid, flags = c["est_valid"], c["est_flags"]
    vx = c["vx"]
    moving = np.abs(vx) > MOVING_MS
    r = {"steps": n, "duration_s": float(c["t_s"][-1] - c["t_s"][0]) if n else 0.0,
         "moving_share": _share(moving, n)}
    for name, bit in VALID_BITS:
        r[f"valid_{name}_share"] = _share((valid & bit) != 0, n)
    for name, bit in FLAG_BITS:
        r[f"flag_{name}_share"] = _share((flags & bit) != 0, n)
    for name in CORE_INPUTS:
        f = c.get(f"in_{name}_fault")
        r[f"input_{name}_valid_share"] = _share(f == "ok", n) if f is not None else 0.0
    vmu = (valid & est_ref.V_MU) != 0
    vb = ((valid & est_ref.V_BETA) != 0) & moving
    r.update(_stats("mu", np.where(vmu, c["mu"], np.nan)))
    r.update(_stats("beta_deg", np.where(vb, c["beta"], np.nan), DEG))
    r["mu_end"] = _f(c["mu"][-1]) if n else None
    r["mu_conf_mean"] = _f(np.mean(c["mu_conf"])) if n else None
    r["mu_conf_max"] = _f(np.max(c["mu_conf"])) if n else None
    r["mu_conf_end"] = _f(c["mu_conf"][-1]) if n else None
    r["yaw_rate_bias_end"] = _f(c["yaw_rate_bias"][-1]) if n else None
    res = residuals(c)
    for q in ("yaw_resid", "ay_resid"):
        x = res[q][np.isfinite(res[q])]
        r[f"{q}_mean"] = float(np.mean(x)) if len(x) else None
        r[f"{q}_rms"] = float(np.sqrt(np.mean(x * x))) if len(x) else None
    r["est_status_errors"] = int(np.count_nonzero(c["est_status"] < 0))
    return r


def residuals(c, truth=None):
    """Per-step residual arrays (NaN where not defined): yaw_resid, ay_resid
    and, with truth ({'beta', 'mu'} on the step grid, 'vx'), beta_err_deg
    and mu_err."""
    valid = c["est_valid"]
    moving = np.abs(c["vx"]) > MOVING_MS
    nan = np.full(len(c["t_s"]), np.nan)
    ok_r = ((valid & est_ref.V_YAW_REF) != 0) & moving & (c.get("in_yaw_rate_fault") == "ok")
    ok_a = ((valid & est_ref.V_AXLE) != 0) & moving & (c.get("in_ay_fault") == "ok")
    out = {"yaw_resid": np.where(ok_r, c["in_yaw_rate"] - c["yaw_rate_ref"], nan),
           "ay_resid": np.where(ok_a, c["in_ay"] - c["ay_model"], nan)}
    if truth is not None:
        ok_b = ((valid & est_ref.V_BETA) != 0) & (truth["vx"] > MOVING_MS)
        ok_m = ((valid & est_ref.V_MU) != 0) & (truth["vx"] > MOVING_MS)
        out["beta_err_deg"] = np.where(ok_b, (c["beta"] - truth["beta"]) * DEG, nan)
        out["mu_err"] = np.where(ok_m, c["mu"] - truth["mu"], nan)
    return out


def bands(c, res):
    """Moments of each residual per speed band: rows of the bands table
    (quantity, band, n, sum, sumsq, min, max); pooled means and RMS over
    many logs are exact from these."""
    kmh = np.abs(c["vx"]) * 3.6
    idx = np.searchsorted(np.asarray(BAND_EDGES_KMH[1:-1]), kmh, side="right")
    rows = []
    for q, _, _ in RESIDUALS:
        if q not in res:
            continue
        x = res[q]
        fin = np.isfinite(x)
        for b, name in enumerate(BAND_NAMES):
            sel = x[fin & (idx == b)]
            if len(sel) == 0:
                continue
            rows.append({"quantity": q, "band": name, "n": int(len(sel)), "sum": float(np.sum(sel)),
                         "sumsq": float(np.sum(sel * sel)), "min": float(np.min(sel)), "max": float(np.max(sel))})
    return rows


_TRUTH_CACHE = {}


def read_truth(path):
    """The columns of a truth.csv that the residual bands need (time, vx,
    beta, mu_road_*), read with pyarrow ('#' lines skipped) and kept per
    process for the next log of the same run (sim-fleet's sensor variants
    share one truth); est_eval.evaluate reads the file itself."""
    import pyarrow.csv as pcsv
    st = os.stat(path)
    key = (os.path.abspath(path), st.st_mtime_ns, st.st_size)
    if key not in _TRUTH_CACHE:
        with open(path, "rb") as f:
            lines = [ln for ln in f if not ln.startswith(b"#")]
        want = ["time", "vx", "beta"] + [f"mu_road_{w}" for w in ("fl", "fr", "rl", "rr")]
        t = pcsv.read_csv(io.BytesIO(b"".join(lines)), read_options=pcsv.ReadOptions(use_threads=False),
                          convert_options=pcsv.ConvertOptions(include_columns=want))
        if len(_TRUTH_CACHE) >= 8:
            _TRUTH_CACHE.pop(next(iter(_TRUTH_CACHE)))
        _TRUTH_CACHE[key] = {n: t.column(n).to_numpy().astype(float) for n in want}
    return _TRUTH_CACHE[key]


def truth_on_grid(tr, t):
    wheels = ("fl", "fr", "rl", "rr")
    return {"beta": np.interp(t, tr["time"], tr["beta"]), "vx": np.interp(t, tr["time"], tr["vx"]),
            "mu": np.mean([np.interp(t, tr["time"], tr[f"mu_road_{w}"]) for w in wheels], axis=0)}


def est_dict(c):
    """The columns as est_eval's estimate dict (what est_eval.evaluate takes)."""
    return {"time": c["t_s"], "beta": c["beta"], "mu": c["mu"], "mu_conf": c["mu_conf"], "fyf": c["fy_front"],
            "fyr": c["fy_rear"], "vx": c["vx"], "valid": c["est_valid"].astype(np.int64),
            "flags": c["est_flags"].astype(np.int64)}


def accuracy(truth_path, c):
    """est_eval.evaluate against truth_path (a truth.csv): {acc_<key>}."""
    from grip_tools.evaluate import est_eval
    if os.path.basename(truth_path) == "truth.csv":
        r = est_eval.evaluate(os.path.dirname(os.path.abspath(truth_path)), est_dict(c))
    else:                                  # evaluate reads <dir>/truth.csv
        with tempfile.TemporaryDirectory(prefix="grip-fleet-truth-") as d:
            shutil.copyfile(truth_path, os.path.join(d, "truth.csv"))
            r = est_eval.evaluate(d, est_dict(c))
    return {f"acc_{k}": _f(r.get(k)) if k not in ("rows", "valid_rows") else r.get(k) for k in ACC_KEYS}


def fixed_vs_float(cf, cx, accf, accx):
    """The fixed build's deviation from the float build on the same log, and
    est_eval's fixed/float error ratio where a truth exists."""
    from grip_tools.evaluate import est_eval
    n = min(len(cf["t_s"]), len(cx["t_s"]))
    r = {"dev_beta_max_rad": _f(np.nanmax(np.abs(cf["beta"][:n] - cx["beta"][:n]))) if n else None,
         "dev_mu_max": _f(np.nanmax(np.abs(cf["mu"][:n] - cx["mu"][:n]))) if n else None,
         "fixed_float_ratio": None, "fixed_float_ratio_metric": None}
    if accf and accx:
        q, which = est_eval.fixed_float_ratio({k[4:]: v for k, v in accf.items()},
                                              {k[4:]: v for k, v in accx.items()})
        r["fixed_float_ratio"], r["fixed_float_ratio_metric"] = _f(q), which
    return r


class EstimatorReference:
    """The measured-data loop's base model for a fleet log: the estimator's
    own predictions of the measured yaw rate (yaw_rate_ref, the bicycle
    reference from the steering) and lateral acceleration (ay_model, its
    axle forces / mass). No vehicle-level terms are declared, so only the
    loop's sensor effects (bias, scale, delay; level "any") apply."""
    kind = "vehicle"
    supports = ()
    name = "grip estimator (yaw_rate_ref, ay_model)"

    def __init__(self, pred):
        self.pred = pred

    def predict(self, ch, over=None):
        return dict(self.pred)


ATTR_COLUMNS = ("attr_n", "attr_chosen", "attr_chosen_score", "attr_accepted", "attr_scores", "attr_params",
                "attr_note")


def attribution(c):
    """grip_tools.loop.attribution.analyse on this log: measured yaw rate and
    ay against EstimatorReference over the moving steps where both are
    valid. Returns the attr_* fields (scores and parameters as JSON)."""
    from grip_tools.loop import attribution as attr
    from grip_tools.loop.io import Dataset
    valid = c["est_valid"]
    sel = ((np.abs(c["vx"]) > MOVING_MS) & ((valid & est_ref.V_YAW_REF) != 0) & ((valid & est_ref.V_AXLE) != 0)
           & (c["in_yaw_rate_fault"] == "ok") & (c["in_ay_fault"] == "ok"))
    for k in ("in_yaw_rate", "in_ay", "yaw_rate_ref", "ay_model", "vx", "delta"):
        sel &= np.isfinite(c[k])
    n = int(np.count_nonzero(sel))
    out = {k: None for k in ATTR_COLUMNS}
    out["attr_n"] = n
    if n < ATTR_MIN_SAMPLES:
        out["attr_note"] = f"too few samples ({n} < {ATTR_MIN_SAMPLES} moving steps with yaw rate and ay valid)"
        return out
    t = c["t_s"][sel] - c["t_s"][sel][0]
    ch = {"t": t, "vx": c["vx"][sel], "delta": c["delta"][sel], "r": c["in_yaw_rate"][sel], "ay": c["in_ay"][sel]}
    ds = Dataset(t, ch, {"t": "s", "vx": "m/s", "delta": "rad", "r": "rad/s", "ay": "m/s2"}, ["r", "ay"],
                 {"source": "fleet log"})
    model = EstimatorReference({"r": c["yaw_rate_ref"][sel], "ay": c["ay_model"][sel]})
    with np.errstate(all="ignore"):
        res = attr.analyse(model, ds)
    out["attr_chosen"] = res.chosen.name if res.chosen else None
    out["attr_chosen_score"] = _f(res.chosen.score) if res.chosen else None
    out["attr_accepted"] = ",".join(sorted(x.name for x in res.ranked if x.accepted))
    out["attr_scores"] = json.dumps({x.name: round(float(x.score), 6) for x in res.ranked}, sort_keys=True)
    out["attr_params"] = json.dumps({x.name: {k: float(f"{v:.6g}") for k, v in x.params.items()}
                                     for x in res.ranked}, sort_keys=True)
    return out


def step_table(c):
    """The per-step table of one log and arithmetic (a pyarrow Table)."""
    import pyarrow as pa
    cols = {"t_s": pa.array(c["t_s"], pa.float64()), "step": pa.array(c["step"], pa.int64())}
    for k in ("est_status", "est_valid", "est_flags"):
        cols[k] = pa.array(c[k].astype(np.int32), pa.int32())
    for k in STEP_FLOAT32:
        cols[k] = pa.array(c[k].astype(np.float32), pa.float32())
    for k in STEP_INPUTS:
        v = c.get(f"in_{k}")
        if v is None:
            v = np.full(len(c["t_s"]), np.nan)
        f = c.get(f"in_{k}_fault")
        if f is not None:
            v = np.where(f == "ok", v, np.nan)
        cols[f"in_{k}"] = pa.array(np.asarray(v, float).astype(np.float32), pa.float32())
    return pa.table(cols)
