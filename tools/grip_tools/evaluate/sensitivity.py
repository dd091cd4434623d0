"""The estimator's constants against the independent judge: what each one is,
and how much the results move when it is halved or doubled.

    grip est-sensitivity [--names EST_K_HI ...] [--factors 0.5 2]
                         [--vehicles ...] [--manoeuvres ...] [--surfaces ...]
                         [--jobs J] [--out docs/estimator]

Every constant of lib/est/est_tuning.h has a class (CLASSES below): a
physical quantity, a sensor specification (a noise or a range a data sheet
states), a limit of the number format (Q15.16), or a tuning. For each
constant that is not fixed by physics or by the format, the study builds
grip-replay (float) with that one value multiplied by each factor
(est_tuning.h's GRIP_EST_TUNING_OVERRIDE hook: a header that #undefs and
redefines it; nothing else changes), runs it over the independent judge's
runs (CommonRoad's multi-body car, docs/independent-judge.md; the runs are
simulated once and reused from build/est_eval/independent) with the generic
tire, and scores it with the judge's own metrics. A constant of the
stiffness learners or of the bank observer (CONFIGS, config_of) is run with
its part switched on, against a baseline in that configuration: with it off
the constant does nothing (the learners' after the judge's learning drives,
run by the same build).

    beta pass   runs meeting the beta target (RMS <= 0.5 deg, max <= 1.5 deg
                where flagged valid)
    all pass    runs meeting every target that applies
    beta RMS    median over the runs of the beta RMS error where valid [deg]
    valid       mean share of moving steps outside spins with beta valid
    bad valid   share of the beta-valid moving steps whose error is above
                1 deg [%]

Writes OUT/sensitivity.md and OUT/sensitivity.json. The figures are those
of the commit the study ran on: a change of the estimator changes them, and
the study is rerun (it takes about 10-20 s of CPU per variant on the reduced
set).
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

from grip_tools.evaluate import est_eval
from grip_tools.paths import REPO_ROOT
from grip_tools.reference import est as est_ref

TUNING_H = os.path.join(REPO_ROOT, "lib", "est", "est_tuning.h")
DEG = 180.0 / math.pi
BAD_DEG = 1.0

# Each constant's class. physics and format are never perturbed (a physical
# constant is not a choice; a format limit keeps Q15.16 in range, and
# changing it changes the fixed build's overflow proof, not the estimate);
# range: a sensor's or the vehicle's range, perturbed only when asked.
CLASSES = {
    "EST_G": "physics",
    "EST_HOLD_T": "tuning", "EST_DELTA_MAX": "range", "EST_DELTA_R_MAX": "range",
    "EST_WS_STEER_MAX": "tuning", "EST_RATE_TOL_DIV": "sensor", "EST_WS_MAX": "range",
    "EST_YAW_MAX": "range", "EST_ACC_MAX": "range",
    "EST_V_STAND": "tuning", "EST_AX_TH": "tuning", "EST_WHEEL_DEV": "tuning", "EST_K_HI": "tuning",
    "EST_K_MID": "tuning", "EST_K_LO": "tuning", "EST_K_SLIP": "tuning", "EST_SPREAD_REL": "tuning",
    "EST_SPREAD_ABS": "tuning", "EST_K_OFF": "tuning", "EST_AX_OFF_MAX": "range", "EST_DR_AX": "tuning",
    "EST_DR_T": "tuning", "EST_NOWHEEL_T": "tuning",
    "EST_V_ON": "tuning", "EST_V_OFF": "tuning",
    "EST_S_VY": "format", "EST_S_R": "format", "EST_S_MU": "format", "EST_S_B": "format",
    "EST_S_AY": "format",
    "EST_R_YAW": "sensor", "EST_R_AY": "sensor", "EST_R_AX": "sensor",
    "EST_Q_VY": "tuning", "EST_Q_R": "tuning", "EST_Q_MU": "tuning", "EST_Q_B": "sensor",
    "EST_P0_VY": "tuning", "EST_P0_R": "tuning", "EST_P0_MU": "tuning", "EST_P0_B": "sensor",
    "EST_P_MIN": "format", "EST_P_MAX": "format", "EST_H_MAX_VY": "format", "EST_H_MAX": "format",
    "EST_NU_SIGMA": "format", "EST_VY_K": "tuning", "EST_B_MAX": "sensor",
    "EST_B_U": "tuning", "EST_B_A": "tuning", "EST_B_AX": "tuning", "EST_B_RACC": "tuning",
    "EST_U_R0": "tuning", "EST_R_LIM": "tuning", "EST_R_AXLE": "tuning", "EST_AY_U_K": "tuning",
    "EST_G_MIN": "tuning", "EST_SIG_MIN": "tuning", "EST_SIG_MAX": "range", "EST_RLX_A_MAX": "format",
    "EST_MU_MIN": "range", "EST_MU_MAX": "range", "EST_MU_INIT": "physics", "EST_V_EXC": "tuning",
    "EST_EXC_U": "tuning", "EST_EXC_A": "tuning",
    "EST_LIM_TAU": "tuning", "EST_LIM_A": "tuning", "EST_LIM_REL": "tuning", "EST_LIM_ABS": "tuning",
    "EST_LIM_T": "tuning",
    "EST_US_D": "tuning", "EST_US_R": "tuning", "EST_US_U0": "tuning", "EST_US_U1": "tuning",
    "EST_US_UMAX": "tuning", "EST_US_ZMAX": "tuning", "EST_REL_K": "tuning", "EST_P_CONF": "derived",
    "EST_CUT_CLEAR": "tuning", "EST_SEC_K": "tuning", "EST_SEC_MIN": "tuning", "EST_SHAPE_F_MIN": "format",
    "EST_LOCK_K": "tuning", "EST_R_LOCK": "tuning",
    "EST_MB_TAU": "tuning", "EST_MB_RACC": "tuning", "EST_MB_AX": "tuning", "EST_SB_TAU": "tuning",
    "EST_CONF_S0": "tuning", "EST_MF_TAU": "tuning", "EST_NIS_HI": "physics", "EST_NIS_LO": "physics",
    "EST_SAT_U": "tuning", "EST_SAT_HI": "tuning", "EST_SAT_LO": "tuning", "EST_CONF_MISFIT": "tuning",
    "EST_SAT_MU": "tuning", "EST_SAT_MU_LO": "tuning",
    "EST_ROLL_TOL": "tuning", "EST_DIS_K": "physics", "EST_SD_CAP": "format", "EST_SD_MIN": "format",
    "EST_Q_MAX": "format", "EST_KIN_Q0": "tuning", "EST_SD_VY_EDGE": "tuning",
    "EST_WS_TOL": "sensor", "EST_SLIP_MAX": "physics",
    "EST_ROAD_L": "tuning", "EST_ROAD_U": "tuning", "EST_ROAD_RACC": "tuning", "EST_ROAD_T_DR": "tuning",
    "EST_ROAD_D": "tuning", "EST_ROAD_T_REST": "tuning", "EST_ROAD_GY_MAX": "range",
    "EST_STF_S_U": "format", "EST_STF_S_Y": "format", "EST_STF_P0": "tuning", "EST_STF_SD_MIN": "tuning",
    "EST_STF_Q": "tuning", "EST_STF_R": "sensor", "EST_STF_T": "tuning", "EST_STF_TC": "tuning",
    "EST_STF_V": "tuning", "EST_STF_AX": "tuning", "EST_STF_U": "tuning", "EST_STF_D": "tuning",
    "EST_STF_H_MIN": "tuning", "EST_STF_SLOPE": "format", "EST_STF_K_MIN": "range", "EST_STF_K_MAX": "range",
    "EST_STF_RACC": "range", "EST_STEADY_K": "physics",
    "EST_KX_S_U": "format", "EST_KX_S_Y": "format", "EST_KX_P0": "tuning", "EST_KX_SD_MIN": "tuning",
    "EST_KX_Q": "tuning", "EST_KX_D0": "range", "EST_KX_D_SD_MIN": "tuning", "EST_KX_QD": "tuning",
    "EST_KX_R": "sensor", "EST_KX_T": "tuning", "EST_KX_TC": "tuning", "EST_KX_V": "tuning",
    "EST_KX_AY": "tuning", "EST_KX_STEER": "tuning", "EST_KX_U": "tuning", "EST_KX_AX_C": "tuning",
    "EST_KX_AX_T": "tuning", "EST_KX_H_MIN": "tuning", "EST_KX_DV_MAX": "format", "EST_KX_K_MIN": "range",
    "EST_KX_K_MAX": "range", "EST_KX_D_MAX": "range",
    "EST_RG_S_U": "format", "EST_RG_P0": "range", "EST_RG_SD_MIN": "tuning", "EST_RG_Q": "tuning",
    "EST_RG_R": "sensor", "EST_RG_TC": "tuning", "EST_RG_T": "tuning", "EST_RG_TH": "tuning",
    "EST_RG_AY": "tuning", "EST_RG_BANK": "tuning", "EST_RG_H_MIN": "tuning", "EST_RG_T_ALT": "tuning", "EST_RG_DK": "tuning",
    "EST_RG_K_MIN": "range", "EST_RG_K_MAX": "range",
}
CLASS_TEXT = {
    "physics": "a physical or statistical constant (g, a chi-square point, the tire as fitted)",
    "sensor": "a sensor specification (noise density, bias range, sampling tolerance)",
    "range": "a range of a sensor or of the vehicle (no car steers further, no gyro reads more)",
    "format": "a scaling or bound of the Q15.16 filter (keeps every product in range)",
    "derived": "computed from other constants",
    "tuning": "a tuning, with its sensitivity below",
}
PERTURBED = ("tuning", "sensor")

# The configuration in which a constant acts: the learners' and the bank
# observer's constants do nothing with them off (the generic configuration),
# so they are perturbed with their part switched on, against a baseline in
# that configuration. "learned" is the judge's learned configuration with
# the slip stiffness too: both learners on, each vehicle's learning drives
# (LEARNING_DRIVES, dry: the judge's) run first by the same build, and every
# run restored from what they learned (grip-replay --learned-in); bank_est
# is switched on from the start of each run.
CONFIGS = {"generic": {}, "learned": {"stiff_est": 1, "kx_est": 1, "roll_est": 1}, "bank_est": {"bank_est": 1}}
_CONFIG_PREFIX = (("EST_STF_", "learned"), ("EST_KX_", "learned"), ("EST_RG_", "learned"), ("EST_ROAD_", "bank_est"))
LEARNING_DRIVES = {"learned": ("learning-drive", "learning-drive-long")}


def config_of(name):
    """The configuration (a key of CONFIGS) in which constant `name` acts."""
    for prefix, cfg in _CONFIG_PREFIX:
        if name.startswith(prefix):
            return cfg
    return "generic"

_DEFINE = re.compile(r"^#define\s+(EST_[A-Z0-9_]+)\s+(\S.*?)\s*(?:/\*.*)?$")


def constants(path=TUNING_H):
    """[(name, value text)] in the order of est_tuning.h."""
    out = []
    with open(path) as f:
        for line in f:
            m = _DEFINE.match(line.rstrip("\n"))
            if m:
                out.append((m.group(1), m.group(2).strip()))
    return out


def check_classes(consts):
    """Every constant of the header has a class and every class a constant:
    a new constant cannot slip past the study."""
    names = [n for n, _ in consts]
    missing = [n for n in names if n not in CLASSES]
    extra = [n for n in CLASSES if n not in names]
    return missing, extra


# ---------------------------------------------------------------------------
# variant builds

def _run(args, cwd=REPO_ROOT):
    p = subprocess.run(args, cwd=cwd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(args)}: exit {p.returncode}\n{p.stderr.strip()}")


def prepare_base(work):
    """The float host build's libraries (make) and grip_replay.c compiled
    once: a variant recompiles lib/est only."""
    _run(["make", "-s", "build/float-gcc/bin/grip-replay"])
    from grip import _build
    base = os.path.join(work, "base")
    os.makedirs(base, exist_ok=True)
    obj = os.path.join(base, "grip_replay.o")
    _run(["gcc"] + _build.port_cflags("float") + ["-Werror", "-c", os.path.join(REPO_ROOT, "port", "linux",
                                                                                 "grip_replay.c"), "-o", obj])
    return obj


def build_variant(work, base_obj, tag, overrides):
    """grip-replay with overrides {name: value text}; returns its path."""
    from grip import _build
    d = os.path.join(work, tag)
    os.makedirs(d, exist_ok=True)
    hdr = os.path.join(d, "override.h")
    with open(hdr, "w") as f:
        for k, v in overrides.items():
            f.write(f"#undef {k}\n#define {k} ({v})\n")
    objs = []
    flags = _build.lib_cflags("float") + ["-Werror"]
    if overrides:
        flags.append(f'-DGRIP_EST_TUNING_OVERRIDE="{hdr}"')
    for src in sorted(os.listdir(os.path.join(REPO_ROOT, "lib", "est"))):
        if src.endswith(".c"):
            o = os.path.join(d, src[:-2] + ".o")
            _run(["gcc"] + flags + ["-c", os.path.join(REPO_ROOT, "lib", "est", src), "-o", o])
            objs.append(o)
    exe = os.path.join(d, "grip-replay")
    b = os.path.join(REPO_ROOT, "build", "float-gcc")
    _run(["gcc", base_obj] + objs + [os.path.join(b, "libgrip_port.a"), os.path.join(b, "libgrip.a"), "-lm",
                                     "-lsocketcan", "-o", exe])
    return exe


# ---------------------------------------------------------------------------
# the judge's runs

def run_dirs(vehicles, manoeuvres, surfaces, runs_dir, resimulate=False):
    """The judge's runs (simulated now where not yet on disk, or all of
    them with resimulate)."""
    from grip_tools.sim.independent import judge
    out = []
    for v in vehicles:
        for m in manoeuvres:
            for s in surfaces:
                d = os.path.join(runs_dir, f"{v}_{m}_{s}")
                if resimulate or not (os.path.exists(os.path.join(d, "inputs.csv")) and
                        os.path.exists(os.path.join(d, "truth.csv"))):
                    judge.simulate_run(v, m, s, d)
                out.append((v, m, s, d))
    return out


def learning_inputs(vehicles, runs_dir):
    """The learning drives' input files of each vehicle {vehicle: [csv]},
    simulated as the judge's learn() does where not yet on disk."""
    from grip_tools.sim.independent import judge
    out = {}
    for v in vehicles:
        out[v] = []
        for name in LEARNING_DRIVES["learned"]:
            path = os.path.join(runs_dir, "learning", f"{v}_{name}_inputs.csv")
            if not os.path.exists(path):
                t, value, valid = judge.learning_drive_inputs(v, name)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                est_eval.write_input_csv(path, t, value, valid)
            out[v].append(path)
    return out


def learn_blob(exe, v, lines, drives, work):
    """Runs the vehicle's learning drives through exe, each from the last
    one's blob; the path of the blob they leave."""
    from grip_tools.sim.independent import judge
    blob = None
    for k, csv in enumerate(drives):
        out = os.path.join(work, f"learned_{v}_{k}.bin")
        extra = (["--learned-in", blob] if blob else []) + ["--learned-out", out]
        est_eval.run_c(exe, judge.GENERIC_TIR, csv, vehicle_lines=lines, extra_args=extra)
        blob = out
    return blob


def load_run(v, d):
    """What scoring a run needs besides the estimate, read and derived once:
    truth, inputs and the judge's generic configuration of the vehicle."""
    from grip_tools.sim.independent import judge, mb
    veh = mb.Vehicle(v)
    values = judge.oem_vehicle(veh)
    return dict(truth=est_eval.read_csv(os.path.join(d, "truth.csv")),
                meas=est_eval.read_csv(os.path.join(d, "inputs.csv")),
                lines={c: judge.vehicle_lines(dict(values, **extra)) for c, extra in CONFIGS.items()},
                norm=judge.mu_norm(veh, judge.GENERIC_TIR),
                bicycle=judge.bicycle_params(values), geom=dict(l=veh.l, lr=veh.p.b))


# the runs' truth and inputs, read once and shared with the forked workers
_LOADED = {}


def score(exe, runs, loaded, config="generic"):
    """The judge's metrics of one build over the runs in a configuration
    (a key of CONFIGS); a summary dict."""
    from grip_tools.sim.independent import judge
    per_run = []
    bad = valid_steps = 0
    blobs = {}
    if config in LEARNING_DRIVES:
        for v in sorted({r[0] for r in runs}):
            blobs[v] = learn_blob(exe, v, loaded[("lines", v)][config], loaded[("learning", v)],
                                  os.path.dirname(exe))
    for (v, m, s, d) in runs:
        run = loaded[d]
        tr = run["truth"]
        est = est_eval.run_c(exe, judge.GENERIC_TIR, os.path.join(d, "inputs.csv"),
                             vehicle_lines=run["lines"][config],
                             extra_args=["--learned-in", blobs[v]] if v in blobs else ())
        r = judge.metrics(tr, run["meas"], est, run["norm"], run["bicycle"], run["geom"])
        n = min(len(tr["time"]), len(est["time"]))
        vb = ((est["valid"][:n] & est_ref.V_BETA) != 0) & (tr["vx"][:n] >= judge.V_MOVING)
        e = np.abs(est["beta"][:n] - tr["beta"][:n]) * DEG
        bad += int(np.sum(vb & (e > BAD_DEG)))
        valid_steps += int(vb.sum())
        per_run.append(dict(run=f"{v}/{m}/{s}", beta_rms=r["beta_rms_deg"], beta_max=r["beta_max_deg"],
                            valid=r["valid_share"], passes=r["pass"]))
    rms = [x["beta_rms"] for x in per_run if x["beta_rms"] is not None]
    val = [x["valid"] for x in per_run if x["valid"] is not None]
    return dict(beta_pass=sum(1 for x in per_run if x["passes"].get("beta")),
                all_pass=sum(1 for x in per_run if x["passes"].get("all")),
                beta_rms_median=float(np.median(rms)) if rms else None,
                valid_mean=float(np.mean(val)) if val else None,
                bad_valid_pct=100.0 * bad / valid_steps if valid_steps else None,
                runs=len(per_run), per_run=per_run)


def _cpu():
    """CPU seconds of this process and its finished children (the compiler,
    grip-replay)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _variant_job(a):
    work, base_obj, tag, overrides, runs, config = a
    t0 = _cpu()
    exe = build_variant(work, base_obj, tag, overrides)
    res = score(exe, runs, _LOADED, config)
    res["config"] = config
    shutil.rmtree(os.path.join(work, tag), ignore_errors=True)
    res["cpu_s"] = _cpu() - t0
    return tag, res


def _fmt_value(v):
    try:
        return f"{float(v):g}"
    except ValueError:
        return v


def _cell(res, base):
    if res is None:
        return "build failed"
    d_beta = res["beta_pass"] - base["beta_pass"]
    d_all = res["all_pass"] - base["all_pass"]
    return (f"{res['beta_pass']} ({d_beta:+d}) / {res['all_pass']} ({d_all:+d}) / "
            f"{res['beta_rms_median']:.2f} / {100 * res['valid_mean']:.0f} / {res['bad_valid_pct']:.1f}")


def markdown(doc):
    base = doc["baseline"]
    bases = doc.get("baselines", {"generic": base})
    lines = ["# The estimator's constants on the independent judge", "",
             f"Generated by `{doc['command']}` at commit {doc['commit']} (float build, generic tire, "
             f"{base['runs']} runs: {', '.join(doc['selection']['vehicles'])} x "
             f"{len(doc['selection']['manoeuvres'])} manoeuvres x {len(doc['selection']['surfaces'])} surfaces; "
             "the judge and its metrics: [independent-judge.md](../independent-judge.md)).", "",
             "Each cell: runs meeting the beta target (change against the values as shipped) / runs meeting "
             "every target (change) / median beta RMS where valid [deg] / beta valid share of the moving steps "
             f"outside spins [%] / share of the beta-valid steps with an error above {BAD_DEG:g} deg [%].", "",
             f"As shipped (generic configuration): {_cell(base, base)}."]
    others = [c for c in bases if c != "generic"]
    if others:
        lines += ["", "The constants of the stiffness learners and of the bank observer act only with their "
                  "part switched on; they are perturbed in that configuration and compared with it as shipped:",
                  ""]
        text = {"learned": "`stiff_est = 1`, `kx_est = 1`, every run restored from what the same build learned "
                           "in the judge's learning drives (dry, ramp steer and speed changes)",
                "bank_est": "`bank_est = 1` from the start of each run"}
        lines += [f"- {c} ({text.get(c, c)}): {_cell(bases[c], bases[c])}" for c in others]
    lines += ["", "| constant | class | configuration | value | x " + " | x ".join(f"{f:g}" for f in doc["factors"])
              + " |", "|---|---|---|---|" + "---|" * len(doc["factors"])]
    for row in doc["rows"]:
        cfg = row.get("config", "generic")
        rb = bases.get(cfg, base)
        cells = [_cell(row["results"].get(f"{f:g}"), rb) if row["perturbed"] else "-" for f in doc["factors"]]
        lines.append(f"| `{row['name']}` | {row['class']} | {cfg} | {_fmt_value(row['value'])} | "
                     + " | ".join(cells) + " |")
    lines += ["", "Classes:", ""]
    lines += [f"- **{k}**: {v}" for k, v in CLASS_TEXT.items()]
    lines += ["", f"Study CPU time: {doc['cpu_s']:.0f} s for {doc['variants']} variants.", ""]
    return "\n".join(lines)


def main(argv=None):
    from grip_tools.sim.independent import judge
    ap = argparse.ArgumentParser(prog="grip est-sensitivity", description=__doc__.split("\n\n")[0])
    ap.add_argument("--names", nargs="+", help="only these constants (default: every tuning and sensor constant)")
    ap.add_argument("--factors", nargs="+", type=float, default=[0.5, 2.0])
    ap.add_argument("--vehicles", nargs="+", default=list(judge.DEFAULT_SET["vehicles"]))
    ap.add_argument("--manoeuvres", nargs="+", default=list(judge.DEFAULT_SET["manoeuvres"]))
    ap.add_argument("--surfaces", nargs="+", default=list(judge.DEFAULT_SET["surfaces"]))
    ap.add_argument("--jobs", type=int, default=max(1, min(os.cpu_count() or 1, 2)))
    ap.add_argument("--runs-dir", default=os.path.join(REPO_ROOT, "build", "est_eval", "independent"))
    ap.add_argument("--resimulate", action="store_true",
                    help="simulate every run again (after a change of the independent simulator)")
    ap.add_argument("--work", default=os.path.join(REPO_ROOT, "build", "sensitivity"))
    ap.add_argument("--out", default=os.path.join(REPO_ROOT, "build", "sensitivity"))
    a = ap.parse_args(argv)
    err = judge.selection_error(a.vehicles, a.manoeuvres, a.surfaces)
    if err or a.jobs < 1:
        print(f"grip est-sensitivity: {err or f'--jobs: {a.jobs}: at least 1'}", file=sys.stderr)
        return 2
    consts = constants()
    missing, extra = check_classes(consts)
    if missing or extra:
        print(f"grip est-sensitivity: {TUNING_H}: constants without a class: {', '.join(missing) or '-'}; "
              f"classes without a constant: {', '.join(extra) or '-'}", file=sys.stderr)
        return 3
    known = {n for n, _ in consts}
    for n in a.names or ():
        if n not in known:
            print(f"grip est-sensitivity: --names: {n} is not a constant of {TUNING_H}", file=sys.stderr)
            return 2
    if any(not (f > 0.0) or f == 1.0 for f in a.factors):
        print("grip est-sensitivity: --factors: each factor must be > 0 and not 1", file=sys.stderr)
        return 2
    study = [(n, v) for n, v in consts
             if (a.names and n in a.names) or (not a.names and CLASSES[n] in PERTURBED)]
    for n, v in study:
        try:
            float(v)
        except ValueError:
            print(f"grip est-sensitivity: {n} = {v} is not a number literal; it cannot be scaled", file=sys.stderr)
            return 2
    os.makedirs(a.work, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    runs = run_dirs(a.vehicles, a.manoeuvres, a.surfaces, a.runs_dir, a.resimulate)
    base_obj = prepare_base(a.work)
    for (v, _, _, d) in runs:
        _LOADED[d] = load_run(v, d)   # before the pool forks: its workers share it
        _LOADED[("lines", v)] = _LOADED[d]["lines"]
    if any(config_of(n) in LEARNING_DRIVES for n, _ in study):
        for v, paths in learning_inputs(a.vehicles, a.runs_dir).items():
            _LOADED[("learning", v)] = paths
    configs = ["generic"] + sorted({config_of(n) for n, _ in study} - {"generic"})
    jobs = [(a.work, base_obj, "baseline" if c == "generic" else f"baseline_{c}", {}, runs, c) for c in configs]
    for n, v in study:
        for f in a.factors:
            val = float(v) * f
            if n == "EST_RATE_TOL_DIV":
                val = max(1, int(round(val)))
            jobs.append((a.work, base_obj, f"{n}_x{f:g}", {n: repr(val)}, runs, config_of(n)))
    t0 = time.time()
    results = {}
    if a.jobs > 1:
        import multiprocessing as mp
        with mp.get_context("fork").Pool(a.jobs) as pool:
            for k, (tag, res) in enumerate(pool.imap_unordered(_variant_job, jobs), 1):
                results[tag] = res
                print(f"est-sensitivity: {k}/{len(jobs)} {tag}: beta pass {res['beta_pass']}, all {res['all_pass']}",
                      file=sys.stderr)
    else:
        for k, j in enumerate(jobs, 1):
            tag, res = _variant_job(j)
            results[tag] = res
            print(f"est-sensitivity: {k}/{len(jobs)} {tag}: beta pass {res['beta_pass']}, all {res['all_pass']}",
                  file=sys.stderr)
    for tag, res in results.items():
        if tag != "baseline":
            res.pop("per_run")   # per run only as shipped: the variants' summaries are the study
    rows = []
    for n, v in consts:
        pert = any(n == s for s, _ in study)
        rows.append(dict(name=n, value=v, **{"class": CLASSES[n]}, perturbed=pert, config=config_of(n),
                         results={f"{f:g}": results.get(f"{n}_x{f:g}") for f in a.factors} if pert else {}))
    cmd = "grip est-sensitivity" + (f" --names {' '.join(a.names)}" if a.names else "")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO_ROOT, capture_output=True,
                            text=True).stdout.strip() or "unknown"
    doc = dict(command=cmd, commit=commit, factors=a.factors, selection=dict(vehicles=a.vehicles, manoeuvres=a.manoeuvres,
                                                               surfaces=a.surfaces),
               baseline=results["baseline"],
               baselines={c: results["baseline" if c == "generic" else f"baseline_{c}"] for c in configs},
               rows=rows, variants=len(jobs),
               cpu_s=sum(r["cpu_s"] for r in results.values()), wall_s=time.time() - t0)
    with open(os.path.join(a.out, "sensitivity.json"), "w") as f:
        json.dump(doc, f, indent=1)
    md = markdown(doc)
    with open(os.path.join(a.out, "sensitivity.md"), "w") as f:
        f.write(md)
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
