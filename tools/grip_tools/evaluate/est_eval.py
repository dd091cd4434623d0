"""Accuracy of the onboard estimator on the reference simulator's manoeuvres.

    grip est-eval --runs DIR [DIR ...] [--out docs/estimator]
    grip est-eval --simulate --out docs/estimator

Each run directory holds a simulator output (grip simulate
... --out DIR: truth.csv, sensors.csv, summary.json). The estimator's
float64 reference (est_ref) is run over sensors.csv at 100 Hz (the sensors'
message rate) and compared with truth.csv:

  beta     RMS and max |beta_est - beta_true| [deg] over the rows where the
           estimate is valid and the true speed is above 5 m/s
  mu       sufficient excitation starts at t0, the first time a tire of the
           TRUTH uses >= 90 % of its friction (|F| / (mu_peak Fz), mu_peak
           from the simulator's tire model and road: the friction limit);
           reported: |mu_est - mu_true| at t0 + 1 s, the share of time after
           t0 + 1 s with |error| <= 0.1, and the confidence at t0 + 1 s; the
           same from the stricter onset at 50 % beside it. mu_true = the
           road's scale of the tire's friction (the same meaning as the
           estimate's mu)
  Fy axle  RMS of the front / rear axle lateral force error (wheel frame)
           as a percentage of the run's peak |Fy| of that axle

The C estimator (float and fixed builds) runs over the same inputs, exactly
as est_ref gets them, through the Python binding of the C library
(grip.est: the library's own code, bit-identical to grip-replay's CSV mode,
tests/python/binding/test_est.py), and is evaluated the same way.
--c-bin ARITH=PATH runs a grip-replay program instead (grip-replay -e TIR
--vehicle generic --vehicle-file F --csv FILE, the inputs written by
write_input_csv): another build of the C code than the binding's (another
compiler, a sanitizer build); a program that is absent is skipped with a
note. Per
run, the fixed/float error ratio: fixed error / float error of each of beta
RMS, beta max, Fy front / rear RMS and |mu err| at t0 + 1 s, taken where the
float error is at least FLOOR (0.05 deg, 0.1 % of peak, 0.01 of mu; below
that the ratio of two near-zero errors says nothing); the run's figure is
the largest of these ratios (issue 5: "fixed within 1.5x of float's
errors").

Writes <out>/accuracy.json, <out>/accuracy.md (tables) and <out>/accuracy.png.
The simulator's runs go to --runs-dir (default build/est_eval/runs).

    grip est-eval --independent [--full] --out docs/estimator/independent

runs the independent judge instead (grip_tools.sim.independent.judge,
docs/independent-judge.md): CommonRoad's multi-body vehicle model, its own
sensors, the C builds configured from vehicle data only; writes
<out>/independent.md, independent.json, worst_runs.png and the fitted
tires. By default a reduced set (the BMW 320i parameter set, every
manoeuvre, dry / wet / snow: about 3 minutes on 2 cores), --full every
vehicle x manoeuvre x surface; --vehicles / --manoeuvres / --surfaces
narrow either.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

from grip_tools.logs import av21 as av21_log
from grip_tools.reference import est as est_ref, tir
from grip_tools.golden import est as golden_est
from grip_tools.paths import REPO_ROOT

DEG = 180.0 / math.pi
WHEELS = ("fl", "fr", "rl", "rr")
ROOT = REPO_ROOT
C_BINS = {a: os.path.join(ROOT, "build", f"{a}-gcc", "bin", "grip-replay") for a in ("float", "fixed")}
IN_COLS = ["wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle", "yaw_rate",
           "ax", "ay", "vehicle_speed", "brake_pressure_fl", "brake_pressure_fr", "brake_pressure_rl",
           "brake_pressure_rr"]
# fixed/float ratio: metrics and the float error below which no ratio is taken
# "sufficient excitation" (docs/estimator.md): a tire of the truth at the
# friction limit, EXC_LIMIT of its friction; EXC_START is the stricter onset
# reported beside it
EXC_START, EXC_LIMIT = 0.5, 0.9
RATIO_METRICS = (("beta_rms_deg", 0.05), ("beta_max_deg", 0.05), ("fy_front_rms_pct", 0.1),
                 ("fy_rear_rms_pct", 0.1), ("mu_err_1s", 0.01), ("mu_err_1s_lim", 0.01))


def read_csv(path):
    with open(path) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    names = lines[0].strip().split(",")
    arr = np.genfromtxt(lines[1:], delimiter=",", dtype=float)
    if arr.ndim == 1:
        arr = arr[None, :]
    return {n: arr[:, k] for k, n in enumerate(names)}


def sim_imu_latency():
    """The simulator's inertial-sensor latency, transport delay plus low-pass
    time constant of its yaw-rate channel (sim/sensors.py: 12 + 8 ms):
    what a sensor data sheet gives for grip_est_config_t.latency."""
    from grip_tools.sim import sensors
    ch = sensors.SensorConfig().channel("YawRate")
    return float(ch.delay + ch.tau)


def sim_steer_latency():
    """The simulator's steering-angle latency (sim/sensors.py: a 10 ms
    transport delay, no low-pass): grip_est_config_t.steer_latency."""
    from grip_tools.sim import sensors
    ch = sensors.SensorConfig().channel("SteeringAngle")
    return float(ch.delay + ch.tau)


def sim_resistance():
    """The simulator car's drag area, air density and rolling-resistance
    coefficient (sim vehicles.passenger; the tire's QSY1, the rolling
    resistance moment the simulator applies to each wheel): what a vehicle
    data sheet gives for grip_est_config_t.cda / air_density / crr."""
    from grip_tools.sim import vehicles
    veh = vehicles.passenger()
    qsy1 = tir.read_tir(golden_est.tire_path()).get("ROLLING_COEFFICIENTS", "QSY1")
    return dict(cda=float(veh.cda), air_density=float(veh.rho), crr=float(qsy1))


# estimator settings every run of this invocation adds (--bank-est: {"bank_est": 1}; --no-bank-est: {"bank_est": 0})
EXTRA = {}
# the estimator switches that est-eval's options (--bank-est, ...) put in EXTRA
EXTRA_OPTIONS = ("bank_est", "stiff_est", "roll_est")


def est_vehicle():
    """The estimator settings for the simulator's runs beyond the passenger
    car of est_ref.config / grip-replay's `generic`: the simulator's IMU
    and steering-angle latencies and its car's drag and rolling resistance. (The simulator sends
    no vehicle-speed signal, so speed_ref_mu stays 0: the longitudinal mu
    update runs only while braking with a wheel at 15 % slip or more.)
    Plus EXTRA."""
    return dict(latency=sim_imu_latency(), steer_latency=sim_steer_latency(), **sim_resistance(), **EXTRA)


def est_config():
    """est_ref's configuration for the simulator's runs (PacejkaBook_Defaults,
    100 Hz, est_vehicle())."""
    return est_ref.config(golden_est.tire_params(), rate_hz=100, **est_vehicle())


def est_vehicle_lines():
    """est_vehicle() as grip-replay vehicle-file lines."""
    return [f"{k} = {v!r}" for k, v in est_vehicle().items()]


def estimate(run_dir):
    """Runs est_ref over a run's sensors.csv; returns time and arrays."""
    cols = read_csv(os.path.join(run_dir, "sensors.csv"))
    t, value, valid = est_ref.inputs_from_sensors(cols)
    outs = est_ref.run(est_config(), value, valid)
    res = {"time": t}
    res["beta"] = np.array([o["beta"] for o in outs])
    res["mu"] = np.array([o["mu"] for o in outs])
    res["mu_conf"] = np.array([o["mu_conf"] for o in outs])
    res["fyf"] = np.array([o["fy_axle"][0] for o in outs])
    res["fyr"] = np.array([o["fy_axle"][1] for o in outs])
    res["valid"] = np.array([o["valid"] for o in outs], dtype=np.int64)
    res["vx"] = np.array([o["vx"] for o in outs])
    res["beta_sd"] = np.array([o["beta_sd"] for o in outs])
    res["flags"] = np.array([o["flags"] for o in outs], dtype=np.int64)
    return res


def write_input_csv(path, t, value, valid):
    """The estimator's inputs as grip-replay --csv reads them (one row per
    step, an empty cell where the input is not valid)."""
    with open(path, "w") as f:
        f.write(",".join(["t_s"] + IN_COLS) + "\n")
        for k in range(len(t)):
            cells = [repr(float(t[k]))]
            for i in range(len(IN_COLS)):
                cells.append(repr(float(value[k, i])) if valid[k, i] else "")
            f.write(",".join(cells) + "\n")


def read_replay(text):
    """grip-replay's output CSV (estimator columns) -> the arrays estimate() returns."""
    import io
    import pyarrow as pa
    import pyarrow.csv as pcsv
    want = {"t_s": "time", "beta": "beta", "mu": "mu", "mu_conf": "mu_conf", "fy_front": "fyf", "fy_rear": "fyr",
            "vx": "vx", "yaw_rate": "yaw_rate", "yaw_rate_ref": "yaw_rate_ref", "yaw_rate_bias": "yaw_rate_bias",
            "ay_model": "ay_model", "est_status": "est_status", "beta_sd": "beta_sd", "mu_sd": "mu_sd",
            "vx_sd": "vx_sd", "fy_front_sd": "fyf_sd", "fy_rear_sd": "fyr_sd"}
    # only the estimator's columns, as float64 (an empty cell is NaN) and
    # the two bit masks as int64; the input and fault columns are not read
    types = {k: pa.float64() for k in want}
    types.update(est_valid=pa.int64(), est_flags=pa.int64())
    tab = pcsv.read_csv(io.BytesIO(text.encode()), read_options=pcsv.ReadOptions(use_threads=False),
                        convert_options=pcsv.ConvertOptions(column_types=types, include_columns=list(types)))
    out = {v: tab.column(k).to_numpy(zero_copy_only=False).astype(float) for k, v in want.items()}
    out["valid"] = tab.column("est_valid").to_numpy(zero_copy_only=False).astype(np.int64)
    out["flags"] = tab.column("est_flags").to_numpy(zero_copy_only=False).astype(np.int64)
    out["fy_axle"] = np.column_stack([out["fyf"], out["fyr"]])
    out["fy_axle_sd"] = np.column_stack([out["fyf_sd"], out["fyr_sd"]])
    return out


def run_c(binary, tir_path, csv_path, vehicle="generic", vehicle_lines=(), step_ms=10.0, extra_args=()):
    """Runs grip-replay -e TIR --csv over csv_path (extra_args: more options,
    e.g. --learned-in F); returns read_replay's dict."""
    with tempfile.TemporaryDirectory() as d:
        args = [binary, "-q", "-e", tir_path, "--vehicle", vehicle, "--step-ms", repr(step_ms)] + list(extra_args)
        args += ["--csv", csv_path]
        if vehicle_lines:
            vf = os.path.join(d, "vehicle.txt")
            with open(vf, "w") as f:
                f.write("\n".join(vehicle_lines) + "\n")
            args[-2:-2] = ["--vehicle-file", vf]
        p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(args)}: exit {p.returncode}: {p.stderr.strip()}")
    return read_replay(p.stdout)


# grip-replay's --vehicle presets (port/linux/vehicle_config.c, vehicle_preset)
# beyond grip_est_config_default ("generic"), for the binding
VEHICLE_PRESETS = {"generic": {}}


def binding_available():
    """None when `import grip` (the C library compiled into Python) works,
    else why not."""
    try:
        import grip  # noqa: F401
        grip.mf.coefficients("float")
    except (ImportError, OSError) as e:
        return f"the Python binding is not built ({e}); `make setup` builds it"
    return None


def c_builds(specs=()):
    """The C estimator builds to run: ({arith: spec}, notes). By default the
    binding, float and fixed (spec ("binding", arith)); ARITH=PATH in specs:
    the grip-replay program PATH for that arithmetic instead (spec
    ("program", PATH)), skipped with a note when absent."""
    builds, notes = {}, []
    why = binding_available()
    for a in ("float", "fixed"):
        if why is None:
            builds[a] = ("binding", a)
        else:
            notes.append(f"C {a} build skipped: {why}")
    for spec in specs:
        k, _, v = spec.partition("=")
        if os.path.exists(v):
            builds[k] = ("program", v)
        else:
            builds.pop(k, None)
            notes.append(f"C {k} build skipped: {v} does not exist")
    return builds, notes


def run_binding(arith, tir_path, t, value, valid, vehicle="generic", vehicle_values=None, step_ms=10.0,
                learned=None, keep_learned=False, keep_out=False, friction=()):
    """The C estimator of `arith` through the binding (grip.est.Estimator
    over samples built as grip-replay's --csv mode builds them), configured
    as grip-replay -e TIR --vehicle VEHICLE --vehicle-file (vehicle_values:
    {key: SI value}) --step-ms STEP_MS, starting from the learned blob
    `learned` (grip_est_learned_set) when given; returns read_replay's
    dict, at full precision (grip-replay prints %.6g), and with
    keep_learned under "learned" grip.est.Estimator.learned() at the end;
    with keep_out under "out" every output column of the binding (per-wheel
    fx, fy, mz, the road-wheel angle delta, ...). friction: grip.est.Estimator.step's
    road-friction measurements, (step, mu_road, mu_road_sd) rows."""
    import grip
    tyre = grip.mf.load(tir_path)
    cfg = {"tire": tyre, "rate_hz": int(round(1000.0 / step_ms))}
    cfg.update(VEHICLE_PRESETS[vehicle])
    cfg.update(vehicle_values or {})
    est = grip.est.Estimator(cfg, arith=arith)
    if learned is not None:
        est.learned_set(learned)
    cols = {c: np.where(valid[:, i] != 0, value[:, i], np.nan) for i, c in enumerate(IN_COLS)}
    o = est.step(grip.signals.Samples.from_columns(cols, t_s=np.asarray(t, np.float64)), friction=friction)
    # grip-replay's ay_model column: the tire model's sum Fy / m in the body
    # frame (the front wheels' forces turned by the road-wheel angle), where
    # the axle forces are valid
    d = o["delta"]
    fyb = (o["fx"][:, 0] + o["fx"][:, 1]) * np.sin(d) + (o["fy"][:, 0] + o["fy"][:, 1]) * np.cos(d) \
        + o["fy"][:, 2] + o["fy"][:, 3]
    mass = float(est.config["mass"])
    ay_model = np.where((o["valid"] & est_ref.V_AXLE) != 0, fyb / mass, np.nan)
    return {"time": np.asarray(t, np.float64), "beta": o["beta"], "mu": o["mu"], "mu_conf": o["mu_conf"],
            "fyf": o["fy_axle"][:, 0], "fyr": o["fy_axle"][:, 1], "vx": o["vx"], "yaw_rate": o["yaw_rate"],
            "yaw_rate_ref": o["yaw_rate_ref"], "yaw_rate_bias": o["yaw_rate_bias"], "ay_model": ay_model,
            "est_status": np.asarray(o["status"], np.float64),
            "valid": np.asarray(o["valid"], np.int64), "flags": np.asarray(o["flags"], np.int64),
            **({"learned": est.learned()} if keep_learned else {}), **({"out": o} if keep_out else {})}


def run_est(build, tir_path, t, value, valid, vehicle="generic", vehicle_values=None, step_ms=10.0, learned=None,
            keep_learned=False):
    """One C build (a c_builds() spec) over the inputs; read_replay's dict.
    learned: a grip_est_learned_t blob to start from; keep_learned: what was
    learned at the end under "learned" (the binding only)."""
    kind, what = build
    if kind == "binding":
        return run_binding(what, tir_path, t, value, valid, vehicle, vehicle_values, step_ms, learned, keep_learned)
    if learned is not None or keep_learned:
        raise ValueError("a learned blob needs the binding (grip.est), not a grip-replay program")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "inputs.csv")
        write_input_csv(path, t, value, valid)
        lines = [f"{k} = {v!r}" for k, v in (vehicle_values or {}).items()]
        return run_c(what, tir_path, path, vehicle=vehicle, vehicle_lines=lines, step_ms=step_ms)


def estimate_c(run_dir, bins):
    """The C builds over a run's sensors.csv, inputs exactly as est_ref gets
    them; {arith: est dict}; builds not in bins (c_builds()) are absent."""
    if not bins:
        return {}
    cols = read_csv(os.path.join(run_dir, "sensors.csv"))
    t, value, valid = est_ref.inputs_from_sensors(cols)
    # as estimate(): the simulator car's latency, drag and rolling resistance
    return {a: run_est(b, golden_est.tire_path(), t, value, valid, vehicle_values=est_vehicle())
            for a, b in bins.items()}


def fixed_float_ratio(rf, rx):
    """Largest fixed/float error ratio over RATIO_METRICS (float error >= floor)."""
    worst, which = None, None
    for k, floor in RATIO_METRICS:
        ef, ex = rf.get(k), rx.get(k)
        if ef is None or ex is None or ef < floor:
            continue
        q = ex / ef
        if worst is None or q > worst:
            worst, which = q, k
    return worst, which


def evaluate(run_dir, est):
    tr = read_csv(os.path.join(run_dir, "truth.csv"))
    t = est["time"]

    def at(name):
        return np.interp(t, tr["time"], tr[name])

    beta_t = at("beta")
    vx_t = at("vx")
    mu_t = np.mean([at(f"mu_road_{w}") for w in WHEELS], axis=0)
    fyf_t = at("fy_fl") + at("fy_fr")
    fyr_t = at("fy_rl") + at("fy_rr")
    util_t = _truth_utilization(at)
    ok = ((est["valid"] & est_ref.V_BETA) != 0) & (vx_t > 5.0)
    r = {"rows": int(len(t)), "valid_rows": int(ok.sum())}
    if ok.sum() == 0:
        return r
    e = (est["beta"] - beta_t)[ok] * DEG
    r["beta_rms_deg"] = float(np.sqrt(np.mean(e ** 2)))
    r["beta_max_deg"] = float(np.max(np.abs(e)))
    r["beta_true_max_deg"] = float(np.max(np.abs(beta_t[ok])) * DEG)
    # the axle forces over the rows their own bit (V_AXLE) vouches for, as
    # the independent judge counts them (V_BETA further needs beta's bound)
    ok_a = ((est["valid"] & est_ref.V_AXLE) != 0) & (vx_t > 5.0)
    for name, est_f, tru_f in (("front", est["fyf"], fyf_t), ("rear", est["fyr"], fyr_t)):
        peak = float(np.max(np.abs(tru_f[ok_a]))) if ok_a.any() else 0.0
        rms = float(np.sqrt(np.mean((est_f - tru_f)[ok_a] ** 2))) if ok_a.any() else 0.0
        r[f"fy_{name}_peak_N"] = peak
        # a straight run (peak below 200 N) has no meaningful percentage
        r[f"fy_{name}_rms_pct"] = 100.0 * rms / peak if peak >= 200.0 else None
        r[f"fy_{name}_rms_N"] = rms
    r["mu_true_end"] = float(mu_t[-1])
    r["mu_est_end"] = float(est["mu"][-1])
    for suffix, u_exc in (("", EXC_START), ("_lim", EXC_LIMIT)):
        r.update(_mu_after(t, util_t, vx_t, est, mu_t, u_exc, suffix))
    return r


def _truth_utilization(at):
    """Largest friction utilization of the truth's four tires at each time
    (at(name): the truth column on the evaluation's time grid)."""
    util_t = 0.0
    for w in WHEELS:
        fz = np.maximum(at(f"fz_{w}"), 1.0)
        peak = np.maximum(np.maximum(at(f"mux_{w}"), at(f"muy_{w}")), 1e-3)
        util_t = np.maximum(util_t, np.hypot(at(f"fx_{w}"), at(f"fy_{w}")) / (peak * fz))
    return util_t


def _onset(t, util_t, vx_t, u_exc):
    """First time a tire of the truth uses u_exc of its friction above
    5 m/s ("sufficient excitation"), or None."""
    exc = np.nonzero((util_t >= u_exc) & (vx_t > 5.0))[0]
    return float(t[exc[0]]) if len(exc) else None


def limit_onset(run_dir, t, u_exc=EXC_LIMIT):
    """The friction-limit onset of a simulator run (evaluate's mu_t0_lim)
    on the time grid t, from the truth alone."""
    tr = read_csv(os.path.join(run_dir, "truth.csv"))

    def at(name):
        return np.interp(t, tr["time"], tr[name])

    return _onset(t, _truth_utilization(at), at("vx"), u_exc)


def _mu_after(t, util_t, vx_t, est, mu_t, u_exc, suffix):
    """mu error, confidence and share within 0.1 one second after the first
    time a tire of the truth uses u_exc of its friction (keys end in suffix)."""
    r = {}
    t0 = _onset(t, util_t, vx_t, u_exc)
    if t0 is None:
        r["mu_t0" + suffix] = None
        return r
    k1 = int(np.searchsorted(t, t0 + 1.0))
    r["mu_t0" + suffix] = t0
    if k1 < len(t):
        r["mu_err_1s" + suffix] = float(abs(est["mu"][k1] - mu_t[k1]))
        r["mu_conf_1s" + suffix] = float(est["mu_conf"][k1])
        after = slice(k1, len(t))
        r["mu_within_0p1_pct" + suffix] = float(100.0 * np.mean(np.abs(est["mu"][after] - mu_t[after]) <= 0.1))
    return r


def simulate_runs(outdir, manoeuvres, surfaces):
    """Runs the simulator (grip simulate) for each pair into
    outdir/runs (kept: a run already there is reused)."""
    from grip_tools.sim import cli
    dirs = []
    for m in manoeuvres:
        for s in surfaces:
            d = os.path.join(outdir, "runs", f"{m}_{s}")
            if not os.path.exists(os.path.join(d, "sensors.csv")):
                cli.main(["-m", m, "-s", s, "-o", d, "--no-plot"])
            dirs.append(d)
    return dirs


def table(results):
    hdr = ("| run | beta RMS [deg] | beta max [deg] | |beta| true max | mu true | mu est (end) "
           "| mu err @ t0+1 s (limit 90 % / onset 50 %) | mu within 0.1 after t0+1 s (90 % / 50 %) "
           "| conf @ t0+1 s (90 % / 50 %) | Fy front RMS [% peak] | Fy rear RMS [% peak] |")
    lines = [hdr, "|" + "---|" * 11]

    def f(x, fmt):
        return "-" if x is None else format(x, fmt)

    def pct(x):
        return "-" if x is None else format(x, ".0f") + " %"

    for name, r in results.items():
        lines.append("| " + " | ".join([
            name, f(r.get("beta_rms_deg"), ".2f"), f(r.get("beta_max_deg"), ".2f"),
            f(r.get("beta_true_max_deg"), ".1f"), f(r.get("mu_true_end"), ".2f"), f(r.get("mu_est_end"), ".2f"),
            f(r.get("mu_err_1s_lim"), ".2f") + " / " + f(r.get("mu_err_1s"), ".2f"),
            pct(r.get("mu_within_0p1_pct_lim")) + " / " + pct(r.get("mu_within_0p1_pct")),
            f(r.get("mu_conf_1s_lim"), ".2f") + " / " + f(r.get("mu_conf_1s"), ".2f"), f(r.get("fy_front_rms_pct"), ".1f"), f(r.get("fy_rear_rms_pct"), ".1f")]) + " |")
    return "\n".join(lines) + "\n"


def table_c(results, c_results, notes):
    """beta / Fy / mu errors of est_ref, the C float build and the C fixed
    build per run, and the fixed/float ratio."""
    builds = [a for a in ("float", "fixed") if any(a in c for c in c_results.values())]
    hdr = ["run", "beta RMS [deg] ref / " + " / ".join(builds), "beta max [deg]",
           "Fy front RMS [% peak]", "Fy rear RMS [% peak]", "mu err @ t0+1 s (90 %)", "mu err @ t0+1 s (50 %)",
           "fixed/float (worst metric)",
           "max abs(C - est_ref) beta [rad] / mu, " + " / ".join(builds)]
    lines = ["| " + " | ".join(hdr) + " |", "|" + "---|" * len(hdr)]

    def f(x, fmt):
        return "-" if x is None else format(x, fmt)
    for name, r in results.items():
        c = c_results.get(name, {})
        rs = [r] + [c.get(a, {}) for a in builds]
        cells = [name]
        for k, fmt in (("beta_rms_deg", ".3f"), ("beta_max_deg", ".3f"), ("fy_front_rms_pct", ".2f"),
                       ("fy_rear_rms_pct", ".2f"), ("mu_err_1s_lim", ".3f"), ("mu_err_1s", ".3f")):
            cells.append(" / ".join(f(x.get(k), fmt) for x in rs))
        if "float" in c and "fixed" in c:
            q, which = fixed_float_ratio(c["float"], c["fixed"])
            cells.append("-" if q is None else f"{q:.3f} ({which})")
        else:
            cells.append("-")
        cells.append(", ".join(f"{f(c[a].get('dev_beta_max_rad'), '.1e')} / {f(c[a].get('dev_mu_max'), '.1e')}"
                               for a in builds if a in c))
        lines.append("| " + " | ".join(cells) + " |")
    out = "\n".join(lines) + "\n"
    if notes:
        out += "\n" + "\n".join(f"Note: {n}" for n in notes) + "\n"
    return out


# ---------------------------------------------------------------------------
# Real data: the Dallara AV-21 on the Putnam Park road course

AV21_RATE_HZ = 100
# No .tir exists for the AV-21's slicks: the stand-in is PacejkaBook_Defaults
# with its nominal load moved to the car's static wheel load (LFZO = 0.5:
# Fz0' = 2000 N; static loads 2253 N front, 1622 N rear) and its friction
# raised to a dry racing slick's (LMUX = LMUY = 1.5, an assumption).
AV21_STANDIN = {"LFZO": "0.5", "LMUX": "1.5", "LMUY": "1.5"}
# grip-replay's `--vehicle av21` preset (port/linux/vehicle_config.c) as est_ref
# configuration keys (tests/python/programs/test_grip_replay_csv.py checks the two agree);
# steer_lag is the value steer_lag_fit identified on the log
AV21_VEHICLE = dict(mass=av21_log.MASS, iz=1000.0, lf=av21_log.LF, lr=av21_log.LR, track_f=1.6, track_r=1.6, h_cg=0.30,
                    steer_ratio=1.0, wheel_radius=0.30, roll_split_front=0.5, roll_gradient=0.001,
                    steer_lag=0.28)
# grip-replay --vehicle av21 (port/linux/vehicle_config.c), for the binding
VEHICLE_PRESETS["av21"] = AV21_VEHICLE


def av21_standin_tir(path):
    """Writes the stand-in .tir (PacejkaBook_Defaults with AV21_STANDIN)."""
    import re
    with open(golden_est.tire_path()) as f:
        text = f.read()
    for k, v in AV21_STANDIN.items():
        text, n = re.subn(rf"(?m)^({k}\s*=\s*)\S+", lambda m: m.group(1) + v, text)
        if n != 1:
            raise RuntimeError(f"stand-in tire: {k} not found once in {golden_est.tire_path()}")
    with open(path, "w") as f:
        f.write("$ grip stand-in for the Dallara AV-21 (no .tir published): PacejkaBook_Defaults with "
                + ", ".join(f"{k} = {v}" for k, v in AV21_STANDIN.items()) + " (tools/grip_tools/evaluate/est_eval.py)\n")
        f.write(text)


def av21_inputs(log):
    """The AV-21 log (25 Hz) as estimator inputs at AV21_RATE_HZ (linear
    interpolation): wheel speeds [m/s], delta (the steering signal, fed
    with steer ratio 1), omega (yaw rate), ax, vehicle speed = the INS vx,
    and the lateral acceleration at the CG (av21_log.lateral_at_cg; vy in
    the log's own sign, av21_log's docstring says why).
    Returns t, value (N, 13 IN_COLS), valid and the INS arrays (vy at the
    CG about the car's axis: the INS's heading misalignment INS_YAW
    removed; ins_x, ins_yaw)."""
    d = av21_log.read(log)
    t, vx, r = d["t"], d["vx"], d["r"]
    ws = d["ws"]
    vy, ay, x_ins = av21_log.lateral_at_cg(t, vx, d["vy"], r)
    cols = [ws[:, 0], ws[:, 1], ws[:, 2], ws[:, 3], d["delta"], r, d["ax"], ay, vx]
    tg = np.arange(0.0, t[-1], 1.0 / AV21_RATE_HZ)
    value = np.zeros((len(tg), len(IN_COLS)))
    valid = np.zeros((len(tg), len(IN_COLS)), dtype=np.uint8)
    for i, c in enumerate(cols):
        value[:, i] = np.interp(tg, t, c)
        valid[:, i] = 1
    # the truth about the car's axis: the INS's heading misalignment
    # (av21_log.INS_YAW, measured on the full log's straights) removed from
    # its vy; the inputs above keep the log's own
    vy_axis = vy - vx * np.tan(av21_log.INS_YAW)
    ins = {"vx": np.interp(tg, t, vx), "vy": np.interp(tg, t, vy_axis), "r": value[:, 5], "ay": value[:, 7],
           "ins_x": x_ins, "ins_yaw": av21_log.INS_YAW}
    return tg, value, valid, ins


def steer_lag_fit(t, delta, vx, yaw, ay, cfg, lags=None, ay_max=4.0):
    """Identifies the lag of the road wheels behind a logged steering signal
    (the estimator's `steer_lag`): the configured car's linear bicycle model
    (est_ref's cornering stiffnesses at static load, mass, yaw inertia, axle
    distances) is driven by the steering signal lagged by each candidate
    first-order time constant; the lag whose yaw rate best matches the
    measured one (least squares over the linear range: vx > 8 m/s,
    |ay| < ay_max) wins, refined by a parabola through its neighbours.
    Returns dict(lag, rms, rms_no_lag, gain (least-squares yaw gain at that
    lag: < 1 means the car understeers more than configured), n, lags, rms_all)."""
    if lags is None:
        lags = np.arange(0.0, 0.5001, 0.025)
    lags = np.asarray(lags, float)
    e = est_ref.Estimator(cfg)
    m, iz, lf, lr = cfg["mass"], cfg["iz"], cfg["lf"], cfg["lr"]
    cf, cr = 2.0 * e.c_alpha[0], 2.0 * e.c_alpha[1]
    dt = np.diff(t, prepend=t[0] - (t[1] - t[0]))
    nl = len(lags)
    dl = np.full(nl, float(delta[0]))
    vy, r = np.zeros(nl), np.zeros(nl)
    rb = np.zeros((len(t), nl))
    sub = 4
    for i in range(len(t)):
        h = dt[i]
        k = np.where(lags > 0.0, np.minimum(h / np.maximum(lags, 1e-9), 1.0), 1.0)
        dl += k * (delta[i] - dl)
        v = vx[i]
        if v < 5.0:
            vy[:], r[:] = 0.0, 0.0
        else:
            hs = h / sub
            for _ in range(sub):
                fyf = cf * (dl - (vy + lf * r) / v)
                fyr = -cr * (vy - lr * r) / v
                vy += hs * ((fyf + fyr) / m - r * v)
                r += hs * ((lf * fyf - lr * fyr) / iz)
        rb[i] = r
    sel = (vx > 8.0) & (np.abs(ay) < ay_max)
    rms_all = np.sqrt(np.mean((rb[sel] - yaw[sel, None]) ** 2, axis=0))
    j = int(np.argmin(rms_all))
    lag = float(lags[j])
    if 0 < j < nl - 1:
        y0, y1, y2 = rms_all[j - 1], rms_all[j], rms_all[j + 1]
        den = y0 - 2.0 * y1 + y2
        if den > 0.0:
            lag += 0.5 * (y0 - y2) / den * (lags[j + 1] - lags[j])
    gain = float(np.sum(yaw[sel] * rb[sel, j]) / np.sum(rb[sel, j] ** 2))
    return {"lag": float(lag), "rms": float(rms_all[j]), "rms_no_lag": float(rms_all[0]) if lags[0] == 0.0 else None,
            "gain": gain, "n": int(sel.sum()), "lags": [float(x) for x in lags],
            "rms_all": [float(x) for x in rms_all]}


def _stats(a, b):
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < 3:
        return {"n": int(ok.sum())}
    a, b = a[ok], b[ok]
    return {"n": int(ok.sum()), "corr": float(np.corrcoef(a, b)[0, 1]), "rms": float(np.sqrt(np.mean((a - b) ** 2))),
            "mean_diff": float(np.mean(a - b)), "max_abs_diff": float(np.max(np.abs(a - b)))}


def av21_bicycle_beta(t, value, ins, cfg):
    """The linear single-track baseline: the steady-state sideslip of the
    configured car (mass, axle distances, the stand-in tire's cornering
    stiffness at the static axle loads) from the logged steering command
    lagged by the preset's steer_lag (first order) and the INS speed: the
    independent judge's baseline formula (judge.bicycle_beta)."""
    from grip_tools.sim.independent import judge
    est = est_ref.Estimator(cfg)
    bp = dict(m=cfg["mass"], lf=cfg["lf"], lr=cfg["lr"], cf=2.0 * est.c_alpha[0], cr=2.0 * est.c_alpha[1])
    dt = float(np.median(np.diff(t)))
    a = min(1.0, dt / AV21_VEHICLE["steer_lag"])
    d = np.zeros(len(t))
    for k in range(1, len(t)):
        d[k] = d[k - 1] + a * (value[k, 4] / cfg["steer_ratio"] - d[k - 1])
    return judge.bicycle_beta(bp, d, ins["vx"])


def av21_report(log, outdir, bins):
    """The C builds on the AV-21 log; writes av21.json and av21.png."""
    tir_path = os.path.join(outdir, "av21_standin.tir")
    av21_standin_tir(tir_path)
    t, value, valid, ins = av21_inputs(log)
    # the log's folder and name in the shared data, not this machine's path
    res = {"log": "/".join(os.path.normpath(log).split(os.sep)[-2:]), "rate_hz": AV21_RATE_HZ, "steps": int(len(t)), "tire": "av21_standin.tir",
           "standin": AV21_STANDIN, "builds": {}}
    # the logged angle is the steering command: how far the road wheels lag
    # it, identified with the configured car (the preset's steer_lag)
    cfg = est_ref.config(tir.load_params(tir_path), rate_hz=AV21_RATE_HZ, **dict(AV21_VEHICLE, steer_lag=0.0))
    fit = steer_lag_fit(t, value[:, 4], ins["vx"], value[:, 5], value[:, 7], cfg)
    res["steer_lag_fit"] = fit
    res["ins_x_m"] = ins["ins_x"]
    res["ins_yaw_deg"] = ins["ins_yaw"] * DEG
    print(f"est-eval av21: steering lag fit {fit['lag']:.3f} s (yaw rate RMS {fit['rms']:.4f} rad/s, "
          f"{fit['rms_no_lag']:.4f} without a lag, yaw gain {fit['gain']:.3f}, {fit['n']} samples); "
          f"preset steer_lag {AV21_VEHICLE['steer_lag']}", file=sys.stderr)
    beta_lin = av21_bicycle_beta(t, value, ins, cfg)
    outs = {}
    for a, b in bins.items():
        outs[a] = o = run_est(b, tir_path, t, value, valid, vehicle="av21", vehicle_values=dict(EXTRA),
                              step_ms=1000.0 / AV21_RATE_HZ, keep_learned=b[0] == "binding")
        learned = o.pop("learned", None)
        moving = ins["vx"] > 5.0
        num = [k for k in o if k not in ("valid", "flags")]
        finite = all(np.all(np.isfinite(o[k][~np.isnan(o[k])])) for k in num) and \
            all(np.all(np.isfinite(o[k])) for k in num if k != "ay_model")
        vb = (o["valid"] & est_ref.V_BETA) != 0
        vr = (o["valid"] & est_ref.V_YAW_REF) != 0
        va = (o["valid"] & est_ref.V_AXLE) != 0
        beta_ins = np.arctan2(ins["vy"], np.maximum(ins["vx"], 1e-3))
        flag_names = {"standstill": est_ref.F_STANDSTILL, "low_speed": est_ref.F_LOW_SPEED,
                      "wheel_lock": est_ref.F_WHEEL_LOCK, "wheel_spin": est_ref.F_WHEEL_SPIN,
                      "excited": est_ref.F_EXCITED, "saturated": est_ref.F_SATURATED,
                      "steer_limit": est_ref.F_STEER_LIMIT, "reset": est_ref.F_RESET,
                      "model_misfit": est_ref.F_MODEL_MISFIT}
        r = {"errors": int(np.sum(o["est_status"] < 0)), "all_finite": bool(finite),
             "moving_steps": int(moving.sum()),
             "valid_steps": {"beta": int(vb.sum()), "yaw_ref": int(vr.sum()), "axle": int(va.sum()),
                             "mu": int(np.sum((o["valid"] & est_ref.V_MU) != 0))},
             "flag_steps": {k: int(np.sum((o["flags"] & v) != 0)) for k, v in flag_names.items()},
             "yaw_ref_vs_measured": _stats(np.where(vr & moving, o["yaw_rate_ref"], np.nan), ins["r"]),
             "yaw_est_vs_measured": _stats(np.where(vb & moving, o["yaw_rate"], np.nan), ins["r"]),
             "ay_model_vs_measured": _stats(np.where(va & moving, o["ay_model"], np.nan), ins["ay"]),
             "beta_vs_ins": _stats(np.where(vb & (ins["vx"] > 10.0), o["beta"], np.nan) * DEG,
                                   np.where(ins["vx"] > 10.0, beta_ins, np.nan) * DEG),
             "beta_ins_max_deg": float(np.max(np.abs(beta_ins[ins["vx"] > 10.0])) * DEG),
             # the baselines over the same steps (V_BETA, vx > 10 m/s)
             "beta_zero_vs_ins": _stats(np.where(vb & (ins["vx"] > 10.0), 0.0, np.nan),
                                        np.where(ins["vx"] > 10.0, beta_ins, np.nan) * DEG),
             "beta_bicycle_vs_ins": _stats(np.where(vb & (ins["vx"] > 10.0), beta_lin, np.nan) * DEG,
                                           np.where(ins["vx"] > 10.0, beta_ins, np.nan) * DEG),
             # every step above 10 m/s, valid or not (what the flags do not decide), and beta = 0 there
             "beta_all_vs_ins": _stats(np.where(ins["vx"] > 10.0, o["beta"], np.nan) * DEG,
                                       np.where(ins["vx"] > 10.0, beta_ins, np.nan) * DEG),
             "beta_zero_all_vs_ins": _stats(np.where(ins["vx"] > 10.0, 0.0, np.nan),
                                            np.where(ins["vx"] > 10.0, beta_ins, np.nan) * DEG),
             "beta_est_max_deg": float(np.nanmax(np.abs(np.where(vb, o["beta"], np.nan))) * DEG),
             "yaw_rate_bias_end": float(o["yaw_rate_bias"][-1]),
             "yaw_rate_bias_range": [float(np.min(o["yaw_rate_bias"])), float(np.max(o["yaw_rate_bias"]))],
             "mu_end": float(o["mu"][-1]), "mu_range": [float(np.min(o["mu"][moving])),
                                                      float(np.max(o["mu"][moving]))],
             "mu_conf_max": float(np.max(o["mu_conf"])),
             }
        if learned is not None and (EXTRA.get("stiff_est") or EXTRA.get("roll_est")):
            r["learned"] = {k: learned[k] for k in ("k_front", "k_rear", "updates", "roll_gradient", "roll_updates")}
        res["builds"][a] = r
        print(f"est-eval av21 {a}: {json.dumps(r)}", file=sys.stderr)
    if "float" in outs and "fixed" in outs:
        f, x = outs["float"], outs["fixed"]
        res["fixed_vs_float"] = {k: float(np.nanmax(np.abs(f[k] - x[k])))
                                 for k in ("beta", "yaw_rate_ref", "mu", "ay_model", "vx")}
    with open(os.path.join(outdir, "av21.json"), "w") as fh:
        json.dump(res, fh, indent=1)
    if outs:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        o = outs.get("float", next(iter(outs.values())))
        fig, ax = plt.subplots(4, 1, figsize=(12, 10), sharex=True)
        ax[0].plot(t, ins["vx"], "k", lw=0.8, label="INS vx")
        ax[0].plot(t, o["vx"], "r", lw=0.8, label="estimate vx")
        ax[0].set_ylabel("speed [m/s]")
        ax[1].plot(t, ins["r"], "k", lw=0.8, label="measured")
        ax[1].plot(t, o["yaw_rate_ref"], "r", lw=0.8, label="bicycle reference")
        ax[1].set_ylabel("yaw rate [rad/s]")
        ax[2].plot(t, ins["ay"], "k", lw=0.8, label="vx r + dvy/dt (INS)")
        ax[2].plot(t, o["ay_model"], "r", lw=0.8, label="model sum Fy / m")
        ax[2].set_ylabel("ay [m/s^2]")
        ax[3].plot(t, np.degrees(np.arctan2(ins["vy"], np.maximum(ins["vx"], 1e-3))), "k", lw=0.8, label="INS")
        ax[3].plot(t, np.degrees(o["beta"]), "r", lw=0.8, label="estimate")
        ax[3].set_ylabel("sideslip [deg]")
        ax[3].set_ylim(-10, 10)
        ax[3].set_xlabel("time [s]")
        for a_ in ax:
            a_.grid(True, alpha=0.3)
            a_.legend(fontsize=7, loc="upper right")
        fig.suptitle("grip estimator (C float, grip-replay --csv) on the Dallara AV-21, Putnam Park run 4_2")
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, "av21.png"), dpi=80)
        plt.close(fig)
    return res


def plot(runs, ests, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(runs)
    fig, ax = plt.subplots(n, 3, figsize=(13, 2.2 * n), squeeze=False)
    for i, (d, est) in enumerate(zip(runs, ests)):
        tr = read_csv(os.path.join(d, "truth.csv"))
        name = os.path.basename(d.rstrip("/"))
        ax[i, 0].plot(tr["time"], tr["beta"] * DEG, "k", lw=1, label="truth")
        ax[i, 0].plot(est["time"], est["beta"] * DEG, "r", lw=1, label="estimate")
        ax[i, 0].set_ylabel(name, fontsize=7)
        mu_t = np.mean([tr[f"mu_road_{w}"] for w in WHEELS], axis=0)
        ax[i, 1].plot(tr["time"], mu_t, "k", lw=1)
        ax[i, 1].plot(est["time"], est["mu"], "r", lw=1)
        ax[i, 1].plot(est["time"], est["mu_conf"], "g:", lw=1, label="confidence")
        ax[i, 1].set_ylim(0, 1.3)
        ax[i, 2].plot(tr["time"], tr["fy_fl"] + tr["fy_fr"], "k", lw=1)
        ax[i, 2].plot(est["time"], est["fyf"], "r", lw=1)
        if i == 0:
            ax[i, 0].set_title("sideslip beta [deg]")
            ax[i, 1].set_title("mu (red), confidence (green)")
            ax[i, 2].set_title("front axle Fy [N]")
            ax[i, 0].legend(fontsize=6)
    for a in ax[-1]:
        a.set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip est-eval", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", nargs="*", default=[], help="simulator output directories")
    ap.add_argument("--simulate", action="store_true", help="run the standard manoeuvres first")
    ap.add_argument("--out", default="build/est_eval")
    ap.add_argument("--runs-dir", default=os.path.join(ROOT, "build", "est_eval"),
                    help="where --simulate writes (and reuses) the simulator runs (DIR/runs)")
    ap.add_argument("--c-bin", action="append", default=[], metavar="ARITH=PATH",
                    help="run this grip-replay program for ARITH instead of the binding (another build of "
                         "the C code)")
    ap.add_argument("--no-c", action="store_true", help="evaluate est_ref only")
    ap.add_argument("--stiff-est", action="store_true",
                    help="every run with the estimator's stiff_est = 1 (each axle's cornering stiffness learned "
                         "online, docs/estimator/stiffness.md)")
    ap.add_argument("--roll-est", action="store_true",
                    help="every run with the estimator's roll_est = 1 (the body's roll gradient learned online, "
                         "docs/estimator/roll.md)")
    ap.add_argument("--kx-est", action="store_true",
                    help="--independent: the learned configuration learns the longitudinal slip stiffness too "
                         "(kx_est = 1, the drive split from the vehicle's parameter set; "
                         "docs/estimator/stiffness.md)")
    ap.add_argument("--bank-est", action="store_true",
                    help="every run with the estimator's bank_est = 1 (the road's bank estimated, "
                         "docs/estimator/road.md); default the configuration's (the fitted one's 1, "
                         "the others' 0)")
    ap.add_argument("--no-bank-est", action="store_true",
                    help="every run with bank_est = 0, the fitted configuration's included")
    ap.add_argument("--av21", nargs="?", const=av21_log.LOG, default=None, metavar="LOG",
                    help="also run the C builds on the Dallara AV-21 log (default %(const)s): <out>/av21.json, "
                         "av21.png, av21_standin.tir")
    ap.add_argument("--independent", action="store_true",
                    help="the independent judge (CommonRoad multi-body model) instead: <out>/independent.md, .json")
    ap.add_argument("--full", action="store_true", help="--independent: every vehicle x manoeuvre x surface")
    ap.add_argument("--vehicles", nargs="+", help="--independent: only these vehicles")
    ap.add_argument("--manoeuvres", nargs="+", help="--independent: only these manoeuvres")
    ap.add_argument("--surfaces", nargs="+", help="--independent: only these surfaces")
    ap.add_argument("--integrity", action="store_true",
                    help="the validity flags' integrity on every judge (est_ref): <out>/integrity_table.md, .json")
    ap.add_argument("--judges", default=None,
                    help="--integrity: comma-separated subset of own, mismatch, independent, fitted, rav4, av21, faults "
                         "(default all)")
    ap.add_argument("--const", action="append", default=[], metavar="NAME=VALUE",
                    help="--integrity: an est_ref constant changed for the run (sensitivity: TIRE_TOL, KIN_ACC, ...)")
    ap.add_argument("--road-friction", type=float, default=None, metavar="SD",
                    help="--integrity: the independent simulator's runs get an outside road-friction source "
                         "(grip_est_measure_friction) of this standard deviation, once a second, one deviation "
                         "too high")
    a = ap.parse_args(argv)
    # an option outside its mode would be ignored without a word: refused
    for opt, given, ok, mode in (("--vehicles", a.vehicles, a.independent, "--independent"),
                                 ("--manoeuvres", a.manoeuvres, a.independent, "--independent"),
                                 ("--surfaces", a.surfaces, a.independent, "--independent"),
                                 ("--kx-est", a.kx_est, a.independent, "--independent"),
                                 ("--full", a.full, a.independent or a.integrity, "--independent or --integrity"),
                                 ("--judges", a.judges is not None, a.integrity, "--integrity"),
                                 ("--const", a.const, a.integrity, "--integrity"),
                                 ("--road-friction", a.road_friction is not None, a.integrity, "--integrity")):
        if given and not ok:
            ap.error(f"{opt}: only with {mode}")
    if a.independent and a.integrity:
        ap.error("--independent and --integrity: one at a time")
    if a.bank_est and a.no_bank_est:
        ap.error("--bank-est and --no-bank-est: one at a time")
    if a.judges is None:
        from grip_tools.evaluate import integrity
        a.judges = ",".join(integrity.JUDGES)
    EXTRA.clear()
    EXTRA.update({k: 1 for k in EXTRA_OPTIONS if getattr(a, k)})
    if a.no_bank_est:
        EXTRA["bank_est"] = 0
    if a.integrity:
        from grip_tools.evaluate import integrity
        judges = [j for j in a.judges.split(",") if j]
        err = integrity.option_error(judges, a.const)
        if err:
            ap.error(err)
        if a.road_friction is not None and not 0.01 <= a.road_friction <= 1.0:
            ap.error(f"--road-friction {a.road_friction}: a standard deviation in [0.01, 1]")
        integrity.run(a.out, judges=judges, runs_dir=a.runs_dir, full=a.full, av21_log=a.av21, consts=a.const,
                      road_friction_sd=a.road_friction)
        return 0
    if a.independent:
        from grip_tools.sim.independent import judge
        err = judge.selection_error(a.vehicles, a.manoeuvres, a.surfaces)
        if err:
            ap.error(err)
        judge.run(a.out, full=a.full, vehicles=a.vehicles, manoeuvres=a.manoeuvres, surfaces=a.surfaces,
                  c_bins=a.c_bin, vehicle_extra=dict(EXTRA), learn_kx=a.kx_est)
        return 0
    os.makedirs(a.out, exist_ok=True)
    runs = list(a.runs)
    if a.simulate:
        runs += simulate_runs(a.runs_dir, ("step-steer", "ramp-steer", "sine-dwell", "brake-in-turn", "mu-step"),
                              ("dry", "wet", "snow"))
    bins, notes = {}, []
    if not a.no_c:
        bins, notes = c_builds(a.c_bin)
        for n in notes:
            print(f"est-eval: {n}", file=sys.stderr)
    results, c_results, ests = {}, {}, []
    for d in runs:
        name = os.path.basename(d.rstrip("/"))
        est = estimate(d)
        ests.append(est)
        results[name] = evaluate(d, est)
        c_ests = estimate_c(d, bins)
        c_results[name] = {k: evaluate(d, e) for k, e in c_ests.items()}
        for k, e in c_ests.items():
            # how far the C build is from est_ref on the same inputs
            c_results[name][k]["dev_beta_max_rad"] = float(np.max(np.abs(e["beta"] - est["beta"])))
            c_results[name][k]["dev_mu_max"] = float(np.max(np.abs(e["mu"] - est["mu"])))
        if "float" in c_results[name] and "fixed" in c_results[name]:
            q, which = fixed_float_ratio(c_results[name]["float"], c_results[name]["fixed"])
            c_results[name]["fixed_float_ratio"] = q
            c_results[name]["fixed_float_ratio_metric"] = which
        print(f"est-eval: {d}: {results[name]}", file=sys.stderr)
    # the simulator tables only when there are runs (--av21 alone must not
    # overwrite them with empty ones)
    if runs:
        with open(os.path.join(a.out, "accuracy.json"), "w") as f:
            json.dump({"est_ref": results, "c": c_results, "notes": notes}, f, indent=1)
        md = "## float64 reference (est_ref)\n\n" + table(results)
        if bins:
            md += ("\n## C builds (the C library through grip.est) next to est_ref\n\n"
                   "Each cell: est_ref / C float / C fixed (errors against the simulator's truth).\n\n"
                   + table_c(results, c_results, notes))
        elif notes:
            md += "\n" + "\n".join(f"Note: {n}" for n in notes) + "\n"
        with open(os.path.join(a.out, "accuracy.md"), "w") as f:
            f.write(md)
        print(md)
        plot(runs, ests, os.path.join(a.out, "accuracy.png"))
    if a.av21:
        if not bins:
            print("est-eval: --av21 needs a C build", file=sys.stderr)
        else:
            av21_report(a.av21, a.out, bins)
    return 0


if __name__ == "__main__":
    sys.exit(main())
