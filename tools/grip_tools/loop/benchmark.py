"""Generality benchmark of the measured-data loop: tyre-rig data sets with
ONE undeclared effect each, generated with physics of their own (never the
grammar's fitted forms), analysed blind with a forward hold-out.

Rig test plan (plan()): alternating blocks and rests at random: a block
holds a speed (6..25 m/s), one to three load levels (0.4..1.6 FNOMIN), a
camber level (when the plan varies camber) and an inflation pressure (when
it varies pressure), and runs one programme: a lateral sweep (alpha
triangle, 4..10 deg, 0.05..0.2 Hz), a longitudinal sweep (kappa 0.05..0.15),
a combined sweep, or dynamic steering (sines of 0.5..3 Hz); a rest rolls
free at 0.3 FNOMIN. Levels ramp over 1 s, programmes fade in and out over
0.5 s. Outputs fx, fy, mz from reference/mf.py with the MF 6.1 example
(tests/data/mfeval-tir/MagicFormula61_Paramerters.tir, TYRESIDE = RIGHT,
evaluated as fitted) plus the effect, then white noise of 0.4..0.8 % of each
output's peak (the noise floor of the criteria).

Kinds (KINDS; the effect's own physics, random parameters):
  friction_temperature   two-node thermal model (tread surface, carcass)
                         heated by eta |F| Vs of the true forces (solved by
                         fixed-point iteration), cooled to ambient; friction
                         x (1 - c ((Ts - Topt) / 50)^2), Topt below ambient
  stiffness_temperature  the same thermal model; slip stiffnesses x
                         exp(-(Tc - Tamb) / theta_E) (carcass node)
  pressure_heating       the same thermal model; the inflation gas follows the
                         carcass: p = p_set (Tc + 273.15) / (Tamb + 273.15),
                         the recorded p stays p_set
  trail_temperature      the same thermal model; pneumatic trail x
                         (1 - b (Ts - Tamb) / 50)
  load_power             friction x (Fz / FNOMIN)^q, q in [-0.3, -0.12]
  load_peaked            friction x (1 - c ln(Fz / FNOMIN)^2)
  stiffness_load         PKY2 and PKX2 of the set changed by 20..40 %
  speed_friction         friction x (|vx| / 15 m/s)^-m
  slip_speed_friction    friction x (r + (1 - r) exp(-(Vs / v_s)^delta))
  relaxation             alpha, kappa through first-order lags with
                         sigma_alpha = sigma0 (Fz / FNOMIN)^0.6 and a shorter
                         sigma_kappa, stepped exactly for inputs linear
                         over the step (first-order hold); low speed, 100 Hz
  sensor_lowpass         every force channel through a 2nd-order
                         Butterworth low-pass, cutoff 2..5 Hz
  gain_drift             one output's gain 1 + g (1 - exp(-t / tau))
  offset_drift           one output's zero b (1 - exp(-t / tau))
  alpha_drift            the rig's slip angle off by d0 + d1 (1 - exp(-t / tau))
  fz_scale               the load cell reads Fz / (1 + s)
  rig_compliance         the wheel yields to Fy: alpha_true = alpha + c Fy
  camber_thrust          extra camber thrust c gamma Fz / (1 + (alpha / 0.15)^2)
  pressure_sensitivity   slip stiffnesses x (p / NOMPRES)^c, p varied per block
  null                   the base model and noise only

Criteria per set (assess()), on the forward hold-out (fit on the first 70 %,
judged on the last 30 %): named correctly (the chosen candidate's
(target, driver) or name is one the kind accepts: ACCEPT), held-out error
halved (on every output whose base-model held-out RMS is at least 1.5 x
its noise floor, the RMS after is at most (base + floor) / 2); null sets:
nothing named and no output more than 5 % worse.

    grip analyze --benchmark N --out DIR [--seed S] [--duration T] [--rate HZ] [--jobs J]
"""
import json
import math
import os
import time
from dataclasses import dataclass, field

import numpy as np

from grip_tools.loop import attribution, datasets
from grip_tools.loop.effects import TireModel
from grip_tools.loop.io import Dataset

T_AMB = 25.0

FRICTION = ("mu", "mux", "muy", "mu2", "grip")
STIFFNESS = ("k", "kx", "ky", "k2", "grip", "kya", "kxk", "kc", "kc2")
ENERGY = ("state:energy", "state2:energy")      # first- or second-order states of the friction power
DRIFT = ("time", "state:run", "state2:run")      # slow changes with running time


def _acc(targets, drivers, names=()):
    return {"pairs": {(t, d) for t in targets for d in drivers}, "names": set(names)}


def _out_acc(mode, o, drivers):
    return {"pairs": {(f"out:{mode}:{o}", d) for d in drivers} | {(f"out:{mode}", d) for d in drivers},
            "names": set()}


# what each kind accepts as named correctly: the coefficient group the
# effect changes (a target containing it) and the physical driver
ACCEPT = {
    "friction_temperature": _acc(FRICTION, (ENERGY), ("thermal",)),
    "stiffness_temperature": _acc(STIFFNESS, (ENERGY), ("thermal",)),
    "pressure_heating": _acc(("in:p",), (ENERGY)),
    "trail_temperature": _acc(("trail",), (ENERGY)),
    "load_power": _acc(FRICTION, ("dfz", "dfz2"), ("load_sensitivity",)),
    "load_peaked": _acc(FRICTION, ("dfz2",)),
    "stiffness_load": _acc(STIFFNESS, ("dfz", "dfz2")),
    "speed_friction": _acc(FRICTION, ("v", "v2")),
    "slip_speed_friction": _acc(FRICTION, ("vs", "vs2"), ("slip_velocity_friction",)),
    "relaxation": _acc(("lag:relax", "lag:relax2"), ("const",), ("relaxation", "relaxation2")),
    "sensor_lowpass": _acc(("out:delay",), ("const",), ("sensor_delay",)),
    "alpha_drift": _acc(("in:alpha",), DRIFT),
    "fz_scale": _acc(("in:fz",), ("const",)),
    "rig_compliance": {"pairs": _acc(("ky", "k", "grip", "kya", "kc"), ("const", "dfz", "dfz2"))["pairs"]
                       | {("in:alpha", "fy")}, "names": set()},
    "camber_thrust": {"pairs": {("kyc", "const"), ("svy", "gamma"), ("svy", "gamma2")}, "names": {"camber"}},
    "pressure_sensitivity": _acc(STIFFNESS, ("dpi", "dpi2"), ("inflation_pressure",)),
    # gain_drift / offset_drift: filled per set (the drifting output)
}
KINDS = ("friction_temperature", "stiffness_temperature", "pressure_heating", "trail_temperature",
         "load_power", "load_peaked", "stiffness_load", "speed_friction", "slip_speed_friction",
         "relaxation", "sensor_lowpass", "gain_drift", "offset_drift", "alpha_drift", "fz_scale",
         "rig_compliance", "camber_thrust", "pressure_sensitivity", "null")


@dataclass
class Truth:
    kind: str
    params: dict
    floor: dict                     # output -> noise standard deviation
    accept: dict = field(default_factory=dict)
    seed: int = 0


# ---------------------------------------------------------------------------
# test plan

def _smooth(x, width):
    w = max(int(width), 1)
    if w <= 1:
        return x
    k = np.ones(w) / w
    pad = np.concatenate([np.full(w, x[0]), x, np.full(w, x[-1])])
    return np.convolve(pad, k, mode="same")[w:-w]


def _tri(x):
    """smooth triangle wave of period 1, amplitude 1"""
    return (2.0 / math.pi) * np.arcsin(np.sin(2 * math.pi * x))


def plan(rng, duration, rate, fz0, nompres, camber=False, pressure=False, speed=(6.0, 25.0), dynamic=0.25):
    """Inputs of a random rig test: dict t, alpha, kappa, gamma, fz, p, vx
    and 'block' (1 inside a programme, 0 at rest)."""
    n = int(round(duration * rate))
    t = np.arange(n) / rate
    alpha, kappa = np.zeros(n), np.zeros(n)
    fz, vx, gam, p = (np.zeros(n) for _ in range(4))
    block = np.zeros(n)
    cur = 0.0
    v_now = rng.uniform(*speed)
    first = True
    while cur < duration:
        rest = rng.uniform(2.0, 5.0) if first else rng.uniform(5.0, 20.0)
        first = False
        i0, i1 = int(cur * rate), min(int((cur + rest) * rate), n)
        fz[i0:i1], vx[i0:i1] = 0.3 * fz0, v_now
        gam[i0:i1] = gam[i0 - 1] if i0 > 0 else 0.0
        p[i0:i1] = p[i0 - 1] if i0 > 0 else nompres
        cur += rest
        if cur >= duration:
            break
        blen = rng.uniform(12.0, 35.0)
        i0, i1 = int(cur * rate), min(int((cur + blen) * rate), n)
        m = i1 - i0
        if m <= 0:
            break
        v_now = rng.uniform(*speed)
        vx[i0:i1] = v_now
        gam[i0:i1] = math.radians(rng.uniform(-3.0, 3.0)) if camber else 0.0
        p[i0:i1] = nompres * (rng.uniform(0.8, 1.2) if pressure else 1.0)
        nl = rng.integers(1, 4)
        cuts = np.sort(rng.integers(0, m, nl - 1)) if nl > 1 else np.array([], int)
        edges = np.concatenate([[0], cuts, [m]])
        for a, b in zip(edges[:-1], edges[1:]):
            fz[i0 + a:i0 + b] = fz0 * rng.uniform(0.4, 1.6)
        tb = t[i0:i1] - t[i0]
        env = np.clip(np.minimum(tb, tb[-1] - tb) / 0.5, 0.0, 1.0)
        env = 0.5 - 0.5 * np.cos(math.pi * env)
        prog = rng.choice(["lat", "long", "comb", "dyn"],
                          p=[0.45 * (1 - dynamic), 0.275 * (1 - dynamic), 0.275 * (1 - dynamic), dynamic])
        ph = rng.uniform(0, 1)
        if prog == "lat":
            alpha[i0:i1] = math.radians(rng.uniform(4, 10)) * _tri(rng.uniform(0.05, 0.2) * tb + ph) * env
            kappa[i0:i1] = 0.0
        elif prog == "long":
            kappa[i0:i1] = rng.uniform(0.05, 0.15) * _tri(rng.uniform(0.05, 0.2) * tb + ph) * env
            alpha[i0:i1] = math.radians(rng.uniform(-1, 1)) * env
        elif prog == "comb":
            alpha[i0:i1] = math.radians(rng.uniform(3, 8)) * _tri(rng.uniform(0.04, 0.1) * tb + ph) * env
            kappa[i0:i1] = rng.uniform(0.04, 0.1) * _tri(rng.uniform(0.15, 0.4) * tb) * env
        else:
            f = rng.uniform(0.5, 3.0, 3)
            amp = rng.uniform(0.3, 1.0, 3)
            s = sum(a * np.sin(2 * math.pi * fr * tb + rng.uniform(0, 6)) for a, fr in zip(amp, f))
            alpha[i0:i1] = math.radians(rng.uniform(2, 5)) * s / np.max(np.abs(s)) * env
            kappa[i0:i1] = rng.uniform(0.0, 0.04) * np.sin(2 * math.pi * rng.uniform(0.3, 1.5) * tb) * env
        block[i0:i1] = 1.0
        cur += blen
    w = int(rate)                              # actuators ramp the levels over ~1 s
    fz, vx, gam, p = (_smooth(x, w) for x in (fz, vx, gam, p))
    return {"t": t, "alpha": alpha, "kappa": kappa, "gamma": gam, "fz": fz, "vx": vx, "p": p, "block": block}


# ---------------------------------------------------------------------------
# the effects' own physics

def two_node(t, q, tau_sc, tau_sa, tau_cs, tau_ca, eta):
    """Surface Ts and carcass Tc [degC]: dTs/dt = eta q - (Ts - Tc)/tau_sc -
    (Ts - Tamb)/tau_sa, dTc/dt = (Ts - Tc)/tau_cs - (Tc - Tamb)/tau_ca
    (explicit Euler at the sample step)."""
    dt = np.diff(t, prepend=t[0]).tolist()
    ql = np.asarray(q, dtype=float).tolist()
    ts, tc = T_AMB, T_AMB
    Ts, Tc = [0.0] * len(ql), [0.0] * len(ql)
    for i in range(len(ql)):
        h = dt[i]
        dts = eta * ql[i] - (ts - tc) / tau_sc - (ts - T_AMB) / tau_sa
        dtc = (ts - tc) / tau_cs - (tc - T_AMB) / tau_ca
        ts, tc = ts + h * dts, tc + h * dtc
        Ts[i], Tc[i] = ts, tc
    return np.array(Ts), np.array(Tc)


def _vs(ch):
    return np.abs(ch["vx"]) * np.hypot(ch["kappa"], np.tan(ch["alpha"]))


def _thermal(rng, ch, model, node, dT_target, make_over, iters=3, eta_ch=None):
    """Solve forces and temperatures together: the heat is eta |F| Vs of the
    forces the heated tyre produces. make_over(Ts, Tc) -> (over dict,
    coefficients changed). eta: the node's peak reaches dT_target on the
    base model's heat on the plan eta_ch (default: ch). Returns outputs, Ts,
    Tc, params."""
    taus = dict(tau_sc=rng.uniform(5, 20), tau_sa=rng.uniform(20, 60), tau_cs=rng.uniform(40, 120),
                tau_ca=rng.uniform(100, 300))
    e_ch = ch if eta_ch is None else eta_ch
    o1 = model.predict(e_ch)
    Ts1, Tc1 = two_node(e_ch["t"], np.hypot(o1["fx"], o1["fy"]) * _vs(e_ch), eta=1.0, **taus)
    ref = (Ts1 if node == "s" else Tc1) - T_AMB
    eta = dT_target / max(float(np.max(ref)), 1e-9)
    out = model.predict(ch)
    vs = _vs(ch)
    q = np.hypot(out["fx"], out["fy"]) * vs
    for _ in range(iters):
        Ts, Tc = two_node(ch["t"], q, eta=eta, **taus)
        over = make_over(Ts, Tc)
        out = model.predict(ch, over)
        q = np.hypot(out["fx"], out["fy"]) * vs
    return out, Ts, Tc, dict(taus, eta=eta, dT_target=dT_target)


def _relax_foh(x, v, t, sigma):
    """dx'/ds = (x - x')/sigma, x linear over each step (exact)."""
    ds = np.abs(v) * np.diff(t, prepend=t[0])
    sg = np.broadcast_to(np.asarray(sigma, dtype=float), x.shape)
    xl, dl, sl = x.tolist(), ds.tolist(), sg.tolist()
    y = [0.0] * len(xl)
    s = xl[0]
    for i in range(len(xl)):
        if i == 0 or dl[i] <= 0.0:
            s = xl[i] if i == 0 else s
            y[i] = s
            continue
        a = dl[i] / sl[i]
        e = math.exp(-a)
        dx = xl[i] - xl[i - 1]
        s = xl[i] - dx / a * (1.0 - e) + (s - xl[i - 1]) * e
        y[i] = s
    return np.array(y)


def _butter_lowpass(y, rate, fc):
    from scipy.signal import butter, lfilter
    b, a = butter(2, fc / (0.5 * rate))
    return lfilter(b, a, y - y[0]) + y[0]


def _rig_plan(kind, prng, duration, rate, fz0, nom):
    """The test plan of a kind: (inputs, rate, duration, camber, pressure)"""
    camber = kind == "camber_thrust" or (kind not in ("pressure_sensitivity",) and prng.uniform() < 0.4)
    pressure = kind == "pressure_sensitivity" or (kind not in ("pressure_heating", "camber_thrust")
                                                  and prng.uniform() < 0.3)
    speed, dyn, r = (6.0, 25.0), 0.25, rate
    if kind == "relaxation":
        speed, dyn, r = (3.0, 10.0), 0.6, max(rate, 100.0)
        duration = min(duration, 90.0)
    if kind == "sensor_lowpass":
        dyn = 0.5
    ch = plan(prng, duration, r, fz0, nom, camber=camber, pressure=pressure, speed=speed, dynamic=dyn)
    return ch, r, duration, camber, pressure


def generate(kind, seed, duration=150.0, rate=40.0, noise=None, plan_seed=None):
    """(Dataset, Truth) of one benchmark set. plan_seed: another test plan
    (and noise) for the same tyre and effect (the effect's parameters come
    from seed)."""
    if kind not in KINDS:
        raise ValueError(f"unknown benchmark kind {kind!r}; kinds: {', '.join(KINDS)}")
    rng = np.random.default_rng(seed)
    prng = rng if plan_seed is None else np.random.default_rng(plan_seed)
    P = datasets.base_params()
    fz0, nom = float(P["fnomin"]), float(P["nompres"])
    ch, r, duration, camber, pressure = _rig_plan(kind, prng, duration, rate, fz0, nom)
    # the thermal kinds scale the heat input eta to the peak temperature on
    # the plan; another plan of the same tyre keeps the eta of the seed's own
    # plan (eta is the tyre's, not the plan's)
    eta_ch = None if plan_seed in (None, seed) else _rig_plan(kind, np.random.default_rng(seed), duration, rate,
                                                               fz0, nom)[0]
    t = ch["t"]
    model = TireModel(P)
    rec = {k: v.copy() for k, v in ch.items() if k != "block"}      # what the rig records
    prm = {}
    outs = ("fx", "fy", "mz")
    post = None                                                       # a sensor fault on the outputs
    acc = ACCEPT.get(kind, {"pairs": set(), "names": set()})
    if kind in ("friction_temperature", "stiffness_temperature", "pressure_heating", "trail_temperature"):
        if kind == "friction_temperature":
            drop, t_opt = rng.uniform(0.08, 0.18), T_AMB - rng.uniform(0.0, 10.0)
            dT = rng.uniform(30.0, 60.0)
            c = drop / ((T_AMB + dT - t_opt) / 50.0) ** 2

            def mk(Ts, Tc):
                f = 1.0 - c * ((Ts - t_opt) / 50.0) ** 2 + c * ((T_AMB - t_opt) / 50.0) ** 2
                return {"lmux": f, "lmuy": f}
            node, prm = "s", dict(drop=drop, t_opt=t_opt, c=c)
        elif kind == "stiffness_temperature":
            dT, drop = rng.uniform(20.0, 40.0), rng.uniform(0.12, 0.25)
            th = -dT / math.log(1.0 - drop)

            def mk(Ts, Tc):
                f = np.exp(-(Tc - T_AMB) / th)
                return {"lkx": f, "lky": f}
            node, prm = "c", dict(theta_E=th, drop=drop)
        elif kind == "pressure_heating":
            rise = rng.uniform(0.06, 0.14)
            dT = rise * (T_AMB + 273.15)
            p_set = rec["p"]

            def mk(Ts, Tc):
                return {"p": p_set * (Tc + 273.15) / (T_AMB + 273.15)}
            node, prm = "c", dict(p_rise=rise)
        else:
            dT, drop = rng.uniform(30.0, 60.0), rng.uniform(0.15, 0.3)
            b = drop / (dT / 50.0)

            def mk(Ts, Tc):
                return {"ltr": np.maximum(1.0 - b * (Ts - T_AMB) / 50.0, 0.05)}
            node, prm = "s", dict(b=b, drop=drop)
        out, Ts, Tc, tp = _thermal(rng, ch, model, node, dT, mk, eta_ch=eta_ch)
        prm.update(tp, dT_peak=float(np.max((Ts if node == "s" else Tc) - T_AMB)))
    elif kind == "load_power":
        q = rng.uniform(-0.3, -0.12)
        f = (np.maximum(ch["fz"], 1.0) / fz0) ** q
        out = model.predict(ch, {"lmux": f, "lmuy": f})
        prm = dict(q=q)
    elif kind == "load_peaked":
        c = rng.uniform(0.15, 0.3)
        f = 1.0 - c * np.log(np.maximum(ch["fz"], 1.0) / fz0) ** 2
        out = model.predict(ch, {"lmux": f, "lmuy": f})
        prm = dict(c=c)
    elif kind == "stiffness_load":
        d1 = rng.choice([-1, 1]) * rng.uniform(0.2, 0.4)
        d2 = rng.choice([-1, 1]) * rng.uniform(0.2, 0.4)
        P2 = dict(P, pky2=P["pky2"] * (1 + d1), pkx2=P["pkx2"] * (1 + d2))
        out = TireModel(P2).predict(ch)
        prm = dict(pky2_rel=d1, pkx2_rel=d2)
    elif kind == "speed_friction":
        m = rng.uniform(0.08, 0.2)
        f = (np.maximum(np.abs(ch["vx"]), 0.5) / 15.0) ** (-m)
        out = model.predict(ch, {"lmux": f, "lmuy": f})
        prm = dict(m=m)
    elif kind == "slip_speed_friction":
        rr, vsc, dl = rng.uniform(0.6, 0.85), rng.uniform(1.5, 5.0), rng.uniform(0.8, 1.4)
        f = rr + (1 - rr) * np.exp(-(_vs(ch) / vsc) ** dl)
        out = model.predict(ch, {"lmux": f, "lmuy": f})
        prm = dict(ratio=rr, v_s=vsc, delta=dl)
    elif kind == "relaxation":
        s0 = rng.uniform(0.3, 0.8)
        sk = rng.uniform(0.3, 0.6)
        sa = s0 * (np.maximum(ch["fz"], 1.0) / fz0) ** 0.6
        at = _relax_foh(ch["alpha"], ch["vx"], t, sa)
        kt = _relax_foh(ch["kappa"], ch["vx"], t, sk * sa)
        out = model.predict(ch, {"alpha": at, "kappa": kt})
        prm = dict(sigma0=s0, sigma_kappa_ratio=sk)
    elif kind == "sensor_lowpass":
        fc = rng.uniform(2.0, 5.0)
        out = model.predict(ch)
        post = lambda o, y: _butter_lowpass(y, r, fc)      # noqa: E731
        prm = dict(cutoff_hz=fc)
    elif kind in ("gain_drift", "offset_drift"):
        o_d = str(rng.choice(outs))
        tau = rng.uniform(0.3, 1.0) * duration
        out = model.predict(ch)
        if kind == "gain_drift":
            g = rng.choice([-1, 1]) * rng.uniform(0.04, 0.1)
            post = lambda o, y: y * (1 + g * (1 - np.exp(-t / tau))) if o == o_d else y   # noqa: E731
            prm = dict(output=o_d, gain=g, tau=tau)
            acc = _out_acc("scale", o_d, DRIFT)
        else:
            prm = dict(output=o_d, tau=tau, sign=float(rng.choice([-1, 1])), size=rng.uniform(4.0, 10.0))
            acc = _out_acc("offset", o_d, DRIFT)
    elif kind == "alpha_drift":
        d0 = math.radians(rng.choice([-1, 1]) * rng.uniform(0.05, 0.2))
        d1 = math.radians(rng.choice([-1, 1]) * rng.uniform(0.3, 0.6))
        tau = rng.uniform(0.5, 2.0) * duration
        out = model.predict(ch, {"alpha": ch["alpha"] + d0 + d1 * (1 - np.exp(-t / tau))})
        prm = dict(d0_deg=math.degrees(d0), d1_deg=math.degrees(d1), tau=tau)
    elif kind == "fz_scale":
        s = rng.choice([-1, 1]) * rng.uniform(0.05, 0.12)
        out = model.predict(ch)          # the tyre ran the true load ...
        rec["fz"] = ch["fz"] / (1 + s)   # ... the cell reads it off by 1 + s
        prm = dict(s=s)
    elif kind == "rig_compliance":
        d = mf_details(P, fz0)
        cK = rng.uniform(0.1, 0.3)
        c = cK / d["Kya"]
        a = ch["alpha"].copy()
        for _ in range(6):
            fy = model.predict(ch, {"alpha": a})["fy"]
            a = ch["alpha"] + c * fy
        out = model.predict(ch, {"alpha": a})
        prm = dict(c_Ky0=cK)
    elif kind == "camber_thrust":
        c = rng.choice([-1, 1]) * rng.uniform(0.5, 1.0)
        out = dict(model.predict(ch))
        out["fy"] = out["fy"] + c * ch["gamma"] * ch["fz"] / (1.0 + (ch["alpha"] / 0.15) ** 2)
        prm = dict(c=c)
    elif kind == "pressure_sensitivity":
        c = rng.choice([-1, 1]) * rng.uniform(0.5, 1.0)
        f = (ch["p"] / nom) ** c
        out = model.predict(ch, {"lkx": f, "lky": f})
        prm = dict(c=c)
    else:
        out = model.predict(ch)
    frac = rng.uniform(0.004, 0.008) if noise is None else noise
    nrng = rng if plan_seed is None else prng
    data, floor = dict(rec), {}
    for o in outs:
        y = np.asarray(out[o], dtype=float)
        if post is not None:
            y = post(o, y)
        sd = frac * float(np.max(np.abs(y)))
        floor[o] = sd
        data[o] = y + sd * nrng.standard_normal(len(y))
    if kind == "offset_drift":
        o_d, tau = prm["output"], prm["tau"]
        b = prm["sign"] * prm["size"] * floor[o_d]
        data[o_d] = data[o_d] + b * (1 - np.exp(-t / tau))
        prm["offset"] = b
    if not (pressure or kind == "pressure_heating"):
        data.pop("p")                    # a rig without a pressure channel: p is nominal
    units = {"t": "s", "alpha": "rad", "kappa": "-", "gamma": "rad", "fz": "N", "vx": "m/s", "p": "Pa",
             "fx": "N", "fy": "N", "mz": "Nm"}
    ds = Dataset(t, data, {k: units[k] for k in data}, list(outs),
                 {"generator": "benchmark.generate", "kind": kind, "seed": seed,
                  "source": f"benchmark.generate('{kind}', seed={seed}, duration={duration:g}, rate={r:g}"
                            + (f", plan_seed={plan_seed})" if plan_seed is not None else ")")})
    return ds, Truth(kind, prm, floor, acc, seed)


def mf_details(P, fz):
    from grip_tools.reference import mf
    o = mf.evaluate(P, 0.0, 0.0, 0.0, fz, None, None, details=True)
    return {k: abs(float(np.ravel(o["details"][k])[0])) for k in ("Kya", "Kxk", "muy", "mux")}


# ---------------------------------------------------------------------------
# assessment

@dataclass
class Outcome:
    kind: str
    seed: int
    chosen: str
    family: tuple
    named: bool
    halved: bool
    detectable: bool
    worse: float                  # largest held-out RMS ratio after / before over the outputs
    rows: int
    cpu_s: float
    per_output: dict              # o -> (base held-out RMS, after, floor)
    score: float
    params: dict
    truth: dict
    correction: str = ""
    ranked: list = field(default_factory=list)   # every ranked candidate (name, family, k, score, IC, ...)
    n_eff: float = 0.0

    @property
    def ok(self):
        if self.kind == "null":
            return self.named and self.worse <= 1.05
        return self.named and self.halved


def assess(ds, truth, res):
    """Outcome of one analysed set (module doc: the criteria)."""
    c = res.chosen
    after = {}
    for o in ds.outputs:
        if c is not None:
            after[o] = c.ho_rms[o]
        elif res.correction is not None and res.correction.useful:
            after[o] = res.correction.ho_rms[o]
        else:
            after[o] = res.base_ho_rms[o]
    per = {o: (res.base_ho_rms[o], after[o], truth.floor[o]) for o in ds.outputs}
    big = [o for o in ds.outputs if res.base_ho_rms[o] >= 1.5 * truth.floor[o]]
    halved = all(after[o] <= 0.5 * (res.base_ho_rms[o] + truth.floor[o]) for o in big)
    worse = max(after[o] / max(res.base_ho_rms[o], 1e-12) for o in ds.outputs)
    if truth.kind == "null":
        named = c is None
    else:
        named = c is not None and (c.family in truth.accept["pairs"] or c.name in truth.accept["names"])
    return Outcome(truth.kind, truth.seed, c.name if c else "", tuple(c.family) if c else (), bool(named),
                   bool(halved), bool(big), float(worse), len(ds),
                   float(res.search.get("cpu_s", 0.0)), per, float(c.score if c else 1.0),
                   dict(c.params) if c else {}, dict(truth.params),
                   res.correction.summary() if res.correction is not None else "",
                   [{"name": d.name, "family": list(d.family), "families": [list(f) for f in d.families],
                     "k": d.k, "score": d.score, "ic": d.ic, "kind": d.kind, "accepted": d.accepted,
                     "score2": d.score2, "ic2": d.ic2, "ho_rms": dict(d.ho_rms)} for d in res.ranked],
                   float(res.search.get("n_eff", 0.0)))


def run_one(args):
    kind, seed, duration, rate, holdout = args
    ds, truth = generate(kind, seed, duration, rate)
    model = TireModel(datasets.base_params(), "MagicFormula61_Paramerters.tir (as fitted)", datasets.TIR)
    res = attribution.analyse(model, ds, holdout=holdout)
    return assess(ds, truth, res)


def schedule(n, seed=0, kinds=KINDS, null_extra=1):
    """n (kind, seed) pairs: the kinds in shuffled rounds (every kind once per
    round, the null kind 1 + null_extra times), a fresh seed per set."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        rnd = list(kinds) + ["null"] * null_extra
        rng.shuffle(rnd)
        out += [(k, int(rng.integers(1, 2 ** 31 - 1))) for k in rnd]
    return out[:n]


def run(n, seed=0, duration=150.0, rate=40.0, jobs=2, holdout="forward:0.3", kinds=KINDS, progress=None,
        plan_=None):
    """Outcomes of n sets, `jobs` processes."""
    sched = plan_ or schedule(n, seed, kinds)
    args = [(k, s, duration, rate, holdout) for k, s in sched]
    out = []
    if jobs > 1:
        import multiprocessing as mp
        ctx = mp.get_context("fork")
        with ctx.Pool(jobs) as pool:
            for i, r in enumerate(pool.imap(run_one, args)):
                out.append(r)
                if progress is not None:
                    progress(i + 1, len(args), r)
    else:
        for i, a in enumerate(args):
            r = run_one(a)
            out.append(r)
            if progress is not None:
                progress(i + 1, len(args), r)
    return out


def summary(outcomes):
    eff = [o for o in outcomes if o.kind != "null"]
    nul = [o for o in outcomes if o.kind == "null"]
    det = [o for o in eff if o.detectable]
    s = {"sets": len(outcomes), "effect_sets": len(eff), "null_sets": len(nul),
         "undetectable": len(eff) - len(det),
         "named": sum(o.named for o in eff), "halved": sum(o.halved for o in eff),
         "named_and_halved": sum(o.ok for o in eff),
         "null_nothing_named": sum(o.named for o in nul),
         "null_ok": sum(o.ok for o in nul),
         "null_worst_ratio": max((o.worse for o in nul), default=1.0),
         "cpu_s_mean": float(np.mean([o.cpu_s for o in outcomes])) if outcomes else 0.0,
         "rows_mean": float(np.mean([o.rows for o in outcomes])) if outcomes else 0.0}
    for k in ("named", "halved", "named_and_halved"):
        s[k + "_rate"] = s[k] / max(len(eff), 1)
    s["null_ok_rate"] = s["null_ok"] / max(len(nul), 1)
    return s


def table(outcomes):
    L = ["| kind | seed | rows | chosen | named | halved | held-out RMS base -> after (floor) | CPU s |",
         "|---|---|---|---|---|---|---|---|"]
    for o in outcomes:
        rms = "; ".join(f"{q} {b:.4g} -> {a:.4g} ({f:.3g})" for q, (b, a, f) in o.per_output.items())
        L.append(f"| {o.kind} | {o.seed} | {o.rows} | {o.chosen or '-'} | {'yes' if o.named else 'no'} | "
                 f"{'yes' if o.halved else ('-' if o.kind == 'null' else 'no')} | {rms} | {o.cpu_s:.1f} |")
    return "\n".join(L)


def by_kind(outcomes):
    rows = {}
    for o in outcomes:
        r = rows.setdefault(o.kind, [0, 0, 0, 0])
        r[0] += 1
        r[1] += o.named
        r[2] += o.halved if o.kind != "null" else (o.worse <= 1.05)
        r[3] += o.ok
    L = ["| kind | sets | named | halved (null: none > 5 % worse) | both |", "|---|---|---|---|---|"]
    for k in KINDS:
        if k in rows:
            n, a, b, c = rows[k]
            L.append(f"| {k} | {n} | {a} | {b} | {c} |")
    return "\n".join(L)


def write(outdir, outcomes, meta):
    os.makedirs(outdir, exist_ok=True)
    s = summary(outcomes)
    with open(os.path.join(outdir, "benchmark.json"), "w") as f:
        json.dump({"meta": meta, "summary": s,
                   "sets": [dict(o.__dict__, family=list(o.family)) for o in outcomes]}, f, indent=1, default=float)
    L = ["# Measured-data loop: generality benchmark", "",
         f"Command: `{meta.get('command', '')}`; {meta.get('wall_s', 0):.0f} s wall, {meta.get('jobs', 1)} processes.", "",
         f"Effect sets: {s['effect_sets']} ({s['undetectable']} with no output 1.5 x above its noise floor); "
         f"named correctly {s['named']} ({100 * s['named_rate']:.0f} %), held-out error halved {s['halved']} "
         f"({100 * s['halved_rate']:.0f} %), both {s['named_and_halved']} ({100 * s['named_and_halved_rate']:.0f} %). "
         f"Null sets: {s['null_sets']}, nothing named in {s['null_nothing_named']}, passing (nothing named, "
         f"no output > 5 % worse) {s['null_ok']}; worst ratio {s['null_worst_ratio']:.3f}. "
         f"Mean {s['rows_mean']:.0f} rows, {s['cpu_s_mean']:.1f} s CPU per analysis.", "",
         by_kind(outcomes), "", table(outcomes), ""]
    path = os.path.join(outdir, "benchmark.md")
    with open(path, "w") as f:
        f.write("\n".join(L))
    return path, s


def _accept_of(s):
    """ACCEPT of a set read back from benchmark.json (the drifts' output from its truth)"""
    k = s["kind"]
    if k in ("gain_drift", "offset_drift"):
        return _out_acc("scale" if k == "gain_drift" else "offset", s["truth"]["output"], DRIFT)
    return ACCEPT.get(k, {"pairs": set(), "names": set()})


def reselect(path, rules=(("ic", 6.0), ("ic", 2.0), ("ic", 20.0), ("best", 0.0),
                          ("score", 0.005), ("score", 0.01), ("score", 0.02))):
    """Effect sets of a benchmark.json named correctly under other selection
    rules, from the ranked candidates it keeps: ("ic", band) the tie band
    of attribution._select, ("best", 0) the lowest IC alone, ("score", f)
    ties within a share f of the best score; each then with the fewest
    parameters, a constant change first, and the named-form replacement of
    attribution._select. Candidates confirmed on the second split (ic2
    recorded, attribution._confirm) are ranked by the sum of both ICs, as
    the tool does. Returns {rule: named}, and the recorded count under
    None."""
    from grip_tools.loop.attribution import SPECIAL_TOL
    with open(path) as f:
        sets = [s for s in json.load(f)["sets"] if s["kind"] != "null"]
    out = {None: sum(bool(s["named"]) for s in sets)}
    for kind, val in rules:
        n = 0
        for s in sets:
            acc = sorted((c for c in s["ranked"] if c["accepted"]), key=lambda c: c["ic"])
            if not acc:
                continue
            conf = [c for c in acc if not math.isnan(c.get("ic2", float("nan")))]
            if conf:                      # the tool's second split: the sum of both ICs
                both = [dict(c, ic=c["ic"] + c["ic2"]) for c in conf if c["ic2"] < 0.0]
                acc = sorted(both, key=lambda c: c["ic"]) if both else conf
            if kind == "ic":
                band = [c for c in acc if c["ic"] <= acc[0]["ic"] + val]
            elif kind == "score":
                best = min(c["score"] for c in acc)
                band = [c for c in acc if c["score"] <= best * (1.0 + val)]
            else:
                band = acc[:1]
            ch = min(band, key=lambda c: (c["k"], tuple(c["family"][1:]) != ("const",), c["ic"]))
            if ch["kind"] == "grammar":
                named = [c for c in acc if c["kind"] == "named" and ch["family"] in c["families"]
                         and 1.0 - c["score"] >= (1.0 - ch["score"]) * (1.0 - SPECIAL_TOL)]
                if named:
                    ch = min(named, key=lambda c: c["score"])
            a = _accept_of(s)
            n += tuple(ch["family"]) in a["pairs"] or ch["name"] in a["names"]
        out[(kind, val)] = n
    return out


def main(n, outdir, seed=0, duration=150.0, rate=40.0, jobs=2, command=""):
    import sys
    t0 = time.time()

    def prog(i, k, r):
        print(f"benchmark: {i}/{k} {r.kind:22s} chosen {r.chosen or '-':28s} named {'yes' if r.named else 'no '} "
              f"halved {'yes' if r.halved else 'no '} ({r.cpu_s:.1f} s CPU)", file=sys.stderr, flush=True)
    outs = run(n, seed, duration, rate, jobs, progress=prog)
    path, s = write(outdir, outs, {"n": n, "seed": seed, "duration": duration, "rate": rate, "jobs": jobs,
                                   "wall_s": time.time() - t0, "command": command})
    return path, s
