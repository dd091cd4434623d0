"""Vehicle parameter sets of the simulator (SI units, ISO 8855 axes).

Two sets ship with the simulator (docs/simulator.md lists every value and
where it comes from):
  passenger  mid-size front-wheel-drive passenger car, 205/60R15 tyres
             (tests/data/mfeval-tir/PacejkaBook_Defaults.tir, MF 6.1)
  av21       Dallara AV-21-like autonomous race car (mass and axle distances
             from the AV-21 data set's README (tests/data/iac-av21); the rest
             assumed), rear-wheel drive, downforce,
             tests/data/mfeval-tir/MagicFormula61_Paramerters.tir with the friction
             scaled to a racing slick
"""
from dataclasses import dataclass, field, fields, replace

G = 9.80665


@dataclass
class VehicleParams:
    name: str = "passenger"
    # mass and geometry
    m: float = 1450.0            # kg, total mass (all of it sprung; no unsprung masses)
    iz: float = 2450.0           # kg m^2, yaw inertia
    ixs: float = 450.0           # kg m^2, roll inertia of the body about the roll axis
    lf: float = 1.10             # m, CG to front axle
    lr: float = 1.60             # m, CG to rear axle
    tf: float = 1.55             # m, front track width
    tr: float = 1.53             # m, rear track width
    h: float = 0.55              # m, CG height
    h_rcf: float = 0.05          # m, front roll-centre height
    h_rcr: float = 0.12          # m, rear roll-centre height
    k_roll: float = 84000.0      # N m/rad, total roll stiffness (springs + anti-roll bars)
    roll_split_front: float = 0.60   # front share of roll stiffness and roll damping
    c_roll: float = 5500.0       # N m s/rad, total roll damping
    tau_pitch: float = 0.05      # s, first-order lag of the longitudinal load transfer (lumped pitch)
    tau_lat_geo: float = 0.02    # s, lag of the geometric (roll-centre) lateral load transfer
    # steering
    steer_ratio: float = 15.5    # steering-wheel angle / road-wheel angle
    ackermann: float = 0.0       # 0 = parallel steer, 1 = full Ackermann geometry
    # wheels and tyres
    tire_file: str = "PacejkaBook_Defaults.tir"
    tire_scale_front: dict = field(default_factory=dict)   # multipliers of LMUX/LMUY/LKX/LKY
    tire_scale_rear: dict = field(default_factory=dict)
    re_front: float = 0.0        # m, effective rolling radius; 0: R0 - Fz_static / (3 Cz)
    re_rear: float = 0.0
    j_front: float = 0.90        # kg m^2, spin inertia of one wheel (tyre, rim, brake, shaft share)
    j_rear: float = 0.80
    # drivetrain and brakes
    drive: str = "fwd"           # fwd / rwd / awd; torque split equally (open differentials)
    drive_torque_max: float = 3000.0   # N m, total at the wheels
    brake_gain_front: float = 18.0     # N m/bar per front wheel
    brake_gain_rear: float = 8.0       # N m/bar per rear wheel
    # aero (rho CdA / 2 v^2 drag at CG height, downforce split by balance)
    rho: float = 1.20            # kg/m^3
    cda: float = 0.62            # m^2
    cla: float = 0.0             # m^2 (downforce > 0)
    aero_balance_front: float = 0.45
    # small numbers of the model
    omega_eps: float = 2.0       # rad/s, smoothing of brake and rolling-resistance torque sign
    v_low: float = 2.0           # m/s, below it the relaxed slips get low-speed damping
    v_eps: float = 1.0           # m/s, slip denominator floor without relaxation

    @property
    def l(self):
        return self.lf + self.lr

    @property
    def h_roll_axis(self):
        """Roll-axis height under the CG."""
        return self.h_rcf + (self.h_rcr - self.h_rcf) * self.lf / self.l

    def wheel_positions(self):
        """(x, y) of FL, FR, RL, RR contact centres relative to the CG."""
        x = [self.lf, self.lf, -self.lr, -self.lr]
        y = [self.tf / 2, -self.tf / 2, self.tr / 2, -self.tr / 2]
        return x, y

    def static_loads(self, g=G):
        """Per-wheel static load front, rear [N]."""
        return self.m * g * self.lr / (2 * self.l), self.m * g * self.lf / (2 * self.l)

    def as_dict(self):
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def with_(self, **kw):
        return replace(self, **kw)


def passenger():
    """Mid-size FWD passenger car (values in docs/simulator.md)."""
    return VehicleParams()


def av21():
    """Dallara AV-21-like race car. Mass, lf, lr from the deep-dynamics
    configuration (README of iac-av21-deepdynamics); every other value is an
    assumption of this simulator (docs/simulator.md)."""
    return VehicleParams(
        name="av21",
        m=790.0, iz=1000.0, ixs=120.0,
        lf=1.248, lr=1.7328, tf=1.64, tr=1.56, h=0.28,
        h_rcf=0.03, h_rcr=0.06,
        k_roll=250000.0, roll_split_front=0.50, c_roll=6000.0,
        tau_pitch=0.03, tau_lat_geo=0.02,
        steer_ratio=12.0,
        tire_file="MagicFormula61_Paramerters.tir",
        tire_scale_front=dict(lmux=1.45, lmuy=1.45),
        tire_scale_rear=dict(lmux=1.45, lmuy=1.45),
        j_front=1.2, j_rear=1.6,
        drive="rwd", drive_torque_max=4500.0,
        brake_gain_front=30.0, brake_gain_rear=20.0,
        cda=0.90, cla=2.50, aero_balance_front=0.42,
    )


VEHICLES = {"passenger": passenger, "av21": av21}


def get(name):
    try:
        return VEHICLES[name]()
    except KeyError:
        raise ValueError(f"unknown vehicle {name!r} (have {sorted(VEHICLES)})") from None
