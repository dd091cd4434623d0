"""Vehicle-level residual analysis on the comma2k19 RAV4 CAN log: yaw rate
and lateral acceleration predicted from steering and speed by the
steady-state single-track (bicycle) model

    r = vx delta / (L (1 + vx^2 / v_ch^2)),   ay = vx r

against the yaw rate and ay the car's own sensors put on CAN. Input samples
come from `grip-replay LOG` (CSV, SI units after the signal table).
Vehicle: RAV4 wheelbase L = 2.69 m; characteristic speed v_ch = 20 m/s
(an assumed understeer; not identified from this log). Only sensor-level
effects (bias, scale, delay) are candidates here.
"""
import subprocess

import numpy as np

from .io import Dataset

L, V_CH = 2.69, 20.0


class BicycleModel:
    name = f"steady-state bicycle L={L} m v_ch={V_CH} m/s"

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
