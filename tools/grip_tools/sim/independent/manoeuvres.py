"""Manoeuvres for the multi-body model and the driver robot that flies them.

Driver robot (Driver), every integration step (1 ms):
  steering  servo on the road-wheel angle: u_steer = 40 (delta_target -
            delta) [rad/s], within +-mb.STEER_RATE_MAX; delta_target from
            the manoeuvre: open-loop profiles, a curvature PI for circles
            (delta = delta_ff + l (1.0 e + 1.5 integral e), e = 1/R -
            r / vx, delta_ff the linear single-track angle), pure pursuit
            on a path (look-ahead max(6 m, 0.9 s x v))
  speed     PI on vx through the acceleration input: a = a_ff + 1.5 e +
            0.3 integral e (anti-windup), within [-9, 4] m/s^2; or an
            acceleration demand (braking), or coasting (u = 0)
  ABS / TCS a factor on the demand, from the wheels' slip (the model's
            truth): any wheel beyond 12 % slip (braking) or 10 % spin
            (driving) lowers it at 10 / s, all below 6 % raise it at 3 / s
A run ends early where the model leaves its domain (mb.simulate): a
wheel load below zero (the model has no lift-off: the three parameter
sets lift an inner wheel at 0.8 - 0.9 g on dry asphalt), or a wheel
rolling sideways or backwards after a spin.

The same steering and speed demands on every surface: the driver asks for
the same path, the road decides what the car does (on snow most of the
manoeuvres are at or past the limit).

Manoeuvres (times from the start of the recorded run; the car has driven
straight at v0 for 1.5 s before it):
  circle-ramp      circle R = 40 m, speed from 8 m/s up at 0.5 m/s^2 to
                   1.08 x the friction-limit speed sqrt(mu g R)
  step-steer       80 km/h held, road-wheel step (at the rate limit) at 1 s
                   to the linear angle for 4 m/s^2
  sine-dwell       80 km/h, coasting; 0.7 Hz sine of 3 x the linear angle
                   for 0.3 g, 0.5 s dwell at the second peak (FMVSS 126's
                   shape; its 5 - 6.5 x amplitudes lift a wheel of these
                   models on dry asphalt within the first half period)
  slalom           60 km/h held, cones 18 m apart: sine at v / 36 m, the
                   linear angle for 5 m/s^2, four periods
  double-lane-change  70 km/h held, pure pursuit of a 3.5 m lateral offset
                   in over 30 m, held 25 m, back over 30 m
  brake-in-turn    80 km/h held on the linear angle for 4 m/s^2, at 3.5 s
                   brake demand -4 m/s^2 (ramped over 0.2 s, ABS), steering
                   held, brake released below 6 m/s
  mu-step          80 km/h, straight braking at 0.8 g x the higher friction
                   (ABS) from 1 s, the friction changes at the X the car
                   reaches 1 s later (to 0.35 from dry and wet, to 1.0 from
                   snow); brake released below 6 m/s
  low-speed-lock   4 m/s held, road wheels to 30 deg at 0.3 rad/s from 1 s,
                   held for a full circle
  banked-curve     20 m/s held, circle R = 80 m on a road banked 8 deg
                   towards the centre (bank and curvature fade in over 2 s)
  bank-grade-road  20 m/s held, bank 5 deg sin(2 pi t / 8 s), grade
                   6 % sin(2 pi t / 11 s + 1), a 0.2 Hz weave of the linear
                   angle for 2 m/s^2
"""
import math

from grip_tools.sim.independent import mb

KMH = 1.0 / 3.6
SETTLE = 1.5


class Driver:
    """Speed PI, steering servo, ABS / TCS (module docstring)."""

    KP_V, KI_V = 1.5, 0.3
    K_STEER = 40.0
    A_MIN, A_MAX = -9.0, 4.0

    def __init__(self, vehicle, scenario):
        self.veh = vehicle
        self.sc = scenario
        self.iv = 0.0
        self.ik = 0.0
        self.slip_f = 1.0
        self.hold_delta = None

    # -- blocks ----------------------------------------------------------
    def steer_servo(self, x, delta_t):
        u = self.K_STEER * (delta_t - x[mb.DELTA])
        return max(-mb.STEER_RATE_MAX, min(mb.STEER_RATE_MAX, u))

    def speed_pi(self, x, v_ref, a_ff, dt):
        e = v_ref - x[mb.VX]
        a = a_ff + self.KP_V * e + self.KI_V * self.iv
        if self.A_MIN < a < self.A_MAX or (a >= self.A_MAX and e < 0) or (a <= self.A_MIN and e > 0):
            self.iv += e * dt
        return max(self.A_MIN, min(self.A_MAX, a))

    def wheel_slips(self, x):
        """Longitudinal slip of each wheel, the model's sign (> 0 braking)."""
        p = self.veh.p
        uw = mb.wheel_rolling_speeds(x, p)
        return [1.0 - p.R_w * x[i] / max(u, 0.5) for i, u in zip(mb.OMEGA, uw)]

    def slip_control(self, x, a, dt):
        """ABS (a < 0) / TCS (a > 0): the demand times a factor."""
        s = self.wheel_slips(x)
        if a < 0.0:
            worst, ok = max(s), max(s) < 0.06
            bad = worst > 0.12
        else:
            worst, ok = -min(s), -min(s) < 0.06
            bad = worst > 0.10
        if bad:
            self.slip_f -= 10.0 * dt
        elif ok:
            self.slip_f += 3.0 * dt
        self.slip_f = max(0.05, min(1.0, self.slip_f))
        return a * self.slip_f

    def curvature_pi(self, x, kappa_ref, dt, delta_ff):
        e = kappa_ref - x[mb.R] / max(x[mb.VX], 1.0)
        self.ik = max(-0.5, min(0.5, self.ik + e * dt * self.veh.l * 1.5))
        return max(-0.6, min(0.6, delta_ff + self.veh.l * 1.0 * e + self.ik))

    def pure_pursuit(self, x, path_y):
        v = max(x[mb.VX], 1.0)
        la = max(6.0, 0.9 * v)
        X, Y, psi = x[mb.X_], x[mb.Y_], x[mb.PSI]
        xl = X + la * math.cos(psi)
        yl = path_y(xl)
        alpha = math.atan2(yl - Y, xl - X) - psi
        return math.atan(2.0 * self.veh.l * math.sin(alpha) / la)

    # -- interface -------------------------------------------------------
    def settle_controls(self, x, dt):
        return [self.steer_servo(x, 0.0), self.speed_pi(x, self.sc.v0, 0.0, dt)]

    def controls(self, t, x, dt):
        delta_t = self.sc.steer(self, t, x, dt)
        mode = self.sc.speed(self, t, x)
        if mode[0] == "hold":
            a = self.speed_pi(x, mode[1], mode[2], dt)
        elif mode[0] == "accel":
            a = mode[1]
        else:
            a = 0.0
        if a != 0.0:
            a = self.slip_control(x, a, dt)
        return [self.steer_servo(x, delta_t), a]


class Scenario:
    """One manoeuvre on one vehicle: v0, duration, steer(drv, t, x, dt) ->
    road-wheel target, speed(drv, t, x) -> ("hold", v, a_ff) | ("accel",
    a) | ("coast",), road(t, x) -> (bank, grade, friction factor relative
    to the surface)."""

    def __init__(self, name, v0, duration, steer, speed, road=None, meta=None):
        self.name = name
        self.v0 = float(v0)
        self.duration = float(duration)
        self.settle = SETTLE
        self.steer = steer
        self.speed = speed
        self.road = road if road is not None else (lambda t, x: (0.0, 0.0, 1.0))
        self.meta = meta or {}

    def driver(self, vehicle):
        return Driver(vehicle, self)


def _ramp(t, t0, rate, target):
    if t <= t0:
        return 0.0
    step = rate * (t - t0)
    return math.copysign(min(step, abs(target)), target)


def circle_ramp(veh, mu_surface, radius=40.0, v_start=8.0, accel=0.5):
    mu_peak = mu_surface * veh.p.tire.p_dy1
    v_end = 1.08 * math.sqrt(mu_peak * mb.G * radius)
    v_end = max(v_end, v_start + 2.0)
    dur = (v_end - v_start) / accel + 1.0

    def speed(drv, t, x):
        return ("hold", v_start + accel * max(t - 0.5, 0.0), accel if t > 0.5 else 0.0)

    def steer(drv, t, x, dt):
        v = max(x[mb.VX], 1.0)
        ff = veh.linear_delta(v, v * v / radius)
        return drv.curvature_pi(x, 1.0 / radius, dt, ff)
    return Scenario("circle-ramp", v_start, dur, steer, speed,
                    meta=dict(radius=radius, v_end=v_end, accel=accel))


def step_steer(veh, mu_surface, v0=80 * KMH, ay=4.0, t0=1.0, duration=6.0):
    d = veh.linear_delta(v0, ay)

    def steer(drv, t, x, dt):
        return d if t >= t0 else 0.0
    return Scenario("step-steer", v0, duration, steer, lambda drv, t, x: ("hold", v0, 0.0),
                    meta=dict(delta=d, t_steer=t0))


def sine_dwell(veh, mu_surface, v0=80 * KMH, scale=3.0, freq=0.7, dwell=0.5, t0=1.0, settle=2.5):
    amp = scale * veh.linear_delta(v0, 0.3 * mb.G)
    w = 2.0 * math.pi * freq
    t_peak2 = t0 + 0.75 / freq
    t_cos = t_peak2 + dwell + 0.25 / freq

    def steer(drv, t, x, dt):
        if t < t0:
            return 0.0
        if t < t_peak2:
            return amp * math.sin(w * (t - t0))
        if t < t_peak2 + dwell:
            return -amp
        if t < t_cos:
            return amp * math.sin(w * (t - t0 - dwell))
        return 0.0

    def speed(drv, t, x):
        return ("hold", v0, 0.0) if t < t0 else ("coast",)
    return Scenario("sine-dwell", v0, t_cos + settle, steer, speed, meta=dict(amp=amp, t_bos=t0, t_cos=t_cos))


def slalom(veh, mu_surface, v0=60 * KMH, pitch=18.0, ay=5.0, periods=4, t0=1.0):
    freq = v0 / (2.0 * pitch)
    amp = veh.linear_delta(v0, ay)
    t1 = t0 + periods / freq

    def steer(drv, t, x, dt):
        return amp * math.sin(2.0 * math.pi * freq * (t - t0)) if t0 <= t < t1 else 0.0
    return Scenario("slalom", v0, t1 + 1.5, steer, lambda drv, t, x: ("hold", v0, 0.0),
                    meta=dict(amp=amp, freq=freq))


def _smooth_step(s):
    s = min(max(s, 0.0), 1.0)
    return 0.5 - 0.5 * math.cos(math.pi * s)


def double_lane_change(veh, mu_surface, v0=70 * KMH, offset=3.5, x_in=20.0, len_shift=30.0, len_hold=25.0):
    x1 = x_in + len_shift
    x2 = x1 + len_hold
    x3 = x2 + len_shift

    def path_y(X):
        if X < x1:
            return offset * _smooth_step((X - x_in) / len_shift)
        return offset * (1.0 - _smooth_step((X - x2) / len_shift))

    def steer(drv, t, x, dt):
        return drv.pure_pursuit(x, path_y)
    return Scenario("double-lane-change", v0, (x3 + 30.0) / v0, steer, lambda drv, t, x: ("hold", v0, 0.0),
                    meta=dict(offset=offset))


def _braking(v0, t_brake, v_release, demand):
    """The speed program of a braking run: v0 held until t_brake, then the
    braking demand(t) [m/s^2, > 0] until vx falls below v_release, rolling
    from then on."""
    state = {"released": False}

    def speed(drv, t, x):
        if t < t_brake:
            return ("hold", v0, 0.0)
        if state["released"] or x[mb.VX] < v_release:
            state["released"] = True
            return ("coast",)
        return ("accel", -demand(t))
    return speed


def brake_in_turn(veh, mu_surface, v0=80 * KMH, ay=4.0, decel=4.0, t_brake=3.5, v_release=6.0):
    d = veh.linear_delta(v0, ay)

    def steer(drv, t, x, dt):
        return _ramp(t, 0.3, 0.5, d)

    speed = _braking(v0, t_brake, v_release, lambda t: decel * min(1.0, (t - t_brake) / 0.2))
    dur = t_brake + v0 / decel * 1.3 + 1.0
    return Scenario("brake-in-turn", v0, dur, steer, speed, meta=dict(delta=d, t_brake=t_brake))


def mu_step(veh, mu_surface, v0=80 * KMH, t_brake=1.0, v_release=6.0):
    rel_after = (0.35 / mu_surface) if mu_surface > 0.35 + 1e-9 else (1.0 / mu_surface)
    mu_hi = max(mu_surface, mu_surface * rel_after)
    decel = 0.8 * mb.G * mu_hi
    x_step = v0 * (t_brake + 1.0)
    speed = _braking(v0, t_brake, v_release, lambda t: decel * min(1.0, (t - t_brake) / 0.2))

    def road(t, x):
        return 0.0, 0.0, (rel_after if x[mb.X_] >= x_step else 1.0)
    dur = t_brake + v0 / (0.8 * mb.G * 0.35) * 0.8 + 1.0
    return Scenario("mu-step", v0, min(dur, 8.0), lambda drv, t, x, dt: 0.0, speed, road,
                    meta=dict(x_step=x_step, mu_after=mu_surface * rel_after))


def low_speed_lock(veh, mu_surface, v0=4.0, angle=30.0 * math.pi / 180.0, rate=0.3, t0=1.0):
    radius = veh.l / math.tan(angle)
    dur = t0 + angle / rate + 2.0 * math.pi * radius / v0 + 1.0

    def steer(drv, t, x, dt):
        return _ramp(t, t0, rate, angle)
    return Scenario("low-speed-lock", v0, dur, steer, lambda drv, t, x: ("hold", v0, 0.0),
                    meta=dict(angle=angle))


def banked_curve(veh, mu_surface, v0=20.0, radius=80.0, bank_deg=8.0, t_in=1.0, t_fade=2.0, duration=14.0):
    bank = -bank_deg * math.pi / 180.0     # left turn: right edge up

    def fade(t):
        return _smooth_step((t - t_in) / t_fade)

    def steer(drv, t, x, dt):
        kap = fade(t) / radius
        v = max(x[mb.VX], 1.0)
        ff = veh.linear_delta(v, v * v * kap) if kap > 0 else 0.0
        return drv.curvature_pi(x, kap, dt, ff)

    def road(t, x):
        return bank * fade(t), 0.0, 1.0
    return Scenario("banked-curve", v0, duration, steer, lambda drv, t, x: ("hold", v0, 0.0), road,
                    meta=dict(radius=radius, bank_deg=bank_deg))


def bank_grade_road(veh, mu_surface, v0=20.0, duration=20.0):
    amp = veh.linear_delta(v0, 2.0)

    def steer(drv, t, x, dt):
        return amp * math.sin(2.0 * math.pi * 0.2 * t)

    def road(t, x):
        return (5.0 * math.pi / 180.0 * math.sin(2.0 * math.pi * t / 8.0),
                math.atan(0.06 * math.sin(2.0 * math.pi * t / 11.0 + 1.0)), 1.0)
    return Scenario("bank-grade-road", v0, duration, steer, lambda drv, t, x: ("hold", v0, 0.0), road)


def ramp_steer(veh, mu_surface, v0=80 * KMH, rate=0.01, t0=1.0, duration=None):
    """Constant-speed slowly increasing steer (ISO 4138): the tire and roll
    characterization run (judge.characterize), not a judged manoeuvre."""
    d_max = 3.0 * veh.linear_delta(v0, mu_surface * veh.p.tire.p_dy1 * mb.G)
    if duration is None:
        duration = t0 + d_max / rate

    def steer(drv, t, x, dt):
        return _ramp(t, t0, rate, d_max)
    return Scenario("ramp-steer", v0, duration, steer, lambda drv, t, x: ("hold", v0, 0.0))


def brake_ramp(veh, mu_surface, v0=100 * KMH, t0=1.0, rate=3.0, v_release=8.0):
    """Straight-line braking whose demand rises by rate [m/s^2 per s] until
    the ABS holds the wheels at its slip band (6 - 12 %), released at
    v_release: the tire's longitudinal characterization run
    (judge.characterize), not a judged manoeuvre."""
    speed = _braking(v0, t0, v_release, lambda t: min(-Driver.A_MIN, rate * (t - t0)))
    return Scenario("brake-ramp", v0, t0 + v0 / (0.5 * mb.G) + 1.0, lambda drv, t, x, dt: 0.0, speed)


def learning_drive(veh, mu_surface, v0=80 * KMH, duration=90.0):
    """Ordinary driving on a dry road for the estimator's online stiffness
    learning (judge.learn): 80 km/h held, a weave of three incommensurate
    sines of the linear angle (0.11, 0.37, 0.83 Hz) up to ~3 m/s^2; not a
    judged manoeuvre."""
    parts = ((1.4, 0.11, 0.0), (0.9, 0.37, 1.0), (0.6, 0.83, 2.0))
    unit = veh.linear_delta(v0, 1.0)

    def steer(drv, t, x, dt):
        ramp = min(1.0, max(0.0, t - 1.0))
        return ramp * unit * sum(a * math.sin(2.0 * math.pi * f * t + ph) for a, f, ph in parts)
    return Scenario("learning-drive", v0, duration, steer, lambda drv, t, x: ("hold", v0, 0.0))


def learning_drive_long(veh, mu_surface, v0=60 * KMH, cycles=4):
    """Ordinary straight driving with speed changes for the estimator's
    longitudinal stiffness learning (judge.learn with kx_est): per 16 s
    cycle 3 s at constant speed, 4 s of traction at 1.5 m/s^2, 4 s rolling
    without drive or brake, 4 s of braking at 1.5 m/s^2, 1 s rolling; not a
    judged manoeuvre."""
    period = 16.0

    def speed(drv, t, x):
        ph = t % period
        if ph < 3.0:
            return ("hold", v0, 0.0)
        if ph < 7.0:
            return ("accel", 1.5)
        if ph < 11.0:
            return ("coast",)
        if ph < 15.0:
            return ("accel", -1.5)
        return ("coast",)
    return Scenario("learning-drive-long", v0, period * cycles, lambda drv, t, x, dt: 0.0, speed)


MANOEUVRES = {
    "circle-ramp": circle_ramp, "step-steer": step_steer, "sine-dwell": sine_dwell, "slalom": slalom,
    "double-lane-change": double_lane_change, "brake-in-turn": brake_in_turn, "mu-step": mu_step,
    "low-speed-lock": low_speed_lock, "banked-curve": banked_curve, "bank-grade-road": bank_grade_road,
}


def build(name, vehicle, surface_factor):
    if name == "ramp-steer":
        return ramp_steer(vehicle, surface_factor)
    if name == "brake-ramp":
        return brake_ramp(vehicle, surface_factor)
    if name == "learning-drive":
        return learning_drive(vehicle, surface_factor)
    if name == "learning-drive-long":
        return learning_drive_long(vehicle, surface_factor)
    return MANOEUVRES[name](vehicle, surface_factor)
