"""Standard manoeuvres, the driver/controller blocks they need, and the
FMVSS 126 sine-with-dwell evaluation.

Every builder returns a model.Scenario (batch of N vehicles); angles given
in degrees of steering-wheel angle (SWA), speeds in m/s, pressures in bar.

  coast            straight line, no inputs (rolling resistance and drag only)
  step-steer       ISO 7401-style step: SWA ramp at 500 deg/s to the target, speed held
  ramp-steer       slowly increasing steer at constant speed (FMVSS 126 13.5 deg/s,
                   ISO 4138 constant-speed method); gives the steady-state circle
  sine-dwell       FMVSS 126 / UN R13-H: 0.7 Hz sine, 500 ms dwell at the second
                   peak, amplitude = scale * SWA(0.3 g); coasting
  fishhook         NHTSA-style fishhook: 720 deg/s to +A, 250 ms dwell, 720 deg/s
                   to -A, hold 3 s, back to zero
  brake-in-turn    ISO 7975-style: steady cornering, then a brake-pressure step
  mu-step          straight-line braking across a friction step along the road
  mu-split-brake   straight-line braking with the left wheels on low friction
"""
import math

import numpy as np

from grip_tools.sim.model import Road, Scenario, SURFACES, simulate
from grip_tools.sim.vehicles import G

DEG = math.pi / 180.0
KMH = 1.0 / 3.6


# ---------------------------------------------------------------------------
# Driver / controller blocks (held over .period; see model.simulate)

class SpeedHold:
    """PI speed controller on vx with feed-forward of drag, rolling
    resistance and (for a time-varying reference) the reference
    acceleration. v_ref: value(s) or callable(t) -> (N,). Positive demand
    goes to the drive torque; negative demand to the brakes when
    use_brakes (else the car coasts). Anti-windup on saturation.
    Active for t in [t_on, t_off)."""

    def __init__(self, v_ref, kp=2.0, ki=0.5, t_on=0.0, t_off=math.inf, period=0.01, use_brakes=False):
        self.v_ref = v_ref
        self.kp, self.ki = kp, ki
        self.t_on, self.t_off = t_on, t_off
        self.period = period
        self.use_brakes = use_brakes

    def reset(self, model, x0):
        self.model = model
        n = x0.shape[0]
        if not callable(self.v_ref):
            ref = np.broadcast_to(np.asarray(self.v_ref, dtype=float), (n,)).copy()
            self._ref = lambda t: ref
        else:
            self._ref = lambda t: np.broadcast_to(np.asarray(self.v_ref(t), dtype=float), (n,))
        self.integ = np.zeros(n)
        self.re = float((model.re * model.drive_share).sum())
        self.brake_k = float((model.brake_gain / model.re).sum())     # N per bar

    def update(self, t, x, out, zoh):
        if not (self.t_on <= t < self.t_off):
            zoh["drive"] = np.zeros_like(self.integ)
            zoh["brake"] = np.zeros_like(self.integ)
            return
        v = self.model.v
        ref = self._ref(t)
        a_ff = (self._ref(t + self.period) - ref) / self.period
        e = ref - out["vx"]
        ff = out["drag"] + self.model.tire.qsy1 * v.m * G
        a_cmd = a_ff + self.kp * e + self.ki * self.integ
        force = v.m * a_cmd + ff
        torque = force * self.re
        lo = -np.inf if self.use_brakes else 0.0
        sat = (torque <= lo) | (torque >= v.drive_torque_max) | ((torque <= 0.0) & (not self.use_brakes))
        self.integ = np.where(sat & (np.sign(e) == np.sign(a_cmd)), self.integ, self.integ + e * self.period)
        zoh["drive"] = np.clip(torque, 0.0, v.drive_torque_max)
        if self.use_brakes:
            # braking force = p * sum(gain_i / Re_i)
            zoh["brake"] = np.maximum(-force / self.brake_k, 0.0)


class ABS:
    """Minimal ABS: per-wheel slip thresholds plus the two standard split-mu
    measures of production systems.

    * each wheel: dump pressure (factor -= dump_rate * period) when kappa <
      -kappa_dump, build (+= build_rate * period) when kappa > -kappa_build,
      hold between; the factor multiplies the master-cylinder pressure;
    * rear axle select-low: both rear wheels get the lower factor;
    * front yaw-moment build-up delay: the front factor difference is limited
      to gma_rate * (time since the brake was applied).
    It reads the true slip (a production ABS estimates it from wheel speeds)."""

    def __init__(self, kappa_dump=0.12, kappa_build=0.06, dump_rate=10.0, build_rate=3.0,
                 gma_rate=1.0, select_low_rear=True, period=0.01):
        self.kd, self.kb = kappa_dump, kappa_build
        self.dump, self.build = dump_rate, build_rate
        self.gma_rate = gma_rate
        self.select_low_rear = select_low_rear
        self.period = period

    def reset(self, model, x0):
        self.t_on = np.full(x0.shape[0], np.nan)

    def update(self, t, x, out, zoh):
        k = out["kappa"]
        f = zoh["brake_factor"]
        f = np.where(k < -self.kd, f - self.dump * self.period,
                     np.where(k > -self.kb, f + self.build * self.period, f))
        f = np.clip(f, 0.0, 1.0)
        if self.select_low_rear:
            low = np.minimum(f[:, 2], f[:, 3])
            f[:, 2] = low
            f[:, 3] = low
        if self.gma_rate is not None:
            braking = out["p_master"] > 1.0
            self.t_on = np.where(braking & np.isnan(self.t_on), t, self.t_on)
            self.t_on = np.where(~braking, np.nan, self.t_on)
            gma = np.where(np.isnan(self.t_on), 0.0, self.gma_rate * (t - np.nan_to_num(self.t_on)))
            low = np.minimum(f[:, 0], f[:, 1])
            f[:, 0] = np.minimum(f[:, 0], low + gma)
            f[:, 1] = np.minimum(f[:, 1], low + gma)
        zoh["brake_factor"] = f


# ---------------------------------------------------------------------------
# Input profiles (vectorised over the batch)

def _per_member(a, n):
    return np.broadcast_to(np.asarray(a, dtype=float), (n,)).copy()


def ramp_profile(t0, rate, target):
    """0 before t0, then rate*(t - t0) up to target (signs follow target)."""
    target = np.asarray(target, dtype=float)
    rate = abs(rate)

    def f(t):
        return np.sign(target) * np.minimum(rate * max(t - t0, 0.0), np.abs(target))
    return f


def sine_dwell_profile(t0, amp, freq=0.7, dwell=0.5):
    """FMVSS 126 sine with dwell: amp*sin(2 pi f (t - t0)) up to the second
    peak (3/4 period), hold for `dwell`, then the last quarter period back to
    zero. amp > 0 steers left first. Returns f(t) and the completion time."""
    amp = np.asarray(amp, dtype=float)
    w = 2 * math.pi * freq
    t_peak2 = 0.75 / freq
    t_end = t0 + 1.0 / freq + dwell

    def f(t):
        s = t - t0
        if s <= 0.0:
            return amp * 0.0
        if s <= t_peak2:
            return amp * math.sin(w * s)
        if s <= t_peak2 + dwell:
            return -amp
        if s <= t_peak2 + dwell + 0.25 / freq:
            return amp * math.sin(w * (s - dwell))
        return amp * 0.0
    return f, t_end


def fishhook_profile(t0, amp, rate=720.0 * DEG, dwell1=0.25, hold=3.0):
    amp = np.asarray(amp, dtype=float)
    a = np.abs(amp)
    sgn = np.sign(amp)
    t_up = a / rate

    def f(t):
        s = t - t0
        if s <= 0:
            return amp * 0.0
        v = np.minimum(rate * s, a)                                   # up to +A
        s2 = s - t_up - dwell1
        v = np.where(s2 > 0, a - np.minimum(rate * s2, 2 * a), v)      # to -A
        s3 = s2 - 2 * t_up - hold
        v = np.where(s3 > 0, -a + np.minimum(rate * s3, a), v)         # back to 0
        return sgn * v
    return f, t0 + 4 * float(np.max(t_up)) + dwell1 + hold


def surface_mu(surface):
    """The friction scale of a surface: a name of SURFACES, a number, or a
    number written as text (a command line's "0.5")."""
    if isinstance(surface, (int, float)):
        return float(surface)
    try:
        return SURFACES[surface]
    except KeyError:
        pass
    try:
        return float(surface)
    except (TypeError, ValueError):
        raise ValueError(f"surface must be one of {sorted(SURFACES)} or a number, not {surface!r}") from None


def parse_surface(text):
    """A surface given on a command line: a name of SURFACES (returned as it
    is) or a friction scale in (0, 2] (returned as a float); ValueError
    naming the text otherwise."""
    if text in SURFACES:
        return text
    try:
        mu = float(text)
    except ValueError:
        mu = None
    if mu is None or not (math.isfinite(mu) and 0.0 < mu <= 2.0):
        raise ValueError(f"{text!r}: one of {', '.join(sorted(SURFACES))} or a friction scale in (0, 2]")
    return mu


def brake_pressure_for(vehicle, decel):
    """Master-cylinder pressure [bar] that gives `decel` [m/s^2] on a
    high-friction road (no lock, rolling radius ~ R0 - 2 %)."""
    from grip_tools.sim.tires import MFTire
    r = MFTire(vehicle.tire_file).r0 * 0.98
    return vehicle.m * decel * r / (2 * vehicle.brake_gain_front + 2 * vehicle.brake_gain_rear)


def linear_swa(vehicle, v, ay, model=None):
    """SWA [rad] for steady-state lateral acceleration ay at speed v from the
    linear bicycle model (seed 000 eqs 2.17-2.18) with the tyres' cornering
    stiffness at static load. A first guess for manoeuvre amplitudes."""
    from grip_tools.sim.tires import MFTire
    tire = model.tire if model is not None else MFTire(vehicle.tire_file)
    fzf, fzr = vehicle.static_loads()
    sf, sr = vehicle.tire_scale_front, vehicle.tire_scale_rear
    kf = float(tire.cornering_stiffness(fzf, sf.get("lmuy", 1.0), sf.get("lky", 1.0)))
    kr = float(tire.cornering_stiffness(fzr, sr.get("lmuy", 1.0), sr.get("lky", 1.0)))
    a = stability_factor(vehicle.m, vehicle.lf, vehicle.lr, kf, kr)
    return vehicle.l * ay / v ** 2 * (1 + a * v ** 2) * vehicle.steer_ratio


def stability_factor(m, lf, lr, kf, kr):
    """Seed 000 eq. 2.17 (per-wheel cornering stiffnesses kf, kr > 0):
    A = -(m / (2 l^2)) (lf Kf - lr Kr) / (Kf Kr)."""
    l = lf + lr
    return -(m / (2 * l * l)) * (lf * kf - lr * kr) / (kf * kr)


# ---------------------------------------------------------------------------
# Builders

def coast(vehicle, v0=25.0, duration=3.0, surface="dry", n=None):
    v0 = np.atleast_1d(np.asarray(v0, dtype=float))
    return Scenario(len(v0), v0, duration, Road.uniform(surface_mu(surface), name=str(surface)),
                    name="coast", meta=dict(manoeuvre="coast"))


def step_steer(vehicle, v0=80 * KMH, swa_deg=None, ay_target=4.0, t0=0.5, rate_deg=500.0,
               duration=3.0, surface="dry"):
    """Step steer to swa_deg (array: one member each; None: the linear-model
    SWA for ay_target) with speed hold at v0."""
    v0 = np.atleast_1d(np.asarray(v0, dtype=float))
    if swa_deg is None:
        swa = np.array([linear_swa(vehicle, v, ay_target) for v in v0])
    else:
        swa = np.asarray(swa_deg, dtype=float) * DEG
    n = max(len(v0), np.size(swa))
    swa = _per_member(swa, n)
    v0 = _per_member(v0, n)
    return Scenario(n, v0, duration, Road.uniform(surface_mu(surface), name=str(surface)),
                    steer=ramp_profile(t0, rate_deg * DEG, swa),
                    controllers=[SpeedHold(v0)], name="step-steer",
                    meta=dict(manoeuvre="step-steer", t_steer=t0, swa_deg=list(swa / DEG)))


def ramp_steer(vehicle, v0=80 * KMH, rate_deg=13.5, swa_max_deg=270.0, t0=0.5, duration=None,
               surface="dry", direction=(1.0,)):
    """Slowly increasing steer at constant speed (one member per direction)."""
    direction = np.asarray(direction, dtype=float)
    n = len(direction)
    if duration is None:
        duration = t0 + swa_max_deg / rate_deg
    target = direction * swa_max_deg * DEG
    v0 = _per_member(v0, n)
    return Scenario(n, v0, duration, Road.uniform(surface_mu(surface), name=str(surface)),
                    steer=ramp_profile(t0, rate_deg * DEG, target),
                    controllers=[SpeedHold(v0)], name="ramp-steer",
                    meta=dict(manoeuvre="ramp-steer", t_steer=t0, rate_deg=rate_deg))


def sine_dwell(vehicle, amp_deg, v0=80 * KMH, t0=0.3, settle=2.0, surface="dry"):
    """FMVSS 126 sine with dwell at amplitude(s) amp_deg [deg SWA]; coasting
    (no drive torque, no brakes). meta: t_bos (beginning of steer), t_cos
    (completion of steer)."""
    amp = np.atleast_1d(np.asarray(amp_deg, dtype=float)) * DEG
    n = len(amp)
    f, t_cos = sine_dwell_profile(t0, amp)
    return Scenario(n, _per_member(v0, n), t_cos + settle,
                    Road.uniform(surface_mu(surface), name=str(surface)),
                    steer=f, name="sine-dwell",
                    meta=dict(manoeuvre="sine-dwell", t_bos=t0, t_cos=t_cos, amp_deg=list(amp / DEG)))


def fishhook(vehicle, amp_deg, v0=70 * KMH, t0=0.3, surface="dry", settle=0.5):
    amp = np.atleast_1d(np.asarray(amp_deg, dtype=float)) * DEG
    n = len(amp)
    f, t_end = fishhook_profile(t0, amp)
    return Scenario(n, _per_member(v0, n), t_end + settle,
                    Road.uniform(surface_mu(surface), name=str(surface)),
                    steer=f, name="fishhook", meta=dict(manoeuvre="fishhook", t_bos=t0, amp_deg=list(amp / DEG)))


def brake_in_turn(vehicle, v0=80 * KMH, ay_target=4.0, decel=4.0, swa_deg=None, t_steer=0.3,
                  t_brake=3.0, ramp_bar_s=300.0, duration=5.0, surface="dry", use_abs=False):
    """Steady cornering (SWA for ay_target, speed held), then at t_brake the
    throttle is released and the master pressure ramps to the pressure of
    `decel` (one member per decel value)."""
    decel = np.atleast_1d(np.asarray(decel, dtype=float))
    n = len(decel)
    swa = linear_swa(vehicle, v0, ay_target) if swa_deg is None else swa_deg * DEG
    p_target = np.array([brake_pressure_for(vehicle, d) for d in decel])

    def brake(t):
        return np.minimum(ramp_bar_s * max(t - t_brake, 0.0), p_target)
    ctl = [SpeedHold(v0, t_off=t_brake)] + ([ABS()] if use_abs else [])
    return Scenario(n, _per_member(v0, n), duration, Road.uniform(surface_mu(surface), name=str(surface)),
                    steer=ramp_profile(t_steer, 100 * DEG, _per_member(swa, n)), brake=brake,
                    controllers=ctl, name="brake-in-turn",
                    meta=dict(manoeuvre="brake-in-turn", t_brake=t_brake, swa_deg=float(swa / DEG),
                              p_target_bar=list(p_target)))


def mu_step(vehicle, v0=80 * KMH, surface="dry", mu_after=None, x_step=None, p_bar=None,
            t_brake=0.3, ramp_bar_s=300.0, duration=3.0, use_abs=True):
    """Straight-line braking that crosses a friction step along the road at
    X = x_step (default: reached about 1 s after the brake application)."""
    mu0 = surface_mu(surface)
    if mu_after is None:
        mu_after = 0.3 if mu0 > 0.3 else 1.0
    if x_step is None:
        x_step = v0 * (t_brake + 1.0)
    if p_bar is None:
        p_bar = brake_pressure_for(vehicle, 0.8 * G * max(mu0, mu_after))
    road = Road.mu_step(x_step, mu0, mu_after)

    def brake(t):
        return np.array([min(ramp_bar_s * max(t - t_brake, 0.0), p_bar)])
    return Scenario(1, [v0], duration, road, brake=brake,
                    controllers=[ABS()] if use_abs else [], name="mu-step",
                    meta=dict(manoeuvre="mu-step", x_step=x_step, mu_before=mu0, mu_after=mu_after,
                              p_bar=p_bar))


def mu_split_brake(vehicle, v0=80 * KMH, surface="dry", mu_low=None, p_bar=None, t_brake=0.3,
                   ramp_bar_s=400.0, duration=2.0, use_abs=True):
    """Straight-line braking with the left wheels on mu_low and the right
    wheels on the surface's friction; steering held at zero."""
    mu_high = surface_mu(surface)
    if mu_low is None:
        mu_low = min(0.3, 0.5 * mu_high) if mu_high > 0.3 else 0.5 * mu_high
    if p_bar is None:
        p_bar = brake_pressure_for(vehicle, 0.9 * G * mu_high)
    road = Road.mu_split(mu_low, mu_high)

    def brake(t):
        return np.array([min(ramp_bar_s * max(t - t_brake, 0.0), p_bar)])
    return Scenario(1, [v0], duration, road, brake=brake,
                    controllers=[ABS()] if use_abs else [], name="mu-split-brake",
                    meta=dict(manoeuvre="mu-split-brake", mu_left=mu_low, mu_right=mu_high,
                              p_bar=p_bar, t_brake=t_brake))


def replay(vehicle, time, vx, delta=None, swa=None, surface="dry", t_end=None, use_brakes=True,
           h_lookahead=0.0):
    """Drive the model with measured inputs (issue 7's measured-data loop):
    steering from a road-wheel angle delta [rad] (converted with the
    steering ratio) or a steering-wheel angle swa [rad], both interpolated
    in time; the speed follows the measured vx with SpeedHold (feed-forward
    of the reference acceleration, PI, brakes for negative demand).
    Starts straight at vx[0]."""
    time = np.asarray(time, dtype=float)
    vx = np.asarray(vx, dtype=float)
    if swa is None:
        if delta is None:
            raise ValueError("give delta (road-wheel angle) or swa")
        swa = np.asarray(delta, dtype=float) * vehicle.steer_ratio
    swa = np.asarray(swa, dtype=float)
    t0 = time[0]

    def steer(t):
        return np.array([np.interp(t + t0 + h_lookahead, time, swa)])

    def v_ref(t):
        return np.array([np.interp(t + t0, time, vx)])
    duration = (t_end if t_end is not None else time[-1]) - t0
    return Scenario(1, [vx[0]], duration, Road.uniform(surface_mu(surface), name=str(surface)),
                    steer=steer, controllers=[SpeedHold(v_ref, kp=1.5, ki=0.3, use_brakes=use_brakes)],
                    name="replay", meta=dict(manoeuvre="replay", t0_data=float(t0)))


# ---------------------------------------------------------------------------
# FMVSS 126 helpers

def swa_at_03g(vehicle, effects=None, v0=80 * KMH, h=2e-3, rate_deg=13.5, return_result=False):
    """SWA [deg] that gives 0.3 g in the FMVSS 126 slowly increasing steer
    (13.5 deg/s at 80 km/h, left and right): linear regression of SWA on
    lateral acceleration over 0.1 g..0.375 g, evaluated at 0.3 g, mean of
    both directions. Runs on a dry road."""
    guess = abs(linear_swa(vehicle, v0, 0.45 * G)) / DEG
    sc = ramp_steer(vehicle, v0, rate_deg=rate_deg, swa_max_deg=270.0, t0=0.2,
                    duration=0.2 + 1.15 * guess / rate_deg, surface="dry", direction=(1.0, -1.0))
    res = simulate(vehicle, sc, effects, h=h)
    vals = []
    for i in range(2):
        ay = np.abs(res["ay_imu"][:, i])
        swa = np.abs(res["swa"][:, i]) / DEG
        sel = (ay >= 0.1 * G) & (ay <= 0.375 * G)
        if sel.sum() < 10 or ay.max() < 0.375 * G:
            raise RuntimeError("ramp steer did not reach 0.375 g")
        c = np.polyfit(ay[sel], swa[sel], 1)
        vals.append(np.polyval(c, 0.3 * G))
    out = float(np.mean(vals))
    return (out, res) if return_result else out


def fmvss126_metrics(res, i=0):
    """FMVSS 126 S5.2 criteria of member i of a sine-with-dwell Result.

    r_peak: first yaw-rate peak after the steering changes sign (the
    peak of the sign of the dwell), ratio_1s / ratio_175: yaw rate 1.00 s
    and 1.75 s after completion of steer divided by r_peak (limits 0.35 and
    0.20), lat_disp_107: lateral displacement of the CG 1.07 s after the
    beginning of steer (limit >= 1.83 m for amplitudes >= 5 x SWA(0.3 g)),
    measured in the initial heading frame."""
    t = res.t
    t_bos, t_cos = res.meta["t_bos"], res.meta["t_cos"]
    r = res["r"][:, i]
    swa = res["swa"][:, i]
    amp_sign = np.sign(swa[np.argmax(np.abs(swa[t <= t_bos + 0.5 / 0.7]))])
    # the steering changes sign half a period after the beginning of steer
    win = (t >= t_bos + 0.5 / 0.7) & (t <= t_cos + 1.75)
    rr = -amp_sign * r[win]
    k = int(np.argmax(rr))
    r_peak = r[win][k]
    t_peak = t[win][k]
    r1 = np.interp(t_cos + 1.0, t, r)
    r175 = np.interp(t_cos + 1.75, t, r)
    y = np.interp(t_bos + 1.07, t, res["Y"][:, i])
    return dict(r_peak=float(r_peak), t_peak=float(t_peak), r_1s=float(r1), r_175=float(r175),
                ratio_1s=float(r1 / r_peak), ratio_175=float(r175 / r_peak),
                lat_disp_107=float(abs(y)),
                pass_stability=bool(abs(r1 / r_peak) <= 0.35 and abs(r175 / r_peak) <= 0.20))


# ---------------------------------------------------------------------------

MANOEUVRES = ("coast", "step-steer", "ramp-steer", "sine-dwell", "fishhook", "brake-in-turn",
              "mu-step", "mu-split-brake")


def build(name, vehicle, surface="dry", **kw):
    """Scenario of a manoeuvre by name with its default settings (kw override).
    sine-dwell and fishhook need amp_deg (see swa_at_03g)."""
    table = {"coast": coast, "step-steer": step_steer, "ramp-steer": ramp_steer,
             "sine-dwell": sine_dwell, "fishhook": fishhook, "brake-in-turn": brake_in_turn,
             "mu-step": mu_step, "mu-split-brake": mu_split_brake}
    if name not in table:
        raise ValueError(f"unknown manoeuvre {name!r} (have {', '.join(MANOEUVRES)})")
    return table[name](vehicle, surface=surface, **kw)
