"""Integrity of the estimator's validity flags: what a valid flag promises,
measured on every judge with a truth.

    grip est-eval --integrity [--out docs/estimator] [--judges own,mismatch,independent,fitted,learned,rav4,av21,faults]

For each output with a standard deviation (beta: beta_sd, mu: mu_sd) and
each run: over the steps the output is flagged valid (V_BETA, V_MU) with
the true speed above 5 m/s, the share whose true error exceeds
max(floor, 3 sd) (beta: 1 deg, mu: 0.1) and the longest such run [s];
beside it the share of moving steps outside spins and full saturation
(both axles of the truth at >= 95 % of their friction) that are flagged
valid. Targets (docs/estimator/integrity.md): at most 0.1 % of valid
steps, no run longer than 100 ms; beta valid on >= 90 % of moving steps
outside spins and full saturation on the independent simulator. Per run,
also why beta was withheld: the ceiling (the share of those steps whose
beta error is within max(1 deg, 3 beta_sd_max), what any bound could flag
valid), the withheld steps' errors and how many had the filter's own
deviation beyond beta_sd_max, and the kinematic vy's drift against the
truth over 1 s windows divided by what its deviation grew by (est_ref's
trace); the table lists them for the runs below 90 %.

Judges, all through the float64 reference (grip_tools.reference.est):
  own          the project's simulator (est_eval --simulate's 15 runs),
               the estimator's own tire (in family)
  mismatch     the project's simulator in a steady turn near the limit
               (step steer 90 deg at 65 km/h, dry, 8 s, ay 7.5 m/s^2) with
               the estimator's rear tire at 0.4 x the car's cornering
               stiffness (LKY): the generic-tire run-away
  independent  CommonRoad's multi-body model (sim/independent), the
               reduced set (BMW 320i, every manoeuvre and surface), the
               generic configuration (PacejkaBook_Defaults on both axles)
  fitted       the same runs in the fitted configuration: the tire fitted
               to a dry ramp steer with wheel-force transducers and the
               measured roll gradient and front roll share
               (judge.characterize, cached beside the runs), the same
               declared tire_tol
  learned      the same runs in the learned configuration: the generic
               tire with the cornering stiffness and the roll gradient
               learned online (stiff_est = 1, roll_est = 1), every run
               started from the blob the vehicle's 90 s learning drive left
               (judge.learn), through the C float build (the binding: the
               reference has no blob)
  rav4         the RAV4 highway drive of the README's main job (60 s, CAN),
               the C float build, sideslip from the drive's fused GNSS/IMU
               pose (the phone mount's yaw removed)
  av21         the Dallara AV-21 road course (476 s), sideslip from the INS
               (est_eval --av21's stand-in tire and preset)
  faults       the fault campaign (grip faults): every fault of every ESC
               signal injected into the project's simulator in six
               manoeuvres, through the monitor and the estimator; one row
               per manoeuvre (its fault-free run and 56 fault runs), once
               for each consumer rule: the monitor's gate with its default
               degraded bits (docs/faults.md), the SUSPECT bit only, and
               the estimator's own valid bits without the monitor's gate
The RAV4 log has no sideslip or friction truth, so it is not a judge of
this table.
"""
import json
import math
import os
import sys

import numpy as np

from grip_tools.evaluate import est_eval
from grip_tools.golden import est as golden_est
from grip_tools.reference import est as est_ref, monitor as monitor_ref, tir

DEG = 180.0 / math.pi
V_MIN = 5.0
FLOOR = {"beta": 1.0 / DEG, "mu": 0.1, "vx": 0.1, "fy_axle": 100.0}
K = 3.0
TARGET_RATE, TARGET_RUN_S, TARGET_VALID = 0.001, 0.1, 0.90
SAT_U = 0.95
# the kinematic vy's drift against its bound: windows of 1 s (a transient's
# length, over which the kinematic vy carries beta) every 0.1 s
KIN_WINDOW_S, KIN_EVERY_S = 1.0, 0.1
JUDGES = ("own", "mismatch", "independent", "fitted", "learned", "rav4", "av21", "faults")
# The fault campaign's consumer rules: grip_monitor_gate's degraded bits
# (docs/faults.md); "estimator alone" is the estimator's valid bits ungated.
FAULT_RULES = {"monitor gate": monitor_ref.DEGR_SUSPECT | monitor_ref.DEGR_UNVERIFIED,
               "SUSPECT only": monitor_ref.DEGR_SUSPECT, "estimator alone": 0}
MISMATCH_LKY = 0.4


def stats(t, err, sd, ok, floor, k=K):
    """Integrity of one output over the steps flagged valid (ok): the number
    of them whose true |err| exceeds max(floor, k sd), their share and the
    longest such run [s] (a run of n steps lasts n steps' periods)."""
    t, err, sd, ok = (np.asarray(a) for a in (t, err, sd, ok))
    bad = ok & ~(np.abs(err) <= np.maximum(floor, k * sd))   # a NaN error counts as bad
    n_ok = int(ok.sum())
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    longest, run = 0, 0
    for b in bad:
        run = run + 1 if b else 0
        longest = max(longest, run)
    return dict(valid_steps=n_ok, violations=int(bad.sum()), rate=(float(bad.sum()) / n_ok if n_ok else 0.0),
                longest_s=longest * dt)


# the estimator's output channels the table judges (with valid and flags)
OUT_KEYS = ("beta", "beta_sd", "vy", "vy_sd", "vx", "vx_sd", "yaw_rate", "yaw_rate_sd", "mu", "mu_sd",
            "fy_axle", "fy_axle_sd")


def reference_run(cfg, value, valid, friction=()):
    """est_ref over the inputs (friction: est_ref.run's road-friction
    measurements): arrays of the outputs the table needs."""
    outs = est_ref.run(cfg, value, valid, friction=friction)
    res = {k: np.array([o[k] for o in outs]) for k in OUT_KEYS}
    res["valid"] = np.array([o["valid"] for o in outs], dtype=np.int64)
    res["flags"] = np.array([o["flags"] for o in outs], dtype=np.int64)
    # the kinematic vy's increments and its deviation's, the filter's vy
    # deviation (a reference trace, absent while the lateral filter is off)
    for k in ("kin_dvy", "kin_dsd", "filter_vy_sd", "filter_vy_sd_tire", "mu_hyp_vy_sd"):
        res[k] = np.array([o.get(k, np.nan) for o in outs])
    # each axle's slip-angle shift under mu's hypothesis (0 without one)
    res["mu_hyp_shift"] = np.array([o.get("mu_hyp_shift", (0.0, 0.0)) for o in outs])
    return res


def kinematic_drift(t, dvy, dsd, vy_true, ok, window=KIN_WINDOW_S, every=KIN_EVERY_S):
    """The kinematic vy against the truth: over windows of window [s]
    starting every every [s], with ok and the trace on every step, the
    kinematic vy integrated from the true vy at the window's start (dvy:
    each step's increment ay + g_y - r vx times the period), its error at
    the end divided by what its deviation grew by (dsd: each step's
    increment). The share of windows with that ratio above 1 and above K
    (the promise's factor), and its median; None without a window."""
    dvy, dsd, vy_true, ok = (np.asarray(a, float) if i < 3 else np.asarray(a, bool)
                             for i, a in enumerate((dvy, dsd, vy_true, ok)))
    ok = ok & np.isfinite(dvy) & np.isfinite(dsd)
    if len(t) < 2:
        return None
    dt = float(np.median(np.diff(t)))
    nw, ns = max(1, int(round(window / dt))), max(1, int(round(every / dt)))
    cv = np.concatenate([[0.0], np.cumsum(np.where(ok, dvy, 0.0))])
    cs = np.concatenate([[0.0], np.cumsum(np.where(ok, dsd, 0.0))])
    cb = np.concatenate([[0], np.cumsum(~ok)])
    ratios = []
    for k0 in range(0, len(t) - nw, ns):
        k1 = k0 + nw
        # steps k0+1 .. k1 integrate from the truth at k0 to k1
        if cb[k1 + 1] - cb[k0 + 1] or not ok[k0] or cs[k1 + 1] - cs[k0 + 1] <= 0.0:
            continue
        drift = abs((cv[k1 + 1] - cv[k0 + 1]) - (vy_true[k1] - vy_true[k0]))
        ratios.append(drift / (cs[k1 + 1] - cs[k0 + 1]))
    if not ratios:
        return None
    ratios = np.array(ratios)
    return dict(windows=len(ratios), ratio_med=float(np.median(ratios)), over_1=float(np.mean(ratios > 1.0)),
                over_k=float(np.mean(ratios > K)))


def judge_run(t, est, truth, moving, outside=None):
    """One run's row: beta's and mu's integrity and beta's valid share over
    the moving steps outside spins and full saturation (outside)."""
    vb = ((est["valid"] & est_ref.V_BETA) != 0) & moving
    vm = ((est["valid"] & est_ref.V_MU) != 0) & moving
    r = {"moving_steps": int(moving.sum())}
    r["beta"] = stats(t, est["beta"] - truth["beta"], est["beta_sd"], vb, FLOOR["beta"])
    r["beta"]["true_err_max_deg"] = float(np.max(np.abs(est["beta"] - truth["beta"])[vb]) * DEG) if vb.any() else None
    r["beta"]["sd_med_deg"] = float(np.median(est["beta_sd"][vb]) * DEG) if vb.any() else None
    if truth.get("mu") is not None:
        r["mu"] = stats(t, est["mu"] - truth["mu"], est["mu_sd"], vm, FLOOR["mu"])
    if truth.get("vx") is not None:
        vv = ((est["valid"] & est_ref.V_VX) != 0) & moving
        r["vx"] = stats(t, est["vx"] - truth["vx"], est["vx_sd"], vv, FLOOR["vx"])
        r["vx"]["sd_med"] = float(np.median(est["vx_sd"][vv])) if vv.any() else None
    if truth.get("fy_axle") is not None:
        va = ((est["valid"] & est_ref.V_AXLE) != 0) & moving
        per = [stats(t, est["fy_axle"][:, a] - truth["fy_axle"][:, a], est["fy_axle_sd"][:, a], va,
                     FLOOR["fy_axle"]) for a in (0, 1)]
        r["fy_axle"] = totals([{"x": s} for s in per], "x")
        r["fy_axle"]["sd_med"] = float(np.median(est["fy_axle_sd"][va])) if va.any() else None
    den = moving if outside is None else (moving & outside)
    r["beta_valid_share"] = float(np.sum(vb & den) / den.sum()) if den.sum() else None
    r["share_steps"], r["share_valid_steps"] = int(den.sum()), int(np.sum(vb & den))
    # availability's ceiling: a step can be flagged valid within the promise
    # only with |error| <= max(1 deg, 3 beta_sd_max), whatever the bound;
    # the withheld steps, and how far off beta was on them
    lim = max(FLOOR["beta"], K * est_ref.BETA_SD_MAX)
    err = np.abs(est["beta"] - truth["beta"])
    fits = den & (err <= lim)
    wh = den & ~vb
    r["ceiling_steps"] = int(fits.sum())
    r["beta_ceiling_share"] = float(fits.sum() / den.sum()) if den.sum() else None
    r["withheld"] = dict(steps=int(wh.sum()), err_over=int(np.sum(wh & ~(err <= lim))),
                         err_med_deg=float(np.median(err[wh]) * DEG) if wh.any() else None,
                         sd_med_deg=float(np.median(est["beta_sd"][wh]) * DEG) if wh.any() else None)
    if "filter_vy_sd" in est:
        # the filter's own deviation in beta (its tire model's term) beyond
        # beta_sd_max: no share of the kinematic vy could have kept it valid
        # without the kinematic deviation itself within the limit
        fb = est["filter_vy_sd"] / np.maximum(np.abs(est["vx"]), est_ref.V_OFF) * np.cos(est["beta"]) ** 2
        over = wh & ~(fb <= est_ref.BETA_SD_MAX)
        r["withheld"]["filter_over"] = int(over.sum())
        if "mu_hyp_vy_sd" in est:
            # of those, the ones whose largest part is mu's term (friction
            # not yet identified), and how alike that hypothesis shifts the
            # two axles' slip angles: |front - rear| over the larger, median.
            # Alike, the steering and the yaw rate (which fix alpha_f -
            # alpha_r) cannot exclude it: friction is unobservable there
            hyp = over & (est["mu_hyp_vy_sd"] > est["filter_vy_sd_tire"])
            r["withheld"]["mu_term"] = int(hyp.sum())
            if hyp.any():
                sh = np.abs(est["mu_hyp_shift"][hyp])
                gap = np.abs(sh[:, 0] - sh[:, 1]) / np.maximum(np.max(sh, axis=1), 1e-9)
                r["withheld"]["mu_shift_gap_med"] = float(np.median(gap))
                r["withheld"]["mu_shift_med_deg"] = float(np.median(np.max(sh, axis=1)) * DEG)
    if truth.get("vy") is not None and "kin_dvy" in est:
        r["kin_drift"] = kinematic_drift(t, est["kin_dvy"], est["kin_dsd"], truth["vy"], moving)
    r["kin_steps"] = int(np.sum(((est["flags"] & est_ref.F_BETA_KIN) != 0) & moving))
    r["disagree_steps"] = int(np.sum(((est["flags"] & est_ref.F_BETA_DISAGREE) != 0) & moving))
    return r


def _axle_saturation(tr, at):
    """Both axles of the truth at >= SAT_U of their friction."""
    sat = []
    for ws in (("fl", "fr"), ("rl", "rr")):
        u = 0.0
        for w in ws:
            fz = np.maximum(at(f"fz_{w}"), 1.0)
            peak = np.maximum(np.maximum(at(f"mux_{w}"), at(f"muy_{w}")), 1e-3)
            u = np.maximum(u, np.hypot(at(f"fx_{w}"), at(f"fy_{w}")) / (peak * fz))
        sat.append(u >= SAT_U)
    return sat[0] & sat[1]


def own_truth(run_dir, t):
    tr = est_eval.read_csv(os.path.join(run_dir, "truth.csv"))

    def at(name):
        return np.interp(t, tr["time"], tr[name])
    truth = {"beta": at("beta"), "vx": at("vx"), "vy": at("vy"),
             "mu": np.mean([at(f"mu_road_{w}") for w in est_eval.WHEELS], axis=0),
             "fy_axle": np.column_stack([at("fy_fl") + at("fy_fr"), at("fy_rl") + at("fy_rr")])}
    beta_kin = np.arctan(1.60 * np.tan(at("delta")) / 2.70)
    spin = np.abs(truth["beta"] - beta_kin) * DEG > 10.0
    if spin.any():
        spin[int(np.argmax(spin)):] = True
    return truth, ~(spin | _axle_saturation(tr, at))


def own_run(run_dir, cfg):
    cols = est_eval.read_csv(os.path.join(run_dir, "sensors.csv"))
    t, value, valid = est_ref.inputs_from_sensors(cols)
    est = reference_run(cfg, value, valid)
    truth, outside = own_truth(run_dir, t)
    return judge_run(t, est, truth, truth["vx"] > V_MIN, outside)


def judge_own(runs_dir):
    dirs = est_eval.simulate_runs(runs_dir, ("step-steer", "ramp-steer", "sine-dwell", "brake-in-turn", "mu-step"),
                                  ("dry", "wet", "snow"))
    cfg = est_eval.est_config()
    return {os.path.basename(d): own_run(d, cfg) for d in dirs}


def mismatch_config(lky=MISMATCH_LKY):
    """est_eval's configuration with the rear tire's cornering stiffness
    (LKY) at lky x the car's."""
    p = golden_est.tire_params()
    rear = dict(p, lky=p["lky"] * lky)
    return est_ref.config(p, tire_rear=rear, rate_hz=100, **est_eval.est_vehicle())


def mismatch_run_dir(runs_dir):
    """The steady turn near the limit (simulated once into runs_dir)."""
    from grip_tools.sim import cli
    d = os.path.join(runs_dir, "runs", "step-steer-90deg-65kmh_dry")
    if not os.path.exists(os.path.join(d, "sensors.csv")):
        cli.main(["-m", "step-steer", "-s", "dry", "--speed", "65", "--duration", "8", "--amplitude", "90",
                  "-o", d, "--no-plot"])
    return d


def judge_mismatch(runs_dir):
    return {"step-steer 90 deg, rear LKY x 0.4": own_run(mismatch_run_dir(runs_dir), mismatch_config())}


def independent_run(vname, mname, sname, cache, fitted=None):
    """One independent-judge run (simulated and sampled as judge.run_one
    does, cached in cache/<run>/) through est_ref in the generic
    configuration, or with fitted (fitted_characterization's: the tire
    fitted to a ramp steer, the measured roll gradient and front roll
    share) in the fitted one."""
    from grip_tools.sim.independent import judge, mb
    veh = mb.Vehicle(vname)
    t, value, valid, tr = _run_inputs(vname, mname, sname, cache)
    if fitted is None:
        tire_path, values = judge.GENERIC_TIR, {**judge.oem_vehicle(veh), **est_eval.EXTRA}
    else:
        tire_path, values = fitted["tir"], judge.fitted_config_values(judge.oem_vehicle(veh), fitted, est_eval.EXTRA)
    cfg = est_ref.config(tir.load_params(tire_path), rate_hz=100, **values)
    return _judge_truth_run(veh, tr, tire_path, t, reference_run(cfg, value, valid, road_friction(veh, t, tr)))


# --road-friction: an outside friction source's standard deviation (None:
# no source); the source reads the simulator's road factor times its tire's
# peak coefficient, once per ROAD_FRICTION_PERIOD_S, ROAD_FRICTION_SD too
# high (the side that shrinks beta's bound): a source off by one deviation.
ROAD_FRICTION_SD = None
ROAD_FRICTION_PERIOD_S = 1.0


def road_friction(veh, t, tr):
    """The measurements grip_est_measure_friction gets in an independent
    run with --road-friction: (step, mu_road, mu_road_sd) rows; () without."""
    if ROAD_FRICTION_SD is None:
        return ()
    rows, nxt = [], float(t[0])
    for k in range(len(t)):
        if t[k] >= nxt:
            mu = float(tr["mu_surface"][k]) * float(veh.p.tire.p_dy1) + ROAD_FRICTION_SD
            rows.append((k, min(max(mu, 0.05), 2.0), ROAD_FRICTION_SD))
            nxt += ROAD_FRICTION_PERIOD_S
    return rows


def _run_inputs(vname, mname, sname, cache):
    """One independent-judge run's inputs (t, value, valid) and truth
    columns, simulated into cache/<run>/ unless there."""
    from grip_tools.sim.independent import judge
    d = os.path.join(cache, f"{vname}_{mname}_{sname}")
    inputs, truth_csv = os.path.join(d, "inputs.csv"), os.path.join(d, "truth.csv")
    if not (os.path.exists(inputs) and os.path.exists(truth_csv)):
        judge.simulate_run(vname, mname, sname, d)
    cols = est_eval.read_csv(inputs)
    t = cols["t_s"]
    value = np.zeros((len(t), est_ref.N_IN))
    valid = np.zeros((len(t), est_ref.N_IN), dtype=np.uint8)
    for i, c in enumerate(est_eval.IN_COLS):
        v = cols[c]
        valid[:, i] = np.isfinite(v)
        value[:, i] = np.where(np.isfinite(v), v, 0.0)
    tr = est_eval.read_csv(truth_csv)
    n = min(len(t), len(tr["time"]))
    return t[:n], value[:n], valid[:n], {k: v[:n] for k, v in tr.items()}


def _judge_truth_run(veh, tr, tire_path, t, est):
    """judge_run over the moving steps outside spins and full saturation,
    against the independent judge's truth."""
    from grip_tools.sim.independent import judge
    moving = tr["vx"] >= V_MIN
    spin = judge.spin_mask(tr, veh.l, veh.p.b, tr["vx"] >= judge.V_MOVING)
    sat = _axle_saturation(tr, lambda k: tr[k])
    truth = {"beta": tr["beta"], "mu": tr["mu_surface"] * judge.mu_norm(veh, tire_path), "vx": tr["vx"],
             "vy": tr["vy"],
             "fy_axle": np.column_stack([tr["fy_fl"] + tr["fy_fr"], tr["fy_rl"] + tr["fy_rr"]])}
    return judge_run(t, est, truth, moving, ~(spin | sat))


def learned_values(vname, cache):
    """The learned configuration of one vehicle: its vehicle values (the
    generic ones with stiff_est = 1, roll_est = 1, and est_eval.EXTRA, the
    options every run gets) and the C float build's blob after the
    vehicle's learning drive (judge.learn)."""
    from grip_tools.sim.independent import judge, mb
    values = judge.oem_vehicle(mb.Vehicle(vname))
    taught = judge.learn(vname, values, {"float": ("binding", "float")}, cache)
    run_values = dict(values, stiff_est=1, roll_est=1)
    run_values.update(est_eval.EXTRA)
    return run_values, taught["float"]


def learned_run(vname, mname, sname, cache, values, learned):
    """One independent-judge run through the C float build in the learned
    configuration, started from the learning drive's blob."""
    from grip_tools.sim.independent import judge, mb
    veh = mb.Vehicle(vname)
    t, value, valid, tr = _run_inputs(vname, mname, sname, cache)
    o = est_eval.run_binding("float", judge.GENERIC_TIR, t, value, valid, vehicle="generic",
                             vehicle_values=values, learned=learned["blob"], keep_out=True,
                             friction=road_friction(veh, t, tr))["out"]
    est = {k: np.asarray(o[k], float) for k in OUT_KEYS}
    est["valid"] = np.asarray(o["valid"], np.int64)
    est["flags"] = np.asarray(o["flags"], np.int64)
    return _judge_truth_run(veh, tr, judge.GENERIC_TIR, t, est)


def judge_learned(cache, full=False):
    """The independent simulator's runs in the learned configuration
    (learned_values, learned_run)."""
    from grip_tools.sim.independent import judge
    sel = judge.FULL_SET if full else judge.DEFAULT_SET
    out = {}
    for v in sel["vehicles"]:
        values, learned = learned_values(v, cache)
        print(f"integrity: learned {v}: k {learned['k_front']:.3f} / {learned['k_rear']:.3f}, "
              f"roll gradient {learned['roll_gradient']:.4f}", file=sys.stderr)
        for m in sel["manoeuvres"]:
            for s in sel["surfaces"]:
                out[f"{v} {m} {s}"] = r = learned_run(v, m, s, cache, values, learned)
                print(f"integrity: learned {v} {m} {s}: {r['beta']}", file=sys.stderr)
    return out


def fitted_characterization(vname, cache):
    """judge.characterize's runs and fits for one vehicle (the fitted
    configuration's tire and roll values), cached in cache/ (redone when
    the cache holds another version of the procedure)."""
    from grip_tools.sim.independent import judge
    os.makedirs(cache, exist_ok=True)
    path = os.path.join(cache, f"characterization_{vname}.json")
    if os.path.exists(path):
        with open(path) as f:
            c = json.load(f)
        if os.path.exists(c["tir"]) and c.get("characterization") == judge.CHARACTERIZATION:
            return c
    c = judge.characterize(vname, cache, cache)
    with open(path, "w") as f:
        json.dump(c, f, indent=1)
    return c


def judge_independent(cache, full=False, fitted=False):
    """The independent simulator's runs in the generic configuration, or
    with fitted in the fitted one: the tire file an OEM fits to a ramp steer
    with wheel-force transducers (docs/independent-judge.md), declared with
    the same tire_tol."""
    from grip_tools.sim.independent import judge
    sel = judge.FULL_SET if full else judge.DEFAULT_SET
    label = "fitted" if fitted else "independent"
    out = {}
    for v in sel["vehicles"]:
        c = fitted_characterization(v, cache) if fitted else None
        for m in sel["manoeuvres"]:
            for s in sel["surfaces"]:
                out[f"{v} {m} {s}"] = r = independent_run(v, m, s, cache, fitted=c)
                print(f"integrity: {label} {v} {m} {s}: {r['beta']}", file=sys.stderr)
    return out


def judge_av21(outdir, log=None):
    log = log or est_eval.av21_log.LOG
    tir_path = os.path.join(outdir, "av21_standin.tir")
    est_eval.av21_standin_tir(tir_path)
    t, value, valid, ins = est_eval.av21_inputs(log)
    full = np.zeros((len(t), est_ref.N_IN))
    fv = np.zeros((len(t), est_ref.N_IN), dtype=np.uint8)
    full[:, :value.shape[1]], fv[:, :valid.shape[1]] = value, valid
    cfg = est_ref.config(tir.load_params(tir_path), rate_hz=est_eval.AV21_RATE_HZ,
                         **dict(est_eval.AV21_VEHICLE, **est_eval.EXTRA))
    est = reference_run(cfg, full, fv)
    # no vx row: the log's vehicle speed, an estimator input, is the INS vx itself
    truth = {"beta": np.arctan2(ins["vy"], np.maximum(ins["vx"], 1e-3)), "vy": ins["vy"], "mu": None}
    return {"road course (INS sideslip)": judge_run(t, est, truth, ins["vx"] > 10.0)}


def judge_rav4():
    """The README's main job as a judge: the RAV4 drive (60 s of highway CAN,
    comma2k19) through the C float build in process (grip.replay: grip-replay
    -e PacejkaBook_Defaults.tir --vehicle rav4, which est_ref equals within
    the golden tolerances), beta against the drive's fused GNSS/IMU pose with
    the phone mount's yaw removed (main_job.rav4_truth_series), vx against its
    forward speed, above 10 m/s. No friction truth."""
    import grip.replay
    from grip_tools.evaluate import main_job
    log = os.path.join(est_eval.ROOT, "tests", "data", "comma2k19-rav4", "rav4_bus0.log")
    res = grip.replay.run(["-e", golden_est.tire_path(), "--vehicle", "rav4", log], arith="float")
    if res.status != 0:
        raise RuntimeError(f"grip-replay on {log}: exit {res.status}: {res.text.strip()}")
    c = res.columns
    est = {"beta": c["beta"], "beta_sd": c["beta_sd"], "vx": c["vx"], "vx_sd": c["vx_sd"],
           "mu": c["mu"], "mu_sd": c["mu_sd"],
           "valid": np.nan_to_num(c["est_valid"]).astype(np.int64),
           "flags": np.nan_to_num(c["est_flags"]).astype(np.int64)}
    truth, vf, _ = main_job.rav4_truth_series(c)
    moving = c["vx"] > 10.0
    return {"highway, 60 s (pose sideslip)": judge_run(c["t_s"], est, {"beta": truth, "vx": vf, "mu": None},
                                                      moving)}


def _faults_scenario(args):
    """One manoeuvre of the fault campaign (si, an index of faults.SCENARIOS):
    its fault-free run and every fault run (only: just these fault cases,
    e.g. ("ay delay",)) through monitor_ref -> est_ref (faults.run_chain);
    per consumer rule (FAULT_RULES) the totals over those runs, as one row."""
    from grip_tools.evaluate import faults as F
    si, cache, only = args
    scn, man, surf, kw, _ = F.SCENARIOS[si]
    cols, truth = F.simulate(man, surf, kw, cache)
    runs = [] if only else [("fault-free", F.inputs(cols))]
    runs += [(case, tvv) for _, _, case, tvv in F.fault_runs(si, cols, (lambda c: c in only) if only else None)]
    per_rule = {rule: [] for rule in FAULT_RULES}
    moving = truth["vx"] > V_MIN
    for _, (t, value, valid) in runs:
        run = F.run_chain(value, valid)
        for rule, mask in FAULT_RULES.items():
            gated, _ = monitor_ref.gate(run["degraded"], mask, run["valid"], run["flags"])
            est = dict(run, valid=gated)
            r = judge_run(t, est, {"beta": truth["beta"], "mu": truth["mu"]}, moving)
            r["beta_valid_steps_moving"] = int(np.sum(((gated & est_ref.V_BETA) != 0) & moving))
            per_rule[rule].append(r)
    rows = {}
    for rule, rs in per_rule.items():
        sds = [r["beta"]["sd_med_deg"] for r in rs if r["beta"]["sd_med_deg"] is not None]
        beta = totals(rs, "beta")
        beta["sd_med_deg"] = float(np.median(sds)) if sds else None
        n_mov = sum(r["moving_steps"] for r in rs)
        rows[rule] = {"runs": len(rs), "moving_steps": n_mov, "beta": beta, "mu": totals(rs, "mu"),
                      "share_steps": n_mov, "share_valid_steps": sum(r["beta_valid_steps_moving"] for r in rs),
                      "beta_valid_share": (sum(r["beta_valid_steps_moving"] for r in rs) / n_mov) if n_mov else None,
                      "kin_steps": sum(r["kin_steps"] for r in rs),
                      "disagree_steps": sum(r["disagree_steps"] for r in rs)}
    print(f"integrity: faults {scn}: {rows[next(iter(FAULT_RULES))]['beta']}", file=sys.stderr)
    return f"{scn} ({len(runs)} runs)", rows


def judge_faults(cache, jobs=2):
    """The fault campaign under each consumer rule: {rule judge: {manoeuvre: row}}."""
    from grip_tools.evaluate import faults as F
    for scn, man, surf, kw, t0 in F.SCENARIOS:
        F.simulate(man, surf, kw, cache)            # simulate (cached) before the workers start
    tasks = [(si, cache, None) for si in range(len(F.SCENARIOS))]
    if jobs > 1:
        import multiprocessing
        with multiprocessing.Pool(jobs) as pool:
            done = pool.map(_faults_scenario, tasks, chunksize=1)
    else:
        done = [_faults_scenario(tk) for tk in tasks]
    return {f"faults, {rule}": {name: rows[rule] for name, rows in done} for rule in FAULT_RULES}


def _pct(x):
    return "-" if x is None else f"{100.0 * x:.2f}"


def _cell(s):
    if s is None:
        return "-", "-", "-"
    return f"{s['valid_steps']}", f"{s['violations']} ({_pct(s['rate'])} %)", f"{1000.0 * s['longest_s']:.0f}"


def totals(rows, key):
    v = sum(r[key]["valid_steps"] for r in rows if r.get(key))
    b = sum(r[key]["violations"] for r in rows if r.get(key))
    lg = max([r[key]["longest_s"] for r in rows if r.get(key)] or [0.0])
    return dict(valid_steps=v, violations=b, rate=(b / v if v else 0.0), longest_s=lg)


def table(results):
    lines = ["| judge | run | beta valid steps | beta violations | beta longest [ms] | beta valid share [%] "
             "| beta sd median [deg] | kinematic / disagree steps | mu valid steps | mu violations "
             "| mu longest [ms] |", "|" + "---|" * 11]
    summary = ["| judge | runs | beta valid steps | beta violations | beta longest [ms] | beta target "
               "| mu valid steps | mu violations | mu longest [ms] | mu target | beta valid >= 90 % (runs) "
               "| beta valid, all runs' steps [%] | beta valid ceiling, all runs' steps [%] |",
               "|" + "---|" * 13]
    limit = ["| judge | run | steps | beta valid [%] | ceiling [%] | withheld | withheld beyond 3 deg "
             "| withheld error median [deg] | withheld beta_sd median [deg] | withheld, filter's sd beyond the limit "
             "| kinematic drift / bound median | windows > 1 [%] | windows > 3 [%] |", "|" + "---|" * 13]
    for j, runs in results.items():
        for name, r in runs.items():
            b, m = _cell(r["beta"]), _cell(r.get("mu"))
            sd = "-" if r["beta"]["sd_med_deg"] is None else f"{r['beta']['sd_med_deg']:.2f}"
            lines.append(f"| {j} | {name} | {b[0]} | {b[1]} | {b[2]} | {_pct(r['beta_valid_share'])} | {sd} "
                         f"| {r['kin_steps']} / {r['disagree_steps']} | {m[0]} | {m[1]} | {m[2]} |")
        rows = list(runs.values())
        tb = totals(rows, "beta")
        has_mu = any(r.get("mu") for r in rows)
        tm = totals(rows, "mu") if has_mu else None
        shares = [r["beta_valid_share"] for r in rows if r["beta_valid_share"] is not None]

        def ok(tt):
            return "met" if tt["rate"] <= TARGET_RATE and tt["longest_s"] <= TARGET_RUN_S + 1e-9 else "**missed**"
        b, m = _cell(tb), _cell(tm)
        n_share = sum(r.get("share_steps", 0) for r in rows)
        agg = _pct(sum(r.get("share_valid_steps", 0) for r in rows) / n_share) if n_share else "-"
        n_ceil = sum(r.get("ceiling_steps", 0) for r in rows)
        ceil = _pct(n_ceil / n_share) if n_share and any("ceiling_steps" in r for r in rows) else "-"
        summary.append(f"| {j} | {len(rows)} | {b[0]} | {b[1]} | {b[2]} | {ok(tb)} | {m[0]} | {m[1]} | {m[2]} "
                       f"| {ok(tm) if tm else '-'} | {sum(s >= TARGET_VALID for s in shares)} / {len(shares)} "
                       f"| {agg} | {ceil} |")
        for name, r in runs.items():
            if r["beta_valid_share"] is None or r["beta_valid_share"] >= TARGET_VALID or "withheld" not in r:
                continue
            w, kd = r["withheld"], r.get("kin_drift")
            f2 = (lambda x: "-" if x is None else f"{x:.2f}")
            kc = ["-"] * 3 if not kd else [f"{kd['ratio_med']:.2f}", _pct(kd["over_1"]), _pct(kd["over_k"])]
            limit.append(f"| {j} | {name} | {r['share_steps']} | {_pct(r['beta_valid_share'])} "
                         f"| {_pct(r['beta_ceiling_share'])} | {w['steps']} | {w['err_over']} | {f2(w['err_med_deg'])} "
                         f"| {f2(w['sd_med_deg'])} | {w.get('filter_over', '-')} | " + " | ".join(kc) + " |")
    summary += ["", "| judge | vx valid steps | vx violations | vx longest [ms] | vx sd median [m/s] | vx target "
                "| axle valid steps | axle violations | axle longest [ms] | axle sd median [N] | axle target |",
                "|" + "---|" * 11]
    for j, runs in results.items():
        rows = list(runs.values())
        cells = []
        for key, fmt in (("vx", "{:.3f}"), ("fy_axle", "{:.0f}")):
            if not any(r.get(key) for r in rows):
                cells += ["-"] * 5
                continue
            tt = totals(rows, key)
            sds = [r[key]["sd_med"] for r in rows if r.get(key) and r[key].get("sd_med") is not None]
            c = _cell(tt)
            met = "met" if tt["rate"] <= TARGET_RATE and tt["longest_s"] <= TARGET_RUN_S + 1e-9 else "**missed**"
            cells += [c[0], c[1], c[2], fmt.format(float(np.median(sds))) if sds else "-", met]
        summary.append(f"| {j} | " + " | ".join(cells) + " |")
    return "\n".join(summary) + "\n", "\n".join(lines) + "\n", "\n".join(limit) + "\n"


def option_error(judges, consts):
    """None when run() can go with these judges and "NAME=VALUE" constants,
    else what is wrong, naming the option (--judges, --const)."""
    unknown = [j for j in judges if j not in JUDGES]
    if unknown or not judges:
        return f"--judges: {', '.join(unknown) or 'none given'}: not a judge (have {', '.join(JUDGES)})"
    for spec in consts:
        name, eq, value = spec.partition("=")
        if not eq or not hasattr(est_ref, name):
            return f"--const {spec}: not NAME=VALUE with NAME a constant of the reference estimator"
        try:
            float(value)
        except ValueError:
            return f"--const {spec}: {value!r} is not a number"
    return None


def run(out, judges=JUDGES, runs_dir=None, full=False, av21_log=None, consts=(), road_friction_sd=None):
    """consts: "NAME=VALUE" pairs, est_ref module constants changed for the
    run (the sensitivity of TIRE_TOL, KIN_ACC, ROLL_TOL, DIS_K, ...);
    road_friction_sd: the independent simulator's runs (independent,
    fitted, learned) get an outside friction source of that deviation
    (road_friction);
    ValueError (option_error's text) before anything runs where they or
    the judges cannot be run."""
    from unittest import mock
    err = option_error(list(judges), consts)
    if err:
        raise ValueError(err)
    runs_dir = runs_dir or os.path.join(est_eval.ROOT, "build", "est_eval")
    os.makedirs(out, exist_ok=True)
    patches = []
    for spec in consts:
        name, _, value = spec.partition("=")
        patches.append(mock.patch.object(est_ref, name, float(value)))
    patches.append(mock.patch(__name__ + ".ROAD_FRICTION_SD", road_friction_sd))
    if road_friction_sd is not None:
        consts = tuple(consts) + (f"road friction +- {road_friction_sd}",)
    for p in patches:
        p.start()
    try:
        return _run(out, judges, runs_dir, full, av21_log, consts)
    finally:
        for p in patches:
            p.stop()


def table_command(full, judges):
    """The command line that decides what the table holds, for its header:
    the set, the judges and the estimator options every run got
    (est_eval.EXTRA)."""
    return "grip est-eval --integrity" + (" --full" if full else "") + (
        "" if list(judges) == list(JUDGES) else f" --judges {','.join(judges)}") + "".join(
        (f" --{k.replace('_', '-')}" if est_eval.EXTRA[k] else f" --no-{k.replace('_', '-')}")
        for k in est_eval.EXTRA_OPTIONS if k in est_eval.EXTRA)


def _run(out, judges, runs_dir, full, av21_log, consts):
    res = {}
    for j in judges:
        if j == "own":
            res[j] = judge_own(runs_dir)
        elif j == "mismatch":
            res[j] = judge_mismatch(runs_dir)
        elif j == "independent":
            res[j] = judge_independent(os.path.join(runs_dir, "independent"), full=full)
        elif j == "fitted":
            res[j] = judge_independent(os.path.join(runs_dir, "independent"), full=full, fitted=True)
        elif j == "learned":
            res[j] = judge_learned(os.path.join(runs_dir, "independent"), full=full)
        elif j == "rav4":
            res[j] = judge_rav4()
        elif j == "av21":
            res[j] = judge_av21(out, av21_log)
        else:                                   # "faults" (run() checked the names)
            res.update(judge_faults(os.path.join(est_eval.ROOT, "build", "faults-cache")))
        print(f"integrity: {j} done", file=sys.stderr)
    summary, detail, limit = table(res)
    with open(os.path.join(out, "integrity.json"), "w") as f:
        json.dump({"consts": list(consts), "vehicle_extra": dict(est_eval.EXTRA), "judges": res}, f, indent=1)
    note = f" with {', '.join(consts)}" if consts else ""
    cmd = table_command(full, judges)
    with open(os.path.join(out, "integrity_table.md"), "w") as f:
        f.write(f"<!-- written by `{cmd}`{note}; do not edit -->\n\n## Summary\n\n" + summary
                + "\n## Every run\n\n" + detail
                + "\n## The runs below 90 % beta valid\n\n"
                "steps: moving, outside spins and full saturation; ceiling: the share of them with |beta error| "
                "<= max(1 deg, 3 beta_sd_max), the most any bound could flag valid within the promise; "
                "withheld: those not flagged valid (filter's sd beyond the limit: the filter's own vy deviation, "
                "its tire model's term, above beta_sd_max); kinematic drift / bound: over 1 s windows of the moving steps, "
                "the kinematic vy integrated from the true vy against what its deviation grew by\n\n" + limit)
    print(summary)
    return res
