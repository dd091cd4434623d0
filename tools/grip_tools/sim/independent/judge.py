"""The independent judge: the estimator's C builds on CommonRoad's multi-body model.

    grip est-eval --independent [--full] [--out docs/estimator/independent]

Per vehicle x manoeuvre x surface: the multi-body model flies the
manoeuvre (mb, manoeuvres), the sensor cluster samples it (sensors), and
both C builds (float and fixed, through the binding grip.est) run over the samples in
two configurations an OEM could have:

  generic  vehicle data only: mass, yaw inertia, axle distances, tracks, CG
           height, wheel radius from the parameter set, steering ratio and
           the sensors' data-sheet latencies; no drag or rolling resistance
           (the model has none); tire tests/data/mfeval-tir/
           PacejkaBook_Defaults.tir; everything else grip_est_config_default
  fitted   the same, plus what a constant-speed ramp steer and a straight
           braking run on dry asphalt with wheel-force transducers give
           (characterize): the lateral and longitudinal Magic Formula groups
           fitted with `grip fit-mf --model fy` / `--model fx` (start
           PacejkaBook_Defaults, its other groups kept), the roll gradient
           and the front share of the lateral load transfer; the tire
           declared as fitted to the car (tire_tol FITTED_TIRE_TOL, the
           calibration of docs/estimator/integrity.md) and the road's bank
           estimated (bank_est = 1, what docs/estimator/road.md asks of a
           tire fitted to the car; est-eval --no-bank-est: without it)
  learned  generic, with the estimator's online stiffness and roll-gradient
           learning on (stiff_est = 1, roll_est = 1) and starting from what it learned in 90 s of
           ordinary driving on a dry road (learn: the learning drive, its
           grip_est_learned_t blob restored at every run's start, as after
           an ignition cycle); needs the binding. With learn_kx (est-eval
           --kx-est) also the longitudinal slip stiffness (kx_est = 1, the
           drive split from the parameter set's T_se), learned on a further
           64 s of straight driving with traction, rolling and braking

Metrics (metrics()), "moving" = true vx >= 3 m/s (the estimator's own
switch-on speed), "spin" = from the first moving step where the true
sideslip departs from the kinematic one atan(lr tan(delta) / l) by more
than 10 deg, to the end of the run:
  beta       RMS and max |beta_est - beta_true| over the moving steps the
             estimator flags V_BETA
  valid      share of the moving steps outside a spin flagged V_BETA
  vx         RMS and max |vx_est - vx_true| over the moving steps flagged V_VX
  mu         |mu_est - mu_true| at t0 + 1 s, t0 the first moving (> 5 m/s)
             step where a tire of the truth uses 90 % of its friction
             (est_eval's "limit" onset); mu_true = the road's friction factor
             x the model tire's lateral peak / the configured tire's lateral
             peak at the vehicle's mean static wheel load (the estimate's mu
             scales the configured tire's friction)
  Fy         RMS of the front / rear axle lateral force error (wheel frame)
             over the moving steps flagged V_AXLE, in % of the run's peak
             |Fy| of that axle (none below 200 N)
Baselines, over the same steps as the estimator's beta:
  beta = 0   the error is the true sideslip
  bicycle    steady-state linear single-track sideslip from the measured
             steering-wheel angle / ratio and the mean wheel speed, with the
             configured mass and axle distances and PacejkaBook_Defaults'
             cornering stiffness at the configured static axle loads
Targets: beta RMS <= 0.5 deg and max <= 1.5 deg; valid on >= 90 % of
moving steps outside spins; beta RMS no worse than the better baseline;
|mu error| <= 0.1 one second after the limit; axle Fy RMS <= 5 % of peak
(the worse axle). A target that does not apply to a run (no valid beta
step, limit never reached, no lateral force) is "-" and not counted.
"""
import argparse
import json
import math
import os
import re
import sys
import time
import zlib

import numpy as np

from grip_tools.evaluate import est_eval
from grip_tools.golden import est as golden_est
from grip_tools.paths import REPO_ROOT
from grip_tools.reference import est as est_ref, mf, tir
from grip_tools.sim.independent import mb, manoeuvres as man_mod, sensors

DEG = 180.0 / math.pi
V_MOVING = 3.0
SPIN_DEG = 10.0
FY_PEAK_MIN = 200.0     # N: no Fy figure for an axle whose peak is below
TARGETS = dict(beta_rms_deg=0.5, beta_max_deg=1.5, valid_share=0.90, mu_err=0.1, fy_pct=5.0)
TARGET_KEYS = ("beta", "valid", "baseline", "mu", "fy")
GENERIC_TIR = golden_est.tire_path()
MANOEUVRES = tuple(man_mod.MANOEUVRES)
VEHICLES = tuple(mb.VEHICLES)
SURFACES = tuple(mb.SURFACES)
# the reduced default set (CI-sized) and the full set
DEFAULT_SET = dict(vehicles=("bmw320i",), manoeuvres=MANOEUVRES, surfaces=SURFACES)
FULL_SET = dict(vehicles=VEHICLES, manoeuvres=MANOEUVRES, surfaces=SURFACES)


def selection_error(vehicles=None, manoeuvres=None, surfaces=None):
    """None when every name given is one of FULL_SET's, else what is wrong
    (the option and the names), for a command line's error."""
    for opt, given, have in (("--vehicles", vehicles, VEHICLES), ("--manoeuvres", manoeuvres, MANOEUVRES),
                             ("--surfaces", surfaces, SURFACES)):
        bad = [n for n in (given or ()) if n not in have]
        if bad:
            return f"{opt}: {', '.join(bad)}: unknown (have {', '.join(have)})"
    return None
# the fitted configuration's lateral fit: coefficients held (a ramp steer
# reaches a wheel lift-off before the tires' peak: curvature, shape and the
# load dependence of the peak are not in its data) and PKY2
FIT_FIX = "pcy1,pey1,pey2,pky2,pky4,pdy2"
FIT_PKY2 = 8.0
# its longitudinal fit, from a straight braking run to the ABS's slip band
# (manoeuvres.brake_ramp): peak, its load dependence, curvature and slip
# stiffness free; the shape factor, the curvature's load and sign terms and
# the shifts held (a braking run at one camber, slips 0 - 12 %, has nothing
# of them in its data)
FIT_FIX_X = "pcx1,pex2,pex3,pex4,pdx3,phx1,phx2,pvx1,pvx2,pkx3"
# the version of characterize's procedure, kept with its cached results
CHARACTERIZATION = 3
# runs whose step is halved once to measure the integration error
# (the low-speed one, with its sub-steps, only with --full)
STEP_CHECK = (("bmw320i", "sine-dwell", "dry"),)
STEP_CHECK_FULL = STEP_CHECK + (("bmw320i", "low-speed-lock", "dry"), ("vanagon", "circle-ramp", "snow"))


def _seed(*names):
    return zlib.crc32("/".join(names).encode())


# ---------------------------------------------------------------------------
# estimator configuration

def oem_vehicle(veh):
    """grip-replay vehicle-file values (SI) from the parameter set alone."""
    p = veh.p
    return dict(mass=float(p.m), iz=float(p.I_z), lf=float(p.a), lr=float(p.b), track_f=float(p.T_f),
                track_r=float(p.T_r), h_cg=float(p.h_cg), steer_ratio=mb.STEER_RATIO, wheel_radius=float(p.R_w),
                latency=sensors.LATENCY, steer_latency=sensors.STEER_LATENCY, cda=0.0, crr=0.0,
                drive_front=float(p.T_se))


def vehicle_lines(values):
    return [f"{k} = {v!r}" for k, v in values.items()]


def lateral_peak(params, fz):
    """Peak |Fy| / Fz of a .tir parameter set at load fz (pure slip, no camber)."""
    a = np.linspace(0.0, 0.6, 601)
    out = mf.evaluate(params, np.zeros_like(a), a, np.zeros_like(a), np.full_like(a, fz), mirror=False)
    return float(np.max(np.abs(out["fy"])) / fz)


def cornering_stiffness(params, fz):
    """|dFy / dalpha| at alpha = 0 [N/rad] of a .tir parameter set."""
    d = 1e-4
    a = np.array([-d, d])
    out = mf.evaluate(params, np.zeros(2), a, np.zeros(2), np.full(2, fz), mirror=False)
    return float(abs(out["fy"][1] - out["fy"][0]) / (2 * d))


def slip_stiffness(params, fz):
    """|dFx / dkappa| at kappa = 0 [N] of a .tir parameter set."""
    d = 1e-4
    k = np.array([-d, d])
    out = mf.evaluate(params, k, np.zeros(2), np.zeros(2), np.full(2, fz), mirror=False)
    return float(abs(out["fx"][1] - out["fx"][0]) / (2 * d))


def stiffness_ratios(veh, fitted_tir):
    """The model car's tire and the fitted tire against the generic one:
    cornering stiffness ratios at the static wheel loads, front and rear;
    the model tire's slip stiffness ratio (model_kx_f, model_kx_r)."""
    fzf, fzr = veh.static_wheel_loads()
    g = tir.load_params(GENERIC_TIR)
    f = tir.load_params(fitted_tir)
    ky = abs(float(veh.p.tire.p_ky1))
    kx = abs(float(veh.p.tire.p_kx1))
    return dict(model_f=ky * fzf / cornering_stiffness(g, fzf), model_r=ky * fzr / cornering_stiffness(g, fzr),
                fitted_f=cornering_stiffness(f, fzf) / cornering_stiffness(g, fzf),
                fitted_r=cornering_stiffness(f, fzr) / cornering_stiffness(g, fzr),
                model_kx_f=kx * fzf / slip_stiffness(g, fzf), model_kx_r=kx * fzr / slip_stiffness(g, fzr))


def mu_norm(veh, tir_path):
    """mu_true per unit of road friction factor: the model tire's lateral
    peak over the configured tire's at the mean static wheel load."""
    fzf, fzr = veh.static_wheel_loads()
    fz = 0.5 * (fzf + fzr)
    return float(veh.p.tire.p_dy1 / lateral_peak(tir.load_params(tir_path), fz))


def bicycle_params(values):
    """Baseline single-track: configured mass and axle distances,
    PacejkaBook_Defaults' cornering stiffness at the configured static loads."""
    P = tir.load_params(GENERIC_TIR)
    m, lf, lr = values["mass"], values["lf"], values["lr"]
    l = lf + lr
    g = 9.81
    cf = 2.0 * cornering_stiffness(P, 0.5 * m * g * lr / l)
    cr = 2.0 * cornering_stiffness(P, 0.5 * m * g * lf / l)
    return dict(m=m, lf=lf, lr=lr, cf=cf, cr=cr)


def bicycle_beta(bp, delta, v):
    """Steady-state sideslip of the linear single-track model."""
    m, lf, lr, cf, cr = bp["m"], bp["lf"], bp["lr"], bp["cf"], bp["cr"]
    l = lf + lr
    k_us = m / l * (lr / cf - lf / cr)
    v = np.maximum(v, 0.5)
    r = v * delta / (l + k_us * v * v)
    return lr * r / v - m * v * r * lf / (l * cr)


# ---------------------------------------------------------------------------
# the fitted configuration: a ramp steer with wheel-force transducers

# The fitted tire's declared relative force error (grip_est_config_t.tire_tol):
# the integrity calibration's value for a tire fitted to the car. The ramp's
# fit reproduces the four wheels' forces within 2.2 % of the peak (BMW 320i,
# fit-mf's report); the margin is for loads, cambers and combined slip the
# dry ramp does not reach. It does not cover the force shape near the peak,
# which the ramp does not reach either (PacejkaBook's: on snow the truth's
# curve is flatter there, docs/estimator/integrity.md, "The fitted
# configuration"). The generic tire keeps the default 0.3.
FITTED_TIRE_TOL = 0.1


def fitted_values(characterization):
    """The fitted configuration's vehicle values beyond the generic ones:
    characterize's measured roll values, the tire's declared tolerance and
    the bank estimated (a tire fitted to the car leaves the bank observer
    little to mistake for a bank: docs/estimator/road.md)."""
    return dict(characterization["values"], tire_tol=FITTED_TIRE_TOL, bank_est=1)


def fitted_config_values(values, characterization, extra=None):
    """The fitted configuration's vehicle values: the generic ones (values),
    fitted_values, then the options every run of the invocation gets
    (extra, est_eval.EXTRA: --no-bank-est turns bank_est off here too)."""
    return {**values, **fitted_values(characterization), **(extra or {})}


def _merge_tir(base_path, fragment, out_path, header):
    with open(base_path) as f:
        text = f.read()
    for line in fragment.splitlines():
        m = re.match(r"^([A-Z0-9_]+)\s*=\s*(\S+)", line)
        if not m:
            continue
        key, val = m.group(1), m.group(2)
        text, n = re.subn(rf"(?m)^({key}\s*=\s*)\S+", lambda mm: mm.group(1) + val, text)
        if n != 1:
            raise RuntimeError(f"fitted tire: {key} not found once in {base_path}")
    with open(out_path, "w") as f:
        f.write(header)
        f.write(text)


def _wheel_data(veh, manoeuvre, slip, force):
    """The four wheels' (slip, Fz, force) of one dry characterization run,
    moving steps, |slip| below its limit and Fz above 200 N, thinned to about
    3,000 points; and the run's truth."""
    sim = mb.simulate(veh, man_mod.build(manoeuvre, veh, 1.0), 1.0)
    t = np.arange(sensors.DELAY, sim["t"][-1], sensors.STEP)
    tr = sensors.truth(sim, veh, t)
    mov = tr["vx"] > 5.0
    x = np.concatenate([tr[f"{slip}_{w}"][mov] for w in mb.WHEELS])
    fz = np.concatenate([tr[f"fz_{w}"][mov] for w in mb.WHEELS])
    f = np.concatenate([tr[f"{force}_{w}"][mov] for w in mb.WHEELS])
    keep = (np.abs(x) < (15.0 / DEG if slip == "alpha" else 0.3)) & (fz > 200.0)
    x, fz, f = x[keep], fz[keep], f[keep]
    step = max(1, len(x) // 3000)
    return {slip: x[::step], "fz": fz[::step], force: f[::step]}, tr


def _fit_group(data, model, start, fix, work_dir, name):
    """grip fit-mf of one group from start with fix held -> (the group's
    .tir fragment, fit-mf's report)."""
    from grip_tools.fit import mf as fit_mf
    import contextlib
    import io
    csv = os.path.join(work_dir, f"{name}_wheels.csv")
    units = {"alpha": "rad", "kappa": "-", "fz": "N", "fx": "N", "fy": "N"}
    sensors.write_csv(csv, {f"{k}[{units[k]}]": v for k, v in data.items()})
    frag = os.path.join(work_dir, f"{name}_{model}.tir")
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rc = fit_mf.main([csv, "--model", model, "--tir", start, "--start", "tir", "--fix", fix,
                          "--tir-out", frag])
    report = buf.getvalue()
    if rc != 0:
        raise RuntimeError(f"fit-mf --model {model} failed for {name}: {report}")
    with open(frag) as f:
        return f.read(), report


def _fit_figures(report):
    """fit-mf's RMS [N] and its largest error as a share of the largest
    measured force."""
    rms = re.search(r"RMS\s+([0-9.eE+-]+)", report)
    share = re.search(r"/ ([0-9.eE+-]+) % of max", report)
    return (float(rms.group(1)) if rms else None), (float(share.group(1)) / 100.0 if share else None)


def _linear_range(tr, acc):
    """The steps of a characterization run's truth tr where the car moves
    (above 5 m/s) and the acceleration column acc is within 1 - 4 m/s^2 in
    magnitude: the body's linear range, where its roll and pitch are lines
    of the acceleration."""
    a = np.abs(tr[acc])
    return (tr["vx"] > 5.0) & (a > 1.0) & (a < 4.0)


def characterize(vname, out_dir, work_dir):
    """The ramp steer and the braking run of one vehicle on dry asphalt ->
    fitted_<vehicle>.tir in out_dir (lateral group from the ramp,
    longitudinal from the braking), the ramp's measured roll gradient and
    front roll share, and the braking run's pitch gradient. Returns a dict
    (tir path, values, fit reports)."""
    veh = mb.Vehicle(vname)
    os.makedirs(work_dir, exist_ok=True)
    data_y, tr = _wheel_data(veh, "ramp-steer", "alpha", "fy")
    # start: PacejkaBook_Defaults with PKY2 = FIT_PKY2 (cornering stiffness
    # linear in load over a car's wheel loads, as the ramp's data are: with
    # PKY2 free the fit drives PKY1 and PKY2 to 1e4..1e5 along that line)
    start = os.path.join(work_dir, f"ramp_{vname}_start.tir")
    _merge_tir(GENERIC_TIR, f"PKY2 = {FIT_PKY2}", start, "")
    frag_y, report = _fit_group(data_y, "fy", start, FIT_FIX, work_dir, f"ramp_{vname}")
    lateral = os.path.join(work_dir, f"ramp_{vname}_lateral.tir")
    _merge_tir(start, frag_y, lateral, "")
    data_x, tr_x = _wheel_data(veh, "brake-ramp", "kappa", "fx")
    frag_x, report_x = _fit_group(data_x, "fx", lateral, FIT_FIX_X, work_dir, f"brake_{vname}")
    # roll gradient and front share of the lateral load transfer, linear range
    lin = _linear_range(tr, "ay_kin")
    roll_gradient = float(np.polyfit(tr["ay_kin"][lin], tr["roll"][lin], 1)[0])
    p = veh.p
    dff = 0.5 * (tr["fz_fr"] - tr["fz_fl"])[lin] * p.T_f
    dfr = 0.5 * (tr["fz_rr"] - tr["fz_rl"])[lin] * p.T_r
    split = float(np.sum(dff * (dff + dfr)) / np.sum((dff + dfr) ** 2))
    # pitch gradient from the braking run, the same linear range (ISO pitch,
    # nose down positive: the line's slope over ax is negative)
    lin_x = _linear_range(tr_x, "ax_kin")
    pitch_gradient = -float(np.polyfit(tr_x["ax_kin"][lin_x], tr_x["pitch"][lin_x], 1)[0])
    values = dict(roll_gradient=round(max(0.0, min(0.05, roll_gradient)), 6),
                  roll_split_front=round(max(0.0, min(1.0, split)), 4),
                  pitch_gradient=round(max(0.0, min(0.05, pitch_gradient)), 6))
    out_tir = os.path.join(out_dir, f"fitted_{vname}.tir")
    header = (f"$ grip independent judge: {veh.label} tire. Lateral group fitted with `grip fit-mf --model fy "
              f"--start tir --fix {FIT_FIX}` from PacejkaBook_Defaults.tir with PKY2 = {FIT_PKY2} to the four "
              f"wheels of a dry ramp steer at 80 km/h ({len(data_y['alpha'])} points); longitudinal group with "
              f"`grip fit-mf --model fx --start tir --fix {FIT_FIX_X}` to the four wheels of a dry straight "
              f"braking run to the ABS's slip band from 100 km/h ({len(data_x['kappa'])} points); every other "
              f"group PacejkaBook_Defaults' (tools/grip_tools/sim/independent/judge.py)\n")
    _merge_tir(lateral, frag_x, out_tir, header)
    rms, share = _fit_figures(report)
    rms_x, share_x = _fit_figures(report_x)
    return dict(vehicle=vname, tir=out_tir, values=values, characterization=CHARACTERIZATION,
                fit_points=int(len(data_y["alpha"])), fit_report=report.strip().splitlines()[:6],
                fit_rms_N=rms, fit_max_share=share,
                fit_x_points=int(len(data_x["kappa"])), fit_x_report=report_x.strip().splitlines()[:6],
                fit_x_rms_N=rms_x, fit_x_max_share=share_x,
                ay_max=float(np.max(np.abs(tr["ay_kin"][tr["vx"] > 5.0]))))


def learning_drive_inputs(vname, name):
    """The estimator's inputs (t, value, valid) of one of the vehicle's
    learning drives (manoeuvres.learning_drive, learning_drive_long; dry)."""
    veh = mb.Vehicle(vname)
    sim = mb.simulate(veh, man_mod.build(name, veh, 1.0), 1.0)
    t, meas = sensors.measure(sim, veh, seed=_seed(vname, name, "dry"))
    value, valid = sensors.estimator_inputs(t, meas, est_eval.IN_COLS)
    return t, value, valid


def learn(vname, values, bins, work_dir, kx=False):
    """The learning drive of one vehicle (manoeuvres.learning_drive, dry)
    through each binding build with stiff_est = 1 and roll_est = 1:
    {arith: learned()} (the scales, the roll gradient, the updates, the
    blob). kx: kx_est = 1 too, and after it (an
    ignition cycle later, from its blob) the straight drive with speed
    changes (manoeuvres.learning_drive_long). Builds that are grip-replay
    programs are left out (the blob goes through grip.est)."""
    drives = ("learning-drive", "learning-drive-long") if kx else ("learning-drive",)
    vv = dict(values, stiff_est=1, roll_est=1, **({"kx_est": 1} if kx else {}))
    inputs = []
    for name in drives:
        t, value, valid = learning_drive_inputs(vname, name)
        os.makedirs(work_dir, exist_ok=True)
        tag = "" if name == "learning-drive" else "_long"
        est_eval.write_input_csv(os.path.join(work_dir, f"learning{tag}_{vname}_inputs.csv"), t, value, valid)
        inputs.append((t, value, valid))
    out = {}
    for arith, b in bins.items():
        if b[0] != "binding":
            continue
        blob = None
        for t, value, valid in inputs:
            out[arith] = est_eval.run_est(b, GENERIC_TIR, t, value, valid, vehicle="generic", vehicle_values=vv,
                                          learned=blob, keep_learned=True)["learned"]
            blob = out[arith]["blob"]
    return out


def _learn_job(a):
    return learn(*a)


# ---------------------------------------------------------------------------
# metrics

def _rms(x):
    return float(np.sqrt(np.mean(np.square(x)))) if len(x) else None


def _max(x):
    return float(np.max(np.abs(x))) if len(x) else None


def spin_mask(tr, l, lr, moving):
    beta_kin = np.arctan(lr * np.tan(tr["delta"]) / l)
    dep = (np.abs(tr["beta"] - beta_kin) * DEG > SPIN_DEG) & moving
    spin = np.zeros(len(dep), dtype=bool)
    if dep.any():
        spin[int(np.argmax(dep)):] = True
    return spin


def utilization(tr):
    u = np.zeros(len(tr["time"]))
    for w in mb.WHEELS:
        fz = np.maximum(tr[f"fz_{w}"], 1.0)
        peak = np.maximum(np.maximum(tr[f"mux_{w}"], tr[f"muy_{w}"]), 1e-3)
        u = np.maximum(u, np.hypot(tr[f"fx_{w}"], tr[f"fy_{w}"]) / (peak * fz))
    return u


def metrics(tr, meas, est, norm, bp, geom):
    """One run x configuration x build (module docstring)."""
    t = tr["time"]
    n = min(len(t), len(est["time"]))
    tr = {k: v[:n] for k, v in tr.items()}
    est = {k: v[:n] for k, v in est.items()}
    moving = tr["vx"] >= V_MOVING
    spin = spin_mask(tr, geom["l"], geom["lr"], moving)
    valid = est["valid"]
    vb = ((valid & est_ref.V_BETA) != 0) & moving
    r = {"steps": int(n), "moving_steps": int(moving.sum()), "spin_steps": int((spin & moving).sum()),
         "beta_valid_steps": int(vb.sum()), "beta_true_max_deg": _max(tr["beta"][moving] * DEG),
         "errors": int(np.sum(est["est_status"] < 0))}
    den = moving & ~spin
    r["valid_share"] = float(np.sum(vb & ~spin) / den.sum()) if den.sum() else None
    e = (est["beta"] - tr["beta"])[vb] * DEG
    r["beta_rms_deg"], r["beta_max_deg"] = _rms(e), _max(e)
    # the estimate on every moving step outside spins, valid or not: what
    # the flags do not decide (two configurations compared on the same steps)
    r["beta_rms_moving_deg"] = _rms((est["beta"] - tr["beta"])[den] * DEG)
    # baselines over the same steps
    e0 = -tr["beta"][vb] * DEG
    delta_m = meas["steer_angle"][:n] / mb.STEER_RATIO
    v_m = np.mean([meas[f"wheel_speed_{w}"][:n] for w in mb.WHEELS], axis=0)
    bb = bicycle_beta(bp, delta_m, v_m)
    e1 = (bb - tr["beta"])[vb] * DEG
    r["zero_rms_deg"], r["zero_max_deg"] = _rms(e0), _max(e0)
    r["bicycle_rms_deg"], r["bicycle_max_deg"] = _rms(e1), _max(e1)
    # the baselines on every moving step outside spins (for reference)
    r["zero_rms_all_deg"] = _rms(-tr["beta"][den] * DEG)
    r["bicycle_rms_all_deg"] = _rms((bb - tr["beta"])[den] * DEG)
    # yaw rate (the estimate, gyro bias removed) against the truth, a diagnostic
    ey = (est["yaw_rate"] - tr["r"])[vb]
    r["yaw_rate_rms"] = _rms(ey)
    # vx
    vv = ((valid & est_ref.V_VX) != 0) & moving
    ev = (est["vx"] - tr["vx"])[vv]
    r["vx_rms"], r["vx_max"] = _rms(ev), _max(ev)
    r["vx_wheel_mean_rms"] = _rms((v_m - tr["vx"])[moving])
    # mu
    mu_t = tr["mu_surface"] * norm
    util = utilization(tr)
    t0 = est_eval._onset(t[:n], util, tr["vx"], est_eval.EXC_LIMIT)
    r["mu_t0"] = t0
    r["mu_true_end"] = float(mu_t[-1])
    r["mu_est_end"] = float(est["mu"][-1])
    if t0 is not None:
        k1 = int(np.searchsorted(t[:n], t0 + 1.0))
        if k1 < n:
            r["mu_err"] = float(abs(est["mu"][k1] - mu_t[k1]))
            r["mu_est_1s"] = float(est["mu"][k1])
            r["mu_true_1s"] = float(mu_t[k1])
            r["mu_conf_1s"] = float(est["mu_conf"][k1])
    # axle forces
    r.update(fy_scores(est["fyf"], est["fyr"], tr, ((valid & est_ref.V_AXLE) != 0) & moving))
    r["pass"] = passes(r)
    return r


def fy_scores(fyf, fyr, tr, steps):
    """The Fy metric of an axle-force estimate (fyf, fyr, wheel frame [N])
    over the boolean mask steps (the judge: moving and flagged V_AXLE):
    fy_<axle>_peak_N, _rms_N and _rms_pct (None below FY_PEAK_MIN)."""
    r = {}
    for name, ef, tf in (("front", fyf, tr["fy_fl"] + tr["fy_fr"]),
                         ("rear", fyr, tr["fy_rl"] + tr["fy_rr"])):
        if steps.sum() == 0:
            r[f"fy_{name}_rms_pct"] = None
            continue
        peak = float(np.max(np.abs(tf[steps])))
        rms = float(np.sqrt(np.mean((ef - tf)[steps] ** 2)))
        r[f"fy_{name}_peak_N"] = peak
        r[f"fy_{name}_rms_N"] = rms
        r[f"fy_{name}_rms_pct"] = 100.0 * rms / peak if peak >= FY_PEAK_MIN else None
    return r


def passes(r):
    """Per target: True / False / None (does not apply)."""
    out = {}
    if r.get("beta_rms_deg") is None:
        out["beta"] = None
        out["baseline"] = None
    else:
        out["beta"] = bool(r["beta_rms_deg"] <= TARGETS["beta_rms_deg"] and r["beta_max_deg"] <= TARGETS["beta_max_deg"])
        out["baseline"] = bool(r["beta_rms_deg"] <= min(r["zero_rms_deg"], r["bicycle_rms_deg"]))
    out["valid"] = None if r.get("valid_share") is None else bool(r["valid_share"] >= TARGETS["valid_share"])
    out["mu"] = None if r.get("mu_err") is None else bool(r["mu_err"] <= TARGETS["mu_err"])
    fy = [r.get(f"fy_{a}_rms_pct") for a in ("front", "rear")]
    fy = [x for x in fy if x is not None]
    out["fy"] = bool(max(fy) <= TARGETS["fy_pct"]) if fy else None
    app = [v for v in out.values() if v is not None]
    out["all"] = bool(all(app)) if app else None
    return out


# ---------------------------------------------------------------------------
# one run

def _read_est(o):
    return o


def simulate_run(vname, mname, sname, run_dir):
    """Simulates one vehicle x manoeuvre x surface and samples the sensors;
    writes run_dir/truth.csv and inputs.csv (the estimator's inputs) and
    returns (veh, scenario, sim, t, meas, truth, value, valid)."""
    veh = mb.Vehicle(vname)
    factor = mb.SURFACES[sname]
    sc = man_mod.build(mname, veh, factor)
    sim = mb.simulate(veh, sc, factor)
    t, meas = sensors.measure(sim, veh, seed=_seed(vname, mname, sname))
    tr = sensors.truth(sim, veh, t)
    os.makedirs(run_dir, exist_ok=True)
    sensors.write_csv(os.path.join(run_dir, "truth.csv"), tr)
    value, valid = sensors.estimator_inputs(t, meas, est_eval.IN_COLS)
    est_eval.write_input_csv(os.path.join(run_dir, "inputs.csv"), t, value, valid)
    return veh, sc, sim, t, meas, tr, value, valid


def run_one(job):
    """Simulates one vehicle x manoeuvre x surface, samples the sensors,
    runs every configuration x build; returns the result dict."""
    vname, mname, sname, configs, bins, run_dir = job
    t_start = time.time()
    veh, sc, sim, t, meas, tr, value, valid = simulate_run(vname, mname, sname, run_dir)
    factor = mb.SURFACES[sname]
    geom = dict(l=veh.l, lr=veh.p.b)
    res = {"vehicle": vname, "manoeuvre": mname, "surface": sname, "surface_factor": factor,
           "duration_s": sc.duration, "simulated_s": float(sim["t"][-1]), "ended": sim["ended"], "meta": {k: (float(v) if isinstance(v, (int, float)) else v)
                                              for k, v in sc.meta.items()},
           "configs": {}}
    traces = {"t": t, "beta_true": tr["beta"], "vx_true": tr["vx"], "fyf_true": tr["fy_fl"] + tr["fy_fr"],
              "mu_surface": tr["mu_surface"]}
    for cname, cfg in configs.items():
        res["configs"][cname] = {}
        for arith, b in bins.items():
            blob = cfg["learned"][arith]["blob"] if "learned" in cfg else None
            est = est_eval.run_est(b, cfg["tir"], t, value, valid, vehicle="generic", vehicle_values=cfg["values"],
                                   learned=blob)
            res["configs"][cname][arith] = metrics(tr, meas, est, cfg["mu_norm"], cfg["bicycle"], geom)
            if arith == "float":
                for k in ("beta", "mu", "mu_conf", "fyf", "vx"):
                    traces[f"{cname}_{k}"] = est[k]
                traces[f"{cname}_vbeta"] = (est["valid"] & est_ref.V_BETA) != 0
    np.savez_compressed(os.path.join(run_dir, "traces.npz"), **traces)
    res["mu_norm"] = {c: cfg["mu_norm"] for c, cfg in configs.items()}
    res["wall_s"] = time.time() - t_start
    return res


def step_check(job):
    """The integration error: the same run at H and H / 2; the largest
    differences of the truth on the 10 ms grid."""
    vname, mname, sname = job
    veh = mb.Vehicle(vname)
    factor = mb.SURFACES[sname]
    out = {}
    sims = []
    for h in (mb.H, 0.5 * mb.H):
        sc = man_mod.build(mname, veh, factor)
        sims.append(mb.simulate(veh, sc, factor, h=h))
    a, b = sims
    ia = np.arange(0, len(a["t"]), 10)
    ib = np.arange(0, len(b["t"]), 20)
    n = min(len(ia), len(ib))
    ia, ib = ia[:n], ib[:n]
    xa, xb = a["x"][ia], b["x"][ib]
    _, aya, _ = mb.kinematic_acceleration(a)
    _, ayb, _ = mb.kinematic_acceleration(b)
    out["beta_deg"] = float(np.max(np.abs(np.arctan2(xa[:, mb.VY], xa[:, mb.VX]) -
                                          np.arctan2(xb[:, mb.VY], xb[:, mb.VX]))) * DEG)
    out["yaw_rate_rad_s"] = float(np.max(np.abs(xa[:, mb.R] - xb[:, mb.R])))
    out["vx_m_s"] = float(np.max(np.abs(xa[:, mb.VX] - xb[:, mb.VX])))
    out["ay_m_s2"] = float(np.max(np.abs(aya[ia] - ayb[ib])))
    m = min(len(a["fy"]), len(b["fy"]))
    out["fy_fl_N"] = float(np.max(np.abs(a["fy"][:m, 0] - b["fy"][:m, 0])))
    out["beta_true_max_deg"] = float(np.max(np.abs(np.arctan2(xa[:, mb.VY], xa[:, mb.VX]))) * DEG)
    return {"vehicle": vname, "manoeuvre": mname, "surface": sname, "h": [mb.H, 0.5 * mb.H], "max_diff": out,
            "ended": [a["ended"], b["ended"]]}


# ---------------------------------------------------------------------------
# tables

def _f(x, fmt):
    return "-" if x is None else format(x, fmt)


def _mark(v):
    return "-" if v is None else ("pass" if v else "FAIL")


def row_cells(res, cname, arith):
    r = res["configs"][cname][arith]
    p = r["pass"]
    mname = res["manoeuvre"] + (f" (ended {res['simulated_s']:.1f} s)" if res.get("ended") else "")
    return [res["vehicle"], mname, res["surface"], cname, arith,
            f"{_f(r.get('beta_rms_deg'), '.2f')} / {_f(r.get('beta_max_deg'), '.2f')}",
            _f(None if r.get("valid_share") is None else 100 * r["valid_share"], ".0f"),
            f"{_f(r.get('vx_rms'), '.2f')} / {_f(r.get('vx_max'), '.2f')}",
            _f(r.get("mu_err"), ".2f") + (f" ({_f(r.get('mu_est_1s'), '.2f')} vs {_f(r.get('mu_true_1s'), '.2f')})"
                                          if r.get("mu_err") is not None else ""),
            f"{_f(r.get('fy_front_rms_pct'), '.1f')} / {_f(r.get('fy_rear_rms_pct'), '.1f')}",
            f"{_f(r.get('zero_rms_deg'), '.2f')} / {_f(r.get('zero_max_deg'), '.2f')}",
            f"{_f(r.get('bicycle_rms_deg'), '.2f')} / {_f(r.get('bicycle_max_deg'), '.2f')}",
            " ".join(_mark(p[k]) for k in TARGET_KEYS), _mark(p["all"])]


HEADER = ["vehicle", "manoeuvre", "surface", "tire", "build", "beta RMS / max [deg]", "valid [%]",
          "vx RMS / max [m/s]", "mu err @ t0+1 s (est vs true)", "Fy front / rear RMS [% peak]",
          "beta=0 RMS / max [deg]", "bicycle RMS / max [deg]", "beta valid baseline mu Fy", "all"]


def count(rows_pass):
    """{target: (passed, applicable)} over a list of pass dicts."""
    out = {}
    for k in TARGET_KEYS + ("all",):
        app = [p[k] for p in rows_pass if p.get(k) is not None]
        out[k] = (int(sum(app)), len(app))
    return out


def in_family_counts(path):
    """The in-family rows (est-eval --simulate: docs/estimator/accuracy.json),
    C builds, on the targets it reports (no baselines there; valid =
    V_BETA rows above 5 m/s over all rows)."""
    if not os.path.exists(path):
        return None
    with open(path) as f:
        d = json.load(f)
    out = {}
    for arith in ("float", "fixed"):
        rows = []
        for name, c in d.get("c", {}).items():
            r = c.get(arith)
            if not r:
                continue
            p = {}
            if r.get("beta_rms_deg") is None:
                p["beta"] = None
            else:
                p["beta"] = bool(r["beta_rms_deg"] <= TARGETS["beta_rms_deg"] and
                                 r["beta_max_deg"] <= TARGETS["beta_max_deg"])
            p["valid"] = bool(r["valid_rows"] / max(r["rows"], 1) >= TARGETS["valid_share"])
            p["baseline"] = None
            p["mu"] = None if r.get("mu_err_1s_lim") is None else bool(r["mu_err_1s_lim"] <= TARGETS["mu_err"])
            fy = [r.get(f"fy_{a}_rms_pct") for a in ("front", "rear")]
            fy = [x for x in fy if x is not None]
            p["fy"] = bool(max(fy) <= TARGETS["fy_pct"]) if fy else None
            app = [v for v in p.values() if v is not None]
            p["all"] = bool(all(app)) if app else None
            rows.append(p)
        if rows:
            out[arith] = count(rows)
    return out


def _cnt(c):
    return "-" if c[1] == 0 else f"{c[0]} / {c[1]}"


def summary_md(results, configs, builds, in_family, step_err, chars):
    lines = []
    lines.append("## Runs meeting each target (passed / runs where it applies)\n")
    hdr = ["source", "tire", "build", "runs", "beta RMS <= 0.5, max <= 1.5 deg", "valid >= 90 %",
           "no worse than the better baseline", "mu within 0.1 @ t0+1 s", "Fy RMS <= 5 % peak", "all targets"]
    lines.append("| " + " | ".join(hdr) + " |")
    lines.append("|" + "---|" * len(hdr))
    if in_family:
        for arith, c in in_family.items():
            lines.append("| " + " | ".join(["in-family (grip simulate, accuracy.json)", "PacejkaBook_Defaults (= the simulator's)", arith,
                                             str(c["all"][1])] + [_cnt(c[k]) for k in TARGET_KEYS + ("all",)]) + " |")
    for cname in configs:
        for arith in builds:
            c = count([r["configs"][cname][arith]["pass"] for r in results])
            lines.append("| " + " | ".join(["out-of-family (multi-body model)", cname, arith, str(len(results))] +
                                            [_cnt(c[k]) for k in TARGET_KEYS + ("all",)]) + " |")
    lines.append("")
    lines.append("## Per vehicle and surface (C float; passed / applicable: beta, valid, baseline, mu, Fy; all)\n")
    hdr2 = ["vehicle", "surface", "tire", "runs"] + list(TARGET_KEYS) + ["all",
                                                                          "median beta RMS [deg]", "median valid [%]"]
    lines.append("| " + " | ".join(hdr2) + " |")
    lines.append("|" + "---|" * len(hdr2))
    veh_names = sorted({r["vehicle"] for r in results}, key=VEHICLES.index)
    surf_names = sorted({r["surface"] for r in results}, key=SURFACES.index)
    arith = "float" if "float" in builds else builds[0]
    for v in veh_names:
        for s in surf_names:
            sel = [r for r in results if r["vehicle"] == v and r["surface"] == s]
            if not sel:
                continue
            for cname in configs:
                rs = [r["configs"][cname][arith] for r in sel]
                c = count([x["pass"] for x in rs])
                br = [x["beta_rms_deg"] for x in rs if x.get("beta_rms_deg") is not None]
                vs = [x["valid_share"] for x in rs if x.get("valid_share") is not None]
                lines.append("| " + " | ".join([v, s, cname, str(len(sel))] + [_cnt(c[k]) for k in TARGET_KEYS + ("all",)] +
                                                [_f(float(np.median(br)) if br else None, ".2f"),
                                                 _f(100 * float(np.median(vs)) if vs else None, ".0f")]) + " |")
    lines.append("")
    if step_err:
        lines.append("## Integration error (RK4, 1 ms against 0.5 ms: largest difference over the run)\n")
        lines.append("| run | beta [deg] | yaw rate [rad/s] | vx [m/s] | ay [m/s^2] | Fy front left [N] | max abs(true beta) [deg] |")
        lines.append("|---|---|---|---|---|---|---|")
        for s in step_err:
            d = s["max_diff"]
            lines.append(f"| {s['vehicle']} {s['manoeuvre']} {s['surface']} | {d['beta_deg']:.2e} | "
                         f"{d['yaw_rate_rad_s']:.2e} | {d['vx_m_s']:.2e} | {d['ay_m_s2']:.2e} | {d['fy_fl_N']:.2e} | "
                         f"{d['beta_true_max_deg']:.1f} |")
        lines.append("")
    if chars:
        lines.append("## Fitted configuration (ramp steer at 80 km/h and braking from 100 km/h, dry)\n")
        lines.append("| vehicle | fitted tire | Fy fit RMS [N] / points | Fx fit RMS [N] / points | roll gradient [rad/(m/s^2)] | front roll share | pitch gradient [rad/(m/s^2)] | mu_true per unit road factor (generic / fitted) |")
        lines.append("|---|---|---|---|---|---|---|---|")
        for c in chars:
            lines.append(f"| {c['vehicle']} | {os.path.basename(c['tir'])} | {_f(c.get('fit_rms_N'), '.0f')} / "
                         f"{c['fit_points']} | {_f(c.get('fit_x_rms_N'), '.0f')} / {c.get('fit_x_points', '-')} | "
                         f"{c['values']['roll_gradient']:.4f} | {c['values']['roll_split_front']:.3f} | "
                         f"{c['values'].get('pitch_gradient', 0.0):.4f} | "
                         f"{c['mu_norm']['generic']:.3f} / {c['mu_norm']['fitted']:.3f} |")
        lines.append("")
    if any("learned" in c for c in chars):
        lines.append("## Learned configuration (generic tire, 90 s learning drive, dry, 80 km/h)\n")
        lines.append("The cornering-stiffness scales the estimator learned (`stiff_est` = 1), restored at the start of "
                     "every run of the `learned` rows, against the ratios of the model car's tire and of the fitted "
                     "tire to the generic one at the static wheel loads.\n")
        lines += _learned_table(chars, LEARNED_K_TABLE)
        if any("roll_gradient" in x for c in chars for x in c.get("learned", {}).values()):
            lines.append("The roll gradient learned on the same drive (`roll_est` = 1, from the configured 0.0088 "
                         "rad/(m/s^2)), against the ramp characterization's.\n")
            lines += _learned_table(chars, LEARNED_RG_TABLE)
        if any("kx" in x for c in chars for x in c.get("learned", {}).values()):
            lines.append("The longitudinal slip-stiffness scale (`kx_est` = 1, the drive split from the parameter "
                         "set's T_se) and the axles' rolling-radius mismatch learned, against the model car's "
                         "tire's slip stiffness over the generic one's at the static wheel loads.\n")
            lines += _learned_table(chars, LEARNED_KX_TABLE)
    return "\n".join(lines)


def _ratio_pair(front, rear):
    """A cell "front / rear" of two of the vehicle's stiffness ratios
    (stiffness_ratios' keys; "-" where absent)."""
    return lambda x, ref: f"{_f(ref.get(front), '.2f')} / {_f(ref.get(rear), '.2f')}"


# The two tables of what the learned configuration learned, one row per
# vehicle and build: (column title, cell(learned values of the build, the
# vehicle's stiffness_ratio) -> text) after the vehicle and build columns.
LEARNED_K_TABLE = (
    ("k front / rear learned", lambda x, ref: f"{x['k_front']:.3f} / {x['k_rear']:.3f}"),
    ("updates", lambda x, ref: f"{x['updates']}"),
    ("model tire / generic f / r", _ratio_pair("model_f", "model_r")),
    ("fitted / generic f / r", _ratio_pair("fitted_f", "fitted_r")),
)
LEARNED_RG_TABLE = (
    ("roll gradient learned [rad/(m/s^2)]", lambda x, ref: f"{x['roll_gradient']:.4f}"),
    ("updates", lambda x, ref: f"{x['roll_updates']}"),
    ("characterized", lambda x, ref: _f(ref.get("roll_char"), ".4f")),
)
LEARNED_KX_TABLE = (
    ("kx learned", lambda x, ref: f"{x['kx']:.3f}"),
    ("radius mismatch [per mille]", lambda x, ref: f"{1000 * x['radius_mismatch']:.2f}"),
    ("updates", lambda x, ref: f"{x['kx_updates']}"),
    ("model tire / generic f / r", _ratio_pair("model_kx_f", "model_kx_r")),
)


def _learned_table(chars, columns):
    """The markdown lines of one table of the learned scales (columns:
    LEARNED_K_TABLE or LEARNED_KX_TABLE), a row per characterized vehicle
    and build, and the blank line after it."""
    cols = ("vehicle", "build") + tuple(title for title, _ in columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for c in chars:
        ref = dict(c.get("stiffness_ratio", {}), roll_char=c.get("values", {}).get("roll_gradient"))
        for a, x in c.get("learned", {}).items():
            lines.append("| " + " | ".join([c["vehicle"], a] + [cell(x, ref) for _, cell in columns]) + " |")
    lines.append("")
    return lines


def worst(results, cname="generic", arith="float", n=4):
    def key(r):
        x = r["configs"][cname][arith]
        b = x.get("beta_rms_deg")
        return -1.0 if b is None else b
    by_beta = sorted(results, key=key, reverse=True)[:n]
    by_mu = sorted([r for r in results if r["configs"][cname][arith].get("mu_err") is not None],
                   key=lambda r: r["configs"][cname][arith]["mu_err"], reverse=True)[:2]
    out = []
    for r in by_beta + by_mu:
        if r not in out:
            out.append(r)
    return out


def plot_worst(sel, runs_dir, path, cname="generic"):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(sel)
    fig, ax = plt.subplots(n, 4, figsize=(16, 2.4 * n), squeeze=False)
    for i, r in enumerate(sel):
        name = f"{r['vehicle']}_{r['manoeuvre']}_{r['surface']}"
        d = np.load(os.path.join(runs_dir, name, "traces.npz"))
        t = d["t"]
        vb = d[f"{cname}_vbeta"]
        ax[i, 0].plot(t, d["beta_true"] * DEG, "k", lw=1, label="truth")
        ax[i, 0].plot(t, np.where(vb, d[f"{cname}_beta"], np.nan) * DEG, "r", lw=1, label="estimate (V_BETA)")
        ax[i, 0].plot(t, np.where(vb, np.nan, d[f"{cname}_beta"]) * DEG, "r:", lw=0.8, label="estimate (not valid)")
        ax[i, 0].set_ylabel(name, fontsize=7)
        ax[i, 1].plot(t, d["mu_surface"] * r["mu_norm"][cname], "k", lw=1)
        ax[i, 1].plot(t, d[f"{cname}_mu"], "r", lw=1)
        ax[i, 1].plot(t, d[f"{cname}_mu_conf"], "g:", lw=1)
        ax[i, 1].set_ylim(0, 1.3)
        ax[i, 2].plot(t, d["fyf_true"], "k", lw=1)
        ax[i, 2].plot(t, d[f"{cname}_fyf"], "r", lw=1)
        ax[i, 3].plot(t, d["vx_true"], "k", lw=1)
        ax[i, 3].plot(t, d[f"{cname}_vx"], "r", lw=1)
        if i == 0:
            ax[i, 0].set_title("sideslip beta [deg]")
            ax[i, 1].set_title("mu (red), confidence (green), truth (black)")
            ax[i, 2].set_title("front axle Fy [N]")
            ax[i, 3].set_title("vx [m/s]")
            ax[i, 0].legend(fontsize=6)
    for a in ax[-1]:
        a.set_xlabel("time [s]")
    fig.suptitle(f"grip estimator (C float, {cname} configuration) on CommonRoad's multi-body model: worst runs")
    fig.tight_layout()
    fig.savefig(path, dpi=75)
    plt.close(fig)


# ---------------------------------------------------------------------------

def find_bins(specs=()):
    """The C builds to run (est_eval.c_builds: the binding, float and fixed;
    --c-bin ARITH=PATH: a grip-replay program instead) and notes."""
    return est_eval.c_builds(specs)


def run(out, full=False, vehicles=None, manoeuvres=None, surfaces=None, jobs=None, runs_dir=None,
        c_bins=(), fitted=True, step_checks=True, plots=True, vehicle_extra=None, learned=True, learn_kx=False):
    """The whole judge; writes out/independent.json and .md (and PNGs).
    vehicle_extra: estimator settings added to every configuration's
    vehicle values (est-eval --bank-est: {"bank_est": 1}); learn_kx: the
    learned configuration learns the longitudinal slip stiffness too
    (est-eval --kx-est). Returns the JSON dict."""
    t_start = time.time()
    sel = dict(FULL_SET if full else DEFAULT_SET)
    if vehicles:
        sel["vehicles"] = tuple(vehicles)
    if manoeuvres:
        sel["manoeuvres"] = tuple(manoeuvres)
    if surfaces:
        sel["surfaces"] = tuple(surfaces)
    runs_dir = runs_dir or os.path.join(REPO_ROOT, "build", "est_eval", "independent")
    os.makedirs(out, exist_ok=True)
    os.makedirs(runs_dir, exist_ok=True)
    bins, notes = find_bins(c_bins)
    for n in notes:
        print(f"est-eval --independent: {n}", file=sys.stderr)
    if not bins:
        raise SystemExit("est-eval --independent: no C build to run (the Python binding: make setup)")
    jobs = jobs or max(1, min(os.cpu_count() or 1, 4))
    import multiprocessing as mp
    ctx = mp.get_context("fork")
    pool = ctx.Pool(jobs) if jobs > 1 else None
    pmap = pool.map if pool else (lambda f, xs: [f(x) for x in xs])
    try:
        chars = []
        if fitted:
            chars = pmap(_characterize_job, [(v, out, runs_dir) for v in sel["vehicles"]])
        configs = {}
        per_vehicle = {}
        for v in sel["vehicles"]:
            veh = mb.Vehicle(v)
            values = dict(oem_vehicle(veh), **(vehicle_extra or {}))
            bp = bicycle_params(values)
            per_vehicle[v] = {"generic": dict(tir=GENERIC_TIR, lines=vehicle_lines(values), values=values,
                                              mu_norm=mu_norm(veh, GENERIC_TIR), bicycle=bp)}
            for c in chars:
                if c["vehicle"] == v:
                    vf = fitted_config_values(values, c, vehicle_extra)
                    per_vehicle[v]["fitted"] = dict(tir=c["tir"], lines=vehicle_lines(vf), values=vf,
                                                    mu_norm=mu_norm(veh, c["tir"]), bicycle=bp)
                    c["mu_norm"] = {"generic": per_vehicle[v]["generic"]["mu_norm"],
                                    "fitted": per_vehicle[v]["fitted"]["mu_norm"]}
        if learned:
            taught = pmap(_learn_job, [(v, per_vehicle[v]["generic"]["values"], bins, runs_dir, learn_kx)
                                       for v in sel["vehicles"]])
            for v, tv in zip(sel["vehicles"], taught):
                # every build needs its own blob: with a grip-replay
                # program among the builds the configuration is left out
                if set(tv) == set(bins):
                    g = per_vehicle[v]["generic"]
                    vl = dict(g["values"], stiff_est=1, roll_est=1, **({"kx_est": 1} if learn_kx else {}))
                    per_vehicle[v]["learned"] = dict(tir=GENERIC_TIR, lines=vehicle_lines(vl), values=vl,
                                                     mu_norm=g["mu_norm"], bicycle=g["bicycle"], learned=tv)
                    for c in chars:
                        if c["vehicle"] == v:
                            keys = ("k_front", "k_rear", "updates", "roll_gradient", "roll_updates") + (
                                ("kx", "radius_mismatch", "kx_updates") if learn_kx else ())
                            c["learned"] = {a: {k: x[k] for k in keys} for a, x in tv.items()}
                            c["stiffness_ratio"] = stiffness_ratios(mb.Vehicle(v), c["tir"])
        configs = list(next(iter(per_vehicle.values())).keys())
        joblist = []
        for v in sel["vehicles"]:
            for m in sel["manoeuvres"]:
                for s in sel["surfaces"]:
                    joblist.append((v, m, s, per_vehicle[v], bins, os.path.join(runs_dir, f"{v}_{m}_{s}")))
        # longest first: the pool's tail stays short
        joblist.sort(key=lambda j: -man_mod.build(j[1], mb.Vehicle(j[0]), mb.SURFACES[j[2]]).duration)
        results = pmap(run_one, joblist)
        step_err = []
        if step_checks:
            step_err = pmap(step_check, [s for s in (STEP_CHECK_FULL if full else STEP_CHECK)
                                         if s[0] in sel["vehicles"]])
    finally:
        if pool:
            pool.close()
            pool.join()
    order = {(v, m, s): i for i, (v, m, s) in enumerate(
        (v, m, s) for v in VEHICLES for m in MANOEUVRES for s in SURFACES)}
    results.sort(key=lambda r: order[(r["vehicle"], r["manoeuvre"], r["surface"])])
    builds = [a for a in ("float", "fixed") if a in bins]
    in_family = in_family_counts(os.path.join(REPO_ROOT, "docs", "estimator", "accuracy.json"))
    doc = {"command": "grip est-eval --independent" + (" --full" if full else "") + (" --kx-est" if learn_kx else ""),
           "selection": {k: list(v) for k, v in sel.items()}, "targets": TARGETS, "builds": builds,
           "configs": {v: {c: {"tir": os.path.relpath(d["tir"], REPO_ROOT), "vehicle": d["values"],
                               "mu_norm": d["mu_norm"], "bicycle_baseline": d["bicycle"]}
                           for c, d in cfgs.items()} for v, cfgs in per_vehicle.items()},
           "characterization": [{k: (os.path.relpath(x, REPO_ROOT) if k == "tir" else x) for k, x in c.items()}
                                for c in chars],
           "integration_error": step_err, "in_family": in_family, "notes": notes,
           "sensors": {"latency": sensors.LATENCY, "steer_latency": sensors.STEER_LATENCY,
                       "spec": {k: list(v) for k, v in sensors.SPEC.items()}},
           "surfaces": mb.SURFACES, "results": results}
    md = ["# Independent judge: measured table\n",
          f"Generated by `{doc['command']}` (tools/grip_tools/sim/independent/judge.py); "
          "docs/independent-judge.md describes the judge. Vehicles: "
          + ", ".join(mb.VEHICLES[v][1] for v in sel["vehicles"]) + "; surfaces: "
          + ", ".join(f"{s} ({mb.SURFACES[s]})" for s in sel["surfaces"]) + ".\n",
          summary_md(results, configs, builds, in_family, step_err, chars)]
    ws = worst(results)
    md.append("## Worst runs (C float, generic configuration)\n")
    md.append("By beta RMS, then by mu error; plotted in worst_runs.png.\n")
    md.append("| run | beta RMS / max [deg] | valid [%] | vx RMS [m/s] | mu err @ t0+1 s | Fy f / r [% peak] | beta=0 RMS | bicycle RMS |")
    md.append("|---|---|---|---|---|---|---|---|")
    for r in ws:
        x = r["configs"]["generic"][builds[0]]
        md.append(f"| {r['vehicle']} {r['manoeuvre']} {r['surface']} | {_f(x.get('beta_rms_deg'), '.2f')} / "
                  f"{_f(x.get('beta_max_deg'), '.2f')} | {_f(None if x.get('valid_share') is None else 100 * x['valid_share'], '.0f')} | "
                  f"{_f(x.get('vx_rms'), '.2f')} | {_f(x.get('mu_err'), '.2f')} | "
                  f"{_f(x.get('fy_front_rms_pct'), '.1f')} / {_f(x.get('fy_rear_rms_pct'), '.1f')} | "
                  f"{_f(x.get('zero_rms_deg'), '.2f')} | {_f(x.get('bicycle_rms_deg'), '.2f')} |")
    md.append("")
    md.append("## Every run\n")
    md.append("Pass marks in the order beta, valid, baseline, mu, Fy; '-' where a target does not apply.\n")
    md.append("| " + " | ".join(HEADER) + " |")
    md.append("|" + "---|" * len(HEADER))
    for r in results:
        for cname in configs:
            for arith in builds:
                md.append("| " + " | ".join(row_cells(r, cname, arith)) + " |")
    md.append("")
    if notes:
        md.extend(f"Note: {n}" for n in notes)
    doc["wall_s"] = time.time() - t_start
    with open(os.path.join(out, "independent.json"), "w") as f:
        json.dump(doc, f, indent=1, default=_json_default)
    with open(os.path.join(out, "independent.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    if plots and ws:
        plot_worst(ws, runs_dir, os.path.join(out, "worst_runs.png"))
    print(f"est-eval --independent: {len(results)} runs, {len(builds)} builds, {len(configs)} configurations, "
          f"{doc['wall_s']:.0f} s; {os.path.join(out, 'independent.md')}", file=sys.stderr)
    return doc


def _json_default(o):
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, np.bool_):
        return bool(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(type(o))


def _characterize_job(a):
    return characterize(*a)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip est-eval --independent", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--full", action="store_true")
    ap.add_argument("--out", default=os.path.join(REPO_ROOT, "docs", "estimator", "independent"))
    ap.add_argument("--vehicles", nargs="*")
    ap.add_argument("--manoeuvres", nargs="*")
    ap.add_argument("--surfaces", nargs="*")
    ap.add_argument("--jobs", type=int)
    a = ap.parse_args(argv)
    err = selection_error(a.vehicles, a.manoeuvres, a.surfaces)
    if err:
        ap.error(err)
    if a.jobs is not None and a.jobs < 1:
        ap.error(f"--jobs: {a.jobs}: at least 1")
    run(a.out, a.full, a.vehicles, a.manoeuvres, a.surfaces, a.jobs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
