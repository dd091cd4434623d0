"""grip sim-fleet: N logs from the reference simulator, with their truth and
a manifest for `grip fleet run`.

    grip sim-fleet N --out DIR [--duration S] [--variants K] [--seed S]
                   [--manoeuvres step-steer,sine-dwell,...] [--surfaces dry,wet,snow]
                   [--dt 0.002] [--batch 16] [--workers W | --scheduler ADDR]

Log i belongs to simulated run r = i // K (K = --variants). Run r drives
manoeuvre r mod M on surface (r // M) mod S at a speed (and a steering
amplitude, deceleration or direction) drawn from a generator seeded with
(--seed, r). Each of a run's K logs measures the same motion with its own
sensors: noise seed, and with probability 3/4 offsets drawn with (--seed,
i): yaw-rate bias and gain error, lateral-acceleration bias, steering-angle
offset, wheel-speed (rolling radius) scale error; else the simulator's
nominal sensors. The offsets are manifest columns.

Runs of one manoeuvre are simulated together as one batch of up to --batch
vehicles (the simulator integrates a batch for about the cost of one
vehicle, docs/simulator.md), one Dask task per batch.

Per log: logs/<log_id>.csv, the estimator's inputs as grip-replay --csv
reads them (est_eval's way: sensors.measure -> est_ref.inputs_from_sensors
-> est_eval.write_input_csv). Per run: runs/<run>/truth.csv at 100 Hz with
the columns est_eval.evaluate reads. DIR/vehicle.txt: the simulator car's
estimator settings (est_eval.est_vehicle_lines). DIR/manifest.csv, sorted by
log id. DIR/sim.json: settings and the cost of each batch.
--duration lengthens every manoeuvre (its last state held: steering held,
a braked car stands still); default: each manoeuvre's own length (2-20 s).
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

from grip_tools.fleet import cluster

DEFAULT_MANOEUVRES = ("step-steer", "ramp-steer", "sine-dwell", "brake-in-turn", "mu-step")
DEFAULT_SURFACES = ("dry", "wet", "snow")
BATCHABLE = ("step-steer", "ramp-steer", "sine-dwell", "fishhook", "brake-in-turn")
WHEELS = ("fl", "fr", "rl", "rr")
TRUTH_SCALARS = ("vx", "vy", "r", "beta", "ax", "ay", "swa", "delta")
TRUTH_WHEEL = ("fx", "fy", "fz", "mu_road", "mux", "muy", "kappa", "alpha")
TRUTH_RATE_HZ = 100.0


def plan(n, seed, manoeuvres, surfaces, variants):
    """The runs and logs (lists of dicts), deterministic in their arguments."""
    from grip_tools.sim import manoeuvres as M
    n_runs = -(-n // variants)
    runs = []
    for r in range(n_runs):
        rng = np.random.default_rng([seed, r])
        m = manoeuvres[r % len(manoeuvres)]
        s = surfaces[(r // len(manoeuvres)) % len(surfaces)]
        run = {"run": r, "manoeuvre": m, "surface": s, "mu": M.surface_mu(s),
               "speed_kmh": float(np.round(rng.uniform(50.0, 100.0), 1))}
        if m == "step-steer":
            run["param"], run["param_name"] = float(np.round(rng.uniform(2.0, 8.0), 2)), "ay_target_m_s2"
        elif m in ("sine-dwell", "fishhook"):
            run["param"], run["param_name"] = float(np.round(rng.uniform(2.0, 6.5), 2)), "scale_of_swa03"
        elif m == "brake-in-turn":
            run["param"], run["param_name"] = float(np.round(rng.uniform(3.0, 8.0), 2)), "decel_m_s2"
        elif m == "ramp-steer":
            run["param"], run["param_name"] = float(rng.choice([-1.0, 1.0])), "direction"
        else:
            run["param"], run["param_name"] = None, None
        runs.append(run)
    logs = []
    for i in range(n):
        rng = np.random.default_rng([seed, 1_000_003, i])
        nominal = bool(rng.uniform() < 0.25)
        off = {"yaw_bias_deg_s": 0.2, "yaw_scale_error": 0.0, "ay_bias_m_s2": 0.05, "steer_offset_deg": 0.0,
               "wheel_scale_error": 0.0}
        draws = {"yaw_bias_deg_s": rng.uniform(-0.8, 0.8), "yaw_scale_error": rng.uniform(-0.03, 0.03),
                 "ay_bias_m_s2": rng.uniform(-0.3, 0.3), "steer_offset_deg": rng.uniform(-3.0, 3.0),
                 "wheel_scale_error": rng.uniform(-0.015, 0.015)}
        if not nominal:
            off = {k: float(np.round(v, 4)) for k, v in draws.items()}
        logs.append({"log_id": f"sim{i:06d}", "run": i // variants, "variant": i % variants,
                     "sensor_seed": int(seed * 100_000 + i), "sensors": "nominal" if nominal else "offsets", **off})
    return runs, logs


def batches(runs, size):
    """Runs grouped into simulator batches: one manoeuvre per batch; the
    manoeuvres the simulator cannot batch (one vehicle per scenario) alone;
    brake-in-turn batches share one initial speed (its builder's)."""
    out, cur = [], {}
    for run in runs:
        m = run["manoeuvre"]
        if m not in BATCHABLE:
            out.append([run])
            continue
        cur.setdefault(m, []).append(run)
        if len(cur[m]) == size:
            out.append(cur.pop(m))
    out += [cur[m] for m in sorted(cur)]
    return sorted(out, key=lambda b: b[0]["run"])


def swa03(dt):
    """SWA at 0.3 g of the passenger car [deg] (FMVSS 126 ramp; sine-dwell and fishhook amplitudes)."""
    from grip_tools.sim import manoeuvres as M, vehicles
    from grip_tools.sim.model import Effects
    return float(M.swa_at_03g(vehicles.passenger(), Effects(), h=max(dt, 1e-3)))


def scenario(batch, vehicle, duration, swa03_deg):
    from grip_tools.sim import manoeuvres as M
    from grip_tools.sim.model import Road
    m = batch[0]["manoeuvre"]
    v0 = np.array([r["speed_kmh"] / 3.6 for r in batch])
    par = np.array([r["param"] if r["param"] is not None else 0.0 for r in batch])
    kw = {} if duration is None else {"duration": duration}
    if m == "step-steer":
        swa = np.array([M.linear_swa(vehicle, v, a) / M.DEG for v, a in zip(v0, par)])
        sc = M.step_steer(vehicle, v0=v0, swa_deg=swa, **kw)
    elif m == "ramp-steer":
        sc = M.ramp_steer(vehicle, v0=v0, direction=par, **kw)
    elif m in ("sine-dwell", "fishhook"):
        amp = np.minimum(par * swa03_deg, 270.0)
        sc = M.build(m, vehicle, amp_deg=amp, v0=v0)
        if duration is not None:
            sc.duration = duration
    elif m == "brake-in-turn":
        sc = M.brake_in_turn(vehicle, v0=float(v0[0]), decel=par, **kw)
    else:
        sc = M.build(m, vehicle, surface=batch[0]["surface"], v0=float(v0[0]), **kw)
    if m in BATCHABLE:
        sc.road = Road.batch([Road.uniform(r["mu"], name=r["surface"]) for r in batch])
    return sc


def sensor_config(log):
    from grip_tools.sim import sensors
    cfg = sensors.SensorConfig(seed=log["sensor_seed"])
    if log["sensors"] == "offsets":
        yaw = cfg.channel("YawRate")
        yaw.bias, yaw.scale_error = log["yaw_bias_deg_s"], log["yaw_scale_error"]
        cfg.channel("LatAcc").bias = log["ay_bias_m_s2"]
        cfg.channel("SteeringAngle").bias = log["steer_offset_deg"]
        for w in WHEELS:
            cfg.channel(f"WheelSpeed_{w.upper()}").scale_error = log["wheel_scale_error"]
    return cfg


def write_truth(path, res, i):
    """The truth of member i at 100 Hz: the columns est_eval.evaluate reads and a few more."""
    rec_dt = float(res.meta["record_dt"])
    k = max(1, int(round(1.0 / (TRUTH_RATE_HZ * rec_dt))))
    names = ["time"] + list(TRUTH_SCALARS) + [f"{q}_{w}" for q in TRUTH_WHEEL for w in WHEELS]
    cols = [res.t[::k]] + [res.data[q][::k, i] for q in TRUTH_SCALARS]
    cols += [res.data[q][::k, i, j] for q in TRUTH_WHEEL for j in range(4)]
    with open(path, "w") as f:
        f.write(f"# grip sim-fleet truth: {res.meta['scenario']}, batch member {i}, RK4 h = {res.meta['h']} s, "
                f"every {k * rec_dt:g} s\n")
        f.write(",".join(names) + "\n")
        np.savetxt(f, np.column_stack(cols), delimiter=",", fmt="%.9g")


def simulate_batch(batch, logs, out, dt, duration, swa03_deg):
    """One simulator batch and its logs' files; returns (manifest rows, info)."""
    from grip_tools.evaluate import est_eval
    from grip_tools.reference import est as est_ref
    from grip_tools.sim import sensors, vehicles
    from grip_tools.sim.model import Effects, simulate
    t0, c0 = time.perf_counter(), time.process_time()
    vehicle = vehicles.passenger()
    sc = scenario(batch, vehicle, duration, swa03_deg)
    h = dt
    try:
        res = simulate(vehicle, sc, Effects(), h=h)
    except FloatingPointError:
        # the explicit scheme's stability limit (docs/simulator.md): once more at half the step
        h = dt / 2
        sc = scenario(batch, vehicle, duration, swa03_deg)
        res = simulate(vehicle, sc, Effects(), h=h)
    t_sim, c_sim = time.perf_counter() - t0, time.process_time() - c0
    rows = []
    for i, run in enumerate(batch):       # (brake-in-turn: the batch's first speed for all)
        rdir = os.path.join(out, "runs", f"r{run['run']:05d}")
        os.makedirs(rdir, exist_ok=True)
        write_truth(os.path.join(rdir, "truth.csv"), res, i)
        truth = res.member(i)
        for log in (x for x in logs if x["run"] == run["run"]):
            sd = sensors.measure(truth, sensor_config(log))
            t, value, valid = est_ref.inputs_from_sensors(sd.wide_columns())
            path = os.path.join(out, "logs", f"{log['log_id']}.csv")
            est_eval.write_input_csv(path + ".tmp", t, value, valid)
            os.replace(path + ".tmp", path)
            row = {"log_id": log["log_id"], "path": f"logs/{log['log_id']}.csv",
                   "truth": f"runs/r{run['run']:05d}/truth.csv", "format": "csv", "vehicle": vehicle.name,
                   "preset": "generic", "vehicle_file": "vehicle.txt", "manoeuvre": run["manoeuvre"],
                   "surface": run["surface"], "speed_kmh": round(float(sc.v0[i]) * 3.6, 1), "param_name": run["param_name"],
                   "param": run["param"], "duration_s": round(float(res.t[-1]), 3)}
            row.update({k: log[k] for k in ("run", "variant", "sensor_seed", "sensors", "yaw_bias_deg_s",
                                            "yaw_scale_error", "ay_bias_m_s2", "steer_offset_deg",
                                            "wheel_scale_error")})
            rows.append(row)
    info = {"manoeuvre": batch[0]["manoeuvre"], "runs": [r["run"] for r in batch], "members": len(batch),
            "logs": len(rows), "h": h, "sim_s": round(float(res.t[-1]), 3), "wall_sim_s": round(t_sim, 2),
            "wall_s": round(time.perf_counter() - t0, 2), "cpu_sim_s": round(c_sim, 2),
            "cpu_s": round(time.process_time() - c0, 2)}
    return rows, info


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="grip sim-fleet", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("n", type=int, help="number of logs")
    ap.add_argument("--out", "-o", required=True)
    ap.add_argument("--duration", type=float, default=None,
                    help="length of every log [s] (default: each manoeuvre's own, 2-20 s)")
    ap.add_argument("--variants", type=int, default=1,
                    help="logs per simulated run, each with its own sensors (default 1)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--manoeuvres", default=",".join(DEFAULT_MANOEUVRES))
    ap.add_argument("--surfaces", default=",".join(DEFAULT_SURFACES),
                    help="dry, wet, snow or numbers (friction scale)")
    ap.add_argument("--dt", type=float, default=0.002, help="simulator RK4 step [s] (default 0.002)")
    ap.add_argument("--batch", type=int, default=16, help="vehicles per simulator batch (default 16)")
    cluster.add_arguments(ap, default_memory="6GiB")
    return ap.parse_args(argv)


def main(argv=None):
    from grip_tools.errors import UsageError
    from grip_tools.evaluate import est_eval
    from grip_tools.sim import manoeuvres as M
    a = parse_args(argv)
    if a.n < 1 or a.variants < 1 or a.batch < 1:
        raise UsageError("N, --variants and --batch must be >= 1")
    mans = [m.strip() for m in a.manoeuvres.split(",") if m.strip()]
    for m in mans:
        if m not in M.MANOEUVRES:
            raise UsageError(f"unknown manoeuvre '{m}' (one of {', '.join(M.MANOEUVRES)})")
    surfs = [s.strip() for s in a.surfaces.split(",") if s.strip()]
    for sf in surfs:
        try:
            M.parse_surface(sf)
        except ValueError as e:
            raise UsageError(f"--surfaces: unknown surface {e}") from None
    if not surfs or not mans:
        raise UsageError("--manoeuvres and --surfaces need at least one name each")
    if not (math.isfinite(a.dt) and 0.0 < a.dt <= 0.01):
        raise UsageError(f"--dt: {a.dt!r}: outside (0, 0.01] s")
    if a.duration is not None and not (math.isfinite(a.duration) and 0.0 < a.duration <= 3600.0):
        raise UsageError(f"--duration: {a.duration!r}: outside (0, 3600] s")
    t0 = time.time()
    runs, logs = plan(a.n, a.seed, mans, surfs, a.variants)
    groups = batches(runs, a.batch)
    os.makedirs(os.path.join(a.out, "logs"), exist_ok=True)
    with open(os.path.join(a.out, "vehicle.txt"), "w") as f:
        f.write("# the simulator car's estimator settings (est_eval.est_vehicle_lines)\n")
        f.write("\n".join(est_eval.est_vehicle_lines()) + "\n")
    need_swa = any(m in ("sine-dwell", "fishhook") for m in mans)
    client = cluster.open_client(a)
    prog = cluster.Progress(len(groups), what="simulator batches", enabled=not a.no_progress)
    rows, infos = [], []
    try:
        by_run = {}
        for log in logs:
            by_run.setdefault(log["run"], []).append(log)
        args = [(g, [x for r in g for x in by_run[r["run"]]]) for g in groups]
        if isinstance(client, cluster.Serial):
            s03 = swa03(a.dt) if need_swa else None
            for g, lg in args:
                r, info = simulate_batch(g, lg, a.out, a.dt, a.duration, s03)
                rows += r
                infos.append(info)
                prog.update()
        else:
            from dask.distributed import as_completed
            s03 = client.submit(swa03, a.dt, pure=False) if need_swa else None
            futs = [client.submit(simulate_batch, g, lg, a.out, a.dt, a.duration, s03, pure=False, retries=1)
                    for g, lg in args]
            for f in as_completed(futs):
                r, info = f.result()
                rows += r
                infos.append(info)
                prog.update()
            if s03 is not None:
                s03 = s03.result()
    finally:
        if not isinstance(client, cluster.Serial):
            cluster.close_client(client)
    import pandas as pd
    df = pd.DataFrame(sorted(rows, key=lambda r: r["log_id"]))
    df.to_csv(os.path.join(a.out, "manifest.csv"), index=False)
    infos.sort(key=lambda x: x["runs"][0])
    wall = time.time() - t0
    sim_seconds = sum(x["sim_s"] * x["members"] for x in infos)
    meta = {"n": a.n, "variants": a.variants, "seed": a.seed, "manoeuvres": mans, "surfaces": surfs, "dt": a.dt,
            "duration": a.duration, "batch": a.batch, "swa03_deg": s03, "runs": len(runs), "batches": infos,
            "wall_s": round(wall, 1), "batch_wall_s_total": round(sum(x["wall_s"] for x in infos), 1),
            "batch_cpu_s_total": round(sum(x["cpu_s"] for x in infos), 1),
            "simulated_vehicle_s": round(sim_seconds, 1), "workers": getattr(client, "n_workers", 0)}
    with open(os.path.join(a.out, "sim.json"), "w") as f:
        json.dump(meta, f, indent=1)
    print(f"grip sim-fleet: {a.n} logs from {len(runs)} simulated runs in {len(groups)} batches, "
          f"{wall:.1f} s wall ({meta['batch_wall_s_total']:.1f} s in the batches) -> {a.out}/manifest.csv",
          file=sys.stderr)
    return 0
