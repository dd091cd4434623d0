"""Accuracy and behaviour figures of docs/simulator.md.

  .venv/bin/python -m grip_tools.sim.report --out docs/simulator

Writes PNG figures and report.json (every number quoted in the document).
Takes a few minutes (fine steps for the step-halving reference).
"""
import argparse
import json
import math
import os
import time

import numpy as np

from grip_tools.logs import av21 as av21_log
from grip_tools.sim import manoeuvres as M, model, sensors, vehicles

DEG = math.pi / 180.0
G = 9.80665


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def step_halving(out, rep):
    v = vehicles.passenger()
    sc = M.sine_dwell(v, [100.0], t0=0.3, settle=0.5)
    sc.duration = 2.6
    hs = [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]
    runs = {}
    for h in hs:
        t0 = time.time()
        runs[h] = model.simulate(v, sc, h=h, record_every=int(round(4e-3 / h)))
        rep.setdefault("wall_per_sim_s", {})[f"{h * 1e3:g} ms"] = round(time.time() - t0, 2)
    ref = runs[hs[-1]]
    t = ref.t
    smooth = t < 1.3           # before the dwell: inputs smooth after the start of steer
    rows = []
    for h in hs[:-1]:
        r = runs[h]
        e_r = np.abs(r["r"] - ref["r"])[:, 0]
        e_vy = np.abs(r["vy"] - ref["vy"])[:, 0]
        e_w = np.abs(r["omega"] - ref["omega"])[:, 0, :].max(axis=1)
        e_fy = np.abs(r["fy"] - ref["fy"])[:, 0, :].max(axis=1)
        rows.append(dict(h_ms=h * 1e3, r_smooth=float(e_r[smooth].max()), r_all=float(e_r.max()),
                         vy_all=float(e_vy.max()), omega_all=float(e_w.max()), fy_all=float(e_fy.max())))
    rep["step_halving"] = rows
    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    hh = [r["h_ms"] for r in rows]
    ax[0].loglog(hh, [r["r_smooth"] for r in rows], "o-", label="yaw rate, t < 1.3 s (smooth inputs)")
    ax[0].loglog(hh, [r["r_all"] for r in rows], "s-", label="yaw rate, whole run (kinks in SWA)")
    ax[0].loglog(hh, [r["omega_all"] for r in rows], "^-", label="wheel speed [rad/s]")
    c = rows[0]["r_smooth"] / hh[0] ** 4
    ax[0].loglog(hh, [c * x ** 4 for x in hh], "k:", label="slope 4")
    ax[0].set_xlabel("RK4 step h [ms]")
    ax[0].set_ylabel("max |x(h) - x(0.25 ms)|")
    ax[0].legend(fontsize=8)
    ax[0].grid(True, which="both", alpha=0.3)
    ax[1].plot(t, ref["r"][:, 0] / DEG, "k", label="yaw rate (h = 0.25 ms) [deg/s]")
    ax[1].plot(t, ref["swa"][:, 0] / DEG / 10, "g", label="SWA / 10 [deg]")
    ax1b = ax[1].twinx()
    ax1b.semilogy(t, np.abs(runs[2e-3]["r"] - ref["r"])[:, 0] + 1e-16, "r", lw=0.8)
    ax1b.set_ylabel("|r(2 ms) - r(0.25 ms)| [rad/s]", color="r")
    ax[1].set_xlabel("time [s]")
    ax[1].legend(fontsize=8, loc="lower left")
    fig.suptitle("Step halving: sine with dwell, 100 deg SWA, 80 km/h, passenger car")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "step_halving.png"), dpi=90)
    plt.close(fig)


def bicycle(out, rep):
    v = vehicles.passenger()
    speeds = np.array([5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0])
    swa = np.array([M.linear_swa(v, s, 0.5) for s in speeds])
    sc = M.step_steer(v, np.concatenate([speeds, speeds]), swa_deg=np.concatenate([swa, -swa]) / DEG,
                      t0=0.2, duration=3.0)
    variants = {
        "linear-bicycle effects (no Mz, no rolling resistance, no drag)":
            model.Effects(aligning_moment=False, aero=False, rolling_resistance=False),
        "+ rolling resistance": model.Effects(aligning_moment=False, aero=False),
        "full model (all effects)": model.Effects(),
    }
    tire = None
    n = len(speeds)
    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    rep["bicycle"] = {}
    for name, eff in variants.items():
        res = model.simulate(v, sc, eff, h=2e-3)
        tire = res.model.tire
        r, d, vx = res["r"][-1], res["delta"][-1], res["vx"][-1]
        gain = (r[:n] - r[n:]) / (d[:n] - d[n:])
        V = 0.5 * (vx[:n] + vx[n:])
        rep["bicycle"][name] = dict(speed=list(V), gain=list(gain))
        ax[0].plot(V, gain, "o-", label=name)
        rep["bicycle"][name]["V"] = list(V)
    fzf, fzr = v.static_loads()
    kf, kr = float(tire.cornering_stiffness(fzf)), float(tire.cornering_stiffness(fzr))
    A = M.stability_factor(v.m, v.lf, v.lr, kf, kr)
    rep["bicycle"]["kf"], rep["bicycle"]["kr"], rep["bicycle"]["A"] = kf, kr, A
    vv = np.linspace(1, 45, 100)
    ax[0].plot(vv, (vv / v.l) / (1 + A * vv ** 2), "k:", label="(V/l)/(1 + A V^2), eq. 2.18")
    ax[0].set_xlabel("speed [m/s]")
    ax[0].set_ylabel("r / delta [1/s]")
    ax[0].legend(fontsize=7)
    for name in variants:
        V = np.array(rep["bicycle"][name]["V"])
        g = np.array(rep["bicycle"][name]["gain"])
        ref = (V / v.l) / (1 + A * V ** 2)
        rep["bicycle"][name]["rel_dev"] = list(g / ref - 1)
        ax[1].plot(V, (g / ref - 1) * 100, "o-", label=name)
    ax[1].set_xlabel("speed [m/s]")
    ax[1].set_ylabel("deviation from eq. 2.18 [%]")
    ax[1].legend(fontsize=7)
    for a in ax:
        a.grid(True, alpha=0.3)
    fig.suptitle(f"Steady-state yaw-rate gain at ay = 0.5 m/s^2 (Kf = {kf:.0f}, Kr = {kr:.0f} N/rad, "
                 f"A = {A:.2e} s^2/m^2)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "bicycle_gain.png"), dpi=90)
    plt.close(fig)


def fmvss(out, rep):
    plt = _plt()
    fig, axs = plt.subplots(2, 2, figsize=(12, 7))
    rep["fmvss126"] = {}
    for col, (vname, surface) in enumerate((("passenger", "dry"), ("passenger", "wet"))):
        v = vehicles.get(vname)
        a03 = M.swa_at_03g(v, h=2e-3)
        scales = np.array([1.5, 2.5, 3.5, 4.5, 5.5, 6.5])
        amps = np.minimum(scales * a03, 270.0)
        sc = M.sine_dwell(v, amps, settle=2.0, surface=surface)
        res = model.simulate(v, sc, h=2e-3)
        rows = []
        for i, s in enumerate(scales):
            m = M.fmvss126_metrics(res, i)
            m.update(scale=float(s), amp_deg=float(amps[i]),
                     max_beta_deg=float(np.abs(res["beta"][:, i]).max() / DEG))
            rows.append(m)
            axs[0, col].plot(res.t, res["r"][:, i] / DEG, label=f"{s:.1f} x")
            axs[1, col].plot(res.t, res["beta"][:, i] / DEG, label=f"{s:.1f} x")
        rep["fmvss126"][f"{vname}/{surface}"] = dict(swa03_deg=a03, runs=rows)
        tc = sc.meta["t_cos"]
        for a in (axs[0, col], axs[1, col]):
            a.axvline(tc + 1.0, color="k", lw=0.5, ls=":")
            a.axvline(tc + 1.75, color="k", lw=0.5, ls=":")
            a.grid(True, alpha=0.3)
            a.legend(fontsize=7, ncol=2)
        axs[0, col].set_title(f"{vname}, {surface}: SWA(0.3 g) = {a03:.1f} deg (dry ramp)")
        axs[0, col].set_ylabel("yaw rate [deg/s]")
        axs[1, col].set_ylabel("sideslip beta [deg]")
        axs[1, col].set_xlabel("time [s] (dotted: COS + 1.00 s, + 1.75 s)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "sine_dwell.png"), dpi=90)
    plt.close(fig)


def sensors_fig(out, rep):
    v = vehicles.passenger()
    sc = M.sine_dwell(v, [80.0], settle=1.0)
    res = model.simulate(v, sc, h=2e-3, record_every=1)
    truth = res.member(0)
    sd = sensors.measure(truth, sensors.SensorConfig(seed=1))
    plt = _plt()
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.6))
    t, y = sd.series("YawRate")
    ax[0].plot(truth["time"], truth["r"] / DEG, "k", label="truth r")
    ax[0].plot(t, y, ".", ms=3, label="YawRate sensor")
    ax[0].set_xlim(0.9, 1.6)
    t, y = sd.series("LatAcc")
    ax[1].plot(truth["time"], truth["ay"], "k", label="truth ay (kinematic)")
    ax[1].plot(truth["time"], truth["ay_imu"], "b", lw=0.8, label="ay_imu (specific force, rolled)")
    ax[1].plot(t, y, ".", ms=3, label="LatAcc sensor")
    ax[1].set_xlim(0.9, 1.6)
    t, y = sd.series("WheelSpeed_FL")
    ax[2].plot(truth["time"], truth["re_omega_fl"] * 3.6, "k", label="truth")
    ax[2].plot(t, y, ".", ms=3, label="WheelSpeed_FL")
    ax[2].set_xlim(0.9, 1.6)
    for a in ax:
        a.legend(fontsize=7)
        a.grid(True, alpha=0.3)
        a.set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "sensors.png"), dpi=90)
    plt.close(fig)


def split_mu(out, rep):
    from grip_tools.sim.cli import plot_overview
    v = vehicles.passenger()
    sc = M.mu_split_brake(v)
    res = model.simulate(v, sc, h=1e-3)
    plot_overview(res, os.path.join(out, "mu_split.png"), 0, "split-mu braking (left 0.3, right 1.0), ABS")
    k = np.searchsorted(res.t, 0.8)
    rep["mu_split"] = dict(r_at_0p8_deg_s=float(res["r"][k, 0] / DEG),
                           beta_end_deg=float(res["beta"][-1, 0] / DEG),
                           v_end_kmh=float(res["vx"][-1, 0] * 3.6))


def replay_av21(out, rep, t_from=255.0, t_to=285.0):
    """Replay of the measured AV-21 steering and speed (open-loop steering,
    speed tracked by SpeedHold): simulated vs measured yaw rate."""
    if not os.path.exists(av21_log.LOG):
        print(f"replay_av21: {av21_log.LOG} not found, skipped")
        return
    d = av21_log.read()
    t = d["t"]
    sel = (t >= t_from) & (t <= t_to)
    v = vehicles.av21()
    sc = M.replay(v, t[sel], d["vx"][sel], delta=d["delta"][sel])
    res = model.simulate(v, sc, h=2e-3, record_every=10)
    ts = res.t + t[sel][0]
    om_meas = np.interp(ts, t, d["r"])
    vx_meas = np.interp(ts, t, d["vx"])
    om_sim = res["r"][:, 0]
    rep["replay_av21"] = dict(window_s=[t_from, t_to],
                              yaw_rms_err=float(np.sqrt(np.mean((om_sim - om_meas) ** 2))),
                              yaw_rms_meas=float(np.sqrt(np.mean(om_meas ** 2))),
                              yaw_corr=float(np.corrcoef(om_sim, om_meas)[0, 1]),
                              vx_rms_err=float(np.sqrt(np.mean((res["vx"][:, 0] - vx_meas) ** 2))))
    plt = _plt()
    fig, ax = plt.subplots(2, 1, figsize=(11, 6), sharex=True)
    ax[0].plot(ts, om_meas, "k", label="measured yaw rate (GNSS/INS)")
    ax[0].plot(ts, om_sim, "r", lw=0.9, label="simulated (av21 set, replayed steer and speed)")
    ax[0].set_ylabel("yaw rate [rad/s]")
    ax[0].legend(fontsize=8)
    ax[1].plot(ts, vx_meas, "k", label="measured vx")
    ax[1].plot(ts, res["vx"][:, 0], "r", lw=0.9, label="simulated vx")
    ax[1].plot(ts, res["ay"][:, 0], "b", lw=0.8, label="simulated ay [m/s^2]")
    ax[1].set_xlabel("log time [s]")
    ax[1].legend(fontsize=8)
    for a in ax:
        a.grid(True, alpha=0.3)
    fig.suptitle("Dallara AV-21 replay, Putnam Park run 4 (deep-dynamics log)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "replay_av21.png"), dpi=90)
    plt.close(fig)


def timing(rep):
    v = vehicles.passenger()
    m = model.Model(v)
    x = m.initial_state(np.array([20.0]))
    u = {"swa": np.array([0.1]), "p_master": np.zeros(1), "drive": np.zeros(1),
         "brake_factor": np.ones((1, 4)), "road": model.Road()}
    for _ in range(20):
        m.rhs(0.0, x, u)
    t0 = time.perf_counter()
    for _ in range(300):
        m.rhs(0.0, x, u)
    rhs = (time.perf_counter() - t0) / 300
    rep["timing_us"] = dict(rhs=round(rhs * 1e6, 1))


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m grip_tools.sim.report")
    p.add_argument("--out", default="docs/simulator")
    p.add_argument("--only", nargs="*", default=None)
    a = p.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "report.json")
    rep = {}
    if os.path.exists(path):
        with open(path) as f:
            rep = json.load(f)
    steps = dict(timing=lambda: timing(rep), step_halving=lambda: step_halving(a.out, rep),
                 bicycle=lambda: bicycle(a.out, rep), fmvss=lambda: fmvss(a.out, rep),
                 sensors=lambda: sensors_fig(a.out, rep), split_mu=lambda: split_mu(a.out, rep),
                 replay_av21=lambda: replay_av21(a.out, rep))
    for name, fn in steps.items():
        if a.only and name not in a.only:
            continue
        t0 = time.time()
        fn()
        print(f"{name}: {time.time() - t0:.1f} s", flush=True)
        with open(path, "w") as f:
            json.dump(rep, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
