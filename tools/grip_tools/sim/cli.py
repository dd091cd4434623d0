"""grip simulate: run a manoeuvre, write truth.csv,
sensors.csv, can.log (candump), summary.json and overview.png.

Example:
  grip simulate --manoeuvre sine-dwell --surface wet --out /tmp/sd
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

from grip_tools.sim import canlog, manoeuvres as M, sensors, vehicles
from grip_tools.sim.model import Effects, simulate

DEG = math.pi / 180.0


def _parser():
    p = argparse.ArgumentParser(prog="grip simulate",
                                description="Reference vehicle simulator (docs/simulator.md).")
    p.add_argument("--manoeuvre", "-m", default="sine-dwell", choices=M.MANOEUVRES)
    p.add_argument("--surface", "-s", default="dry",
                   help="dry (mu 1.0), wet (0.6), snow (0.3) or a number (scale of the tyre's friction)")
    p.add_argument("--vehicle", default="passenger", choices=sorted(vehicles.VEHICLES))
    p.add_argument("--out", "-o", required=True, help="output directory (created)")
    p.add_argument("--dt", type=float, default=1e-3, help="RK4 step [s] (default 0.001)")
    p.add_argument("--speed", type=float, default=None, help="initial speed [km/h]")
    p.add_argument("--duration", type=float, default=None, help="duration [s] (manoeuvre default)")
    p.add_argument("--amplitude", type=float, default=None,
                   help="SWA amplitude [deg] (step-steer, sine-dwell, fishhook)")
    p.add_argument("--scale", type=float, default=5.0,
                   help="sine-dwell / fishhook amplitude as a multiple of SWA(0.3 g) (default 5.0; "
                        "fishhook uses 6.5 unless given)")
    p.add_argument("--swa03", type=float, default=None,
                   help="SWA at 0.3 g [deg] (default: measured by the FMVSS 126 ramp on a dry road)")
    p.add_argument("--no-relaxation", action="store_true", help="steady-state slips (blended at low speed)")
    p.add_argument("--thermal", action="store_true", help="tyre temperature model on")
    p.add_argument("--no-aero", action="store_true")
    p.add_argument("--no-load-transfer", action="store_true")
    p.add_argument("--abs", choices=("on", "off"), default=None, help="ABS for braking manoeuvres")
    p.add_argument("--bank", type=float, default=0.0, help="road bank angle [deg], road higher on the left")
    p.add_argument("--grade", type=float, default=0.0, help="road grade [%%], rising along +X")
    p.add_argument("--seed", type=int, default=0, help="sensor noise seed")
    p.add_argument("--ideal-sensors", action="store_true", help="no noise, bias, delay (quantization kept)")
    p.add_argument("--no-plot", action="store_true")
    return p


def build_scenario(a, vehicle, effects):
    kw = {}
    v0 = a.speed / 3.6 if a.speed is not None else None
    info = {}
    if a.manoeuvre in ("sine-dwell", "fishhook"):
        if a.amplitude is not None:
            amp = a.amplitude
        else:
            swa03 = a.swa03 if a.swa03 is not None else M.swa_at_03g(vehicle, effects, h=max(a.dt, 1e-3))
            scale = a.scale if (a.manoeuvre == "sine-dwell" or a.scale != 5.0) else 6.5
            amp = min(scale * swa03, 270.0)
            info.update(swa03_deg=swa03, scale=scale)
        kw["amp_deg"] = amp
    elif a.manoeuvre == "step-steer" and a.amplitude is not None:
        kw["swa_deg"] = a.amplitude
    if v0 is not None:
        kw["v0"] = v0
    if a.abs is not None and a.manoeuvre in ("brake-in-turn", "mu-step", "mu-split-brake"):
        kw["use_abs"] = a.abs == "on"
    if a.duration is not None and a.manoeuvre not in ("sine-dwell", "fishhook"):
        kw["duration"] = a.duration
    sc = M.build(a.manoeuvre, vehicle, surface=M.parse_surface(a.surface), **kw)
    if a.duration is not None and a.manoeuvre in ("sine-dwell", "fishhook"):
        sc.duration = a.duration
    sc.road.bank = math.tan(a.bank * DEG)
    sc.road.grade = a.grade / 100.0
    sc.meta.update(info)
    return sc


def plot_overview(res, path, i=0, title=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = res.t
    d = res.data
    fig, ax = plt.subplots(4, 2, figsize=(13, 11), sharex=True)
    ax = ax.ravel()
    ax[0].plot(t, d["swa"][:, i] / DEG, "k")
    ax[0].set_ylabel("SWA [deg]")
    ax0b = ax[0].twinx()
    ax0b.plot(t, d["p_master"][:, i], "r", lw=0.8)
    ax0b.set_ylabel("p master [bar]", color="r")
    ax[1].plot(t, d["r"][:, i] / DEG, label="yaw rate [deg/s]")
    ax[1].plot(t, d["beta"][:, i] / DEG, label="sideslip beta [deg]")
    ax[1].legend(fontsize=8)
    ax[2].plot(t, d["ay"][:, i], label="ay")
    ax[2].plot(t, d["ax"][:, i], label="ax")
    ax[2].set_ylabel("[m/s^2]")
    ax[2].legend(fontsize=8)
    ax[3].plot(t, d["vx"][:, i] * 3.6, label="vx")
    for j, w in enumerate(("FL", "FR", "RL", "RR")):
        ax[3].plot(t, d["re_omega"][:, i, j] * 3.6, lw=0.7, label=f"wheel {w}")
    ax[3].set_ylabel("[km/h]")
    ax[3].legend(fontsize=7)
    for j, w in enumerate(("FL", "FR", "RL", "RR")):
        ax[4].plot(t, d["kappa"][:, i, j], label=w)
        ax[5].plot(t, d["alpha"][:, i, j] / DEG, label=w)
        ax[6].plot(t, d["fz"][:, i, j], label=w)
        ax[7].plot(t, np.hypot(d["fx"][:, i, j], d["fy"][:, i, j]) / np.maximum(d["fz"][:, i, j], 1.0),
                   label=f"{w} used")
    ax[7].plot(t, d["muy"][:, i, 0], "k:", lw=0.8, label="FL peak mu_y")
    ax[4].set_ylabel("slip ratio [-]")
    ax[5].set_ylabel("slip angle ISO-W [deg]")
    ax[6].set_ylabel("Fz [N]")
    ax[7].set_ylabel("|F|/Fz [-]")
    for a_ in (ax[4], ax[5], ax[6], ax[7]):
        a_.legend(fontsize=7)
    for a_ in ax:
        a_.grid(True, alpha=0.3)
    ax[6].set_xlabel("time [s]")
    ax[7].set_xlabel("time [s]")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _check(p, a):
    """Values the simulator cannot run with: exit 2 with the option named."""
    def bad(opt, value, why):
        p.error(f"{opt}: {value!r}: {why}")
    try:
        M.parse_surface(a.surface)
    except ValueError as e:
        p.error(f"--surface: {e}")
    checks = (("--dt", a.dt, 0.0, 0.01, False), ("--speed", a.speed, 0.0, 400.0, True),
              ("--duration", a.duration, 0.0, 3600.0, False), ("--amplitude", a.amplitude, -720.0, 720.0, True),
              ("--scale", a.scale, 0.0, 50.0, False), ("--swa03", a.swa03, 0.0, 720.0, False),
              ("--bank", a.bank, -45.0, 45.0, True), ("--grade", a.grade, -100.0, 100.0, True))
    for opt, v, lo, hi, lo_ok in checks:
        if v is None:
            continue
        if not (math.isfinite(v) and (v >= lo if lo_ok else v > lo) and v <= hi):
            bad(opt, v, f"outside {'[' if lo_ok else '('}{lo:g}, {hi:g}]")


def main(argv=None):
    p = _parser()
    a = p.parse_args(argv)
    _check(p, a)
    vehicle = vehicles.get(a.vehicle)
    effects = Effects(relaxation=not a.no_relaxation, thermal=a.thermal, aero=not a.no_aero,
                      load_transfer=not a.no_load_transfer)
    os.makedirs(a.out, exist_ok=True)
    t0 = time.time()
    sc = build_scenario(a, vehicle, effects)
    res = simulate(vehicle, sc, effects, h=a.dt)
    wall = time.time() - t0
    cfg = sensors.SensorConfig(seed=a.seed)
    if a.ideal_sensors:
        cfg = cfg.ideal()
    truth = res.member(0)
    sd = sensors.measure(truth, cfg)
    header = [f"grip vehicle simulator: {sc.name} on {sc.road.name}, vehicle {vehicle.name}, "
              f"tyre {res.meta['tire']}, effects {res.meta['effects']}, RK4 h = {a.dt} s",
              "axes ISO 8855 (x forward, y left, z up); tyre slip angle alpha in ISO-W "
              "(tan alpha = Vcy/|Vcx|, > 0 gives Fy < 0); wheels fl fr rl rr"]
    res.write_csv(os.path.join(a.out, "truth.csv"), 0, header)
    sd.write_csv(os.path.join(a.out, "sensors.csv"),
                 [f"sensor samples (seed {a.seed}); NaN = channel not sampled at this time"])
    frames = canlog.encode_frames(sd)
    canlog.write_candump(os.path.join(a.out, "can.log"), frames)
    summary = dict(manoeuvre=sc.name, surface=a.surface, vehicle=vehicle.name, dt=a.dt,
                   duration=sc.duration, wall_s=round(wall, 2), frames=len(frames),
                   meta={k: v for k, v in res.meta.items() if isinstance(v, (int, float, str, list))},
                   max_abs_ay=float(np.abs(res["ay"][:, 0]).max()),
                   max_abs_beta_deg=float(np.abs(res["beta"][:, 0]).max() / DEG),
                   max_abs_r_deg_s=float(np.abs(res["r"][:, 0]).max() / DEG),
                   final_speed_kmh=float(res["vx"][-1, 0] * 3.6))
    if sc.name == "sine-dwell":
        summary["fmvss126"] = M.fmvss126_metrics(res, 0)
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    if not a.no_plot:
        plot_overview(res, os.path.join(a.out, "overview.png"), 0,
                      f"{sc.name}, {sc.road.name}, {vehicle.name}")
    print(json.dumps(summary, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
