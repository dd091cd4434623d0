"""Accuracy of the onboard estimator on the reference simulator's manoeuvres.

    python -m grip_tools est-eval --runs DIR [DIR ...] [--out docs/estimator]
    python -m grip_tools est-eval --simulate --out docs/estimator

Each run directory holds a simulator output (python -m grip_tools simulate
... --out DIR: truth.csv, sensors.csv, summary.json). The estimator's
float64 reference (est_ref) is run over sensors.csv at 100 Hz (the sensors'
message rate) and compared with truth.csv:

  beta     RMS and max |beta_est - beta_true| [deg] over the rows where the
           estimate is valid and the true speed is above 5 m/s
  mu       the excitation onset t0 is the first time a tire of the TRUTH
           uses >= 50 % of its friction (|F| / (mu_peak Fz), mu_peak from the
           simulator's tire model and road); reported: |mu_est - mu_true| at
           t0 + 1 s, the share of time after t0 + 1 s with |error| <= 0.1,
           and the confidence at t0 + 1 s. mu_true = the road's scale of the
           tire's friction (the same meaning as the estimate's mu)
  Fy axle  RMS of the front / rear axle lateral force error (wheel frame)
           as a percentage of the run's peak |Fy| of that axle

Writes <out>/accuracy.json, <out>/accuracy.md (table) and <out>/accuracy.png.
With --c-outputs DIR the C outputs dumped by tests/unit/test_est_golden.c
(GRIP_EST_DUMP) are evaluated the same way (one column set per arithmetic).
"""
import argparse
import json
import math
import os
import sys

import numpy as np

from . import est_ref, golden_est

DEG = 180.0 / math.pi
WHEELS = ("fl", "fr", "rl", "rr")


def read_csv(path):
    with open(path) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    names = lines[0].strip().split(",")
    arr = np.genfromtxt(lines[1:], delimiter=",", dtype=float)
    if arr.ndim == 1:
        arr = arr[None, :]
    return {n: arr[:, k] for k, n in enumerate(names)}


def estimate(run_dir):
    """Runs est_ref over a run's sensors.csv; returns time and arrays."""
    cols = read_csv(os.path.join(run_dir, "sensors.csv"))
    t, value, valid = est_ref.inputs_from_sensors(cols)
    # The simulator's vehicle-speed signal is the true speed with sensor
    # noise, i.e. a calibrated reference: it may drive the longitudinal mu
    # update (grip_est_config_t.speed_ref_mu).
    cfg = est_ref.config(golden_est.tire_params(), rate_hz=100, speed_ref_mu=1)
    outs = est_ref.run(cfg, value, valid)
    res = {"time": t}
    res["beta"] = np.array([o["beta"] for o in outs])
    res["mu"] = np.array([o["mu"] for o in outs])
    res["mu_conf"] = np.array([o["mu_conf"] for o in outs])
    res["fyf"] = np.array([o["fy_axle"][0] for o in outs])
    res["fyr"] = np.array([o["fy_axle"][1] for o in outs])
    res["valid"] = np.array([o["valid"] for o in outs], dtype=np.int64)
    res["vx"] = np.array([o["vx"] for o in outs])
    return res


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
    util_t = np.zeros_like(t)
    for w in WHEELS:
        fz = np.maximum(at(f"fz_{w}"), 1.0)
        peak = np.maximum(np.maximum(at(f"mux_{w}"), at(f"muy_{w}")), 1e-3)
        util_t = np.maximum(util_t, np.hypot(at(f"fx_{w}"), at(f"fy_{w}")) / (peak * fz))
    ok = ((est["valid"] & est_ref.V_BETA) != 0) & (vx_t > 5.0)
    r = {"rows": int(len(t)), "valid_rows": int(ok.sum())}
    if ok.sum() == 0:
        return r
    e = (est["beta"] - beta_t)[ok] * DEG
    r["beta_rms_deg"] = float(np.sqrt(np.mean(e ** 2)))
    r["beta_max_deg"] = float(np.max(np.abs(e)))
    r["beta_true_max_deg"] = float(np.max(np.abs(beta_t[ok])) * DEG)
    for name, est_f, tru_f in (("front", est["fyf"], fyf_t), ("rear", est["fyr"], fyr_t)):
        peak = float(np.max(np.abs(tru_f[ok])))
        rms = float(np.sqrt(np.mean((est_f - tru_f)[ok] ** 2)))
        r[f"fy_{name}_peak_N"] = peak
        # a straight run (peak below 200 N) has no meaningful percentage
        r[f"fy_{name}_rms_pct"] = 100.0 * rms / peak if peak >= 200.0 else None
        r[f"fy_{name}_rms_N"] = rms
    exc = np.nonzero((util_t >= 0.5) & (vx_t > 5.0))[0]
    r["mu_true_end"] = float(mu_t[-1])
    r["mu_est_end"] = float(est["mu"][-1])
    if len(exc):
        t0 = float(t[exc[0]])
        k1 = int(np.searchsorted(t, t0 + 1.0))
        r["mu_t0"] = t0
        if k1 < len(t):
            r["mu_err_1s"] = float(abs(est["mu"][k1] - mu_t[k1]))
            r["mu_conf_1s"] = float(est["mu_conf"][k1])
            after = slice(k1, len(t))
            r["mu_within_0p1_pct"] = float(100.0 * np.mean(np.abs(est["mu"][after] - mu_t[after]) <= 0.1))
    else:
        r["mu_t0"] = None
    return r


def simulate_runs(outdir, manoeuvres, surfaces):
    """Runs the simulator (python -m grip_tools simulate) for each pair."""
    from .vehsim import cli
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
           "| mu err @ t0+1 s | mu within 0.1 after t0+1 s | conf @ t0+1 s | Fy front RMS [% peak] "
           "| Fy rear RMS [% peak] |")
    lines = [hdr, "|" + "---|" * 11]

    def f(x, fmt):
        return "-" if x is None else format(x, fmt)

    for name, r in results.items():
        lines.append("| " + " | ".join([
            name, f(r.get("beta_rms_deg"), ".2f"), f(r.get("beta_max_deg"), ".2f"),
            f(r.get("beta_true_max_deg"), ".1f"), f(r.get("mu_true_end"), ".2f"), f(r.get("mu_est_end"), ".2f"),
            f(r.get("mu_err_1s"), ".2f"), f(r.get("mu_within_0p1_pct"), ".0f") + ("" if r.get("mu_within_0p1_pct") is None else " %"),
            f(r.get("mu_conf_1s"), ".2f"), f(r.get("fy_front_rms_pct"), ".1f"), f(r.get("fy_rear_rms_pct"), ".1f")]) + " |")
    return "\n".join(lines) + "\n"


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
    ap = argparse.ArgumentParser(prog="grip_tools est-eval", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", nargs="*", default=[], help="simulator output directories")
    ap.add_argument("--simulate", action="store_true", help="run the standard manoeuvres first")
    ap.add_argument("--out", default="build/est_eval")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    runs = list(a.runs)
    if a.simulate:
        runs += simulate_runs(a.out, ("step-steer", "ramp-steer", "sine-dwell", "brake-in-turn", "mu-step"),
                              ("dry", "wet", "snow"))
    results, ests = {}, []
    for d in runs:
        est = estimate(d)
        ests.append(est)
        results[os.path.basename(d.rstrip("/"))] = evaluate(d, est)
        print(f"est-eval: {d}: {results[os.path.basename(d.rstrip('/'))]}", file=sys.stderr)
    with open(os.path.join(a.out, "accuracy.json"), "w") as f:
        json.dump(results, f, indent=1)
    md = table(results)
    with open(os.path.join(a.out, "accuracy.md"), "w") as f:
        f.write(md)
    print(md)
    if runs:
        plot(runs, ests, os.path.join(a.out, "accuracy.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
