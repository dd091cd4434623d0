"""The README's main job, Python side (tools/scripts/main_job.sh runs the C
programs first):

1. --rav4 FLOAT.csv FIXED.csv: the estimator's outputs on the real RAV4
   drive (grip-replay -e): validity, mu, and the yaw-rate reference against
   the measured yaw rate, float and fixed; a PNG of the drive.
2. the Magic Formula of a real tire with grip's C library (float and fixed
   builds, in-process through the Python binding grip.mf: the code of
   grip-tire, bit for bit) against the float64 reference: error table and
   curves.

Tire: Goodyear G275 MSA 335/65R22.5 at 60 psi, an MF-Tyre 5.x (PAC2002) file
fitted to Calspan flat-belt measurements (tests/data/chrono-tir).
"""
import argparse
import csv
import os
import sys

import numpy as np

from grip_tools.golden import mf as golden_mf
from grip_tools.reference import mf, tir
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
TIRE = os.path.join(golden_mf.shared_data_dir(), "chrono-tir", "335_65R22_5_G275MSA_60psi.tir")
COLS = ["kappa", "alpha", "gamma", "fz", "p", "vx"]


def sweeps(params):
    """Pure longitudinal, pure lateral and combined sweeps at three loads."""
    fnom = params["fnomin"]
    vx = params["longvl"]
    rows = []
    for load in (0.5, 1.0, 1.5):
        fz = load * fnom
        for k in np.linspace(-0.5, 0.5, 201):
            rows.append(("pure_kappa", load, k, 0.0, 0.0, fz, 0.0, vx))
        for a in np.radians(np.linspace(-15, 15, 201)):
            rows.append(("pure_alpha", load, 0.0, a, 0.0, fz, 0.0, vx))
        for k in np.linspace(-0.5, 0.5, 201):
            rows.append(("combined_alpha4", load, k, np.radians(4.0), 0.0, fz, 0.0, vx))
    return rows


def run_c_mf(arith, tire, rows):
    """grip's C Magic Formula (grip_mf_eval of the `arith` build, through
    the binding: what grip-tire --tir TIRE computes for these rows, bit for
    bit) -> {"fx", "fy", "mz"} in N, N m."""
    import grip
    params = grip.mf.load(tire)
    x = np.array([r[2:] for r in rows], dtype=np.float64)
    out = grip.mf.evaluate(params, x[:, 0], x[:, 1], x[:, 2], x[:, 3], x[:, 4], x[:, 5], arith=arith,
                           errors="raise")
    return {k: out[k] for k in ("fx", "fy", "mz")}


def read_replay(path):
    with open(path) as f:
        data = list(csv.reader(f))
    # column names are unique (grip-replay -e names the measured gyro
    # yaw_rate_in, the estimate with the bias removed yaw_rate)
    names = list(data[0]) if data else []
    rows = [dict(zip(names, r)) for r in data[1:]]
    if not rows or "est_status" not in rows[0]:
        raise SystemExit(f"main job: {path} has no estimator columns (grip-replay -e)")

    def col(k):
        return np.array([float(r[k]) if r[k] != "" else np.nan for r in rows])
    out = {k: col(k) for k in ("t_s", "yaw_rate_in", "yaw_rate", "yaw_rate_ref", "beta", "mu", "mu_conf", "vx", "ay",
                               "steer_angle", "fy_front", "fy_rear", "est_status")}
    # columns added later (grip-replay's estimator: gyro-bias state, model ay)
    for k in ("yaw_rate_bias", "ay_model"):
        out[k] = col(k) if k in rows[0] else np.full(len(rows), np.nan)
    out["valid"] = np.array([int(r["est_valid"]) for r in rows])
    return out


POSE_DIR = os.path.join(ROOT, "tests", "data", "comma2k19-rav4", "global_pose")


def quat_to_matrix(q):
    """The rotation matrix of a unit quaternion (w, x, y, z): frame -> ECEF."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def pose_truth(pose_dir=POSE_DIR):
    """The drive's pose (GNSS and IMU fused, 20 Hz) as the estimator's
    truth: time [s, the CAN log's clock], the velocity in the device frame
    [forward, right, down] (m/s), and its sideslip atan2(-v_right,
    v_forward) in ISO 8855 signs (y left) [rad]. The device (a phone on the
    windscreen) is not aligned with the car: its sideslip carries the
    mount's yaw, which rav4_truth removes."""
    t = np.load(os.path.join(pose_dir, "frame_times"))
    v = np.load(os.path.join(pose_dir, "frame_velocities"))
    q = np.load(os.path.join(pose_dir, "frame_orientations"))
    vd = np.array([quat_to_matrix(q[i]).T @ v[i] for i in range(len(t))])
    return t, vd, np.arctan2(-vd[:, 1], vd[:, 0])


def rav4_truth_series(r, pose_dir=POSE_DIR, v_min=10.0, straight=0.005):
    """The pose's sideslip [rad] and forward speed [m/s] at the replay's
    steps (r: t_s, vx, beta, yaw_rate), the mount's yaw removed: the pose's
    mean sideslip above v_min where the car drives straight (|yaw rate| <
    straight rad/s). Returns (truth, forward speed, mount yaw)."""
    t, vd, beta_dev = pose_truth(pose_dir)
    bp = np.interp(r["t_s"], t, beta_dev)
    vf = np.interp(r["t_s"], t, vd[:, 0])
    ok = (r["vx"] > v_min) & np.isfinite(r["beta"])
    st = ok & (np.abs(r["yaw_rate"]) < straight)
    mount = float(np.mean(bp[st]))
    return bp - mount, vf, mount


def rav4_truth(r, pose_dir=POSE_DIR, v_min=10.0, straight=0.005):
    """The estimate against the pose over the steps above v_min with an
    estimated sideslip: the mount's yaw is the pose's mean sideslip where
    the car drives straight (|yaw rate| < straight rad/s), removed; then
    beta's RMS error and the baseline beta = 0, their correlation, vx's RMS
    error against the pose's forward speed."""
    truth, vf, mount = rav4_truth_series(r, pose_dir, v_min, straight)
    ok = (r["vx"] > v_min) & np.isfinite(r["beta"])
    e = r["beta"][ok] - truth[ok]
    return {"steps": int(ok.sum()), "mount_yaw_deg": float(np.degrees(mount)),
            "truth_range_deg": [float(np.degrees(np.min(truth[ok]))), float(np.degrees(np.max(truth[ok])))],
            "beta_rms_deg": float(np.degrees(np.sqrt(np.mean(e ** 2)))),
            "zero_rms_deg": float(np.degrees(np.sqrt(np.mean(truth[ok] ** 2)))),
            "corr": float(np.corrcoef(r["beta"][ok], truth[ok])[0, 1]),
            "vx_rms": float(np.sqrt(np.mean((r["vx"][ok] - vf[ok]) ** 2))),
            "vx_mean_diff": float(np.mean(r["vx"][ok] - vf[ok]))}


def rav4_report(paths, outdir):
    """Estimator outputs on the RAV4 drive, float and fixed."""
    runs = {a: read_replay(p) for a, p in zip(("float", "fixed"), paths)}
    print("RAV4 drive through the estimator (grip-replay -e, 100 Hz):")
    print(f"{'build':6s} {'steps':>6s} {'errors':>6s} {'beta ok':>8s} {'mu ok':>6s} {'max|beta|':>10s} "
          f"{'yaw: rms(meas-ref)':>19s} {'corr':>5s} {'mean meas/ref [rad/s]':>22s}")
    for a, r in runs.items():
        yr, ref = r["yaw_rate_in"], r["yaw_rate_ref"]   # the measured gyro (CAN)
        ok = np.isfinite(yr) & np.isfinite(ref)
        print(f"{a:6s} {len(yr):6d} {int(np.sum(r['est_status'] < 0)):6d} "
              f"{int(np.sum((r['valid'] & 2) != 0)):8d} {int(np.sum((r['valid'] & 1024) != 0)):6d} "
              f"{np.degrees(np.nanmax(np.abs(r['beta']))):8.2f} deg "
              f"{np.sqrt(np.mean((yr[ok] - ref[ok]) ** 2)):15.4f} {np.corrcoef(yr[ok], ref[ok])[0, 1]:8.2f} "
              f"{np.mean(yr[ok]):10.4f} / {np.mean(ref[ok]):.4f}")
    for a, r in runs.items():
        b = r["yaw_rate_bias"]
        if np.all(np.isnan(b)):
            continue
        print(f"{a:6s} learned yaw-rate bias: end {b[-1]:.4f} rad/s, mean over the last 10 s "
              f"{np.mean(b[r['t_s'] >= r['t_s'][-1] - 10.0]):.4f}, range {np.min(b):.4f} .. {np.max(b):.4f}")
        yr, ref = r["yaw_rate_in"] - b, r["yaw_rate_ref"]
        ok = np.isfinite(yr) & np.isfinite(ref)
        print(f"{a:6s} measured minus learned bias vs reference: rms {np.sqrt(np.mean((yr[ok] - ref[ok]) ** 2)):.4f} "
              f"rad/s, corr {np.corrcoef(yr[ok], ref[ok])[0, 1]:.2f}, mean {np.mean(yr[ok]):.4f} / {np.mean(ref[ok]):.4f}")
        am, ay = r["ay_model"], r["ay"]
        ok = np.isfinite(am) & np.isfinite(ay)
        if ok.sum() > 2:
            print(f"{a:6s} model ay (sum Fy / m) vs measured ay: rms {np.sqrt(np.mean((am[ok] - ay[ok]) ** 2)):.3f} "
                  f"m/s^2, corr {np.corrcoef(am[ok], ay[ok])[0, 1]:.2f}")
    if os.path.isdir(POSE_DIR):
        print("against the drive's pose (GNSS and IMU fused, 20 Hz; the phone mount's yaw, the pose's mean "
              "sideslip on the straight, removed), above 10 m/s:")
        for a, r in runs.items():
            m = rav4_truth(r)
            print(f"{a:6s} {m['steps']} steps, mount yaw {m['mount_yaw_deg']:.3f} deg, true sideslip "
                  f"{m['truth_range_deg'][0]:.3f} .. {m['truth_range_deg'][1]:.3f} deg: beta RMS error "
                  f"{m['beta_rms_deg']:.3f} deg (beta = 0: {m['zero_rms_deg']:.3f}), correlation {m['corr']:.2f}; "
                  f"vx RMS error {m['vx_rms']:.3f} m/s (mean {m['vx_mean_diff']:+.3f})")
    f, x = runs["float"], runs["fixed"]
    print(f"fixed vs float: max |beta| diff {np.nanmax(np.abs(f['beta'] - x['beta'])):.2e} rad, "
          f"max |yaw ref| diff {np.nanmax(np.abs(f['yaw_rate_ref'] - x['yaw_rate_ref'])):.2e} rad/s, "
          f"max |mu| diff {np.nanmax(np.abs(f['mu'] - x['mu'])):.2e}")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = f["t_s"] - f["t_s"][0]
    fig, ax = plt.subplots(4, 1, figsize=(11, 10), sharex=True)
    ax[0].plot(t, f["vx"], label="vx estimate")
    ax[0].set_ylabel("speed [m/s]")
    ax[1].plot(t, f["yaw_rate_in"], lw=0.8, label="measured (CAN)")
    ax[1].plot(t, f["yaw_rate"], lw=0.8, label="estimate (gyro bias removed)")
    ax[1].plot(t, f["yaw_rate_ref"], lw=0.8, label="bicycle reference (float)")
    ax[1].plot(t, x["yaw_rate_ref"], "--", lw=0.8, label="bicycle reference (fixed)")
    ax[1].set_ylabel("yaw rate [rad/s]")
    ax[2].plot(t, np.degrees(f["beta"]), label="float")
    ax[2].plot(t, np.degrees(x["beta"]), "--", label="fixed")
    ax[2].set_ylabel("sideslip [deg]")
    ax[3].plot(t, f["mu"], label="mu estimate")
    ax[3].plot(t, f["mu_conf"], label="mu confidence")
    ax[3].set_ylabel("mu [-]")
    ax[3].set_xlabel("time [s]")
    for a_ in ax:
        a_.grid(True, alpha=0.3)
        a_.legend(fontsize=8, loc="upper right")
    fig.suptitle("grip estimator on the comma2k19 Toyota RAV4 drive (60 s of real CAN)")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "rav4_estimator.png"), dpi=100)
    print(f"wrote {outdir}/rav4_estimator.png")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip main-job", description=__doc__)
    ap.add_argument("--outdir", default=os.path.join(ROOT, "build", "main-job"))
    ap.add_argument("--tir", default=TIRE)
    ap.add_argument("--rav4", nargs=2, metavar=("FLOAT_CSV", "FIXED_CSV"),
                    help="grip-replay -e outputs of the RAV4 log to report on first")
    args = ap.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    if args.rav4:
        rav4_report(args.rav4, args.outdir)
    params = tir.load_params(args.tir)
    rows = sweeps(params)
    inputs = np.array([r[2:] for r in rows], dtype=float)
    ref = mf.evaluate(params, *[inputs[:, i] for i in range(5)], vx=inputs[:, 5])
    c_out = {a: run_c_mf(a, args.tir, rows) for a in ("float", "fixed")}

    fz = inputs[:, 3]
    print(f"grip main job: Magic Formula of {os.path.basename(args.tir)} "
          f"(FITTYP {params['fittyp']}, FNOMIN {params['fnomin']:.0f} N), {len(rows)} evaluations")
    print(f"{'build':6s} {'output':4s} {'max |err|':>12s} {'max |err|/Fz':>13s} {'max |err|/peak':>15s}")
    for a in ("float", "fixed"):
        for k in ("fx", "fy", "mz"):
            err = np.abs(c_out[a][k] - ref[k])
            peak = np.max(np.abs(ref[k]))
            unit = "N m" if k == "mz" else "N"
            print(f"{a:6s} {k:4s} {np.max(err):9.3g} {unit:3s} {np.max(err / fz):12.2e} "
                  f"{np.max(err) / peak:14.2e}")

    with open(os.path.join(args.outdir, "mf_curves.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "load"] + COLS + ["fx_ref", "fy_ref", "mz_ref", "fx_float", "fy_float",
                                              "mz_float", "fx_fixed", "fy_fixed", "mz_fixed"])
        for i, r in enumerate(rows):
            w.writerow(list(r) + [ref[k][i] for k in ("fx", "fy", "mz")]
                       + [c_out[a][k][i] for a in ("float", "fixed") for k in ("fx", "fy", "mz")])
    plot(rows, inputs, ref, c_out, os.path.join(args.outdir, "mf_curves.png"), args.tir)
    print(f"wrote {args.outdir}/mf_curves.csv and mf_curves.png")
    return 0


def plot(rows, inputs, ref, c_out, path, tire):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cases = np.array([r[0] for r in rows])
    loads = np.array([r[1] for r in rows])
    panels = [("pure_kappa", 0, "fx", "slip ratio [-]", "Fx [kN]"),
              ("pure_alpha", 1, "fy", "slip angle [deg]", "Fy [kN]"),
              ("pure_alpha", 1, "mz", "slip angle [deg]", "Mz [kN m]"),
              ("combined_alpha4", 0, "fx", "slip ratio at alpha = 4 deg [-]", "Fx [kN] (combined)")]
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    for ax, (case, col, out, xl, yl) in zip(axes.flat, panels):
        for load in (0.5, 1.0, 1.5):
            m = (cases == case) & (loads == load)
            x = inputs[m, col] * (180 / np.pi if col == 1 else 1)
            ax.plot(x, ref[out][m] / 1e3, "k-", lw=1)
            ax.plot(x[::8], c_out["float"][out][m][::8] / 1e3, "o", color="tab:blue", ms=4, mfc="none")
            ax.plot(x[::8], c_out["fixed"][out][m][::8] / 1e3, "x", color="tab:red", ms=4)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.grid(True, alpha=0.3)
    axes[0, 0].legend(["float64 reference", "grip float", "grip fixed"], fontsize=8)
    fig.suptitle(f"grip Magic Formula vs reference: {os.path.basename(tire)} at 0.5/1.0/1.5 FNOMIN")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    sys.exit(main())
