"""Two-track vehicle model with roll, wheel spin and Magic Formula tyres,
integrated with a fixed-step classical Runge-Kutta (RK4) scheme.

Every array carries a leading batch dimension N: one call simulates N
vehicles (same parameters, individual inputs and initial speeds), so a
manoeuvre series costs about as much as a single run (the tyre model is
evaluated once per RK4 stage for all 4 N wheels).

Axes: ISO 8855 vehicle axes (x forward, y left, z up), yaw rate r > 0 to
the left, road-wheel and steering-wheel angles > 0 to the left, roll phi > 0
when the body leans to the right (left side up, as in a left turn).
Wheel order FL, FR, RL, RR. Tyre quantities in ISO-W (see tires.py).
The equations are written out in docs/simulator.md.

State vector per vehicle (NS = 26):
  0 X, 1 Y [m]       position of the CG in the road (earth) frame
  2 psi [rad]        yaw angle
  3 vx, 4 vy [m/s]   CG velocity in body axes
  5 r [rad/s]        yaw rate
  6 phi, 7 phid      roll angle [rad] and rate [rad/s]
  8 fxf, 9 fyf       lagged specific tyre forces sum(Fx)/m, sum(Fy)/m [m/s^2]
                     (longitudinal load transfer, roll-centre load transfer)
  10..13 omega       wheel spin speeds [rad/s]
  14..17 kappa'      relaxed longitudinal slips (relaxation on)
  18..21 tan(alpha') relaxed lateral slips (relaxation on)
  22..25 T           tyre surface temperatures [degC] (thermal on)
"""
from dataclasses import dataclass, fields

import numpy as np

from grip_tools.sim.tires import MFTire
from grip_tools.sim.vehicles import G

NS = 26
IX, IY, IPSI, IVX, IVY, IR, IPHI, IPHID, IFXF, IFYF = range(10)
IW = slice(10, 14)
IK = slice(14, 18)
IA = slice(18, 22)
IT = slice(22, 26)
WHEELS = ("fl", "fr", "rl", "rr")
DIVERGED_SLIP = 1e3     # |relaxed slip state| beyond this means the explicit scheme went unstable


# ---------------------------------------------------------------------------
# Thermal coefficients: taken from grip_tools.reference.mf_thermal (seed 000 ch. 4)
# when present, else the same default values.

@dataclass
class _ThermalFallback:
    t0: float = 30.0
    ax: float = -0.004
    bx: float = -0.006
    ay: float = -0.003
    by: float = -0.008
    w: float = 1500.0
    kappa: float = 0.08
    t_min: float = -30.0
    t_max: float = 130.0


def default_thermal():
    try:
        from grip_tools.reference import mf_thermal
        return mf_thermal.ThermalParams()
    except ImportError:      # pragma: no cover - only without the sibling module
        return _ThermalFallback()


@dataclass
class Effects:
    """Switchable model effects (docs/simulator.md, 'Effects')."""
    relaxation: bool = True        # first-order slip lag per wheel (else blended steady-state slip)
    thermal: bool = False          # tyre surface temperature scales friction and slip stiffness
    aero: bool = True              # drag and downforce (vehicle cda, cla)
    load_transfer: bool = True     # longitudinal + lateral (roll) load transfer
    aligning_moment: bool = True   # tyre Mz enters the yaw balance
    rolling_resistance: bool = True
    thermal_params: object = None  # mf_thermal.ThermalParams (None: defaults)
    t_init: float = None           # initial tyre temperature [degC] (None: thermal t0)

    def label(self):
        """Comma-separated names of the effects that are on."""
        return ",".join(f.name for f in fields(self) if getattr(self, f.name) is True)


# ---------------------------------------------------------------------------
# Road: friction field, grade and bank.

def _smoothstep(u):
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


class Road:
    """Road surface: friction scale mu(X, Y) at each contact point (1.0 =
    the tyre as fitted, i.e. a dry road), plane grade and bank, road
    temperature. mu multiplies LMUX and LMUY of the tyre at that wheel.

    grade: rise per metre along +X (tan of the grade angle);
    bank: rise per metre along +Y (road higher on the left for bank > 0).
    """

    def __init__(self, mu=1.0, mu_fn=None, grade=0.0, bank=0.0, t_road=25.0, name=None):
        self.mu = float(mu)
        self.mu_fn = mu_fn
        self.grade = float(grade)
        self.bank = float(bank)
        self.t_road = float(t_road)
        self.name = name or f"mu={mu:g}"

    def mu_at(self, X, Y):
        if self.mu_fn is None:
            return np.full(np.shape(X), self.mu)
        return np.asarray(self.mu_fn(X, Y), dtype=float)

    @classmethod
    def batch(cls, roads, **kw):
        """One friction field per batch member (member i uses roads[i].mu_at);
        grade, bank and temperature from kw (shared)."""
        roads = list(roads)

        def f(X, Y):
            if X.shape[0] != len(roads):
                raise ValueError(f"Road.batch has {len(roads)} roads for a batch of {X.shape[0]}")
            return np.stack([r.mu_at(X[i], Y[i]) for i, r in enumerate(roads)])
        kw.setdefault("name", " | ".join(r.name for r in roads))
        return cls(mu=roads[0].mu, mu_fn=f, **kw)

    @classmethod
    def uniform(cls, mu, **kw):
        return cls(mu=mu, **kw)

    @classmethod
    def mu_step(cls, x0, mu_before, mu_after, length=0.2, **kw):
        """Friction changes from mu_before to mu_after at X = x0 (smooth over `length` m)."""
        def f(X, Y):
            return mu_before + (mu_after - mu_before) * _smoothstep((X - x0) / length + 0.5)
        kw.setdefault("name", f"mu-step {mu_before:g}->{mu_after:g} at X={x0:g} m")
        return cls(mu=mu_before, mu_fn=f, **kw)

    @classmethod
    def mu_split(cls, mu_left, mu_right, y0=0.0, length=0.1, **kw):
        """mu_left for Y > y0 (left of the start line), mu_right for Y < y0."""
        def f(X, Y):
            return mu_right + (mu_left - mu_right) * _smoothstep((Y - y0) / length + 0.5)
        kw.setdefault("name", f"mu-split left {mu_left:g} / right {mu_right:g}")
        return cls(mu=mu_left, mu_fn=f, **kw)


SURFACES = {"dry": 1.0, "wet": 0.6, "snow": 0.3}


# ---------------------------------------------------------------------------
# Scenario: what the simulator needs from a manoeuvre.

class Scenario:
    """Inputs of one (batched) simulation.

    n: batch size; v0: initial speeds (N,); duration [s]; road: Road;
    steer(t) -> steering-wheel angle (N,) [rad]; brake(t) -> master-cylinder
    pressure (N,) [bar]; drive(t) -> total drive torque at the wheels (N,)
    [N m] (open loop, added to the controllers'); controllers: objects with
    .period [s], .reset(sim, x0) and .update(t, x, out, zoh) that change the
    zero-order-held inputs zoh['drive'] (N,) [N m], zoh['brake'] (N,) [bar,
    added to the master pressure] and zoh['brake_factor'] (N, 4).
    """

    def __init__(self, n, v0, duration, road=None, steer=None, brake=None, drive=None,
                 controllers=(), name="scenario", meta=None, init=None):
        self.n = int(n)
        self.v0 = np.broadcast_to(np.asarray(v0, dtype=float), (self.n,)).copy()
        self.duration = float(duration)
        self.road = road or Road()
        zero = np.zeros(self.n)
        self.steer = steer or (lambda t: zero)
        self.brake = brake or (lambda t: zero)
        self.drive = drive or (lambda t: zero)
        self.controllers = list(controllers)
        self.name = name
        self.meta = dict(meta or {})
        self.init = init     # optional callable(x0) -> x0 (extra initial conditions)


# ---------------------------------------------------------------------------

class Model:
    """The vehicle model: parameters, effects, tyre adapter, right-hand side."""

    def __init__(self, vehicle, effects=None, tire=None):
        self.v = vehicle
        self.fx = effects or Effects()
        self.tire = tire or MFTire(vehicle.tire_file)
        self.th = self.fx.thermal_params or default_thermal()
        v = vehicle
        x, y = v.wheel_positions()
        self.xw = np.array(x)
        self.yw = np.array(y)
        self.left = np.array([True, False, True, False])
        self.front = np.array([True, True, False, False])
        self.mirror = self.tire.mirror_for(self.left)
        sf, sr = v.tire_scale_front, v.tire_scale_rear
        self.scale = {k: np.array([sf.get(k, 1.0)] * 2 + [sr.get(k, 1.0)] * 2)
                      for k in ("lmux", "lmuy", "lkx", "lky")}
        fzf, fzr = v.static_loads()
        self.fz_static = np.array([fzf, fzf, fzr, fzr])
        re_auto = self.tire.r0 - self.fz_static / (3.0 * self.tire.cz)
        self.re = np.array([v.re_front or re_auto[0], v.re_front or re_auto[1],
                            v.re_rear or re_auto[2], v.re_rear or re_auto[3]])
        self.j = np.array([v.j_front, v.j_front, v.j_rear, v.j_rear])
        self.brake_gain = np.array([v.brake_gain_front] * 2 + [v.brake_gain_rear] * 2)
        drv = {"fwd": [1, 1, 0, 0], "rwd": [0, 0, 1, 1], "awd": [1, 1, 1, 1]}[v.drive]
        self.drive_share = np.array(drv, dtype=float) / sum(drv)
        self.k_roll_axle = np.array([v.k_roll * v.roll_split_front, v.k_roll * (1 - v.roll_split_front)])
        self.c_roll_axle = np.array([v.c_roll * v.roll_split_front, v.c_roll * (1 - v.roll_split_front)])
        self.h_s = v.h - v.h_roll_axis
        # low-speed damping of the relaxed slips (zeta = 0.5 at standstill)
        t0 = self.tire.evaluate(0.0, 0.0, self.fz_static, self.tire.vxlow,
                                self.scale["lmux"], self.scale["lmuy"], self.scale["lkx"], self.scale["lky"],
                                self.mirror)
        sk, sa = self.tire.relaxation_lengths(self.fz_static, t0["kx"], t0["ky"])
        self.kx_static, self.ky_static = t0["kx"], t0["ky"]
        zeta = 0.5
        wn_x = np.sqrt(self.re ** 2 * t0["kx"] / (self.j * sk))
        self.cd_x = 2 * zeta / (wn_x * sk)
        m4 = v.m / 4.0
        wn_y = np.sqrt(t0["ky"] / (sa * m4))
        self.cd_y = 2 * zeta * wn_y * m4 / t0["ky"]

    # ------------------------------------------------------------------
    def initial_state(self, v0):
        v0 = np.asarray(v0, dtype=float)
        n = v0.shape[0]
        x = np.zeros((n, NS))
        x[:, IVX] = v0
        x[:, IW] = v0[:, None] / self.re[None, :]
        t_init = self.fx.t_init if self.fx.t_init is not None else self.th.t0
        x[:, IT] = t_init
        return x

    def _steer_angles(self, swa):
        d = swa / self.v.steer_ratio                       # (N,)
        z = np.zeros_like(d)
        a = self.v.ackermann
        if a:
            l, t2 = self.v.l, self.v.tf / 2
            td = np.tan(d)
            dl = np.arctan2(l * td, l - a * t2 * td)
            dr = np.arctan2(l * td, l + a * t2 * td)
            return np.stack([dl, dr, z, z], axis=1)
        return np.stack([d, d, z, z], axis=1)

    def rhs(self, t, x, u):
        """dx/dt and the output dict at state x (N, NS) with inputs u:
        swa (N,) [rad], p_master (N,) [bar], drive (N,) [N m], brake_factor (N, 4)."""
        v, fx_on, th = self.v, self.fx, self.th
        road = u["road"]
        X, Y, psi = x[:, IX], x[:, IY], x[:, IPSI]
        vx, vy, r = x[:, IVX], x[:, IVY], x[:, IR]
        phi, phid = x[:, IPHI], x[:, IPHID]
        om = x[:, IW]
        cpsi, spsi = np.cos(psi), np.sin(psi)

        # road slope -> gravity in body axes
        sx = road.grade * cpsi + road.bank * spsi           # rise along the heading
        sy = -road.grade * spsi + road.bank * cpsi          # rise to the vehicle's left
        g_x = -G * sx / np.sqrt(1 + sx * sx)
        g_y = -G * sy / np.sqrt(1 + sy * sy)
        g_n = G / np.sqrt(1 + sx * sx + sy * sy)

        # steering and contact-centre velocities
        delta = self._steer_angles(u["swa"])                # (N, 4)
        cd, sd = np.cos(delta), np.sin(delta)
        vix = vx[:, None] - r[:, None] * self.yw[None, :]
        viy = vy[:, None] + r[:, None] * self.xw[None, :]
        vcx = vix * cd + viy * sd
        vcy = -vix * sd + viy * cd
        avx = np.abs(vcx)

        # vertical loads
        scale_n = g_n / G
        fz = np.broadcast_to(self.fz_static * scale_n[:, None], vcx.shape).copy()
        drag = np.zeros_like(vx)
        if fx_on.aero:
            q = 0.5 * v.rho * vx * vx
            drag = 0.5 * v.rho * v.cda * vx * np.abs(vx)
            down = q * v.cla
            fz += down[:, None] * np.array([v.aero_balance_front / 2] * 2
                                           + [(1 - v.aero_balance_front) / 2] * 2)[None, :]
        if fx_on.load_transfer:
            dfx = v.m * x[:, IFXF] * v.h / v.l             # front -> rear (N,)
            fz += dfx[:, None] * np.array([-0.5, -0.5, 0.5, 0.5])[None, :]
            el = (self.k_roll_axle[None, :] * phi[:, None] + self.c_roll_axle[None, :] * phid[:, None])
            geo = v.m * x[:, IFYF][:, None] * np.array([v.lr * v.h_rcf, v.lf * v.h_rcr])[None, :] / v.l
            dfy = (el + geo) / np.array([v.tf, v.tr])[None, :]          # (N, 2) to the right wheels
            fz += np.stack([-dfy[:, 0], dfy[:, 0], -dfy[:, 1], dfy[:, 1]], axis=1)
        fz = np.maximum(fz, 0.0)

        # slips
        re_om = om * self.re[None, :]
        if fx_on.relaxation:
            wl = 0.5 * (1.0 + np.cos(np.pi * np.minimum(avx / v.v_low, 1.0)))
            kappa = x[:, IK] + self.cd_x[None, :] * wl * (re_om - vcx)
            tana = x[:, IA] + self.cd_y[None, :] * wl * vcy
        else:
            den = np.sqrt(vcx * vcx + v.v_eps ** 2)
            kappa = (re_om - vcx) / den
            tana = vcy / den
        alpha = np.arctan(tana)

        # friction and stiffness scaling: road mu, tyre temperature
        xw_e = X[:, None] + self.xw[None, :] * cpsi[:, None] - self.yw[None, :] * spsi[:, None]
        yw_e = Y[:, None] + self.xw[None, :] * spsi[:, None] + self.yw[None, :] * cpsi[:, None]
        mu = road.mu_at(xw_e, yw_e)
        lmux = mu * self.scale["lmux"]
        lmuy = mu * self.scale["lmuy"]
        lkx = np.broadcast_to(self.scale["lkx"], mu.shape)
        lky = np.broadcast_to(self.scale["lky"], mu.shape)
        temp = x[:, IT]
        if fx_on.thermal:
            dT = temp - th.t0
            lmux = lmux * np.clip(1.0 + th.ax * dT, 0.2, 2.0)
            lmuy = lmuy * np.clip(1.0 + th.ay * dT, 0.2, 2.0)
            lkx = lkx * np.clip(1.0 + th.bx * dT, 0.2, 2.0)
            lky = lky * np.clip(1.0 + th.by * dT, 0.2, 2.0)

        vmf = np.maximum(avx, self.tire.vxlow)
        tf = self.tire.evaluate(kappa, alpha, fz, vmf, lmux, lmuy, lkx, lky,
                                np.broadcast_to(self.mirror, fz.shape))
        fxw, fyw, mz = tf["fx"], tf["fy"], tf["mz"]

        # body forces and moments
        fxb = fxw * cd - fyw * sd
        fyb = fxw * sd + fyw * cd
        sfx = fxb.sum(axis=1)
        sfy = fyb.sum(axis=1)
        mzb = (self.xw[None, :] * fyb - self.yw[None, :] * fxb).sum(axis=1)
        if fx_on.aligning_moment:
            mzb = mzb + mz.sum(axis=1)
        ax = (sfx - drag) / v.m + g_x
        ay = sfy / v.m + g_y

        dx = np.zeros_like(x)
        dx[:, IX] = vx * cpsi - vy * spsi
        dx[:, IY] = vx * spsi + vy * cpsi
        dx[:, IPSI] = r
        dx[:, IVX] = ax + r * vy
        dx[:, IVY] = ay - r * vx
        dx[:, IR] = mzb / v.iz
        if fx_on.load_transfer:
            roll_m = v.m * self.h_s * (sfy / v.m * np.cos(phi) + g_n * np.sin(phi))
            dx[:, IPHI] = phid
            dx[:, IPHID] = (roll_m - v.k_roll * phi - v.c_roll * phid) / v.ixs
            dx[:, IFXF] = (sfx / v.m - x[:, IFXF]) / v.tau_pitch
            dx[:, IFYF] = (sfy / v.m - x[:, IFYF]) / v.tau_lat_geo

        # wheel spin
        sgn = np.tanh(om / v.omega_eps)
        t_drive = u["drive"][:, None] * self.drive_share[None, :]
        p_wheel = u["p_master"][:, None] * u["brake_factor"]
        t_brake = self.brake_gain[None, :] * p_wheel
        m_rr = self.tire.qsy1 * fz * self.tire.r0 if fx_on.rolling_resistance else np.zeros_like(fz)
        dx[:, IW] = (t_drive - (t_brake + m_rr) * sgn - self.re[None, :] * fxw) / self.j[None, :]

        # relaxation lengths and slip lag
        sig_k, sig_a = self.tire.relaxation_lengths(fz, tf["kx"], tf["ky"])
        if fx_on.relaxation:
            dx[:, IK] = (re_om - vcx - avx * x[:, IK]) / sig_k
            dx[:, IA] = (vcy - avx * x[:, IA]) / sig_a

        # tyre temperature (seed 000 eqs 4.1-4.6): W dT/dt = F Vs - lambda A (T - TR)
        vs = np.sqrt((vcx - re_om) ** 2 + vcy ** 2)
        q_heat = np.hypot(fxw, fyw) * vs
        if fx_on.thermal:
            dx[:, IT] = q_heat / th.w - th.kappa * (temp - road.t_road)

        out = dict(
            X=X, Y=Y, psi=psi, vx=vx, vy=vy, r=r, phi=phi, phid=phid,
            beta=np.arctan2(vy, vx),
            speed=np.hypot(vx, vy), ax=ax, ay=ay,
            ax_imu=(sfx - drag) / v.m,
            ay_imu=(sfy / v.m) * np.cos(phi) + g_n * np.sin(phi),
            yaw_imu=r * np.cos(phi),
            swa=u["swa"], delta=delta[:, 0] * 0.5 + delta[:, 1] * 0.5,
            p_master=u["p_master"], drive=u["drive"], drag=drag, mz_total=mzb,
            omega=om, kappa=kappa, alpha=alpha, fz=fz, fx=fxw, fy=fyw, mz=mz,
            mu_road=mu, mux=tf["mux"], muy=tf["muy"], temp=temp,
            vcx=vcx, vcy=vcy, vs=vs, q_heat=q_heat, delta_w=delta,
            t_drive=t_drive, t_brake=t_brake, p_brake=p_wheel,
            sigma_k=sig_k, sigma_a=sig_a, kx=tf["kx"], ky=tf["ky"],
            m_rr=m_rr, re_omega=re_om,
        )
        return dx, out


SCALARS = ("X", "Y", "psi", "vx", "vy", "r", "phi", "phid", "beta", "speed", "ax", "ay",
           "ax_imu", "ay_imu", "yaw_imu", "swa", "delta", "p_master", "drive", "drag", "mz_total")
PER_WHEEL = ("omega", "re_omega", "kappa", "alpha", "fz", "fx", "fy", "mz", "mu_road", "mux", "muy",
             "temp", "vcx", "vcy", "vs", "q_heat", "delta_w", "t_drive", "t_brake", "p_brake",
             "sigma_k", "sigma_a", "kx", "ky", "m_rr")
UNITS = dict(X="m", Y="m", psi="rad", vx="m/s", vy="m/s", r="rad/s", phi="rad", phid="rad/s",
             beta="rad", speed="m/s", ax="m/s^2", ay="m/s^2", ax_imu="m/s^2", ay_imu="m/s^2",
             yaw_imu="rad/s", swa="rad", delta="rad", p_master="bar", drive="N m", drag="N",
             mz_total="N m", omega="rad/s", re_omega="m/s", kappa="-", alpha="rad", fz="N", fx="N",
             fy="N", mz="N m", mu_road="-", mux="-", muy="-", temp="degC", vcx="m/s", vcy="m/s",
             vs="m/s", q_heat="W", delta_w="rad", t_drive="N m", t_brake="N m", p_brake="bar",
             sigma_k="m", sigma_a="m", kx="N", ky="N/rad", m_rr="N m")


class Result:
    """Recorded outputs. t: (nt,); data[name]: (nt, N) or (nt, N, 4);
    x_final: (N, NS). member(i) gives flat 1-D columns of vehicle i."""

    def __init__(self, t, data, meta, x_final):
        self.t = t
        self.data = data
        self.meta = meta
        self.x_final = x_final

    @property
    def n(self):
        return self.data["vx"].shape[1]

    def __getitem__(self, name):
        return self.data[name]

    def member(self, i=0):
        cols = {"time": self.t}
        for k in SCALARS:
            cols[k] = self.data[k][:, i]
        for k in PER_WHEEL:
            for j, w in enumerate(WHEELS):
                cols[f"{k}_{w}"] = self.data[k][:, i, j]
        return cols

    def columns(self):
        names = ["time"] + list(SCALARS) + [f"{k}_{w}" for k in PER_WHEEL for w in WHEELS]
        units = ["s"] + [UNITS[k] for k in SCALARS] + [UNITS[k] for k in PER_WHEEL for _ in WHEELS]
        return names, units

    def write_csv(self, path, i=0, comment=None):
        cols = self.member(i)
        names, units = self.columns()
        arr = np.column_stack([cols[n] for n in names])
        with open(path, "w") as f:
            for line in (comment or []):
                f.write(f"# {line}\n")
            f.write("# units: " + ",".join(units) + "\n")
            f.write(",".join(names) + "\n")
            np.savetxt(f, arr, delimiter=",", fmt="%.9g")


def read_csv(path):
    """Columns of a truth.csv / sensors.csv file as a dict of arrays."""
    with open(path) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    names = lines[0].strip().split(",")
    arr = np.loadtxt(lines[1:], delimiter=",", ndmin=2)
    return {n: arr[:, k] for k, n in enumerate(names)}


# ---------------------------------------------------------------------------

def simulate(vehicle, scenario, effects=None, h=1e-3, record_every=None, model=None):
    """Integrate `scenario` with fixed-step RK4 of step h [s].

    Inputs given as functions of time (steer, brake, drive) are evaluated
    at every RK4 stage; controller outputs are held over their period
    (which must be a multiple of h). Outputs are recorded every
    record_every steps (default: every 1 ms or every step if h > 1 ms).
    Returns a Result.
    """
    model = model or Model(vehicle, effects)
    sc = scenario
    n = sc.n
    nsteps = int(round(sc.duration / h))
    if record_every is None:
        record_every = max(1, int(round(1e-3 / h)))
    x = model.initial_state(sc.v0)
    if sc.init is not None:
        x = sc.init(x)
    zoh = {"drive": np.zeros(n), "brake": np.zeros(n), "brake_factor": np.ones((n, 4))}
    ctrl_every = []
    for c in sc.controllers:
        k = c.period / h
        if abs(k - round(k)) > 1e-9 or round(k) < 1:
            raise ValueError(f"controller period {c.period} s is not a multiple of h = {h} s")
        ctrl_every.append(int(round(k)))
        c.reset(model, x)

    def inputs(t):
        return {"swa": np.asarray(sc.steer(t), dtype=float) * np.ones(n),
                "p_master": np.maximum(np.asarray(sc.brake(t), dtype=float) * np.ones(n) + zoh["brake"], 0.0),
                "drive": np.clip(np.asarray(sc.drive(t), dtype=float) + zoh["drive"],
                                 -vehicle.drive_torque_max, vehicle.drive_torque_max),
                "brake_factor": zoh["brake_factor"], "road": sc.road}

    nrec = nsteps // record_every + 1
    t_rec = np.zeros(nrec)
    data = {}
    for k in SCALARS:
        data[k] = np.zeros((nrec, n))
    for k in PER_WHEEL:
        data[k] = np.zeros((nrec, n, 4))

    def record(irec, t, out):
        t_rec[irec] = t
        for k in SCALARS:
            data[k][irec] = out[k]
        for k in PER_WHEEL:
            data[k][irec] = out[k]

    irec = 0
    if True:
        for step in range(nsteps + 1):
            t = step * h
            k1, out = model.rhs(t, x, inputs(t))
            changed = False
            for c, every in zip(sc.controllers, ctrl_every):
                if step % every == 0:
                    c.update(t, x, out, zoh)
                    changed = True
            if changed:
                k1, out = model.rhs(t, x, inputs(t))
            if step % record_every == 0:
                record(irec, t, out)
                irec += 1
            if step == nsteps:
                break
            u2 = inputs(t + 0.5 * h)
            k2, _ = model.rhs(t + 0.5 * h, x + 0.5 * h * k1, u2)
            k3, _ = model.rhs(t + 0.5 * h, x + 0.5 * h * k2, u2)
            k4, _ = model.rhs(t + h, x + h * k3, inputs(t + h))
            x = x + (h / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
            if not np.all(np.isfinite(x)) or np.abs(x[:, 14:22]).max() > DIVERGED_SLIP:
                raise FloatingPointError(f"integration diverged at t = {t + h:.4f} s with h = {h} s "
                                         "(slip state out of range): reduce the step")
    meta = dict(scenario=sc.name, h=h, record_dt=h * record_every, vehicle=vehicle.name,
                re=[float(r) for r in model.re],
                tire=model.tire.name, effects=model.fx.label(), road=sc.road.name, **sc.meta)
    res = Result(t_rec[:irec], {k: a[:irec] for k, a in data.items()}, meta, x)
    res.model = model
    return res
