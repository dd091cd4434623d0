"""Golden vectors of the ESC sensor-plausibility monitor (lib/monitor):
input sequences run through the float64 reference grip_tools.reference.monitor,
written as build/golden/monitor_<name>.txt for tests/unit/test_monitor.c.

Input sequences (the C test replays exactly the same rows):
  generator_100hz  golden_est's single-track generator (steer steps,
                   slalom, braking in a turn; road mu 1.0 then 0.5), no
                   injected fault (its steering jumps by up to 1.2 rad in one
                   sample where a phase starts: the monitor flags those steps)
  <signal>_100hz   the same run with the seven fault types of
                   grip_tools.evaluate.faults (dropout, stuck, spike, offset, scale,
                   delay, noise burst; the fault tool's magnitudes) on one
                   signal, one after the other (0.6 s each, 1 s apart);
                   signals ws_fl ws_fr ws_rl ws_rr steer yaw ax ay
  wheels_lost      three wheel speeds lost for 1 s: the monitor takes the
                   estimator's previous vx (est_ref run in the loop)
  yaw_chain_100hz  the yaw-rate faults with est_ref in the loop (its beta
                   and understeer indication hold the model checks off)
  mixed_1khz       the generator at 1 kHz (mu 0.6) with a yaw-rate offset,
                   a frozen steering angle, ay noise and NaN / out-of-range
                   values with the valid flag set

Each row: time, 18 input values, the valid mask (bit i = input i valid),
est_vx, est_beta, est_steer_char, est_valid (the fields of the previous
estimator output the monitor reads; est_valid 0 = no estimator output
given), then the reference outputs: code[0..8], faulty mask,
dropped mask, detected, resid[0..8] (the residual of each plausibility
check, 0 where it did not run), degraded. Configuration: monitor_ref.config() (the passenger
car of grip_monitor_config_default) at the sequence's rate.
"""
import math
import os

import numpy as np

from grip_tools.reference import est as est_ref, monitor as monitor_ref
from grip_tools.evaluate import faults
from grip_tools.golden import est as golden_est
from grip_tools.golden.io import header

SEED = 8
T_FAULT, T_GAP, T_START = 0.6, 1.0, 0.8


def _fmt(x):
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    x = float(x)
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


def inject_si(value, valid, idx, fault, k0, k1, mag, rng, rate):
    """One fault on input idx for rows k0 <= k < k1 (SI units, in place)."""
    if fault == "dropout":
        ks = k0 + faults.STALE_STEPS
        for k in range(k0, min(ks, k1)):
            value[k, idx] = value[k0 - 1, idx]
        valid[ks:k1, idx] = 0
        value[ks:k1, idx] = 0.0
    elif fault == "stuck":
        value[k0:k1, idx] = value[k0, idx]
    elif fault == "spike":
        every = int(round(faults.SPIKE_EVERY * rate / 100.0))
        for j, k in enumerate(range(k0, k1, every)):
            value[k, idx] += mag["spike"] if j % 2 == 0 else -mag["spike"]
    elif fault == "offset":
        value[k0:k1, idx] += mag["offset"]
    elif fault == "scale":
        value[k0:k1, idx] *= mag["scale"]
    elif fault == "delay":
        nd = int(round(faults.DELAY_T * rate))
        src = value[:, idx].copy()
        for k in range(k0, k1):
            value[k, idx] = src[max(k - nd, 0)]
    elif fault == "noise":
        value[k0:k1, idx] += rng.normal(0.0, mag["noise"], size=k1 - k0)
    else:
        raise ValueError(fault)


def si_mag(sig):
    """The fault tool's magnitudes (faults.MAG, CSV units) in SI."""
    name, _, _, si = sig[0], sig[1], sig[2], sig[3]
    m = faults.MAG["ws"] if name.startswith("ws") else faults.MAG[name]
    return dict(offset=m["offset"] * si, scale=m["scale"], spike=m["spike"] * si, noise=m["noise"] * si)


EST_BITS = est_ref.V_VX | est_ref.V_BETA | est_ref.V_STEER


def est_dict(col):
    """The estimator-output fields the monitor reads, from a golden row."""
    vx, beta, steer_char, valid = col
    return {"vx": vx, "beta": beta, "steer_char": steer_char, "valid": valid} if valid else None


def est_col(o):
    return (float(o["vx"]), float(o["beta"]), int(o["steer_char"]), int(o["valid"]) & EST_BITS)


def run_monitor(value, valid, rate, est_cols=None):
    mon = monitor_ref.Monitor(monitor_ref.config(rate_hz=rate))
    outs = []
    for k in range(len(value)):
        est = est_dict(est_cols[k]) if est_cols is not None else None
        outs.append(mon.step(value[k], valid[k], est))
    return outs


def run_chain(value, valid, rate):
    """monitor_ref -> est_ref in the loop; returns the estimator columns
    each monitor step saw (the previous estimator output)."""
    est = est_ref.Estimator(est_ref.config(golden_est.tire_params(), rate_hz=rate))
    mon = monitor_ref.Monitor(monitor_ref.config(rate_hz=rate))
    cols, prev = [], (0.0, 0.0, 0, 0)
    for k in range(len(value)):
        cols.append(prev)
        rep = mon.step(value[k], valid[k], est_dict(prev))
        prev = est_col(est.step(rep["value"], rep["valid"]))
    return cols


def write_sequence(outdir, name, rate, t, value, valid, note, est_cols=None):
    outs = run_monitor(value, valid, rate, est_cols)
    in_cols = (["t"] + [f"in{i}" for i in range(est_ref.N_IN)] +
               ["valid_mask", "est_vx", "est_beta", "est_steer_char", "est_valid"])
    out_cols = ([f"code{s}" for s in range(monitor_ref.N_MON)] + ["faulty", "dropped", "detected"] +
                [f"resid{s}" for s in range(monitor_ref.N_MON)] + ["degraded"])
    text = header("grip_tools.golden.monitor", monitor_ref.Monitor, SEED, in_cols + out_cols,
                  {"sequence": name, "rate_hz": rate, "config": "monitor_ref.config (passenger)", "note": note})
    lines = [text.rstrip("\n")]
    for k in range(len(t)):
        mask = int(sum(int(valid[k, i]) << i for i in range(est_ref.N_IN)))
        o = outs[k]
        dropped = sum(1 << s for s in range(monitor_ref.N_MON) if valid[k, s] and not o["valid"][s])
        ev = est_cols[k] if est_cols is not None else (0.0, 0.0, 0, 0)
        vals = ([float(t[k])] + [float(x) for x in value[k]] + [mask, ev[0], ev[1], int(ev[2]), int(ev[3])] +
                [int(c) for c in o["code"]] + [int(o["faulty"]), int(dropped), int(bool(o["detected"]))] +
                [float(r) for r in o["res"]] + [int(o["degraded"])])
        lines.append(" ".join(_fmt(x) for x in vals))
    with open(os.path.join(outdir, f"monitor_{name}.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")
    return outs


def sequences():
    """(name, rate, t, value, valid, note, est_cols) of every sequence."""
    seqs = []
    t, v0, ok0, _ = golden_est.bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 0.5), seed=SEED)
    seqs.append(("generator_100hz", 100, t, v0, ok0, "single-track generator, no injected fault", None))
    for gi, sig in enumerate(faults.SIGNALS):
        v, ok = v0.copy(), ok0.copy()
        mag = si_mag(sig)
        for fi, fault in enumerate(faults.FAULTS):
            k0 = int(round((T_START + fi * (T_FAULT + T_GAP)) * 100))
            k1 = k0 + int(round(T_FAULT * 100))
            inject_si(v, ok, sig[1], fault, k0, k1, mag, np.random.default_rng([SEED, gi, fi]), 100)
        seqs.append((f"{sig[0]}_100hz", 100, t, v, ok, f"seven faults on {sig[0]}", None))
    # three wheels lost: the estimator's vx is the monitor's speed
    v, ok = v0.copy(), ok0.copy()
    ok[300:400, 0:3] = 0
    v[300:400, 0:3] = 0.0
    seqs.append(("wheels_lost", 100, t, v, ok, "three wheel speeds lost 3..4 s, estimator in the loop",
                 run_chain(v, ok, 100)))
    # the yaw-rate faults again with the estimator in the loop (unstable-driving hold)
    name, _, t_, v, ok, _, _ = seqs[1 + 5]
    assert name == "yaw_100hz"
    seqs.append(("yaw_chain_100hz", 100, t_, v, ok, "seven yaw-rate faults, estimator in the loop",
                 run_chain(v, ok, 100)))
    # 1 kHz
    t, v, ok, _ = golden_est.bicycle_inputs(dt=0.001, duration=4.0, mu_road=(0.6, 0.6), seed=SEED + 1)
    rng = np.random.default_rng([SEED, 99])
    v[800:1400, est_ref.YAW] += 5.0 * math.pi / 180.0
    v[1600:2200, est_ref.STEER] = v[1600, est_ref.STEER]
    v[2400:2800, est_ref.AY] += rng.normal(0.0, 1.5, size=400)
    v[3000, est_ref.AX] = math.nan
    v[3100, est_ref.AY] = 40.0
    v[3200, 1] = math.inf
    seqs.append(("mixed_1khz", 1000, t, v, ok, "1 kHz: yaw offset, frozen steering, ay noise, NaN/range", None))
    return seqs


def write_golden(outdir):
    os.makedirs(outdir, exist_ok=True)
    for name, rate, t, v, ok, note, est_cols in sequences():
        write_sequence(outdir, name, rate, t, v, ok, note, est_cols)


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="grip golden-monitor", description=__doc__)
    ap.add_argument("-o", "--outdir", default="build/golden")
    a = ap.parse_args(argv)
    write_golden(a.outdir)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
