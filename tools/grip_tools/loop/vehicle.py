"""Vehicle-level models of the residual tool.

1. `BicycleModel` + `load`: the comma2k19 RAV4 CAN log. Yaw rate and lateral
   acceleration from steering and speed by the steady-state single-track
   (bicycle) model

       r = vx delta / (L (1 + vx^2 / v_ch^2)),   ay = vx r

   against the yaw rate and ay the car's own sensors put on CAN (samples from
   `grip-replay LOG`, SI units after the signal table). RAV4 wheelbase
   L = 2.69 m; characteristic speed v_ch = 20 m/s (assumed). Only sensor
   effects (bias, scale, delay) apply to it.

2. `VehicleModel`: a dynamic single-track model with roll for a vehicle
   parameter set of the reference simulator (grip_tools.sim.vehicles),
   driven by the measured steering-wheel angle and speed, predicting the
   IMU's yaw rate r cos(phi) and lateral specific force. It is the model
   under test of the vehicle-level undeclared-effect data sets
   (datasets.vehicle_make) and declares: lateral dynamics (vy, r), roll
   (phi, with the simulator's roll stiffness and damping split per axle),
   lateral load transfer (elastic through roll, geometric through the
   roll-centre heights with the lag tau_lat_geo), longitudinal load
   transfer from the measured acceleration (lag tau_pitch), the vehicle's
   declared downforce (cla), the Magic Formula tyres of its .tir file per
   wheel (Fy and Mz, tabulated over slip angle and load), the front
   longitudinal force's lateral component Fx sin(delta), and the
   simulator's slip-angle definition without relaxation
   (tan(alpha) = Vcy / sqrt(Vcx^2 + v_eps^2)).
   It does NOT declare (these are the tool's candidate effects,
   `predict(ch, over)` switches them on):
     sigma      [m]   relaxation length of the lateral slip (first order,
                      sigma d(tan a')/dt + |Vcx| tan a' = Vcy per axle)
     tan_bank, tan_grade [-]  road plane: rise per metre to the left of and
                      along the initial heading (earth-fixed, so the body sees
                      sy = tan_bank cos(psi) - tan_grade sin(psi), psi from the
                      model's own yaw rate)
     cla_add    [m^2] downforce coefficient in addition to the declared one,
                      split by the vehicle's aero balance
     thermal    (a, b, kappa, w): one surface temperature per axle,
                      w dT/dt = q - kappa w (T - T0), q = mean |F| Vs of the
                      axle's tyres, LMUY x (1 + a (T - T0)),
                      LKY x (1 + b (T - T0)) (seed 000 ch. 4 as in
                      lib/mf_thermal; T0 = road = initial temperature)
   Integration: classical RK4 with one step per sample (inputs linearly
   interpolated between samples), pure Python floats (about 40 ms per
   6 s at 100 Hz).
"""
import math
import subprocess

import numpy as np

from grip_tools.loop.io import Dataset

L, V_CH = 2.69, 20.0
G = 9.80665


class BicycleModel:
    name = f"steady-state bicycle L={L} m v_ch={V_CH} m/s"
    kind = "vehicle"
    supports = ()

    def predict(self, ch, over=None):
        v = ch["vx"]
        r = v * ch["delta"] / (L * (1.0 + v ** 2 / V_CH ** 2))
        return {"r": r, "ay": v * r}


def load(log, replay_bin):
    txt = subprocess.run([replay_bin, log], check=True, capture_output=True, text=True).stdout
    lines = txt.strip().splitlines()
    names = lines[0].split(",")
    rows = [l.split(",") for l in lines[1:]]
    col = {n: i for i, n in enumerate(names)}

    def num(n):
        return np.array([float(r[col[n]]) for r in rows])
    ok = np.array([all(r[col[f + "_fault"]] == "ok" for f in ("steer_angle", "yaw_rate", "ay", "vehicle_speed"))
                   for r in rows])
    t = num("t_s")[ok]
    ch = {"t": t - t[0], "vx": num("vehicle_speed")[ok], "delta": num("steer_angle")[ok],
          "r": num("yaw_rate")[ok], "ay": num("ay")[ok]}
    units = {"t": "s", "vx": "m/s", "delta": "rad", "r": "rad/s", "ay": "m/s2"}
    return Dataset(ch["t"], ch, units, ["r", "ay"], {"source": f"{log} via grip-replay"}), BicycleModel()


# ---------------------------------------------------------------------------
# Dynamic single-track model with roll (model under test of the vehicle-level sets)

A_MAX, NA = 0.5, 801          # slip-angle grid [rad]
NZ = 61                       # load grid points


class _Table:
    """Fy, Mz of one tyre side over (alpha, fz) for bilinear lookup."""

    def __init__(self, tire, mirror, fz_max):
        self.da = 2 * A_MAX / (NA - 1)
        self.dz = fz_max / (NZ - 1)
        a = np.linspace(-A_MAX, A_MAX, NA)
        z = np.linspace(0.0, fz_max, NZ)
        A, Z = np.meshgrid(a, z)
        o = tire.evaluate(0.0, A, Z, 20.0, mirror=mirror)
        self.fy = o["fy"].tolist()
        self.mz = o["mz"].tolist()

    def __call__(self, alpha, fz):
        x = (min(max(alpha, -A_MAX), A_MAX - 1e-12) + A_MAX) / self.da
        y = min(max(fz, 0.0), self.dz * (NZ - 1) - 1e-9) / self.dz
        i, j = int(x), int(y)
        u, w = x - i, y - j
        f0, f1 = self.fy[j], self.fy[j + 1]
        m0, m1 = self.mz[j], self.mz[j + 1]
        fy = (1 - w) * (f0[i] + u * (f0[i + 1] - f0[i])) + w * (f1[i] + u * (f1[i + 1] - f1[i]))
        mz = (1 - w) * (m0[i] + u * (m0[i + 1] - m0[i])) + w * (m1[i] + u * (m1[i + 1] - m1[i]))
        return fy, mz


def smooth_derivative(x, t, win=0.1):
    """dx/dt by central differences after a centred moving average over win [s]."""
    dt = float(np.median(np.diff(t)))
    k = max(1, int(round(win / dt)))
    xs = np.convolve(np.pad(x, k, mode="edge"), np.ones(2 * k + 1) / (2 * k + 1), mode="valid")
    return np.gradient(xs, t)


class VehicleModel:
    kind = "vehicle"
    supports = ("relaxation", "road_bank", "aero_load", "thermal")

    def __init__(self, vehicle, name=None):
        from grip_tools.sim.tires import MFTire
        self.v = vehicle
        self.name = name or f"single-track + roll, {vehicle.name} ({vehicle.tire_file})"
        tire = MFTire(vehicle.tire_file)
        self.tire = tire
        fzf, fzr = vehicle.static_loads()
        self.fz_static = (fzf, fzf, fzr, fzr)
        fz_max = 3.0 * max(fzf, fzr)
        mir = tire.mirror_for(np.array([True, False]))
        self.tab = (_Table(tire, bool(mir[0]), fz_max), _Table(tire, bool(mir[1]), fz_max))
        self._cache = {}

    # ------------------------------------------------------------------
    def predict(self, ch, over=None):
        over = over or {}
        key = (id(ch["t"]), len(ch["t"]), tuple(sorted((k, _hashable(v)) for k, v in over.items())))
        if key not in self._cache:
            if len(self._cache) > 64:
                self._cache.clear()
            self._cache[key] = self.simulate(ch, **over)
        return self._cache[key]

    def simulate(self, ch, sigma=0.0, tan_bank=0.0, tan_grade=0.0, cla_add=0.0, thermal=None):
        v = self.v
        t = np.asarray(ch["t"], dtype=float)
        vx_in = np.asarray(ch["vx"], dtype=float)
        delta_in = np.asarray(ch["swa"], dtype=float) / v.steer_ratio
        ax_in = smooth_derivative(vx_in, t)
        m, iz, ixs, lf, lr, l = v.m, v.iz, v.ixs, v.lf, v.lr, v.l
        hs = v.h - v.h_roll_axis
        kf, kr = v.k_roll * v.roll_split_front, v.k_roll * (1 - v.roll_split_front)
        cf, cr = v.c_roll * v.roll_split_front, v.c_roll * (1 - v.roll_split_front)
        geo_f, geo_r = m * lr * v.h_rcf / l, m * lf * v.h_rcr / l
        tf, tr = v.tf, v.tr
        fz_s = self.fz_static
        cla = v.cla + cla_add
        abf = v.aero_balance_front
        rho, cda, veps2 = v.rho, v.cda, v.v_eps ** 2
        tl, tp, h_l = v.tau_lat_geo, v.tau_pitch, v.h / l
        tab_l, tab_r = self.tab
        qsy1 = self.tire.qsy1
        tf2, tr2 = 0.5 * v.tf, 0.5 * v.tr
        drive_f = {"fwd": 1.0, "rwd": 0.0, "awd": 0.5}[v.drive]
        bg = 2 * v.brake_gain_front / max(v.re_front or self.tire.r0, 1e-3)
        brake_f = bg / (bg + 2 * v.brake_gain_rear / max(v.re_rear or self.tire.r0, 1e-3))
        th = thermal is not None
        if th:
            ta, tb, tk, tw = (float(x) for x in thermal)
        relax = sigma > 0.0
        sig = float(sigma)

        def rhs(s, vx, ax, d):
            vy, r, phi, phid, fyf, fxf, psi = s[:7]
            cp, sp = math.cos(psi), math.sin(psi)
            sx = tan_grade * cp + tan_bank * sp
            sy = -tan_grade * sp + tan_bank * cp
            g_x = -G * sx / math.sqrt(1.0 + sx * sx)
            g_y = -G * sy / math.sqrt(1.0 + sy * sy)
            g_n = G / math.sqrt(1.0 + sx * sx + sy * sy)
            q = 0.5 * rho * vx * vx
            down = q * cla
            dfx = m * fxf * h_l
            dyf = (kf * phi + cf * phid + geo_f * fyf) / tf
            dyr = (kr * phi + cr * phid + geo_r * fyf) / tr
            fzn = g_n / G
            fa = down * abf * 0.5 - 0.5 * dfx
            ra = down * (1 - abf) * 0.5 + 0.5 * dfx
            z_fl = fz_s[0] * fzn + fa - dyf
            z_fr = fz_s[1] * fzn + fa + dyf
            z_rl = fz_s[2] * fzn + ra - dyr
            z_rr = fz_s[3] * fzn + ra + dyr
            cd, sd = math.cos(d), math.sin(d)
            viy_f = vy + lf * r
            vcx_f = vx * cd + viy_f * sd
            vcy_f = -vx * sd + viy_f * cd
            vcy_r = vy - lr * r
            if relax:
                taf, tar = s[7], s[8]
            else:
                taf = vcy_f / math.sqrt(vcx_f * vcx_f + veps2)
                tar = vcy_r / math.sqrt(vx * vx + veps2)
            af, ar = math.atan(taf), math.atan(tar)
            if th:
                Tf, Tr = s[-2], s[-1]
                sdf, skf = max(1.0 + ta * Tf, 0.05), max(1.0 + tb * Tf, 0.05)
                sdr, skr = max(1.0 + ta * Tr, 0.05), max(1.0 + tb * Tr, 0.05)
                ef, er = af * skf / sdf, ar * skr / sdr
            else:
                sdf = sdr = 1.0
                ef, er = af, ar
            y1, m1 = tab_l(ef, z_fl)
            y2, m2 = tab_r(ef, z_fr)
            y3, m3 = tab_l(er, z_rl)
            y4, m4 = tab_r(er, z_rr)
            y1, y2, y3, y4 = y1 * sdf, y2 * sdf, y3 * sdr, y4 * sdr
            yf, yr = y1 + y2, y3 + y4
            mzt = (m1 + m2) * sdf + (m3 + m4) * sdr
            # longitudinal forces: rolling resistance qsy1 Fz per wheel, the
            # rest of the measured acceleration from the drive (or the brakes)
            drag = 0.5 * rho * cda * vx * abs(vx)
            sfx = m * (ax - r * vy - g_x) + drag
            x1, x2, x3, x4 = -qsy1 * z_fl, -qsy1 * z_fr, -qsy1 * z_rl, -qsy1 * z_rr
            rest = sfx - (x1 + x2 + x3 + x4)
            sh_f = drive_f if rest > 0.0 else brake_f
            x1 += 0.5 * sh_f * rest
            x2 += 0.5 * sh_f * rest
            x3 += 0.5 * (1 - sh_f) * rest
            x4 += 0.5 * (1 - sh_f) * rest
            yfb = (x1 + x2) * sd + yf * cd
            sfy = yfb + yr
            mzb = (lf * yfb - lr * yr + mzt - tf2 * ((x1 - x2) * cd - (y1 - y2) * sd) - tr2 * (x3 - x4))
            ay_s = sfy / m
            dv = [ay_s + g_y - r * vx,
                  mzb / iz,
                  phid,
                  (m * hs * (ay_s * math.cos(phi) + g_n * math.sin(phi)) - v.k_roll * phi - v.c_roll * phid) / ixs,
                  (ay_s - fyf) / tl,
                  (sfx / m - fxf) / tp,
                  r]
            if relax:
                dv += [0.0, 0.0]                 # advanced once per sample, below
            if th:
                hf = 0.5 * abs(yf) * abs(vcy_f)      # mean |Fy| Vs of the axle's two tyres
                hr = 0.5 * abs(yr) * abs(vcy_r)
                dv += [hf / tw - tk * Tf, hr / tw - tk * Tr]
            out = (r * math.cos(phi), ay_s * math.cos(phi) + g_n * math.sin(phi),
                   vcy_f / max(abs(vcx_f), 0.1), vcy_r / max(abs(vx), 0.1), abs(vcx_f), abs(vx))
            return dv, out

        n = len(t)
        ns = 7 + (2 if relax else 0) + (2 if th else 0)
        s = [0.0] * ns                        # starts straight, in equilibrium
        r_out = np.zeros(n)
        ay_out = np.zeros(n)
        vxl, axl, dl = vx_in.tolist(), ax_in.tolist(), delta_in.tolist()
        tt = t.tolist()
        for k in range(n):
            d1, o = rhs(s, vxl[k], axl[k], dl[k])
            r_out[k], ay_out[k] = o[0], o[1]
            if k == n - 1:
                break
            h = tt[k + 1] - tt[k]
            um = (0.5 * (vxl[k] + vxl[k + 1]), 0.5 * (axl[k] + axl[k + 1]), 0.5 * (dl[k] + dl[k + 1]))
            s2 = [a + 0.5 * h * b for a, b in zip(s, d1)]
            d2, _ = rhs(s2, *um)
            s3 = [a + 0.5 * h * b for a, b in zip(s, d2)]
            d3, _ = rhs(s3, *um)
            s4 = [a + h * b for a, b in zip(s, d3)]
            d4, _ = rhs(s4, vxl[k + 1], axl[k + 1], dl[k + 1])
            s = [a + h / 6.0 * (b1 + 2 * b2 + 2 * b3 + b4) for a, b1, b2, b3, b4 in zip(s, d1, d2, d3, d4)]
            if relax:
                # lib/relax's step (input held, exact exponential), input = the
                # mean of the steady slips at both ends of the step
                _, o2 = rhs(s, vxl[k + 1], axl[k + 1], dl[k + 1])
                for j in (0, 1):
                    x_in = 0.5 * (o[2 + j] + o2[2 + j])
                    v_m = 0.5 * (o[4 + j] + o2[4 + j])
                    s[7 + j] += -math.expm1(-v_m * h / sig) * (x_in - s[7 + j])
        return {"r": r_out, "ay": ay_out}


def _hashable(v):
    if isinstance(v, (list, tuple, np.ndarray)):
        return tuple(float(x) for x in np.ravel(v))
    return float(v)
