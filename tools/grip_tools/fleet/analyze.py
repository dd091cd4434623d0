"""grip fleet analyze: what the fleet's logs say together.

    grip fleet analyze DIR [--arith float] [--out DIR/analysis]

DIR is a `grip fleet run` results folder. Only rows with status 'ok' count.

1. Residuals pooled by vehicle, surface, speed band and the three together
   (bands.parquet: per log, arithmetic, quantity and band the count, sum,
   sum of squares, min and max, so the pooled mean, RMS and standard
   deviation are exact, whatever the number of logs):
     yaw_resid     measured yaw rate - the estimator's bicycle reference [rad/s]
     ay_resid      measured ay - the estimator's model ay (sum Fy / m) [m/s^2]
     beta_err_deg  estimated - true sideslip [deg]           (logs with a truth)
     mu_err        estimated - true friction while mu valid  (logs with a truth)
   A log weighs by its number of samples in the group.

2. Effects across logs. `fleet run` applies the measured-data loop's
   attribution (grip_tools.loop.attribution.analyse) to each log: the
   measured yaw rate and ay against the estimator's own predictions of them
   (yaw_rate_ref, ay_model), held-out blocks, a penalty per parameter. With
   that base model only the loop's sensor-level effects apply (bias, scale,
   delay; the tire- and vehicle-level ones need a model that declares
   them). Per effect: in how many of the analysed logs it was accepted
   (explains enough of the held-out residual for its parameters) and in how
   many it ranked first; the share with a 95 % Wilson interval. It says how
   often an effect is visible in single logs, not how large it is, and logs
   with too few moving samples (attr_note) are not analysed.
   Where the manifest has the simulator's injected offsets (grip sim-fleet:
   yaw_bias_deg_s), the fitted yaw-rate bias is compared with the injected
   one (a check of the attribution), and so is the estimator's own gyro
   offset at the end of the log (yaw_rate_bias_end).

Writes residuals.parquet, effects.parquet, analysis.json and analysis.md.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

from grip_tools.errors import UsageError
from grip_tools.fleet import store, summary

GROUPINGS = (("vehicle",), ("surface",), ("band",), ("vehicle", "surface", "band"))


def load(results, arith=None):
    import pandas as pd
    p = os.path.join(results, store.LOGS)
    if not os.path.exists(p):
        raise UsageError(f"{results}: no {store.LOGS} (run grip fleet run --out {results} first)")
    logs = pd.read_parquet(p)
    bp = os.path.join(results, store.BANDS)
    bands = pd.read_parquet(bp) if os.path.exists(bp) else pd.DataFrame(
        columns=["log_id", "arith", "quantity", "band", "n", "sum", "sumsq", "min", "max"])
    if arith:
        logs = logs[logs["arith"] == arith]
        bands = bands[bands["arith"] == arith]
    return logs, bands


def pick_arith(logs, arith):
    """The arithmetic to analyse: the one asked for (UsageError when the run
    has none of its rows), else float if present."""
    have = sorted(logs["arith"].unique())
    if arith:
        if have and arith not in have:
            raise UsageError(f"--arith {arith}: the run has rows of {', '.join(have)} only")
        return arith
    return "float" if "float" in have else (have[0] if have else "float")


def pooled_residuals(logs, bands):
    """One row per grouping, group key, quantity: n, logs, mean, std, rms, min, max."""
    import pandas as pd
    ok = logs[logs["status"] == "ok"][["log_id", "arith", "vehicle", "surface", "manoeuvre"]]
    b = bands.merge(ok, on=["log_id", "arith"], how="inner")
    b = b.assign(vehicle=b["vehicle"].fillna("?"), surface=b["surface"].fillna("?"))
    rows = []
    for grouping in GROUPINGS:
        keys = list(grouping) + ["quantity"]
        if b.empty:
            break
        g = b.groupby(keys, sort=True, observed=True)
        agg = g.agg(n=("n", "sum"), s=("sum", "sum"), ss=("sumsq", "sum"), lo=("min", "min"), hi=("max", "max"),
                    logs=("log_id", "nunique")).reset_index()
        for r in agg.to_dict("records"):
            mean = r["s"] / r["n"]
            rms = math.sqrt(r["ss"] / r["n"])
            rows.append({"grouping": "+".join(grouping), "key": " / ".join(str(r[k]) for k in grouping),
                         "quantity": r["quantity"], "n": int(r["n"]), "logs": int(r["logs"]), "mean": mean,
                         "std": math.sqrt(max(rms * rms - mean * mean, 0.0)), "rms": rms,
                         "min": float(r["lo"]), "max": float(r["hi"])})
    band_order = {b: i for i, b in enumerate(summary.BAND_NAMES)}
    df = pd.DataFrame(rows, columns=["grouping", "key", "quantity", "n", "logs", "mean", "std", "rms", "min", "max"])
    if not df.empty:
        df["_o"] = df["key"].map(lambda k: band_order.get(k.split(" / ")[-1], -1))
        df = df.sort_values(["grouping", "quantity", "_o", "key"]).drop(columns="_o").reset_index(drop=True)
    return df


def wilson(k, n, z=1.96):
    """95 % Wilson score interval of a share k / n."""
    if n == 0:
        return (None, None)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def effects_across(logs, by=None):
    """Per effect (and per `by` value): analysed logs, accepted / first shares."""
    import pandas as pd
    ok = logs[(logs["status"] == "ok") & logs["attr_scores"].notna()]
    groups = [("all", ok)] if by is None else [(str(k), g) for k, g in ok.groupby(ok[by].fillna("?"), sort=True)]
    rows = []
    for key, g in groups:
        n = len(g)
        names = set()
        for s in g["attr_scores"]:
            names.update(json.loads(s).keys())
        acc = g["attr_accepted"].fillna("").map(lambda s: set(x for x in s.split(",") if x))
        for e in sorted(names):
            k_acc = int(sum(e in s for s in acc))
            k_first = int((g["attr_chosen"] == e).sum())
            scores = [json.loads(s).get(e) for s in g["attr_scores"]]
            scores = [x for x in scores if x is not None]
            lo, hi = wilson(k_acc, n)
            rows.append({"group": key, "effect": e, "logs": n, "accepted": k_acc, "accepted_share": k_acc / n,
                         "accepted_lo95": lo, "accepted_hi95": hi, "first": k_first, "first_share": k_first / n,
                         "median_score": float(np.median(scores)) if scores else None})
    df = pd.DataFrame(rows)
    if not df.empty:
        df = df.sort_values(["group", "accepted_share", "effect"], ascending=[True, False, True]).reset_index(drop=True)
    return df


def injected_check(logs):
    """Fitted yaw-rate bias (sensor_bias_r) against the simulator's injected
    yaw-rate bias, where the manifest has it; None otherwise."""
    if "yaw_bias_deg_s" not in logs.columns:
        return None
    ok = logs[(logs["status"] == "ok") & logs["attr_params"].notna()]
    inj, fit = [], []
    for p, b in zip(ok["attr_params"], ok["yaw_bias_deg_s"]):
        v = json.loads(p).get("sensor_bias", {}).get("sensor_bias_r")
        if v is not None and b is not None and np.isfinite(b):
            inj.append(float(b) * math.pi / 180.0)
            fit.append(float(v))
    if len(inj) < 3:
        return {"logs": len(inj)}
    inj, fit = np.array(inj), np.array(fit)
    big = np.abs(inj) >= 0.4 * math.pi / 180.0
    acc = ok["attr_accepted"].fillna("")
    has_bias = acc.map(lambda s: "sensor_bias" in s.split(",")).to_numpy()
    b_inj = np.abs(ok["yaw_bias_deg_s"].to_numpy(dtype=float)) >= 0.4
    # beside it, the estimator's own gyro-offset state at the log's end
    est = ok["yaw_rate_bias_end"].to_numpy(dtype=float)
    inj_all = ok["yaw_bias_deg_s"].to_numpy(dtype=float) * math.pi / 180.0
    sel = np.isfinite(est) & np.isfinite(inj_all)
    est_corr = float(np.corrcoef(inj_all[sel], est[sel])[0, 1]) if sel.sum() > 2 and np.std(inj_all[sel]) > 0 else None
    return {"logs": int(len(inj)), "corr": float(np.corrcoef(inj, fit)[0, 1]) if np.std(inj) > 0 else None,
            "estimator_bias_end_corr": est_corr,
            "estimator_bias_end_rms_diff_rad_s": float(np.sqrt(np.mean((est[sel] - inj_all[sel]) ** 2)))
            if sel.any() else None,
            "rms_diff_rad_s": float(np.sqrt(np.mean((fit - inj) ** 2))),
            "mean_diff_rad_s": float(np.mean(fit - inj)),
            "accepted_share_injected_ge_0p4": float(np.mean(has_bias[b_inj])) if b_inj.any() else None,
            "accepted_share_injected_lt_0p4": float(np.mean(has_bias[~b_inj])) if (~b_inj).any() else None,
            "logs_injected_ge_0p4": int(b_inj.sum()), "big_share": float(np.mean(big))}


def _md_table(df, cols, fmt=None, limit=None):
    fmt = fmt or {}
    if df is None or df.empty:
        return "(none)\n"
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in df.head(limit).to_dict("records") if limit else df.to_dict("records"):
        cells = []
        for c in cols:
            v = r.get(c)
            if v is None or (isinstance(v, float) and not math.isfinite(v)):
                cells.append("-")
            elif c in fmt:
                cells.append(format(v, fmt[c]))
            elif isinstance(v, float):
                cells.append(f"{v:.4g}")
            else:
                cells.append(str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def analyse(results, arith=None):
    """(residuals, effects, effects_by_vehicle, check, arith) of a results folder."""
    logs, bands = load(results)
    arith = pick_arith(logs, arith)
    logs = logs[logs["arith"] == arith]
    bands = bands[bands["arith"] == arith]
    return (pooled_residuals(logs, bands), effects_across(logs), effects_across(logs, "vehicle"),
            injected_check(logs), arith, logs)


def markdown(res, eff, eff_v, check, arith, logs):
    units = {q: u for q, u, _ in summary.RESIDUALS}
    what = {q: w for q, _, w in summary.RESIDUALS}
    n_ok = int((logs["status"] == "ok").sum())
    md = [f"# Fleet analysis ({arith})\n",
          f"{n_ok} logs with status ok of {len(logs)}.\n",
          "## Residuals pooled\n"]
    for q in [q for q, _, _ in summary.RESIDUALS if not res.empty and q in set(res["quantity"])]:
        md.append(f"### {q} [{units[q]}]: {what[q]}\n")
        for grouping in ("vehicle", "surface", "band"):
            sub = res[(res["grouping"] == grouping) & (res["quantity"] == q)]
            if grouping == "band":
                sub = sub.assign(_o=sub["key"].map({b: i for i, b in enumerate(summary.BAND_NAMES)})).sort_values("_o")
            md.append(f"By {grouping if grouping != 'band' else 'speed band [km/h]'}:\n")
            md.append(_md_table(sub, ["key", "logs", "n", "mean", "std", "rms", "min", "max"]))
    md.append("## Effects across logs (measured-data loop attribution per log)\n")
    n_an = int(eff["logs"].iloc[0]) if not eff.empty else 0
    md.append(f"{n_an} logs analysed (the others: {', '.join(sorted(set(logs['attr_note'].dropna().map(lambda s: s.split(' (')[0])))) or 'none'}).\n")
    md.append(_md_table(eff, ["effect", "logs", "accepted", "accepted_share", "accepted_lo95", "accepted_hi95", "first",
                              "first_share", "median_score"],
                        {"accepted_share": ".1%", "accepted_lo95": ".1%", "accepted_hi95": ".1%", "first_share": ".1%",
                         "median_score": ".3f"}))
    if eff_v is not None and not eff_v.empty and eff_v["group"].nunique() > 1:
        md.append("By vehicle:\n")
        md.append(_md_table(eff_v, ["group", "effect", "logs", "accepted_share", "first_share"],
                            {"accepted_share": ".1%", "first_share": ".1%"}))
    if check:
        md.append("### Check against the injected yaw-rate bias (simulator logs)\n")
        md.append("```\n" + json.dumps(check, indent=1) + "\n```\n")
    return "\n".join(md)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip fleet analyze", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="a grip fleet run results folder")
    ap.add_argument("--arith", choices=("float", "fixed"), default=None, help="default: float if present")
    ap.add_argument("--out", default=None, help="default RESULTS/analysis")
    a = ap.parse_args(argv)
    out = a.out or os.path.join(a.results, "analysis")
    os.makedirs(out, exist_ok=True)
    res, eff, eff_v, check, arith, logs = analyse(a.results, a.arith)
    res.to_parquet(os.path.join(out, "residuals.parquet"), index=False)
    import pandas as pd
    pd.concat([eff.assign(by="all"), eff_v.assign(by="vehicle")] if not eff.empty else [eff]).to_parquet(
        os.path.join(out, "effects.parquet"), index=False)
    md = markdown(res, eff, eff_v, check, arith, logs)
    with open(os.path.join(out, "analysis.md"), "w") as f:
        f.write(md)
    with open(os.path.join(out, "analysis.json"), "w") as f:
        json.dump({"arith": arith, "injected_check": check,
                   "effects": eff.to_dict("records") if not eff.empty else []}, f, indent=1, default=str)
    print(md)
    print(f"grip fleet analyze: {out}/analysis.md", file=sys.stderr)
    return 0
