"""ESC sensor models: wheel-speed sensors, steering-wheel angle sensor, an
IMU cluster (yaw rate, lateral and longitudinal acceleration) and the
master-cylinder brake-pressure sensor.

Each channel turns a truth signal x(t) (recorded every 1 ms by the
simulator) into samples at the times of its CAN message:

    t_k  = phase + k * period                     (the message's sample grid)
    y    = lowpass(x)                             (first order, time constant tau; 0 = off)
    s_k  = (1 + scale_error) * y(t_k - delay) + bias + noise_k   (noise_k ~ N(0, sigma^2), white)
    s_k  = clip(s_k, lo, hi); |s_k| < deadband -> 0
    s_k  = quant * round(s_k / quant)             (the DBC scale of the signal)

y(t_k - delay) is linearly interpolated in the truth; before the first
truth sample the first value is held. The random stream is seeded per
channel (seed, channel index), so a channel's noise does not change when
another channel is reconfigured.

Truth sources (columns of model.Result.member()):
  wheel speed  re_omega_<w> * 3.6  [km/h]  (wheel spin times the effective
               rolling radius the ECU is calibrated with; scale_error models
               a radius error)
  SWA          swa [deg]
  yaw rate     yaw_imu [deg/s] = r cos(phi) (gyro in the rolled body)
  ay, ax       ay_imu, ax_imu [m/s^2]: specific force in the rolled sensor
               axes (gravity components of roll, bank and grade included)
  brake        p_master [bar]
"""
import copy
import math
from dataclasses import dataclass, field

import numpy as np

RAD2DEG = 180.0 / math.pi


@dataclass
class Channel:
    name: str                  # signal name (= DBC signal name)
    source: object             # truth column name or callable(cols) -> array
    unit: str = ""
    noise: float = 0.0         # standard deviation, white
    bias: float = 0.0
    scale_error: float = 0.0   # relative gain error
    delay: float = 0.0         # s
    tau: float = 0.0           # s, first-order low-pass (sensor bandwidth); 0 = none
    quant: float = 0.0         # quantization step (0 = none)
    lo: float = -math.inf
    hi: float = math.inf
    deadband: float = 0.0      # |value| below this reads 0 (wheel-speed sensors at crawl speed)


@dataclass
class Group:
    """Channels sampled together and sent in one CAN message."""
    message: str               # DBC message name
    period: float              # s
    phase: float = 0.0         # s, first sample time
    tx_latency: float = 0.0005  # s, CAN frame timestamp = sample time + tx_latency
    channels: list = field(default_factory=list)


def _src(col, factor=1.0):
    return lambda c: np.asarray(c[col]) * factor


def default_groups():
    """Typical ESC signals (values in docs/simulator.md, 'Sensor models')."""
    wss = [Channel(f"WheelSpeed_{w.upper()}", _src(f"re_omega_{w}", 3.6), "km/h", noise=0.04,
                   delay=0.008, quant=0.01, lo=0.0, hi=655.35, deadband=1.5)
           for w in ("fl", "fr", "rl", "rr")]
    sas = [Channel("SteeringAngle", _src("swa", RAD2DEG), "deg", noise=0.05, delay=0.010, quant=0.1,
                   lo=-3276.8, hi=3276.7)]
    imu = [Channel("YawRate", _src("yaw_imu", RAD2DEG), "deg/s", noise=0.10, bias=0.20, delay=0.012,
                   tau=0.008, quant=0.01, lo=-327.68, hi=327.67),
           Channel("LatAcc", _src("ay_imu"), "m/s^2", noise=0.03, bias=0.05, delay=0.012, tau=0.008,
                   quant=0.01, lo=-327.68, hi=327.67),
           Channel("LongAcc", _src("ax_imu"), "m/s^2", noise=0.03, bias=-0.04, delay=0.012, tau=0.008,
                   quant=0.01, lo=-327.68, hi=327.67)]
    brk = [Channel("BrakePressure", _src("p_master"), "bar", noise=0.3, delay=0.015, tau=0.01,
                   quant=0.1, lo=0.0, hi=6553.5)]
    return {
        "wss": Group("ESC_WheelSpeeds", 0.010, 0.0, 0.0005, wss),
        "sas": Group("SAS_SteeringAngle", 0.010, 0.0, 0.0010, sas),
        "imu": Group("IMU_YawAcc", 0.010, 0.0, 0.0015, imu),
        "brake": Group("ESC_Brake", 0.020, 0.0, 0.0020, brk),
    }


@dataclass
class SensorConfig:
    groups: dict = field(default_factory=default_groups)
    seed: int = 0

    def channel(self, name):
        for g in self.groups.values():
            for c in g.channels:
                if c.name == name:
                    return c
        raise KeyError(name)

    def ideal(self):
        """Copy with noise, bias, scale error, delay, low-pass and deadband
        off (quantization kept: it is the CAN resolution)."""
        cfg = copy.deepcopy(self)
        for g in cfg.groups.values():
            for c in g.channels:
                c.noise = c.bias = c.scale_error = c.delay = c.tau = c.deadband = 0.0
        return cfg


def lowpass(t, x, tau):
    """First-order low-pass with time constant tau, exact for an input held
    constant over each truth interval:
    y_k = y_{k-1} + (1 - exp(-dt_k / tau)) (x_k - y_{k-1}), y_0 = x_0."""
    x = np.asarray(x, dtype=float)
    if tau <= 0.0 or len(x) < 2:
        return x
    dt = np.diff(t)
    a = 1.0 - np.exp(-dt / tau)
    if np.allclose(dt, dt[0], rtol=1e-6, atol=0.0):
        from scipy.signal import lfilter
        y, _ = lfilter([a[0]], [1.0, -(1.0 - a[0])], x[1:], zi=[(1.0 - a[0]) * x[0]])
        return np.concatenate([[x[0]], y])
    y = np.empty_like(x)
    y[0] = acc = x[0]
    for k in range(1, len(x)):
        acc += a[k - 1] * (x[k] - acc)
        y[k] = acc
    return y


def quantize(v, q):
    if q <= 0.0:
        return v
    return np.round(v / q) * q


def process(ch, t, x, t_samples, rng):
    """Samples of one channel at t_samples from truth (t, x)."""
    y = lowpass(t, x, ch.tau)
    s = (1.0 + ch.scale_error) * np.interp(t_samples - ch.delay, t, y) + ch.bias
    if ch.noise > 0.0:
        s = s + rng.normal(0.0, ch.noise, size=s.shape)
    s = np.clip(s, ch.lo, ch.hi)
    if ch.deadband > 0.0:
        s = np.where(np.abs(s) < ch.deadband, 0.0, s)
    return quantize(s, ch.quant)


class SensorData:
    """groups[name] = {'time': (K,), '<channel>': (K,), ...}; config kept."""

    def __init__(self, groups, config):
        self.groups = groups
        self.config = config

    def channel_names(self):
        return [c.name for g in self.config.groups.values() for c in g.channels]

    def series(self, name):
        """(time, values) of one channel."""
        for gname, g in self.config.groups.items():
            for c in g.channels:
                if c.name == name:
                    return self.groups[gname]["time"], self.groups[gname][name]
        raise KeyError(name)

    def wide_columns(self):
        """Every channel on the union of all sample times ('time' and one
        column per channel); a channel is NaN in the rows where it was not
        sampled (slower messages). The form of sensors.csv, and what
        est_ref.inputs_from_sensors takes."""
        times = np.unique(np.concatenate([g["time"] for g in self.groups.values()]))
        cols = {"time": times}
        for gname, g in self.groups.items():
            idx = np.searchsorted(times, g["time"])
            for c in self.config.groups[gname].channels:
                col = np.full(len(times), np.nan)
                col[idx] = g[c.name]
                cols[c.name] = col
        return cols

    def write_csv(self, path, comment=None):
        """Wide CSV (wide_columns)."""
        cols = self.wide_columns()
        times = cols["time"]
        names = self.channel_names()
        units = ["s"] + [c.unit for gg in self.config.groups.values() for c in gg.channels]
        with open(path, "w") as f:
            for line in (comment or []):
                f.write(f"# {line}\n")
            f.write("# units: " + ",".join(units) + "\n")
            f.write("time," + ",".join(names) + "\n")
            arr = np.column_stack([times] + [cols[n] for n in names])
            np.savetxt(f, arr, delimiter=",", fmt="%.10g")


def measure(truth, config=None, t_end=None):
    """Sensor samples from truth columns (a dict with 'time' and the source
    columns, e.g. model.Result.member(i)). Returns SensorData."""
    config = config or SensorConfig()
    t = np.asarray(truth["time"], dtype=float)
    if t_end is None:
        t_end = t[-1]
    out = {}
    idx = 0
    for gname, g in config.groups.items():
        ts = np.arange(g.phase, t_end + 1e-9, g.period)
        ts = np.round(ts, 9)
        d = {"time": ts}
        for c in g.channels:
            rng = np.random.default_rng([config.seed, idx])
            idx += 1
            x = c.source(truth) if callable(c.source) else np.asarray(truth[c.source], dtype=float)
            d[c.name] = process(c, t, x, ts, rng)
        out[gname] = d
    return SensorData(out, config)
