"""ESC sensor cluster from the multi-body model's states, and the truth.

True signals, computed at every integration step (1 ms):
  wheel speeds    R_w x omega_i (x[23..26], mb.OMEGA: the mirror image's
                  sides), circumferential [m/s]
  steering wheel  STEER_RATIO x road-wheel angle (x[2]) [rad]
  yaw rate        body z angular rate (ZYX Euler, body roll phi and pitch
                  theta relative to the road, ISO signs):
                  -theta' sin(phi) + psi' cos(theta) cos(phi)
  ax, ay          specific force of the sprung mass's centre in the body
                  frame: s = a - g_r in the road frame (a from the state
                  derivatives: dvx/dt - r vy, dvy/dt + r vx, -dvz/dt; g_r
                  the road's gravity with bank and grade, mb.road_gravity),
                  rotated into the body by pitch then roll:
                  s_body = Rx(phi)^T Ry(theta)^T s
                  (at rest on a road banked by b: ay = g sin(b); a body
                  rolled outwards in a turn reads ay + g sin(phi))

Sensor model (values of a typical automotive ESC inertial cluster and
wheel-speed / steering-angle sensors; per run, offsets and scale errors
drawn once from a seeded generator, uniformly within the bounds):

  channel        noise (1 sigma)  offset / scale     low-pass  delay  LSB
  yaw rate       0.10 deg/s       +-0.3 deg/s        tau 5 ms  10 ms  0.01 deg/s
  ax, ay         0.03 m/s^2       +-0.10 m/s^2       tau 5 ms  10 ms  0.01 m/s^2
  steering wheel 0.05 deg         +-0.5 deg          -         10 ms  0.1 deg
  wheel speeds   0.02 m/s         scale +-0.2 %      -         10 ms  1/64 km/h

Every channel is sampled every 10 ms (the estimator's step) from the
delayed, filtered 1 ms signal; noise is added per sample, then the value
is quantized. No vehicle-speed or brake-pressure signal is sent (the model
has no brake pressures; the estimator version does not use them).

The estimator's latency settings are what a data sheet gives for this
cluster: latency = 10 ms + 5 ms (inertial channels), steer_latency = 10 ms.
"""
import math

import numpy as np

from grip_tools.sim.independent import mb

DEG = math.pi / 180.0
KMH = 1.0 / 3.6
STEP = 0.01                 # estimator step and sample period [s]
DELAY = 0.010               # transport delay of every channel [s]
IMU_TAU = 0.005             # inertial channels' low-pass [s]
LATENCY = DELAY + IMU_TAU   # grip_est_config_t.latency
STEER_LATENCY = DELAY       # grip_est_config_t.steer_latency
SPEC = {
    # channel: (noise, offset bound, relative scale bound, tau, lsb)
    "yaw_rate": (0.10 * DEG, 0.3 * DEG, 0.0, IMU_TAU, 0.01 * DEG),
    "ax": (0.03, 0.10, 0.0, IMU_TAU, 0.01),
    "ay": (0.03, 0.10, 0.0, IMU_TAU, 0.01),
    "steer_angle": (0.05 * DEG, 0.5 * DEG, 0.0, 0.0, 0.1 * DEG),
    "wheel_speed": (0.02, 0.0, 0.002, 0.0, KMH / 64.0),
}


def true_signals(sim, vehicle):
    """The ideal sensor signals at every integration step (module docstring)."""
    x = sim["x"]
    phi, theta, dphi, dtheta = mb.body_angles_iso(sim)
    r = x[:, mb.R]
    yaw = -dtheta * np.sin(phi) + r * np.cos(theta) * np.cos(phi)
    ax_k, ay_k, az_k = mb.kinematic_acceleration(sim)
    g = np.array([mb.road_gravity(b, gr) for b, gr in zip(sim["bank"], sim["grade"])])
    sx = ax_k - g[:, 0]
    sy = ay_k - g[:, 1]
    sz = az_k + g[:, 2]
    ct, st = np.cos(theta), np.sin(theta)
    cp, sp = np.cos(phi), np.sin(phi)
    # Ry(theta)^T s
    ux = ct * sx - st * sz
    uz = st * sx + ct * sz
    # Rx(phi)^T u
    fx = ux
    fy = cp * sy + sp * uz
    out = {"yaw_rate": yaw, "ax": fx, "ay": fy, "steer_angle": mb.STEER_RATIO * x[:, mb.DELTA]}
    for i, w in enumerate(mb.WHEELS):
        out[f"wheel_speed_{w}"] = vehicle.p.R_w * x[:, mb.OMEGA[i]]
    return out


def specific_force(ax_k, ay_k, az_k, bank, grade, roll, pitch):
    """Body-frame specific force (x, y) from the road-frame acceleration,
    road bank / grade and body roll / pitch (ISO signs): the accelerometer
    equation of true_signals for single values."""
    gx, gy, gn = mb.road_gravity(bank, grade)
    sx, sy, sz = ax_k - gx, ay_k - gy, az_k + gn
    ux = math.cos(pitch) * sx - math.sin(pitch) * sz
    uz = math.sin(pitch) * sx + math.cos(pitch) * sz
    return ux, math.cos(roll) * sy + math.sin(roll) * uz


def _lowpass(x, tau, h):
    if tau <= 0.0:
        return x
    a = h / (tau + h)
    y = np.empty_like(x)
    acc = x[0]
    for k in range(len(x)):
        acc += a * (x[k] - acc)
        y[k] = acc
    return y


def measure(sim, vehicle, seed=0, ideal=False):
    """Samples the sensors every STEP. Returns (t, channels dict) at the
    estimator's steps, t from DELAY on (the first sample that has a
    delayed value)."""
    h = sim["h"]
    sig = true_signals(sim, vehicle)
    rng = np.random.default_rng(seed)
    t_all = sim["t"]
    n_step = int(round(STEP / h))
    n_delay = int(round(DELAY / h))
    idx = np.arange(n_delay, len(t_all), n_step)
    t = t_all[idx]
    out = {}
    for name, x in sig.items():
        key = "wheel_speed" if name.startswith("wheel_speed") else name
        noise, off, scale, tau, lsb = SPEC[key]
        y = _lowpass(x, tau, h)[idx - n_delay]
        if not ideal:
            y = y * (1.0 + rng.uniform(-scale, scale)) + rng.uniform(-off, off)
            y = y + rng.normal(0.0, noise, len(y))
            y = np.round(y / lsb) * lsb
        out[name] = y
    return t, out


def truth(sim, vehicle, t):
    """The truth at the sample times t (a subset of the integration
    steps; the per-wheel forces at the nearest recorded 10 ms step)."""
    k = np.rint(t / sim["h"]).astype(int)
    x = sim["x"][k]
    ax_k, ay_k, _ = mb.kinematic_acceleration(sim)
    phi, theta, _, _ = mb.body_angles_iso(sim)
    tr = {"time": t, "vx": x[:, mb.VX], "vy": x[:, mb.VY], "beta": np.arctan2(x[:, mb.VY], x[:, mb.VX]),
          "r": x[:, mb.R], "delta": x[:, mb.DELTA], "ax_kin": ax_k[k], "ay_kin": ay_k[k],
          "roll": phi[k], "pitch": theta[k], "bank": sim["bank"][k], "grade": sim["grade"][k],
          "mu_surface": sim["mu"][k], "X": x[:, mb.X_], "Y": x[:, mb.Y_]}
    kw = np.clip(np.searchsorted(sim["t_w"], t - 0.5 * sim["h"]), 0, len(sim["t_w"]) - 1)
    for i, w in enumerate(mb.WHEELS):
        for q in ("fx", "fy", "fz", "kappa", "alpha", "gamma"):
            tr[f"{q}_{w}"] = sim[q][kw, i]
        # absolute friction coefficients in effect (surface included)
        tr[f"mux_{w}"] = sim["mux"][kw, i]
        tr[f"muy_{w}"] = sim["muy"][kw, i]
    return tr


def write_csv(path, cols):
    names = list(cols)
    arr = np.column_stack([np.asarray(cols[n], float) for n in names])
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        np.savetxt(f, arr, delimiter=",", fmt="%.9g")


def estimator_inputs(t, meas, in_cols):
    """(value, valid) arrays in the order of in_cols (est_eval.IN_COLS);
    channels this cluster does not send are not valid."""
    value = np.zeros((len(t), len(in_cols)))
    valid = np.zeros((len(t), len(in_cols)), dtype=np.uint8)
    for i, c in enumerate(in_cols):
        if c in meas:
            value[:, i] = meas[c]
            valid[:, i] = 1
    return value, valid
