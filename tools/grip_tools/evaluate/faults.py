"""Fault injection on the ESC inputs of the onboard estimator.

    grip faults --out docs/faults          # table + false alarms
    grip faults --out DIR --only yaw        # a subset (regex on the case name)

For each ESC input signal (four wheel speeds, steering-wheel angle, yaw
rate, ax, ay; the reference simulator has no vehicle-speed signal, so that
input stays unmapped as in est-eval) and each fault type (dropout,
stuck-at, spike, offset, scale, delay, noise burst), the fault is injected
into the reference simulator's sensor outputs during a manoeuvre (start
mid-manoeuvre, fixed duration, then removed). The faulty samples go
through the float64 references monitor_ref (the plausibility monitor) and
est_ref (the estimator) in the order of the firmware data flow
CAN -> signals -> monitor -> estimator; the C code follows both references
through the golden tests (test_monitor.c, test_est_golden.c).

Everything is deterministic: fixed simulator settings, fixed sensor-noise
seed, fixed fault-noise seeds. Simulator runs are cached in
build/faults-cache (keyed by the scenario; --no-cache to rerun).

Outputs: <out>/faults.json (every number), <out>/table.md (the fault
table), <out>/false_alarms.md (the monitor on the fault-free suite).
docs/faults.md explains the method and quotes the summary.
"""
import argparse
import hashlib
import json
import math
import os
import re
import sys
import time

import numpy as np

from grip_tools.evaluate import est_eval
from grip_tools.reference import est as est_ref, monitor as monitor_ref
from grip_tools.golden import est as golden_est

DEG = math.pi / 180.0
KMH = 1.0 / 3.6
SEED = 11                  # sensor noise seed (simulator), fixed
FAULT_SEED = 2026          # noise-burst seeds derive from this
H_SIM = 2e-3               # RK4 step of the simulator runs
STALE_STEPS = 3            # the signal layer's stale_periods (grip-replay default)
FAULT_T = 1.0              # fault duration [s]
DELAY_T = 0.2              # delay fault [s]
SPIKE_EVERY = 10           # one spike sample every 10 samples (100 ms)
DET_T = 0.2                # detection target [s]
BETA_RMS, BETA_MAX, MU_TOL = 0.5, 1.5, 0.1   # accuracy targets [deg, deg, -]

# Representative scenarios: (name, manoeuvre, surface, builder kwargs, fault start [s])
SCENARIOS = [
    ("step-steer dry", "step-steer", "dry", dict(duration=4.0), 1.0),
    ("step-steer wet", "step-steer", "wet", dict(duration=4.0), 1.0),
    ("sine-dwell dry", "sine-dwell", "dry", dict(amp_deg=100.0), 0.8),
    ("sine-dwell wet", "sine-dwell", "wet", dict(amp_deg=50.0), 0.8),
    ("brake-in-turn dry", "brake-in-turn", "dry", dict(), 2.5),
    ("brake-in-turn wet", "brake-in-turn", "wet", dict(), 2.5),
]

# Signals: (name, input id, sensors.csv column, SI per CSV unit, CAN resolution [CSV unit], lo, hi)
SIGNALS = [
    ("ws_fl", 0, "WheelSpeed_FL", KMH, 0.01, 0.0, 655.35),
    ("ws_fr", 1, "WheelSpeed_FR", KMH, 0.01, 0.0, 655.35),
    ("ws_rl", 2, "WheelSpeed_RL", KMH, 0.01, 0.0, 655.35),
    ("ws_rr", 3, "WheelSpeed_RR", KMH, 0.01, 0.0, 655.35),
    ("steer", est_ref.STEER, "SteeringAngle", DEG, 0.1, -3276.8, 3276.7),
    ("yaw", est_ref.YAW, "YawRate", DEG, 0.01, -327.68, 327.67),
    ("ax", est_ref.AX, "LongAcc", 1.0, 0.01, -327.68, 327.67),
    ("ay", est_ref.AY, "LatAcc", 1.0, 0.01, -327.68, 327.67),
]

# Fault magnitudes in the CSV units (km/h, deg, deg/s, m/s^2), fixed before
# any result was seen: offset, scale factor, spike height, noise-burst sigma.
MAG = {
    "ws": dict(offset=5.4, scale=1.10, spike=29.0, noise=3.6),     # 1.5 m/s, +10 %, 8 m/s, 1 m/s
    "steer": dict(offset=15.0, scale=1.3, spike=90.0, noise=10.0),
    "yaw": dict(offset=5.0, scale=1.3, spike=40.0, noise=3.0),
    "ax": dict(offset=1.5, scale=1.3, spike=10.0, noise=1.5),
    "ay": dict(offset=1.5, scale=1.3, spike=10.0, noise=1.5),
}
FAULTS = ("dropout", "stuck", "spike", "offset", "scale", "delay", "noise")

# Fault-free suite for the false-alarm rate: every manoeuvre of the
# simulator that runs at speed, on three surfaces, default settings.
SUITE_MANOEUVRES = ("coast", "step-steer", "ramp-steer", "sine-dwell", "fishhook", "brake-in-turn",
                    "mu-step", "mu-split-brake")
SUITE_SURFACES = ("dry", "wet", "snow")


def _mag(signame):
    return MAG["ws"] if signame.startswith("ws") else MAG[signame]


# ---------------------------------------------------------------------------
# simulator runs (cached)

def _cache_path(cache, key):
    h = hashlib.sha256(key.encode()).hexdigest()[:16]
    return os.path.join(cache, f"sim_{h}.npz")


def simulate(manoeuvre, surface, kw, cache=None):
    """Sensor columns (sensors.csv layout, 100 Hz rows) and truth at the
    row times for one run; cached as npz."""
    key = json.dumps([manoeuvre, surface, kw, SEED, H_SIM], sort_keys=True)
    path = _cache_path(cache, key) if cache else None
    if path and os.path.exists(path):
        z = np.load(path)
        cols = {k[2:]: z[k] for k in z.files if k.startswith("s_")}
        truth = {k[2:]: z[k] for k in z.files if k.startswith("t_")}
        return cols, truth
    from grip_tools.sim import manoeuvres as M, model as VM, sensors, vehicles
    veh = vehicles.passenger()
    kw = dict(kw)
    if manoeuvre in ("sine-dwell", "fishhook") and "amp_deg" not in kw:
        # default amplitude of the simulator CLI: 5 x (sine) / 6.5 x (fishhook) SWA(0.3 g), dry value
        kw["amp_deg"] = min((5.0 if manoeuvre == "sine-dwell" else 6.5) * SWA03, 270.0)
    sc = M.build(manoeuvre, veh, surface=surface, **kw)
    res = VM.simulate(veh, sc, h=H_SIM)
    tr = res.member(0)
    sd = sensors.measure(tr, sensors.SensorConfig(seed=SEED))
    cols = sd.wide_columns()
    times = cols["time"]
    t = np.asarray(tr["time"], float)

    def at(name):
        return np.interp(times, t, np.asarray(tr[name], float))

    truth = {"time": times, "beta": at("beta"), "vx": at("vx"), "r": at("r"), "ay": at("ay"),
             "mu": np.mean([at(f"mu_road_{w}") for w in ("fl", "fr", "rl", "rr")], axis=0)}
    if path:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        np.savez(path, **{"s_" + k: v for k, v in cols.items()}, **{"t_" + k: v for k, v in truth.items()})
    return cols, truth


# SWA at 0.3 g of the passenger car (docs/simulator.md, swa_at_03g: 20.5 deg);
# a constant so that the suite does not rerun the FMVSS 126 ramp.
SWA03 = 20.5


# ---------------------------------------------------------------------------
# fault injection (on the sensor columns, in CSV units, then the CAN resolution)

def inject(cols, signal, fault, t0, t1, seed):
    """Returns (cols', dropout_rows): a copy of the sensor columns with the
    fault on `signal` for t0 <= t < t1. Dropout is returned as row indices
    (frames missing: the signal layer holds the value, then marks it stale)."""
    name, idx, col, si, q, lo, hi = signal
    mag = _mag(name)
    out = dict(cols)
    x = np.asarray(cols[col], float).copy()
    t = np.asarray(cols["time"], float)
    win = (t >= t0 - 1e-9) & (t < t1 - 1e-9) & np.isfinite(x)
    rows = np.nonzero(win)[0]
    drop = np.zeros(len(t), bool)
    if fault == "dropout":
        drop[rows] = True
        return out, drop
    y = x.copy()
    if fault == "stuck":
        y[rows] = x[rows[0]]
    elif fault == "spike":
        for j, k in enumerate(rows[::SPIKE_EVERY]):
            y[k] = x[k] + (mag["spike"] if j % 2 == 0 else -mag["spike"])
    elif fault == "offset":
        y[rows] = x[rows] + mag["offset"]
    elif fault == "scale":
        y[rows] = x[rows] * mag["scale"]
    elif fault == "delay":
        nd = int(round(DELAY_T / 0.01))
        for k in rows:
            y[k] = x[max(k - nd, 0)]
    elif fault == "noise":
        rng = np.random.default_rng(seed)
        y[rows] = x[rows] + rng.normal(0.0, mag["noise"], size=len(rows))
    else:
        raise ValueError(fault)
    y[rows] = np.round(np.clip(y[rows], lo, hi) / q) * q
    out[col] = y
    return out, drop


def inputs(cols, drop=None, drop_idx=None):
    t, value, valid = est_ref.inputs_from_sensors(cols)
    if drop is not None and drop.any():
        rows = np.nonzero(drop)[0]
        # frames missing: held and still valid for STALE_STEPS, then stale (invalid, value 0)
        for k in rows[STALE_STEPS:]:
            valid[k, drop_idx] = 0
            value[k, drop_idx] = 0.0
        for k in rows[:STALE_STEPS]:
            value[k, drop_idx] = value[rows[0] - 1, drop_idx]
    return t, value, valid


# ---------------------------------------------------------------------------
# running monitor -> estimator

def est_config():
    # as est-eval: the passenger car, PacejkaBook_Defaults, 100 Hz, the
    # simulator's IMU latency
    return est_eval.est_config()


_EST_CFG = None


def run_chain(value, valid, monitor=True):
    """monitor_ref -> est_ref over a sequence; returns arrays."""
    global _EST_CFG
    if _EST_CFG is None:
        _EST_CFG = est_config()
    est = est_ref.Estimator(_EST_CFG)
    mon = monitor_ref.Monitor(monitor_ref.config(rate_hz=100))
    n = len(value)
    r = {k: np.zeros(n) for k in ("beta", "beta_sd", "mu", "mu_sd", "vx", "yaw")}
    r["valid"] = np.zeros(n, np.int64)
    r["flags"] = np.zeros(n, np.int64)
    r["faulty"] = np.zeros(n, np.int64)
    r["detected"] = np.zeros(n, bool)
    r["degraded"] = np.zeros(n, np.int64)
    r["codes"] = np.zeros((n, monitor_ref.N_MON), np.int64)
    r["finite"] = np.ones(n, bool)
    r["res"] = []
    prev = None
    for k in range(n):
        if monitor:
            rep = mon.step(value[k], valid[k], prev)
            v_in, ok_in = rep["value"], rep["valid"]
            r["faulty"][k] = rep["faulty"]
            r["detected"][k] = rep["detected"]
            r["degraded"][k] = int(rep["degraded"])
            r["codes"][k] = rep["code"]
            r["res"].append(rep["res"])
        else:
            v_in, ok_in = value[k], valid[k]
        o = est_ref.Estimator.step(est, v_in, ok_in)
        prev = o
        r["beta"][k], r["mu"][k], r["vx"][k], r["yaw"][k] = o["beta"], o["mu"], o["vx"], o["yaw_rate"]
        r["beta_sd"][k], r["mu_sd"][k] = o["beta_sd"], o["mu_sd"]
        r["valid"][k], r["flags"][k] = o["valid"], o["flags"]
        fin = True
        for key in ("vx", "vy", "beta", "yaw_rate", "yaw_rate_ref", "yaw_error", "delta", "mu", "mu_conf",
                    "fy_margin_front"):
            fin = fin and math.isfinite(o[key])
        for key in ("kappa", "alpha", "fz", "fx", "fy", "mz", "util", "fy_axle", "util_axle"):
            fin = fin and bool(np.all(np.isfinite(o[key])))
        r["finite"][k] = fin
    return r


# ---------------------------------------------------------------------------
# metrics

# Which grip_monitor_report_t.degraded bits the consumer honours (docs/faults.md):
# the table's verdicts use both; the summary also gives SUSPECT alone.
DEGR_ALL = monitor_ref.DEGR_SUSPECT | monitor_ref.DEGR_UNVERIFIED
POLICY = {"mask": DEGR_ALL}


def trusted(run, bit):
    """Rows where the consumer may use the output `bit`: its valid bit after
    grip_monitor_gate (monitor_ref.gate) with the degraded bits of
    POLICY["mask"], i.e. the estimator marks it valid AND the monitor does
    not report the sample degraded (docs/faults.md)."""
    valid, _ = monitor_ref.gate(run["degraded"], POLICY["mask"], run["valid"], run["flags"])
    return (valid & bit) != 0


def errors(run, truth, sel):
    """beta RMS / max [deg] over the rows of sel where beta is trusted (valid
    and not degraded) and the true speed is above 5 m/s (as est-eval); mu max
    error over the rows where mu is trusted (V_MU); the share of sel where
    beta is trusted."""
    okb = sel & trusted(run, est_ref.V_BETA) & (truth["vx"] > 5.0)
    out = {"beta_valid_pct": 100.0 * okb.sum() / max(sel.sum(), 1)}
    if okb.any():
        e = (run["beta"] - truth["beta"])[okb] / DEG
        out["beta_rms"] = float(np.sqrt(np.mean(e ** 2)))
        out["beta_max"] = float(np.max(np.abs(e)))
    else:
        out["beta_rms"] = out["beta_max"] = None
    okm = sel & trusted(run, est_ref.V_MU)
    out["mu_max"] = float(np.max(np.abs(run["mu"] - truth["mu"])[okm])) if okm.any() else None
    return out


def within(e):
    ok = True
    if e["beta_rms"] is not None:
        ok = ok and e["beta_rms"] <= BETA_RMS and e["beta_max"] <= BETA_MAX
    if e["mu_max"] is not None:
        ok = ok and e["mu_max"] <= MU_TOL
    return ok


def no_worse(e, b):
    """Fault run no worse than the fault-free run (beta RMS + 0.1 deg, max +
    0.3 deg, mu error + 0.05)."""
    ok = True
    if e["beta_rms"] is not None and b["beta_rms"] is not None:
        ok = ok and e["beta_rms"] <= b["beta_rms"] + 0.1 and e["beta_max"] <= b["beta_max"] + 0.3
    if e["mu_max"] is not None:
        ok = ok and e["mu_max"] <= (b["mu_max"] if b["mu_max"] is not None else MU_TOL) + 0.05
    return ok


def unflagged(run, base, truth, sel):
    """Rows of sel where the fault run shows beta trusted (valid, not
    degraded) beyond 1.5 deg error (or mu trusted beyond 0.1) while the
    fault-free run is inside at that row."""
    eb = np.abs(run["beta"] - truth["beta"]) / DEG
    ebb = np.abs(base["beta"] - truth["beta"]) / DEG
    vb = trusted(run, est_ref.V_BETA) & (truth["vx"] > 5.0)
    em = np.abs(run["mu"] - truth["mu"])
    emb = np.abs(base["mu"] - truth["mu"])
    vm = trusted(run, est_ref.V_MU)
    bad = sel & ((vb & (eb > BETA_MAX) & (ebb <= BETA_MAX)) | (vm & (em > MU_TOL) & (emb <= MU_TOL)))
    return int(bad.sum())


def evaluate_case(t, run, base, truth, t0, t1, sig_idx):
    during = (t >= t0) & (t < t1)
    after = t >= t1
    d = {"during": errors(run, truth, during), "after": errors(run, truth, after),
         "base_during": errors(base, truth, during), "base_after": errors(base, truth, after)}
    det = np.nonzero(run["detected"] & (t >= t0 - 1e-9) & (t < t1 + DET_T))[0]
    d["det_t"] = float(t[det[0]] - t0) if len(det) else None
    iso = [k for k in np.nonzero(run["codes"][:, sig_idx] != 0)[0] if t0 - 1e-9 <= t[k] < t1 + DET_T]
    d["iso_t"] = float(t[iso[0]] - t0) if iso else None
    others = run["codes"].copy()
    others[:, sig_idx] = 0
    d["other_flagged"] = [monitor_ref.NAMES[s] for s in range(monitor_ref.N_MON)
                          if ((others[:, s] & ~monitor_ref.C_LOST) != 0)[during | after].any()]
    d["nonfinite"] = int((~run["finite"]).sum())
    d["unflagged_rows"] = unflagged(run, base, truth, during | after)
    d["within"] = within(d["during"]) and within(d["after"])
    # "no worse" compares on the same rows: the fault-free run's errors over
    # the rows where the fault run's beta (mu) is trusted
    # (the whole window when the fault-free run has no valid beta there)
    tb = trusted(run, est_ref.V_BETA | est_ref.V_MU)
    for w, sel in (("during", during), ("after", after)):
        m = errors(base, truth, sel & tb)
        d[f"base_{w}_m"] = m if m["beta_rms"] is not None or d[w]["beta_rms"] is None else d[f"base_{w}"]
    d["no_worse"] = no_worse(d["during"], d["base_during_m"]) and no_worse(d["after"], d["base_after_m"])
    if d["det_t"] is not None and d["det_t"] <= DET_T:
        d["verdict"] = "detected"
    elif d["within"]:
        d["verdict"] = "within targets"
    elif d["no_worse"]:
        d["verdict"] = "as fault-free"
    else:
        d["verdict"] = "NEITHER"
    return d


# ---------------------------------------------------------------------------

def fault_runs(si, cols, keep=None):
    """The fault runs of scenario si (an index of SCENARIOS) from its sensor
    columns: (signal index, signal, case name, (t, value, valid)) for every
    signal x fault (keep: a predicate on the case name, tested before the
    fault is injected), with the table's fixed fault seeds."""
    t0 = SCENARIOS[si][4]
    for gi, sig in enumerate(SIGNALS):
        for fi, fault in enumerate(FAULTS):
            case = f"{sig[0]} {fault}"
            if keep is not None and not keep(case):
                continue
            c2, drop = inject(cols, sig, fault, t0, t0 + FAULT_T, [FAULT_SEED, si, gi, fi])
            yield gi, sig, case, inputs(c2, drop, sig[1])


def _scenario(args):
    si, cache, only = args
    scn, man, surf, kw, t0 = SCENARIOS[si]
    cols, truth = simulate(man, surf, kw, cache)
    t, v, ok = inputs(cols)
    base = run_chain(v, ok)
    base_nomon = run_chain(v, ok, monitor=False)
    out = {"baseline": {"during": errors(base, truth, (t >= t0) & (t < t0 + FAULT_T)),
                        "after": errors(base, truth, t >= t0 + FAULT_T),
                        "all": errors(base, truth, t >= 0),
                        "false_alarm_rows": int(base["detected"].sum()),
                        "degraded_rows": int((base["degraded"] != 0).sum()),
                        "nomon_all": errors(base_nomon, truth, t >= 0)}, "cases": {}}
    t1 = t0 + FAULT_T
    keep = (lambda case: re.search(only, f"{scn} {case}") is not None) if only else None
    for gi, sig, case, (tt, vv, oo) in fault_runs(si, cols, keep):
        run = run_chain(vv, oo)
        POLICY["mask"] = monitor_ref.DEGR_SUSPECT
        d1 = evaluate_case(tt, run, base, truth, t0, t1, sig[1])
        POLICY["mask"] = DEGR_ALL
        d = evaluate_case(tt, run, base, truth, t0, t1, sig[1])
        d["suspect_only"] = {"verdict": d1["verdict"], "unflagged_rows": d1["unflagged_rows"],
                             "during": d1["during"], "after": d1["after"]}
        nm = run_chain(vv, oo, monitor=False)
        d["nomon_during"] = errors(nm, truth, (tt >= t0) & (tt < t1))
        d["nomon_after"] = errors(nm, truth, tt >= t1)
        d["nomon_nonfinite"] = int((~nm["finite"]).sum())
        out["cases"][case] = d
        print(f"faults: {scn:18s} {case:14s} det {d['det_t']} {d['verdict']} "
              f"beta {d['during']['beta_rms']}/{d['during']['beta_max']} "
              f"(no monitor {d['nomon_during']['beta_rms']}/{d['nomon_during']['beta_max']})",
              file=sys.stderr, flush=True)
    return scn, out


def fault_table(cache, only=None, jobs=2):
    # simulate first (cached), one at a time, then evaluate in parallel
    for scn, man, surf, kw, t0 in SCENARIOS:
        simulate(man, surf, kw, cache)
    tasks = [(si, cache, only) for si in range(len(SCENARIOS))]
    if jobs > 1:
        import multiprocessing
        with multiprocessing.Pool(jobs) as pool:
            done = pool.map(_scenario, tasks, chunksize=1)
    else:
        done = [_scenario(tk) for tk in tasks]
    return {scn: out for scn, out in done}


def false_alarms(cache, log=sys.stderr):
    rows = {}
    for man in SUITE_MANOEUVRES:
        for surf in SUITE_SURFACES:
            cols, truth = simulate(man, surf, {}, cache)
            t, v, ok = inputs(cols)
            run = run_chain(v, ok)
            det = run["detected"]
            per = {monitor_ref.NAMES[s]: int(((run["codes"][:, s] & ~monitor_ref.C_LOST) != 0).sum())
                   for s in range(monitor_ref.N_MON)}
            dropped = int(sum(((run["codes"][:, s] & ~monitor_ref.C_LOST) != 0).sum()
                              for s in range(monitor_ref.N_MON)))
            rows[f"{man} {surf}"] = {"rows": int(len(t)), "alarm_rows": int(det.sum()),
                                     "degraded_rows": int((run["degraded"] != 0).sum()),
                                     "suspect_rows": int(((run["degraded"] & monitor_ref.DEGR_SUSPECT) != 0).sum()),
                                     "unverified_rows": int(((run["degraded"] & monitor_ref.DEGR_UNVERIFIED) != 0).sum()),
                                     "per_signal": {k: v for k, v in per.items() if v},
                                     "signal_rows_dropped": dropped,
                                     "max_beta_true_deg": float(np.max(np.abs(truth["beta"])) / DEG),
                                     "res_max": _res_max(run["res"])}
            print(f"faults: suite {man} {surf}: {det.sum()} alarm rows, {((run['degraded'] & 1) != 0).sum()} suspect, {((run['degraded'] & 2) != 0).sum()} unverified, of {len(t)} {per}", file=log)
    return rows


def _res_max(res):
    """Largest |residual| of each plausibility check over a run."""
    arr = np.abs(np.array(res, float)) if len(res) else np.zeros((1, monitor_ref.N_MON))
    return {monitor_ref.NAMES[s]: round(float(arr[:, s].max()), 4) for s in range(monitor_ref.N_MON)}


def _f(x, fmt=".2f"):
    return "-" if x is None else format(x, fmt)


def summary(res):
    """Counts over every fault case."""
    c = {"cases": 0, "detected": 0, "within targets": 0, "as fault-free": 0, "NEITHER": 0,
         "nonfinite": 0, "unflagged_cases": 0, "isolated": 0, "det_any": 0,
         "suspect_only": {"detected": 0, "within targets": 0, "as fault-free": 0, "NEITHER": 0,
                          "unflagged_cases": 0}}
    for scn, r in res.get("faults", {}).items():
        for case, d in r["cases"].items():
            c["cases"] += 1
            c[d["verdict"]] += 1
            c["nonfinite"] += d["nonfinite"]
            c["unflagged_cases"] += 1 if d["unflagged_rows"] else 0
            c["isolated"] += 1 if d["iso_t"] is not None and d["iso_t"] <= DET_T else 0
            c["det_any"] += 1 if d["det_t"] is not None else 0
            so = d.get("suspect_only")
            if so:
                c["suspect_only"][so["verdict"]] += 1
                c["suspect_only"]["unflagged_cases"] += 1 if so["unflagged_rows"] else 0
    return c


def write_tables(res, out):
    lines = []
    if "faults" in res:
        sm = summary(res)
        lines += [f"Fault cases: {sm['cases']}; detected within {DET_T * 1000:.0f} ms: {sm['detected']}; "
                  f"not detected in time but beta and mu within the targets: {sm['within targets']}; "
                  f"neither, but no worse than the fault-free run: {sm['as fault-free']}; "
                  f"neither: {sm['NEITHER']}. Faulted signal itself flagged within {DET_T * 1000:.0f} ms: "
                  f"{sm['isolated']}. Non-finite outputs: {sm['nonfinite']}. Cases with unflagged invalid "
                  f"output rows: {sm['unflagged_cases']}. (Rows flagged = estimator valid bit clear or monitor "
                  f"degraded SUSPECT or UNVERIFIED.)", "",
                  f"Honouring only the monitor's SUSPECT bit: detected {sm['suspect_only']['detected']}; within "
                  f"targets {sm['suspect_only']['within targets']}; as fault-free "
                  f"{sm['suspect_only']['as fault-free']}; neither {sm['suspect_only']['NEITHER']}; cases with "
                  f"unflagged invalid output rows {sm['suspect_only']['unflagged_cases']}.", ""]
        for scn, r in res["faults"].items():
            b = r["baseline"]
            lines += [f"### {scn}", "",
                      f"Fault-free run: beta RMS/max during the fault window {_f(b['during']['beta_rms'])} / "
                      f"{_f(b['during']['beta_max'])} deg, after {_f(b['after']['beta_rms'])} / "
                      f"{_f(b['after']['beta_max'])} deg; mu max error (V_MU rows) during {_f(b['during']['mu_max'])}, "
                      f"after {_f(b['after']['mu_max'])}; monitor alarm rows {b['false_alarm_rows']}, "
                      f"degraded rows {b.get('degraded_rows', '-')}.", "",
                      "| fault | detected [s] | own signal [s] | other signals flagged | beta RMS / max during [deg] "
                      "| beta trusted during | beta RMS / max after [deg] | mu max err during / after | "
                      "without monitor: beta during | unflagged rows | verdict | SUSPECT bit only: unflagged rows, "
                      "verdict |",
                      "|" + "---|" * 12]
            for case, d in r["cases"].items():
                du, af, nm = d["during"], d["after"], d["nomon_during"]
                lines.append("| " + " | ".join([
                    case, _f(d["det_t"]), _f(d["iso_t"]), ", ".join(d["other_flagged"]) or "-",
                    f"{_f(du['beta_rms'])} / {_f(du['beta_max'])}", f"{du['beta_valid_pct']:.0f} %",
                    f"{_f(af['beta_rms'])} / {_f(af['beta_max'])}", f"{_f(du['mu_max'])} / {_f(af['mu_max'])}",
                    f"{_f(nm['beta_rms'])} / {_f(nm['beta_max'])}", str(d["unflagged_rows"]),
                    ("**NEITHER**" if d["verdict"] == "NEITHER" else d["verdict"]),
                    (f"{d['suspect_only']['unflagged_rows']}, {d['suspect_only']['verdict']}"
                     if "suspect_only" in d else "-")]) + " |")
            lines.append("")
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    if "suite" in res:
        rows = ["| run | steps | max true beta [deg] | steps with an alarm | signals (steps) | degraded SUSPECT / "
                "UNVERIFIED steps | largest residual per check |",
                "|---|---|---|---|---|---|---|"]
        tot = al = sus = unv = 0
        for name, d in res["suite"].items():
            tot += d["rows"]
            al += d["alarm_rows"]
            sus += d.get("suspect_rows", 0)
            unv += d.get("unverified_rows", 0)
            rm = ", ".join(f"{k} {v:.2f}" for k, v in d["res_max"].items() if v > 0)
            rows.append(f"| {name} | {d['rows']} | {d['max_beta_true_deg']:.1f} | {d['alarm_rows']} | "
                        f"{', '.join(f'{k} ({v})' for k, v in d['per_signal'].items()) or '-'} | "
                        f"{d.get('suspect_rows', '-')} / {d.get('unverified_rows', '-')} | {rm} |")
        rows += ["", f"Total: {al} steps with an alarm of {tot} ({100.0 * al / max(tot, 1):.2f} %); degraded SUSPECT "
                 f"{sus} ({100.0 * sus / max(tot, 1):.2f} %), UNVERIFIED {unv} ({100.0 * unv / max(tot, 1):.2f} %)."]
        with open(os.path.join(out, "false_alarms.md"), "w") as f:
            f.write("\n".join(rows) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip faults", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="build/faults")
    ap.add_argument("--cache", default="build/faults-cache")
    ap.add_argument("--no-cache", action="store_true")
    ap.add_argument("--only", default=None, help="regular expression on 'scenario signal fault'")
    ap.add_argument("--skip-suite", action="store_true", help="no false-alarm suite")
    ap.add_argument("--skip-table", action="store_true", help="no fault table")
    ap.add_argument("--jobs", type=int, default=2, help="parallel processes for the fault table")
    a = ap.parse_args(argv)
    if a.only is not None:
        try:
            re.compile(a.only)
        except re.error as e:
            ap.error(f"--only {a.only!r}: not a regular expression ({e})")
    if a.jobs < 1:
        ap.error(f"--jobs: {a.jobs}: at least 1")
    os.makedirs(a.out, exist_ok=True)
    cache = None if a.no_cache else a.cache
    t_start = time.time()
    res = {}
    if not a.skip_table:
        res["faults"] = fault_table(cache, a.only, a.jobs)
    if not a.skip_suite:
        res["suite"] = false_alarms(cache)
    with open(os.path.join(a.out, "faults.json"), "w") as f:
        json.dump(res, f, indent=1)
    write_tables(res, a.out)
    if "faults" in res:
        print(json.dumps(summary(res)))
    print(f"faults: done in {time.time() - t_start:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
