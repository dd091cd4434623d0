"""The independent judge's axle lateral forces, error by error source.

    grip est-axle [--runs-dir build/est_eval/independent]
                  [--judge docs/estimator/independent/independent.json]
                  [--configs generic,fitted,learned] [--tau 0.05] [--out FILE.md]

Reads the runs that `grip est-eval --independent [--full]` left in its runs
directory (per run truth.csv and inputs.csv; learning_<vehicle>_inputs.csv
for the learned configuration) and that run's independent.json (each
configuration's tire and vehicle values, the ramp characterization's roll
gradient). Runs the C float build (the binding) as the judge does and
scores, with the judge's Fy metric (judge.fy_scores: RMS over the moving
steps the estimator flags V_AXLE, in % of the axle's peak |Fy|), these axle
force estimates, wheel frame:

  model    the estimator's fy_axle, as the judge scores it
  balance  model-free, from the sensors the estimator gets: the lateral
           force sum m ay and the yaw moment Iz dr/dt solved for the axles,
               m ay     = Fyf cos d + Fxf sin d + Fyr
               Iz dr/dt = lf (Fyf cos d + Fxf sin d) - lr Fyr + Mx
           ay the measured one with the estimator's roll correction
           (ay / (1 + g roll_gradient)), r the gyro less the estimator's
           offset, dr/dt its backward difference low-passed over --tau
           (first order, causal), d the estimator's road-wheel angle, the
           front Fx and the left / right Fx moment Mx = -(Tf / 2)(Fx_fl -
           Fx_fr) cos d - (Tr / 2)(Fx_rl - Fx_rr) from the estimator's wheel
           forces
  blend    the mean of model and balance
  car_roll the model again, configured with the car's roll gradient (the
           ramp characterization's; the fitted configuration has it already)
  drive_roll the same with the roll gradient regressed from the learning
           drive's sensors alone (drive_roll_gradient)
  true_fx  the balance with the truth's wheel Fx in place of the
           estimator's (what the estimated longitudinal forces cost it)
  shifted  the estimate SHIFT steps earlier, front / rear (what its lag
           behind the truth costs)
  ideal    the balance from the truth (the lateral specific force, dr/dt,
           Fx, d): how far the balance's equations hold on the multi-body
           model

and, in % of the front peak, the RMS error of the estimate's lateral sum
(fyf cos d + fyr against the truth's) and the accelerometer's error
m (ay_used - f_y), f_y the true lateral specific force of the road frame
(kinematic ay + g cos(grade) sin(bank)); the RMS of the front wheels'
left-minus-right Fx, estimated and true [N]. A second table gives the
estimate in N: the truth's peak, the estimate's RMS and mean error, its
fy_axle_sd (median, share of steps within 3 of it), its lag (best_lag) and
the used ay's against the true lateral specific force. The per-step noise of the balance's
front force from the sensors' data-sheet noise (sensors.SPEC) is printed
with the table.
"""
import argparse
import itertools
import json
import math
import os
import sys

import numpy as np

from grip_tools.errors import EXIT_HELP, DataError, UsageError
from grip_tools.evaluate import est_eval
from grip_tools.paths import REPO_ROOT
from grip_tools.reference import est as est_ref
from grip_tools.sim.independent import judge, sensors

G = 9.81
DT = sensors.STEP
# the vehicle values the balance needs
VEHICLE_KEYS = ("mass", "iz", "lf", "lr", "track_f", "track_r")
ESTIMATES = ("model", "balance", "blend", "car_roll", "drive_roll", "true_fx", "shifted", "ideal")
# shifted: the estimate this many steps earlier, front / rear (its lag)
SHIFT = (2, 1)
# the lags searched [steps]: the estimate against the truth, the used ay
# against the true lateral specific force
LAGS = range(0, 6)
# the learning drive's roll-gradient regression: both sides low-passed over
# ROLL_TAU [s], moving steps after ROLL_SKIP [s]
ROLL_TAU, ROLL_SKIP = 1.0, 5.0


def lowpass(x, tau, dt=DT):
    """First-order causal low-pass, y += (dt / tau)(x - y), from x[0]."""
    a = min(dt / tau, 1.0) if tau > 0 else 1.0
    y = np.empty_like(x)
    acc = float(x[0])
    for k in range(len(x)):
        acc += a * (float(x[k]) - acc)
        y[k] = acc
    return y


def solve_axles(ay, racc, delta, fx, v):
    """The axle forces (front, rear; wheel frame) of the lateral force and
    yaw moment balance (module docstring). ay, racc [m/s^2, rad/s^2],
    delta [rad], fx (n, 4) wheel-frame Fx [N] FL FR RL RR, v the vehicle
    values (mass, iz, lf, lr, track_f, track_r)."""
    m, iz, lf, lr = v["mass"], v["iz"], v["lf"], v["lr"]
    l = lf + lr
    c, s = np.cos(delta), np.sin(delta)
    mx = -0.5 * v["track_f"] * (fx[:, 0] - fx[:, 1]) * c - 0.5 * v["track_r"] * (fx[:, 2] - fx[:, 3])
    front_body = (lr * m * ay + iz * racc - mx) / l
    rear = (lf * m * ay - iz * racc + mx) / l
    front = (front_body - (fx[:, 0] + fx[:, 1]) * s) / np.maximum(c, 0.05)
    return front, rear


def balance_noise(v, tau):
    """Per-step standard deviation [N] of the balance's front force from the
    data-sheet noise of ay and the gyro (sensors.SPEC, 1 sigma, white)
    through the roll correction and the derivative filter. The filter
    y_k = y_k-1 + a ((x_k - x_k-1) / dt - y_k-1), a = dt / tau, has the
    impulse response (a / dt)(1, -a b^0, -a b^1, ...), b = 1 - a, whose
    squares sum to (a / dt)^2 2 / (2 - a)."""
    a = min(DT / tau, 1.0)
    s_r = sensors.SPEC["yaw_rate"][0] * a / DT * math.sqrt(2.0 / (2.0 - a))
    s_ay = sensors.SPEC["ay"][0] / (1.0 + G * v.get("roll_gradient", est_eval_default_roll()))
    l = v["lf"] + v["lr"]
    return math.hypot(v["lr"] * v["mass"] * s_ay / l, v["iz"] * s_r / l)


def est_eval_default_roll():
    """grip_est_config_default's roll gradient (the reference's default,
    which the golden tests hold the C default to)."""
    return float(est_ref.config(None)["roll_gradient"])


def _load_csv(path):
    if not os.path.isfile(path):
        raise UsageError(f"cannot open {path}: no such file (run `grip est-eval --independent` first)")
    cols = est_eval.read_csv(path)
    for name, x in cols.items():
        if len(x) == 0:
            raise DataError(path, 2, name, "no rows")
    return cols


def load_run(run_dir):
    """truth and the estimator's inputs (t, value, valid) of one run."""
    tr = _load_csv(os.path.join(run_dir, "truth.csv"))
    inp_path = os.path.join(run_dir, "inputs.csv")
    inp = _load_csv(inp_path)
    missing = [c for c in ["t_s"] + est_eval.IN_COLS if c not in inp]
    if missing:
        raise DataError(inp_path, 1, missing[0], "column missing")
    for name in ("time", "vx", "ay_kin", "r", "delta", "bank", "grade") + tuple(
            f"{q}_{w}" for q in ("fx", "fy") for w in est_eval.WHEELS):
        if name not in tr:
            raise DataError(os.path.join(run_dir, "truth.csv"), 1, name, "column missing")
    t = inp["t_s"]
    raw = np.stack([inp[c] for c in est_eval.IN_COLS], axis=1)
    valid = np.isfinite(raw).astype(np.int64)
    return tr, inp, t, np.nan_to_num(raw), valid


def learned_blob(runs_dir, vname, cfg):
    """The learned configuration's starting blob: the learning drive's
    inputs (as est-eval --independent wrote them) through the float build;
    and the roll gradient its runs start with (the learned one with
    roll_est 1, else None: the configured one)."""
    t, value, valid = load_run_inputs(os.path.join(runs_dir, f"learning_{vname}_inputs.csv"))
    out = est_eval.run_binding("float", cfg["tir"], t, value, valid, vehicle_values=cfg["values"],
                               keep_learned=True)
    roll = out["learned"]["roll_gradient"] if cfg["values"].get("roll_est") else None
    return out["learned"]["blob"], roll


def load_run_inputs(path):
    inp = _load_csv(path)
    missing = [c for c in ["t_s"] + est_eval.IN_COLS if c not in inp]
    if missing:
        raise DataError(path, 1, missing[0], "column missing")
    raw = np.stack([inp[c] for c in est_eval.IN_COLS], axis=1)
    return inp["t_s"], np.nan_to_num(raw), np.isfinite(raw).astype(np.int64)


def estimates(tr, inp, t, value, valid, cfg, rolls, tau, blob=None, roll_used=None):
    """{name: (fyf, fyr)} of ESTIMATES, the V_AXLE step mask and the
    diagnostic series (lateral sum error, accelerometer error) of one run.
    rolls: {estimate name: roll gradient} of the roll-gradient variants
    (car_roll, drive_roll) to run, each with that gradient fixed (roll_est
    0); roll_used: the roll gradient the estimate starts with when it was
    learned (the balance's ay and the accelerometer error use it; None: the
    configured one)."""
    v = cfg["values"]
    o = est_eval.run_binding("float", cfg["tir"], t, value, valid, vehicle_values=v, learned=blob, keep_out=True)
    n = min(len(t), len(tr["time"]))
    tr = {k: x[:n] for k, x in tr.items()}
    out = {k: np.asarray(x)[:n] for k, x in o["out"].items() if np.ndim(x) >= 1 and len(x) >= n}
    steps = ((np.asarray(o["valid"])[:n] & est_ref.V_AXLE) != 0) & (tr["vx"] >= judge.V_MOVING)
    rg = roll_used if roll_used is not None else v.get("roll_gradient", est_eval_default_roll())
    ay = np.nan_to_num(inp["ay"][:n]) / (1.0 + G * rg)
    r = np.nan_to_num(inp["yaw_rate"][:n]) - out["yaw_rate_bias"]
    dr = np.zeros(n)
    dr[1:] = np.diff(r) / DT
    racc = lowpass(dr, tau)
    delta = out["delta"]
    res = {"model": (o["fyf"][:n], o["fyr"][:n])}
    res["balance"] = solve_axles(ay, racc, delta, out["fx"], v)
    res["blend"] = tuple(0.5 * (a + b) for a, b in zip(res["model"], res["balance"]))
    for name, k in rolls.items():
        o2 = est_eval.run_binding("float", cfg["tir"], t, value, valid,
                                  vehicle_values=dict(v, roll_gradient=k, roll_est=0), learned=blob)
        res[name] = (o2["fyf"][:n], o2["fyr"][:n])
    # the true lateral specific force (road frame): what the tires push
    f_y = tr["ay_kin"] + G * np.cos(tr["grade"]) * np.sin(tr["bank"])
    fx_t = np.stack([tr[f"fx_{w}"] for w in est_eval.WHEELS], axis=1)
    res["true_fx"] = solve_axles(ay, racc, delta, fx_t, v)
    res["ideal"] = solve_axles(f_y, np.gradient(tr["r"], DT), tr["delta"], fx_t, v)
    res["shifted"] = tuple(advance(x, k) for x, k in zip(res["model"], SHIFT))
    d = tr["delta"]
    sum_t = (tr["fy_fl"] + tr["fy_fr"]) * np.cos(d) + tr["fy_rl"] + tr["fy_rr"]
    sum_e = res["model"][0] * np.cos(delta) + res["model"][1]
    diag = {"sum_err": sum_e - sum_t, "acc_err": v["mass"] * (ay - f_y),
            "fx_lr_est": out["fx"][:, 0] - out["fx"][:, 1], "fx_lr_true": tr["fx_fl"] - tr["fx_fr"],
            "sd": (out["fy_axle_sd"][:, 0], out["fy_axle_sd"][:, 1]), "ay_used": ay, "f_y": f_y}
    return res, steps, tr, diag


def advance(x, k):
    """x k steps earlier: x[i + k], the last value held."""
    return np.concatenate([x[k:], np.full(k, x[-1])]) if k > 0 else x


def best_lag(est, true, steps):
    """The shift in LAGS [steps] by which est advanced best matches true
    (least RMS over steps, the last max(LAGS) steps left out)."""
    sel = steps.copy()
    sel[len(sel) - max(LAGS):] = False
    if not sel.any():
        return None
    return min(LAGS, key=lambda k: float(np.mean((advance(est, k) - true)[sel] ** 2)))


def score_run(res, steps, tr, diag):
    """{estimate: [front %, rear %]}, the diagnostics in % of the front peak
    and the front left-minus-right Fx's RMS [N] (fx_lr_est, fx_lr_true)."""
    sc = {}
    for name, (f, r) in res.items():
        x = judge.fy_scores(f, r, tr, steps)
        sc[name] = [x.get("fy_front_rms_pct"), x.get("fy_rear_rms_pct")]
    peak = float(np.max(np.abs((tr["fy_fl"] + tr["fy_fr"])[steps]))) if steps.any() else 0.0
    for k in ("sum_err", "acc_err", "fx_lr_est", "fx_lr_true"):
        rms = float(np.sqrt(np.mean(diag[k][steps] ** 2))) if steps.any() else None
        if k.startswith("fx_lr"):
            sc[k] = rms
        else:
            sc[k] = 100.0 * rms / peak if peak >= judge.FY_PEAK_MIN and rms is not None else None
    # the estimate in N: peak, RMS and mean error, its own bound
    # (fy_axle_sd: median, share of steps within 3 of it), its lag
    f = judge.fy_scores(*res["model"], tr, steps)
    for a, (name, t_ax) in enumerate((("front", tr["fy_fl"] + tr["fy_fr"]), ("rear", tr["fy_rl"] + tr["fy_rr"]))):
        e = res["model"][a] - t_ax
        sd = diag["sd"][a]
        sc[f"{name}_N"] = None if not steps.any() else dict(
            peak=f[f"fy_{name}_peak_N"], rms=f[f"fy_{name}_rms_N"], mean=float(np.mean(e[steps])),
            sd_median=float(np.median(sd[steps])), in_3sd=float(np.mean(np.abs(e[steps]) <= 3.0 * sd[steps])),
            lag=best_lag(res["model"][a], t_ax, steps))
    sc["ay_lag"] = best_lag(diag["ay_used"], diag["f_y"], steps)
    return sc


def passes(pair):
    p = [x for x in pair if x is not None]
    return None if not p else max(p) <= judge.TARGETS["fy_pct"]


def _f(x):
    return "-" if x is None else f"{x:.1f}"


def read_judge(path):
    """Configurations {vehicle: {cname: {tir, values}}} and the car's roll
    gradient {vehicle: value} of an independent.json."""
    if not os.path.isfile(path):
        raise UsageError(f"cannot open {path}: no such file (run `grip est-eval --independent` first)")
    try:
        with open(path) as f:
            doc = json.load(f)
    except json.JSONDecodeError as e:
        raise DataError(path, e.lineno, "-", f"not JSON: {e.msg}") from None
    if not isinstance(doc.get("configs"), dict):
        raise DataError(path, None, "configs", "missing")
    configs = {}
    for vname, cfgs in doc["configs"].items():
        configs[vname] = {}
        for cname, c in cfgs.items():
            if "tir" not in c or "vehicle" not in c:
                raise DataError(path, None, f"configs.{vname}.{cname}", "needs tir and vehicle")
            for k in VEHICLE_KEYS:
                x = c["vehicle"].get(k)
                if not isinstance(x, (int, float)) or not math.isfinite(x) or x <= 0:
                    raise DataError(path, None, f"configs.{vname}.{cname}.vehicle.{k}",
                                    f"{x!r}: not a positive number")
            configs[vname][cname] = {"tir": os.path.join(REPO_ROOT, c["tir"]), "values": c["vehicle"]}
    roll = {c["vehicle"]: c["values"]["roll_gradient"] for c in doc.get("characterization", [])}
    return configs, roll


def run(runs_dir, judge_json, cnames, tau, vehicles=None):
    """Every run of the judge's selection that is in runs_dir; returns the
    rows [(run, cname, scores)] and the balance noise per vehicle."""
    configs, roll = read_judge(judge_json)
    sel = [v for v in judge.VEHICLES if v in configs and (not vehicles or v in vehicles)]
    if not any(os.path.isdir(os.path.join(runs_dir, f"{v}_{m}_{s}"))
               for v in sel for m in judge.MANOEUVRES for s in judge.SURFACES):
        raise UsageError(f"{runs_dir}: no run of the judge (run `grip est-eval --independent` first)")
    rows, noise, drive = [], {}, {}
    for vname in judge.VEHICLES:
        if vname not in configs or (vehicles and vname not in vehicles):
            continue
        if vname not in roll:
            raise DataError(judge_json, None, "characterization", f"no roll gradient of {vname}")
        drive[vname] = drive_roll_gradient(os.path.join(runs_dir, f"learning_{vname}_inputs.csv"))
        blobs = {}
        for cname in cnames:
            if cname not in configs[vname]:
                raise UsageError(f"--configs: {cname}: not in {judge_json} (have {', '.join(configs[vname])})")
            if cname == "learned":
                blobs[cname] = learned_blob(runs_dir, vname, configs[vname][cname])
        noise[vname] = balance_noise(configs[vname][cnames[0]]["values"], tau)
        for mname, sname in itertools.product(judge.MANOEUVRES, judge.SURFACES):
            run_dir = os.path.join(runs_dir, f"{vname}_{mname}_{sname}")
            if not os.path.isdir(run_dir):
                continue
            tr, inp, t, value, valid = load_run(run_dir)
            for cname in cnames:
                cfg = configs[vname][cname]
                rolls = {} if cname == "fitted" else {"car_roll": roll[vname], "drive_roll": drive[vname]}
                blob, roll_used = blobs.get(cname, (None, None))
                res, steps, trn, diag = estimates(tr, inp, t, value, valid, cfg, rolls, tau, blob, roll_used)
                rows.append((f"{vname} {mname} {sname}", cname, score_run(res, steps, trn, diag)))
    return rows, noise, {v: (drive[v], roll[v]) for v in drive}


def drive_roll_gradient(path):
    """The roll gradient [rad/(m/s^2)] from the learning drive's sensors
    alone: on a level road the accelerometer reads the lateral acceleration
    (vx r + dvy/dt) times 1 + g k (the body rolls by k ay and its
    accelerometer sees g sin(roll)) plus offsets, so the least-squares line
    of ay over vx r (vx the mean wheel speed, r the gyro; the intercept takes
    the ay and gyro offsets) has the slope 1 + g k. Both are low-passed over
    ROLL_TAU first: dvy/dt is in quadrature with vx r at a weave's
    frequencies and shrinks towards the low ones, where the roll follows ay
    (unfiltered, the slope was 0.0131 for the BMW 320i's 0.0159)."""
    t, value, valid = load_run_inputs(path)
    col = {c: i for i, c in enumerate(est_eval.IN_COLS)}
    ok = np.all(valid[:, [col["ay"], col["yaw_rate"]]] != 0, axis=1)
    ws = [col[f"wheel_speed_{w}"] for w in est_eval.WHEELS]
    vx = np.mean(value[:, ws], axis=1)
    a = lowpass(np.where(ok, value[:, col["ay"]], 0.0), ROLL_TAU)
    x = lowpass(np.where(ok, vx * value[:, col["yaw_rate"]], 0.0), ROLL_TAU)
    sel = ok & (vx > judge.V_MOVING) & (t >= t[0] + ROLL_SKIP)
    if sel.sum() < 100:
        raise DataError(path, None, "ay", "fewer than 100 moving steps with ay and yaw rate")
    c = np.linalg.lstsq(np.column_stack([np.ones(sel.sum()), x[sel]]), a[sel], rcond=None)[0]
    return float((c[1] - 1.0) / G)


def table(rows, noise, tau, cnames, rolls=None):
    head = ["run", "configuration"] + [f"{e} F / R [%]" for e in ESTIMATES] + ["sum error [%]", "ay error [%]",
                                                                        "front Fx left - right, estimate / truth [N]"]
    md = ["# Axle forces by error source", "",
          "Generated by `grip est-axle` (tools/grip_tools/sim/independent/axle.py) from the runs of "
          "`grip est-eval --independent`; docs/independent-judge.md, \"Axle forces by error source\", "
          "says what each column is.", "",
          f"Axle Fy RMS in % of the axle's peak (judge metric); derivative filter tau {tau} s. "
          "Balance front-force noise from the sensors' data sheet: "
          + ", ".join(f"{k} {x:.0f} N" for k, x in noise.items()) + ".", "",
          "Roll gradient [rad/(m/s^2)] regressed from the learning drive (drive_roll) / from the ramp "
          "characterization (car_roll): " + ", ".join(f"{k} {d:.4f} / {c:.4f}" for k, (d, c) in (rolls or {}).items())
          + ".", "",
          "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for run_name, cname, sc in rows:
        cells = [run_name, cname]
        for e in ESTIMATES:
            cells.append(" / ".join(_f(x) for x in sc[e]) if e in sc else "-")
        cells += [_f(sc["sum_err"]), _f(sc["acc_err"]),
                  "-" if sc["fx_lr_est"] is None else f"{sc['fx_lr_est']:.0f} / {sc['fx_lr_true']:.0f}"]
        md.append("| " + " | ".join(cells) + " |")
    md += ["", "## The estimate in N", "",
           "Per axle: the truth's peak, the estimate's RMS and mean error, the median of its fy_axle_sd and "
           "the share of steps within 3 of it, and the shift [10 ms steps] by which the estimate moved earlier "
           "matches the truth best; the same shift of the used ay against the true lateral specific force.", "",
           "| run | configuration | peak F / R [N] | RMS F / R [N] | mean F / R [N] | fy_axle_sd median F / R [N] "
           "| within 3 sd F / R [%] | lag F / R [steps] | ay lag [steps] |", "|" + "---|" * 9]
    for run_name, cname, sc in rows:
        f, r = sc["front_N"], sc["rear_N"]

        def pair(key, fmt):
            return " / ".join("-" if x is None or x.get(key) is None else format(
                100.0 * x[key] if key == "in_3sd" else x[key], fmt) for x in (f, r))
        md.append(f"| {run_name} | {cname} | {pair('peak', '.0f')} | {pair('rms', '.0f')} | {pair('mean', '+.0f')} | "
                  f"{pair('sd_median', '.0f')} | {pair('in_3sd', '.0f')} | {pair('lag', 'd')} | "
                  f"{'-' if sc['ay_lag'] is None else sc['ay_lag']} |")
    md += ["", "## Pass counts", "", "Runs meeting Fy <= 5 % (worse axle), per configuration:", "",
           "| configuration | runs | " + " | ".join(ESTIMATES) + " |", "|---|---|" + "---|" * len(ESTIMATES)]
    for cname in cnames:
        mine = [sc for _, c, sc in rows if c == cname]
        cells = [cname, str(len(mine))]
        for e in ESTIMATES:
            got = [passes(sc[e]) for sc in mine if e in sc]
            cells.append(f"{sum(1 for g in got if g)} / {sum(1 for g in got if g is not None)}" if got else "-")
        md.append("| " + " | ".join(cells) + " |")
    return "\n".join(md) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip est-axle", description=__doc__.split("\n\n")[0], epilog=EXIT_HELP)
    ap.add_argument("--runs-dir", default=os.path.join(REPO_ROOT, "build", "est_eval", "independent"))
    ap.add_argument("--judge", default=os.path.join(REPO_ROOT, "docs", "estimator", "independent", "independent.json"),
                    help="the independent.json of the est-eval run that wrote --runs-dir")
    ap.add_argument("--configs", default="generic,fitted,learned")
    ap.add_argument("--vehicles", default=None, help="comma-separated; default every vehicle of --judge")
    ap.add_argument("--tau", type=float, default=0.05, help="the yaw-rate derivative's low-pass [s]")
    ap.add_argument("--out", default=None, help="write the table here too (Markdown)")
    a = ap.parse_args(argv)
    if not 0.0 < a.tau <= 10.0:
        raise UsageError(f"--tau: {a.tau}: not in (0, 10] s")
    err = est_eval.binding_available()
    if err:
        raise UsageError(f"needs the Python binding of the C library: {err}")
    cnames = [c for c in a.configs.split(",") if c]
    vehicles = [v for v in a.vehicles.split(",") if v] if a.vehicles else None
    bad = judge.selection_error(vehicles=vehicles)
    if bad:
        raise UsageError(bad)
    rows, noise, rolls = run(a.runs_dir, a.judge, cnames, a.tau, vehicles)
    if not rows:
        raise UsageError(f"{a.runs_dir}: no run of the judge (run `grip est-eval --independent` first)")
    md = table(rows, noise, a.tau, cnames, rolls)
    sys.stdout.write(md)
    if a.out:
        with open(a.out, "w") as f:
            f.write(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
