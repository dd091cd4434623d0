"""grip fleet report: Markdown + PNG from a fleet run's Parquet results.

    grip fleet report DIR [--baseline DIR0] [--arith float] [--out DIR/report]
                      [--fail-on-regression]

Sections: the run (versions, counts, errors by stage), distributions
(distributions.png), accuracy by manoeuvre / surface / vehicle for logs
with a truth (accuracy.png), the worst logs per metric, fixed against
float (when both ran), pooled residuals and effects (grip fleet analyze's
tables), and, with --baseline, regressions against an earlier run's results
folder over the same logs: per (log, arithmetic) and metric, a change
worse than the metric's tolerance (absolute, or relative to the baseline
value, whichever is larger) is a regression, a change better by as much an
improvement; a log ok before and an error now is a regression too.
regressions.csv lists them all. --fail-on-regression: exit status 1 if
there is one.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

from grip_tools.fleet import analyze, store

# metric, direction (+1: lower is better, -1: higher is better), absolute and relative tolerance, label
METRICS = (
    ("acc_beta_rms_deg", +1, 0.05, 0.10, "beta RMS [deg]"),
    ("acc_beta_max_deg", +1, 0.1, 0.10, "beta max [deg]"),
    ("acc_mu_err_1s_lim", +1, 0.02, 0.10, "|mu err| 1 s after the limit [-]"),
    ("acc_mu_err_1s", +1, 0.02, 0.10, "|mu err| 1 s after 50 % [-]"),
    ("acc_mu_within_0p1_pct_lim", -1, 2.0, 0.0, "mu within 0.1 after the limit [%]"),
    ("acc_fy_front_rms_pct", +1, 1.0, 0.10, "Fy front RMS [% peak]"),
    ("acc_fy_rear_rms_pct", +1, 1.0, 0.10, "Fy rear RMS [% peak]"),
    ("yaw_resid_rms", +1, 0.002, 0.10, "yaw-rate residual RMS [rad/s]"),
    ("ay_resid_rms", +1, 0.05, 0.10, "ay residual RMS [m/s^2]"),
    ("flag_model_misfit_share", +1, 0.02, 0.0, "model-misfit share"),
    ("valid_beta_share", -1, 0.02, 0.0, "beta valid share"),
    ("valid_mu_share", -1, 0.02, 0.0, "mu valid share"),
)
DIST = (("acc_beta_rms_deg", "beta RMS error [deg]"), ("acc_mu_err_1s_lim", "|mu error| 1 s after the limit"),
        ("flag_model_misfit_share", "model-misfit share of steps"), ("valid_beta_share", "beta valid share"),
        ("yaw_resid_rms", "yaw-rate residual RMS [rad/s]"), ("mu_p50", "median mu estimate (mu valid)"))
WORST = (("acc_beta_rms_deg", "beta RMS [deg]"), ("acc_mu_err_1s_lim", "|mu err| 1 s after the limit"),
         ("flag_model_misfit_share", "model-misfit share"), ("yaw_resid_rms", "yaw-rate residual RMS [rad/s]"))
GROUP_METRICS = ("acc_beta_rms_deg", "acc_mu_err_1s_lim", "acc_mu_within_0p1_pct_lim", "acc_fy_front_rms_pct",
                 "flag_model_misfit_share")


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _num(df, col):
    return df[col].astype(float) if col in df.columns else None


def distributions_png(ok, path):
    plt = _plt()
    fig, ax = plt.subplots(2, 3, figsize=(13, 6.5))
    for a, (col, label) in zip(ax.ravel(), DIST):
        x = _num(ok, col)
        x = x[np.isfinite(x)] if x is not None else []
        if len(x):
            a.hist(x, bins=min(40, max(5, int(math.sqrt(len(x))))), color="tab:blue", alpha=0.8)
            a.axvline(float(np.median(x)), color="k", ls="--", lw=1, label=f"median {np.median(x):.3g}")
            a.legend(fontsize=7)
        else:
            a.text(0.5, 0.5, "no data", ha="center", va="center", transform=a.transAxes)
        a.set_title(f"{label} (n={len(x)})", fontsize=9)
        a.set_ylabel("logs", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def accuracy_png(ok, path, keys=("manoeuvre", "surface", "vehicle")):
    plt = _plt()
    mets = (("acc_beta_rms_deg", "beta RMS [deg]"), ("acc_mu_err_1s_lim", "|mu err| 1 s after the limit"))
    fig, ax = plt.subplots(len(mets), len(keys), figsize=(4.5 * len(keys), 3.2 * len(mets)), squeeze=False)
    for j, key in enumerate(keys):
        for i, (col, label) in enumerate(mets):
            a = ax[i, j]
            if col not in ok.columns:
                continue
            groups, data = [], []
            for g, d in ok.groupby(ok[key].fillna("?"), sort=True):
                x = d[col].astype(float).to_numpy()
                x = x[np.isfinite(x)]
                if len(x):
                    groups.append(str(g))
                    data.append(x)
            if data:
                a.boxplot(data, showfliers=True)
                a.set_xticks(range(1, len(groups) + 1))
                a.set_xticklabels(groups, rotation=30, fontsize=7)
            a.set_title(f"{label} by {key}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def by_group(ok, key):
    rows = []
    for g, d in ok.groupby(ok[key].fillna("?"), sort=True):
        r = {key: g, "logs": len(d)}
        for m in GROUP_METRICS:
            if m in d.columns:
                x = d[m].astype(float)
                x = x[np.isfinite(x)]
                r[f"{m} median"] = float(np.median(x)) if len(x) else None
                r[f"{m} p90"] = float(np.percentile(x, 90)) if len(x) else None
        rows.append(r)
    import pandas as pd
    return pd.DataFrame(rows)


def regressions(cur, base):
    """Rows (log_id, arith, metric, base, now, change, kind) of changes beyond
    the tolerances, and a per-metric count table."""
    import pandas as pd
    m = cur.merge(base, on=["log_id", "arith"], how="outer", suffixes=("", "_base"), indicator=True)
    rows = []
    for r in m.to_dict("records"):
        key = {"log_id": r["log_id"], "arith": r["arith"]}
        if r["_merge"] == "left_only":
            rows.append({**key, "metric": "log", "kind": "new"})
            continue
        if r["_merge"] == "right_only":
            rows.append({**key, "metric": "log", "kind": "missing"})
            continue
        if r["status_base"] == "ok" and r["status"] != "ok":
            rows.append({**key, "metric": "status", "kind": "regression", "note": r.get("error")})
            continue
        if r["status_base"] != "ok" and r["status"] == "ok":
            rows.append({**key, "metric": "status", "kind": "improvement", "note": r.get("error_base")})
            continue
        for col, sign, atol, rtol, _ in METRICS:
            if col not in cur.columns or f"{col}_base" not in m.columns:
                continue
            a, b = r.get(f"{col}_base"), r.get(col)
            if a is None or b is None or not (np.isfinite(a) and np.isfinite(b)):
                continue
            tol = max(atol, rtol * abs(a))
            worse = sign * (b - a)
            if worse > tol:
                rows.append({**key, "metric": col, "base": a, "now": b, "change": b - a, "kind": "regression"})
            elif -worse > tol:
                rows.append({**key, "metric": col, "base": a, "now": b, "change": b - a, "kind": "improvement"})
    df = pd.DataFrame(rows, columns=["log_id", "arith", "metric", "base", "now", "change", "kind", "note"])
    counts = (df.groupby(["metric", "kind"]).size().unstack(fill_value=0).reset_index()
              if not df.empty else pd.DataFrame(columns=["metric"]))
    return df, counts


def _read_run(d):
    p = os.path.join(d, store.RUN)
    if os.path.exists(p):
        with open(p) as f:
            return json.load(f)
    return {}


def build(results, out, arith=None, baseline=None):
    """Writes report.md and the PNGs; returns (path, number of regressions)."""
    md_t = analyze._md_table
    logs_all, bands = analyze.load(results)
    arith = analyze.pick_arith(logs_all, arith)
    logs = logs_all[logs_all["arith"] == arith]
    ok = logs[logs["status"] == "ok"]
    run = _read_run(results)
    os.makedirs(out, exist_ok=True)
    md = [f"# Fleet report: {os.path.abspath(results)}\n"]
    md.append(f"grip {run.get('grip_version', '?')}, backend {run.get('backend', '?')}; "
              + ", ".join(f"{k} {v['sha256'][:12]}" for k, v in run.get("replay", {}).items())
              + f". Run of {run.get('started', '?')}: {run.get('logs', '?')} logs, {run.get('computed', '?')} "
              f"computed, {run.get('skipped', '?')} unchanged, {run.get('wall_s', '?')} s on "
              f"{run.get('workers', '?')} worker(s).\n")
    md.append(f"Arithmetic shown: **{arith}** ({', '.join(sorted(logs_all['arith'].unique()))} in the results). "
              f"{len(logs)} logs: {len(ok)} ok, {len(logs) - len(ok)} errors; "
              f"{int(ok['has_truth'].sum()) if len(ok) else 0} with a truth; "
              f"{float(ok['duration_s'].sum()) / 3600 if len(ok) else 0:.2f} h of driving, "
              f"{int(ok['steps'].sum()) if len(ok) else 0} estimator steps.\n")
    err = logs[logs["status"] != "ok"]
    if len(err):
        md.append("## Errors\n")
        md.append(md_t(err.groupby("stage").size().rename("logs").reset_index(), ["stage", "logs"]))
        md.append(md_t(err.sort_values("log_id"), ["log_id", "stage", "error"], limit=20))
    md.append("## Distributions\n\n![distributions](distributions.png)\n")
    distributions_png(ok, os.path.join(out, "distributions.png"))
    shares = [c for c in logs.columns if c.startswith(("valid_", "flag_")) and c.endswith("_share")]
    if len(ok):
        s = ok[shares].astype(float).describe(percentiles=[0.05, 0.5, 0.95]).T.reset_index()
        s = s.rename(columns={"index": "share of steps"})
        md.append("Validity and flag shares over the logs:\n")
        md.append(md_t(s[s["max"] > 0], ["share of steps", "mean", "5%", "50%", "95%", "max"],
                       {"mean": ".3f", "5%": ".3f", "50%": ".3f", "95%": ".3f", "max": ".3f"}))
    truth = ok[ok["has_truth"]] if len(ok) else ok
    if len(truth):
        md.append("## Accuracy (logs with a truth: est_eval's metrics)\n\n![accuracy](accuracy.png)\n")
        accuracy_png(truth, os.path.join(out, "accuracy.png"))
        for key in ("manoeuvre", "surface", "vehicle"):
            g = by_group(truth, key)
            md.append(f"By {key}:\n")
            md.append(md_t(g, list(g.columns)))
    md.append("## Worst logs\n")
    for col, label in WORST:
        if col in ok.columns and (ok[col].astype(float) > 0).any():
            w = ok[ok[col].astype(float) > 0].sort_values([col, "log_id"], ascending=[False, True])
            cols = ["log_id", col] + [c for c in ("manoeuvre", "surface", "vehicle") if c in w.columns]
            md.append(f"{label}:\n")
            md.append(md_t(w, cols, limit=10))
    if "dev_beta_max_rad" in logs_all.columns and logs_all["dev_beta_max_rad"].notna().any():
        fx = logs_all[(logs_all["arith"] == "fixed") & (logs_all["status"] == "ok")]
        md.append("## Fixed against float\n")
        r = fx["fixed_float_ratio"].astype(float)
        r = r[np.isfinite(r)]
        md.append(f"{len(fx)} logs in both: max |beta fixed - float| median "
                  f"{fx['dev_beta_max_rad'].median():.3g} rad, max {fx['dev_beta_max_rad'].max():.3g} rad; "
                  f"max |mu fixed - float| median {fx['dev_mu_max'].median():.3g}, max {fx['dev_mu_max'].max():.3g}. "
                  + (f"est_eval's fixed/float error ratio over {len(r)} logs with a truth: median {np.median(r):.3f}, "
                     f"max {np.max(r):.3f}, {int((r > 1.5).sum())} above 1.5.\n" if len(r) else "\n"))
    res, eff, eff_v, check, _, _ = analyze.analyse(results, arith)
    if not res.empty:
        md.append("## Residuals pooled by speed band (all vehicles)\n")
        band = res[res["grouping"] == "band"]
        md.append(md_t(band, ["quantity", "key", "logs", "n", "mean", "std", "rms", "max"]))
        md.append("(by vehicle and surface: `grip fleet analyze`)\n")
    if not eff.empty:
        md.append("## Effects across logs\n")
        md.append(md_t(eff, ["effect", "logs", "accepted_share", "accepted_lo95", "accepted_hi95", "first_share"],
                       {"accepted_share": ".1%", "accepted_lo95": ".1%", "accepted_hi95": ".1%",
                        "first_share": ".1%"}))
    n_reg = 0
    if baseline:
        b_all, _ = analyze.load(baseline)
        b = b_all[b_all["arith"] == arith]
        brun = _read_run(baseline)
        md.append(f"## Regressions against {os.path.abspath(baseline)}\n")
        md.append(f"Baseline: grip {brun.get('grip_version', '?')}, "
                  + ", ".join(f"{k} {v['sha256'][:12]}" for k, v in brun.get("replay", {}).items())
                  + f", {len(b)} logs. Tolerances: "
                  + "; ".join(f"{c} {atol:g}" + (f" or {rtol:.0%}" if rtol else "") for c, _, atol, rtol, _ in METRICS)
                  + ".\n")
        df, counts = regressions(logs, b)
        df.to_csv(os.path.join(out, "regressions.csv"), index=False)
        n_reg = int((df["kind"] == "regression").sum()) if not df.empty else 0
        md.append(f"**{n_reg} regressions**, {int((df['kind'] == 'improvement').sum()) if not df.empty else 0} "
                  f"improvements (regressions.csv).\n")
        if not counts.empty:
            md.append(md_t(counts, list(counts.columns)))
            reg = df[df["kind"] == "regression"].copy()
            if len(reg):
                reg["abs_change"] = reg["change"].abs()
                md.append("Largest regressions:\n")
                md.append(md_t(reg.sort_values(["abs_change", "log_id"], ascending=[False, True]),
                               ["log_id", "metric", "base", "now", "change", "note"], limit=20))
    path = os.path.join(out, "report.md")
    with open(path, "w") as f:
        f.write("\n".join(md))
    return path, n_reg


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip fleet report", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="a grip fleet run results folder")
    ap.add_argument("--baseline", help="an earlier run's results folder (same logs)")
    ap.add_argument("--arith", choices=("float", "fixed"), default=None, help="default: float if present")
    ap.add_argument("--out", default=None, help="default RESULTS/report")
    ap.add_argument("--fail-on-regression", action="store_true")
    a = ap.parse_args(argv)
    out = a.out or os.path.join(a.results, "report")
    path, n_reg = build(a.results, out, a.arith, a.baseline)
    print(f"grip fleet report: {path}" + (f" ({n_reg} regressions)" if a.baseline else ""), file=sys.stderr)
    return 1 if (a.fail_on_regression and n_reg) else 0
