"""Driver for CommonRoad's multi-body vehicle model (vehiclemodels.vehicle_dynamics_mb).

The model (Althoff and Wuersching, "CommonRoad: Vehicle Models", 2020) is
used through its public functions; its code is not repeated here. Its
conventions, as this driver handles them:

  states   x[0..28] (0-based): 0 X, 1 Y (global, CG), 2 delta (road-wheel
           angle), 3 vx, 4 yaw angle, 5 yaw rate, 6 roll, 7 roll rate,
           8 pitch, 9 pitch rate, 10 vy (sprung mass, CG), 11 z, 12 vz
           (sprung mass, z positive DOWN), 13..17 front unsprung mass (roll,
           roll rate, vy, z, vz), 18..22 rear unsprung mass, 23..26 wheel
           angular speeds FL FR RL RR, 27..28 compliant-joint deflections
  inputs   u[0] = road-wheel steering RATE [rad/s] (clipped to the
           parameter set's steering limits), u[1] = a longitudinal
           acceleration demand [m/s^2] that the model turns into an engine
           torque m R_w u (u > 0, split T_se front) or a brake torque
           (u < 0, split T_sb front), clipped by its acceleration limits
  axes     SAE J670's: x forward, y RIGHT, z DOWN (positive steering,
           yaw rate, vy and lateral force point right; positive roll puts
           the right side down, positive pitch the nose up; the left
           wheels' speed is vx + T/2 r). This driver reads the model as its
           mirror image, y to the LEFT. The model is left / right symmetric
           (the parameter sets are; the tire's camber terms are odd in
           camber), so the mirror image is the same model with its labels
           changed: X, Y, delta, yaw, r, vy and the tire forces read as ISO
           8855 (y left, yaw counter-clockwise); the model's left wheels
           are the mirror car's right wheels (OMEGA, MIRROR); ISO roll =
           -x[6] (right side down in a left turn), ISO pitch = -x[8] (nose
           down positive), z stays down
  slip     the model's slip angle atan((vy + a r) / vx) - delta is, read
           this way, the tire convention ISO-W's (a .tir file's: alpha > 0
           gives Fy < 0), the negative of the vehicle-dynamics slip angle
           delta - atan(...) of ISO 8855; its longitudinal slip is
           1 - R_w omega / v, positive in braking (ISO-W kappa = -slip)
  low      below |vx| = 0.1 m/s it switches to a kinematic single-track
  speed    model (slips and tire forces zero); this driver never goes there
           during a judged run, and adds no road gravity there
  gravity  9.81 m/s^2 along the road normal only: no bank, no grade

Bank and grade (road_gravity, derivative): the road plane is the model's
ground; the car sees the road pitched by the grade (uphill positive) and
then rolled by the bank (ISO roll sign: positive = left edge up), both
given as functions of time along the run (as the car meets them). Gravity
in that road frame is g_r = (-g sin(grade), -g cos(grade) sin(bank),
-g cos(grade) cos(bank)). Added to the model's derivatives:
  d vx / dt  += g_rx                    (whole car; the model lumps its
                                         longitudinal dynamics)
  d vy / dt  += g_ry  for the sprung mass and both unsprung masses
  d vz / dt  -= g (1 - cos(grade) cos(bank)) for all three masses (the
                                         model's own +g is the full g)
Neglected: the rotation of the road itself (d bank / dt, d grade / dt: no
gyroscopic or centripetal terms from a twisting road surface), the
heading of the car relative to the slope's direction (bank and grade are
already the car's), and gravity's moments (gravity acts at each mass's
centre, so it adds none about it; the roll and pitch moments come, as in
the model, from the suspension and tire forces that react to it).

Integration: fixed-step classical RK4 at H = 1 ms; below |vx| = 4 m/s four
sub-steps of H/4 (the wheel spin mode, R_w^2 dFx/dkappa / (I_w |vx|),
leaves RK4's stability region at 1 ms below about 1.5 m/s). Inputs are
held over a step. The wheel speeds are kept >= 0 after each step (the
model forbids negative wheel spin but only zeroes the derivative).

A run ends early (simulate's "ended") where the model leaves its domain:
a wheel load below zero at a 10 ms truth step (the model has no lift-off;
the run keeps the steps before), a wheel rolling at under 1 m/s along its
heading above 3 m/s (a spin; the model's slip divides by that speed next),
or a state that is not finite.

Truth forces: during the first stage of every `truth_every`-th step the
tire-model module the model calls is swapped for a recorder that calls the
real functions and keeps their arguments and results (load, camber, slip,
slip angle, pure and combined Fx, Fy, friction coefficient per wheel).
"""
import copy
import math

import numpy as np
import vehiclemodels.utils.tire_model as _tire_model
import vehiclemodels.vehicle_dynamics_mb as _vdm
from vehiclemodels.init_mb import init_mb
from vehiclemodels.parameters_vehicle1 import parameters_vehicle1
from vehiclemodels.parameters_vehicle2 import parameters_vehicle2
from vehiclemodels.parameters_vehicle3 import parameters_vehicle3

G = 9.81            # the model's own gravity constant
H = 1e-3            # integration step [s]
N_STATE = 29
X_, Y_, DELTA, VX, PSI, R, ROLL, ROLL_RATE, PITCH, PITCH_RATE, VY, Z, VZ = range(13)
VY_F, VZ_F, VY_R, VZ_R = 15, 17, 20, 22
MB_OMEGA = (23, 24, 25, 26)       # the model's own labels: LF RF LR RR (SAE sides)
WHEELS = ("fl", "fr", "rl", "rr")  # ISO sides (the mirror image)
MIRROR = (1, 0, 3, 2)              # ISO wheel i is the model's wheel MIRROR[i]
OMEGA = tuple(MB_OMEGA[j] for j in MIRROR)
LOW_SPEED_SUB = 3.0     # |vx| below which a step is split into SUBSTEPS
SUBSTEPS = 4

# name -> (constructor, label)
VEHICLES = {
    "escort": (parameters_vehicle1, "Ford Escort (parameters_vehicle1)"),
    "bmw320i": (parameters_vehicle2, "BMW 320i (parameters_vehicle2)"),
    "vanagon": (parameters_vehicle3, "VW Vanagon (parameters_vehicle3)"),
}
# surface -> factor on the tire's friction coefficients p_dx1 and p_dy1
# (the slip stiffnesses p_kx1, p_ky1 stay: the curves' initial slopes are
# the tire's, the peaks the road's)
SURFACES = {"dry": 1.0, "wet": 0.7, "snow": 0.35}
STEER_RATIO = 15.0       # steering-wheel angle / road-wheel angle
# road-wheel steering-rate limit of the driver robot [rad/s] (860 deg/s at
# the steering wheel); the parameter sets' 0.4 rad/s is a motion-planning
# bound, too slow for a sine with dwell
STEER_RATE_MAX = 1.0


class Vehicle:
    """A parameter set with friction-scaled copies per surface factor."""

    def __init__(self, name):
        ctor, self.label = VEHICLES[name]
        self.name = name
        self.p = ctor()
        self.p.steering.v_max = STEER_RATE_MAX
        self.p.steering.v_min = -STEER_RATE_MAX
        self._scaled = {}

    def params(self, factor):
        """The parameter set with p_dx1, p_dy1 scaled by factor."""
        key = round(float(factor), 6)
        if key not in self._scaled:
            q = copy.deepcopy(self.p)
            q.tire.p_dx1 = self.p.tire.p_dx1 * key
            q.tire.p_dy1 = self.p.tire.p_dy1 * key
            self._scaled[key] = q
        return self._scaled[key]

    @property
    def l(self):
        return self.p.a + self.p.b

    def static_wheel_loads(self):
        """Static wheel loads (front, rear) [N], as init_mb sets them."""
        p = self.p
        fzf = (p.m_s * G * p.b / self.l + p.m_uf * G) / 2.0
        fzr = (p.m_s * G * p.a / self.l + p.m_ur * G) / 2.0
        return fzf, fzr

    def cornering_stiffness(self):
        """Axle cornering stiffnesses (front, rear) [N/rad] of the model's
        tire at static load and zero camber (its K_y = p_ky1 Fz per wheel)."""
        fzf, fzr = self.static_wheel_loads()
        k = abs(self.p.tire.p_ky1)
        return 2.0 * k * fzf, 2.0 * k * fzr

    def linear_delta(self, v, ay):
        """Road-wheel angle [rad] for steady-state ay at speed v from the
        linear single-track model with the model tire's stiffnesses."""
        cf, cr = self.cornering_stiffness()
        p = self.p
        k_us = p.m / self.l * (p.b / cf - p.a / cr)
        return (self.l + k_us * v * v) * ay / (v * v)

    def initial_state(self, v0):
        return list(init_mb([0.0, 0.0, 0.0, float(v0), 0.0, 0.0, 0.0], self.p))


def road_gravity(bank, grade):
    """Gravity in the road frame, (g_x, g_y, g_normal) with g_normal > 0
    pointing into the road: g_r = (g_x, g_y, -g_normal) in ISO axes."""
    cg = math.cos(grade)
    return -G * math.sin(grade), -G * cg * math.sin(bank), G * cg * math.cos(bank)


def derivative(x, u, p, grav):
    """The model's derivative plus the road's gravity (module docstring)."""
    f = _vdm.vehicle_dynamics_mb(list(x), u, p)
    if abs(x[VX]) >= 0.1:
        gx, gy, gn = grav
        f[VX] += gx
        f[VY] += gy
        f[VY_F] += gy
        f[VY_R] += gy
        dz = G - gn
        f[VZ] -= dz
        f[VZ_F] -= dz
        f[VZ_R] -= dz
    return f


class _TireRecorder:
    """Stands in for vehiclemodels.utils.tire_model during one derivative
    call: calls the real functions, keeps arguments and results."""

    def __init__(self):
        self.lon, self.lat, self.lon_c, self.lat_c = [], [], [], []

    def formula_longitudinal(self, kappa, gamma, F_z, p):
        out = _tire_model.formula_longitudinal(kappa, gamma, F_z, p)
        self.lon.append((kappa, gamma, F_z, out))
        return out

    def formula_lateral(self, alpha, gamma, F_z, p):
        out = _tire_model.formula_lateral(alpha, gamma, F_z, p)
        self.lat.append((alpha, gamma, F_z, out[0], out[1], p.p_dx1))
        return out

    def formula_longitudinal_comb(self, kappa, alpha, F0_x, p):
        out = _tire_model.formula_longitudinal_comb(kappa, alpha, F0_x, p)
        self.lon_c.append(out)
        return out

    def formula_lateral_comb(self, kappa, alpha, gamma, mu_y, F_z, F0_y, p):
        out = _tire_model.formula_lateral_comb(kappa, alpha, gamma, mu_y, F_z, F0_y, p)
        self.lat_c.append(out)
        return out


def derivative_with_forces(x, u, p, grav):
    """derivative() and the per-wheel tire quantities of that call:
    dict of 4-lists fz, gamma, kappa (ISO), alpha (ISO), fx, fy (wheel
    frame, ISO), muy (the lateral friction coefficient with camber), mux.
    kappa and alpha in the tire convention ISO-W (a .tir file's, grip's
    Magic Formula's): kappa > 0 driving, alpha = atan(v_y / v_x) of the
    wheel's contact point in its own frame (the model's alpha; the negative
    of the vehicle-dynamics slip angle delta - atan(...))."""
    rec = _TireRecorder()
    _vdm.tireModel = rec
    try:
        f = derivative(x, u, p, grav)
    finally:
        _vdm.tireModel = _tire_model
    if len(rec.lon) != 4 or len(rec.lat) != 4 or len(rec.lon_c) != 4 or len(rec.lat_c) != 4:
        raise RuntimeError("vehicle_dynamics_mb: unexpected tire-model call pattern")
    w = {"fz": [c[2] for c in rec.lon], "gamma": [c[1] for c in rec.lat],
         "kappa": [-c[0] for c in rec.lon], "alpha": [c[0] for c in rec.lat],
         "fx": list(rec.lon_c), "fy": list(rec.lat_c),
         "muy": [c[4] for c in rec.lat], "mux": [c[5] for c in rec.lat]}
    # the model calls its wheels LF RF LR RR (SAE sides): ISO order
    return f, {k: [v[j] for j in MIRROR] for k, v in w.items()}


def wheel_rolling_speeds(x, p):
    """Each wheel centre's speed along its own heading [m/s], ISO order
    FL FR RL RR (of the mirror image: its left wheels are inner in a left
    turn)."""
    d, vx, vy, r = x[DELTA], x[VX], x[VY], x[R]
    cd, sd = math.cos(d), math.sin(d)
    return [(vx - 0.5 * p.T_f * r) * cd + (vy + p.a * r) * sd, (vx + 0.5 * p.T_f * r) * cd + (vy + p.a * r) * sd,
            vx - 0.5 * p.T_r * r, vx + 0.5 * p.T_r * r]


def _axpy(x, h, k):
    return [a + h * b for a, b in zip(x, k)]


def rk4_step(x, u, p, grav, h, k1=None):
    if k1 is None:
        k1 = derivative(x, u, p, grav)
    k2 = derivative(_axpy(x, 0.5 * h, k1), u, p, grav)
    k3 = derivative(_axpy(x, 0.5 * h, k2), u, p, grav)
    k4 = derivative(_axpy(x, h, k3), u, p, grav)
    h6 = h / 6.0
    xn = [a + h6 * (b1 + 2.0 * b2 + 2.0 * b3 + b4) for a, b1, b2, b3, b4 in zip(x, k1, k2, k3, k4)]
    for i in OMEGA:
        if xn[i] < 0.0:
            xn[i] = 0.0
    return xn


def simulate(vehicle, scenario, surface_factor, h=H, truth_every=None):
    """Runs a scenario (manoeuvres.Scenario) on a surface.

    The car first drives straight at scenario.v0 for scenario.settle
    seconds (the suspension settles; not recorded), then the scenario runs
    from t = 0 to scenario.duration. Returns a dict of numpy arrays:
    t, x (N, 29), f (N, 29: the derivative at x, road gravity included),
    u (N, 2), bank, grade, mu (surface factor in effect), and at every
    truth_every-th step (default: every 10 ms) t_w and the per-wheel
    quantities of derivative_with_forces as (M, 4) arrays."""
    if truth_every is None:
        truth_every = max(1, int(round(0.01 / h)))
    x = vehicle.initial_state(scenario.v0)
    drv = scenario.driver(vehicle)
    # settle: straight, speed held, no gravity extras
    n_settle = int(round(scenario.settle / h))
    p0 = vehicle.params(surface_factor)
    g0 = road_gravity(0.0, 0.0)
    for k in range(n_settle):
        u = drv.settle_controls(x, h)
        x = rk4_step(x, u, p0, g0, h)
    n = int(round(scenario.duration / h)) + 1
    ts = np.arange(n) * h
    X = np.zeros((n, N_STATE))
    F = np.zeros((n, N_STATE))
    U = np.zeros((n, 2))
    bank = np.zeros(n)
    grade = np.zeros(n)
    mu = np.zeros(n)
    wk = {k: [] for k in ("fz", "gamma", "kappa", "alpha", "fx", "fy", "muy", "mux")}
    tw = []
    ended = None
    for k in range(n):
        t = float(ts[k])
        bk, gr, mrel = scenario.road(t, x)
        p = vehicle.params(surface_factor * mrel)
        grav = road_gravity(bk, gr)
        u = drv.controls(t, x, h)
        if k % truth_every == 0:
            k1, w = derivative_with_forces(x, u, p, grav)
            if min(w["fz"]) < 0.0 and k > 0:
                # the model has no lift-off: a wheel load below zero pulls
                # the car to the road. The run ends at the last step before
                ended = f"wheel lift-off (Fz < 0) at t = {t:.3f} s"
                n = k
                break
            tw.append(t)
            for key in wk:
                wk[key].append(w[key])
        else:
            k1 = derivative(x, u, p, grav)
        X[k] = x
        F[k] = k1
        U[k] = u
        bank[k], grade[k], mu[k] = bk, gr, surface_factor * mrel
        if k == n - 1:
            break
        try:
            if abs(x[VX]) < LOW_SPEED_SUB:
                hs = h / SUBSTEPS
                xs = rk4_step(x, u, p, grav, hs, k1)
                for _ in range(SUBSTEPS - 1):
                    xs = rk4_step(xs, u, p, grav, hs)
            else:
                xs = rk4_step(x, u, p, grav, h, k1)
            if not all(math.isfinite(v) for v in xs):
                raise FloatingPointError("state not finite")
            if abs(xs[VX]) > LOW_SPEED_SUB and min(wheel_rolling_speeds(xs, vehicle.p)) < 1.0:
                # a wheel rolls sideways or backwards: the car has spun, and
                # the model's slip 1 - R_w omega / u divides by ~0 next
                raise FloatingPointError("a wheel's rolling speed fell below 1 m/s (spin)")
        except (ZeroDivisionError, FloatingPointError, ValueError, OverflowError) as ex:
            # the model leaves its domain (a wheel moving backwards after a
            # spin divides by zero in its slip): the run ends here
            ended = f"model stopped at t = {t:.3f} s: {type(ex).__name__}: {ex}"
            n = k + 1
            break
        x = xs
    ts, X, F, U, bank, grade, mu = ts[:n], X[:n], F[:n], U[:n], bank[:n], grade[:n], mu[:n]
    out = {"t": ts, "x": X, "f": F, "u": U, "bank": bank, "grade": grade, "mu": mu, "t_w": np.array(tw),
           "h": h, "ended": ended}
    for key, v in wk.items():
        out[key] = np.array(v)
    return out


def kinematic_acceleration(sim):
    """Acceleration of the sprung mass's centre in the road (yaw) frame,
    ISO axes: (dvx/dt - r vy, dvy/dt + r vx, -dvz/dt) [m/s^2] (road
    gravity included in the derivatives: this is the true acceleration)."""
    x, f = sim["x"], sim["f"]
    ax = f[:, VX] - x[:, R] * x[:, VY]
    ay = f[:, VY] + x[:, R] * x[:, VX]
    az = -f[:, VZ]
    return ax, ay, az


def body_angles_iso(sim):
    """Body roll, pitch [rad] and their rates relative to the road, ISO signs."""
    x = sim["x"]
    return -x[:, ROLL], -x[:, PITCH], -x[:, ROLL_RATE], -x[:, PITCH_RATE]
