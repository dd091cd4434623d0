"""Report: Markdown + PNG figures, and the updated parameter set (JSON)."""
import json
import os

import numpy as np

from grip_tools.loop import attribution


# ESC inputs the vehicle-level outputs are measured by (grip_calib input index)
CALIB_OF_OUTPUT = {"r": 5, "ay": 7}
# inputs that drive the vehicle models (delayed when the outputs lag them)
CALIB_MODEL_INPUTS = (0, 1, 2, 3, 4, 6, 8)


def onboard_config(name, params, model, dt=None):
    """The vehicle-level effects as onboard settings (docs/calibration.md,
    docs/estimator.md): {"grip_est_config": {...}} with the estimator's
    aero / road-plane fields, or {"grip_calib_config": {offset, gain, delay,
    inputs}} for the sensor effects, SI units, arrays over the GRIP_CALIB_N
    inputs. A value outside the onboard range is still written, with
    "representable": false and the reason. {} for effects that have no
    vehicle-level onboard setting here (tyre-level sensor effects: their
    outputs are not ESC inputs)."""
    from grip_tools.reference import calib as calib_ref
    kind = getattr(model, "kind", "")
    if kind != "vehicle":
        return {}
    if name == "road_bank" and "tan_bank" in params:
        tb, tg = float(params["tan_bank"]), float(params["tan_grade"])
        ok = abs(tb) <= 0.5 and abs(tg) <= 0.5
        return {"grip_est_config": {"tan_bank": tb, "tan_grade": tg,
                                    "note": "earth-fixed plane at the heading of grip_est_init / grip_est_reset, as the tool's"},
                "representable": ok}
    if name == "aero_load" and hasattr(model, "v"):
        v = model.v
        cla = float(np.mean(v.cla)) + float(params["cla_add_m2"])
        return {"grip_est_config": {"cla": cla, "aero_front": float(v.aero_balance_front),
                                    "air_density": float(v.rho)},
                "representable": bool(0.0 <= cla <= 20.0)}
    if name not in ("sensor_bias", "sensor_scale", "sensor_delay"):
        return {}
    cal = calib_ref.identity()
    why = []
    if name in ("sensor_bias", "sensor_scale"):
        for o, x in params.items():
            o = o.split("_")[-1] if o not in CALIB_OF_OUTPUT else o
            if o not in CALIB_OF_OUTPUT:
                continue
            i = CALIB_OF_OUTPUT[o]
            if name == "sensor_bias":
                cal["offset"][i] = float(x)        # sensor reads true + b
            else:
                cal["gain"][i] = 1.0 / (1.0 + float(x))   # sensor reads (1 + s) true
    else:
        d = float(params["delay_s"])
        steps = int(round(abs(d) / dt)) if dt else 0
        # outputs lag the model by d > 0: delay the model's inputs; d < 0: the outputs
        for i in (CALIB_MODEL_INPUTS if d > 0 else CALIB_OF_OUTPUT.values()):
            cal["delay"][i] = steps
        if steps > calib_ref.DELAY_MAX:
            why.append(f"delay {steps} steps > GRIP_CALIB_DELAY_MAX {calib_ref.DELAY_MAX}")
    try:
        calib_ref.check(cal)
    except ValueError as e:
        why.append(str(e))
    out = {"grip_calib_config": dict(cal, inputs=list(calib_ref.NAMES)), "representable": not why}
    if why:
        out["not_representable"] = "; ".join(why)
    return out


def grammar_update(effect, params, model):
    """update.json entries of a grammar candidate: "grammar" (target, driver,
    the states' source normalisation u_ref, what each parameter is) for
    `grip analyze apply`, and "tir_update" when the change is a .tir value
    (a scaling factor with a constant driver)."""
    from grip_tools.loop import grammar
    sp = effect.spec
    g = {"target": sp.target.name, "driver": sp.driver.name, "description": sp.description(),
         "modulation": "m_j = sum_c theta_jc g_c (module grip_tools.loop.grammar)"}
    if isinstance(sp.driver, grammar.StateDriver) and effect.u_ref:
        g["u_ref"] = {sp.driver.source: float(effect.u_ref[sp.driver.source])}
        g["state"] = ("x_i = x_{i-1} + (1 - exp(-dt/tau)) (u_i/u_ref - x_{i-1}), x_0 = 0, tau = tau_heat_s "
                      "while u_i/u_ref > x_{i-1}, else tau_rec_s")
    upd = {"grammar": g}
    P = getattr(model, "params", None)
    if P is not None and sp.driver.name == "const" and isinstance(sp.target, grammar.ScaleTarget):
        vals = list(params.values())
        tir = {}
        for (_, lams), th in zip(sp.target.groups, vals):
            for lam in lams:
                tir[lam.upper()] = float(P.get(lam, 1.0)) * max(1.0 + float(th), grammar.LAMBDA_MIN)
        upd["tir_update"] = tir
    return upd


def effect_update(name, params, model, dt=None):
    """Where the fitted parameters go onboard (JSON-able): .tir keys for
    MF coefficients (load sensitivity PDY2/PDX2, LMUV, camber PKY6/PVY3,
    pressure PPX1/PPY1/PPX3/PPY3), grip_relax_params, grip_mf_thermal_params + the LMU/LK
    temperature scaling; for the vehicle-level effects `onboard_config`
    (grip_est_config / grip_calib_config values)."""
    upd = {}
    oc = onboard_config(name, params, model, dt)
    if oc:
        upd["onboard_config"] = oc
    P = getattr(model, "params", None)
    if name == "load_sensitivity" and P is not None:
        upd["tir_update"] = {"PDY2": P["pdy2"] + params["c_dfz"] * P["pdy1"],
                             "PDX2": P["pdx2"] + params["c_dfz"] * P["pdx1"]}
    if name in ("camber", "inflation_pressure") and P is not None:
        from grip_tools.loop.effects import Camber, Pressure
        e = Camber() if name == "camber" else Pressure()
        x = [params[e.pnames[0]]]
        upd["tir_update"] = {k.upper(): v for k, v in e.coefficients(P, x).items()}
    if name == "slip_velocity_friction":
        upd["tir_update"] = {"LMUV": params["lmuv"]}
    if name == "relaxation":
        upd["grip_relax_params"] = {"sigma_alpha": params["sigma_m"], "sigma_kappa": params["sigma_m"]}
    if name == "thermal" and P is not None:
        from grip_tools.loop.effects import Thermal, thermal_params_from_mf
        th = thermal_params_from_mf(P, params["a_mu_per_K"], params["b_k_per_K"], params["kappa_per_s"],
                                    Thermal.W, Thermal.T0)
        upd["grip_mf_thermal_params"] = th.as_dict()
        upd["mf_scaling"] = {"LMUX, LMUY": f"x (1 + {params['a_mu_per_K']:.6g} (T - {Thermal.T0}))",
                             "LKX, LKY": f"x (1 + {params['b_k_per_K']:.6g} (T - {Thermal.T0}))"}
    return upd


def write_tir(base_path, updates, out_path, note="grip_tools analyze"):
    """Copy of the .tir file base_path with KEY = value lines replaced (or
    added to [SCALING_COEFFICIENTS] when absent); line endings kept; the
    changed lines say they were written by `note`."""
    with open(base_path, newline="") as f:
        lines = f.readlines()
    todo = {k.upper(): v for k, v in updates.items()}
    out = []
    for ln in lines:
        key = ln.split("=", 1)[0].strip().upper() if "=" in ln and not ln.lstrip().startswith(("$", "!")) else None
        if key in todo:
            eol = "\r\n" if ln.endswith("\r\n") else "\n"
            out.append(f"{key:<26s}= {float(todo.pop(key))!r:<18} $ updated by {note}{eol}")
        else:
            out.append(ln)
    if todo:
        idx = next(i for i, ln in enumerate(out) if ln.strip().upper().startswith("[SCALING_COEFFICIENTS]"))
        eol = "\r\n" if out[idx].endswith("\r\n") else "\n"
        for k, v in todo.items():
            out.insert(idx + 1, f"{k:<26s}= {float(v)!r:<18} $ added by {note}{eol}")
    with open(out_path, "w", newline="") as f:
        f.writelines(out)
    return out_path


def updated_params(res, model, ds=None):
    """JSON-able update: the chosen effect, its parameters, and where they go;
    without one, the non-parametric correction when it was useful."""
    from grip_tools.loop import grammar
    if res.chosen is None:
        upd = {"effect": None, "base": model.name}
        k = getattr(res, "correction", None)
        if k is not None and k.useful:
            upd["correction"] = k.as_dict()
        return upd
    c = res.chosen
    upd = {"effect": c.name, "params": c.params, "onboard": c.onboard, "base": model.name}
    if c.description:
        upd["description"] = c.description
    dt = float(np.median(np.diff(ds.t))) if ds is not None and len(ds.t) > 1 else None
    e = getattr(res, "effect", None)
    if isinstance(e, grammar.GrammarEffect):
        upd.update(grammar_update(e, c.params, model))
    upd.update(effect_update(c.name, c.params, model, dt))
    return upd


def figures(res, ds, outdir, prefix):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    files = []
    from grip_tools.loop import candidates
    cands = candidates.derived(ds, res.base_pred)
    for o in ds.outputs:
        r0 = ds.ch[o] - res.base_pred[o]
        top = [n for n, _, _ in res.dependence[o][:3]]
        fig, axs = plt.subplots(1, len(top) + 1, figsize=(4 * (len(top) + 1), 3.4))
        axs[0].plot(ds.t, r0, lw=0.5, label="before")
        if res.chosen_pred is not None:
            axs[0].plot(ds.t, ds.ch[o] - res.chosen_pred[o], lw=0.5, label=f"after ({res.chosen.name})")
        axs[0].set_xlabel("t [s]")
        axs[0].set_ylabel(f"residual {o} [{ds.units.get(o, '')}]")
        axs[0].legend(fontsize=7)
        for ax, n in zip(axs[1:], top):
            ax.plot(cands[n], r0, ",", alpha=0.5)
            ax.set_xlabel(n)
        fig.tight_layout()
        path = os.path.join(outdir, f"{prefix}residual_{o}.png")
        fig.savefig(path, dpi=90)
        plt.close(fig)
        files.append(path)
    return files


def write(res, ds, model, outdir, title="Residual analysis", prefix=""):
    os.makedirs(outdir, exist_ok=True)
    figs = figures(res, ds, outdir, prefix)
    upd = updated_params(res, model, ds)
    tir_path = getattr(model, "tir_path", None)
    if "tir_update" in upd and tir_path:
        upd["tir_file"] = write_tir(tir_path, upd["tir_update"], os.path.join(outdir, f"{prefix}updated.tir"))
    with open(os.path.join(outdir, f"{prefix}update.json"), "w") as f:
        json.dump(upd, f, indent=2, default=float)
    L = [f"# {title}", "", f"Data: {ds.meta.get('source', '?')}, {len(ds)} samples, "
         f"{ds.t[-1] - ds.t[0]:.1f} s; outputs {', '.join(ds.outputs)}; model {model.name}.", "",
         f"**Verdict:** {attribution.verdict(res)}", "",
         "## Base model", "",
         "| output | residual RMS | explained (R2) | likely cause of a misfit |", "|---|---|---|---|"]
    for f in (res.sanity.findings if res.sanity is not None else []):
        L.append(f"| {f.output} | {f.rms:.4g} | {f.r2:.4f} | "
                 + (f"{f.cause}: {f.detail} (then RMS {f.rms_cause:.4g})" if f.cause else "-") + " |")
    L += ["",
         f"Hold-out {res.holdout}: " + ("fit on the first part of the record, judged on the last share."
                                        if res.holdout.startswith("forward") else
                                        "contiguous time blocks, fit on the even ones, judged on the odd ones.")
         + ("" if len(res.cross) < 2 else " The chosen effect re-fitted on the other split(s): "
            + ", ".join(f"{k} score {v:.3f}" for k, v in res.cross.items() if k != res.holdout) + "."), "",
         "| output | held-out RMS before | after | max before | after |", "|---|---|---|---|---|"]
    for o in ds.outputs:
        a = res.chosen.ho_rms[o] if res.chosen else res.base_ho_rms[o]
        m = res.chosen.ho_max[o] if res.chosen else res.base_ho_max[o]
        L.append(f"| {o} | {res.base_ho_rms[o]:.4g} | {a:.4g} | {res.base_ho_max[o]:.4g} | {m:.4g} |")
    if res.search:
        sr = res.search
        L += ["", "## Search", "",
              f"Grammar: {sr.get('pairs', 0)} (target x driver) pairs screened with a linear fit "
              f"({sr.get('wall_screen_s', 0.0):.1f} s), the best {sr.get('refined', 0)} refined with the full "
              f"model ({sr.get('wall_refine_s', 0.0):.1f} s), named forms {sr.get('wall_named_s', 0.0):.1f} s; "
              f"analysis {sr.get('wall_s', 0.0):.1f} s wall. Criterion: held-out BIC, IC = N_eff ln(S/S_0) + k ln N_eff, "
              f"N_eff = {sr.get('n_eff', 0.0):.0f}; accepted when IC < 0 and the score is at most "
              f"{1 - attribution.MIN_GAIN:.2f}."
              + (f" The best {len(sr['second']['score'])} accepted re-fitted and scored on "
                 f"{sr['second']['split']} (N_eff = {sr['second']['n_eff']:.0f}) and chosen on the sum of "
                 "both ICs." if sr.get("second") else ""), "",
              "Best screened pairs (linear held-out score): "
              + ", ".join(f"{n} {s:.3f}" for n, s, _ in sr.get("screen_top", [])[:12]) + "."]
        L += ["", "## Ranking (held-out BIC relative to the base model; score 1.0 = baseline)", "",
              "| effect | kind | k | score | IC | second split: score, IC | accepted | parameters | what |",
              "|---|---|---|---|---|---|---|---|---|"]
        for c in res.ranked:
            two = "-" if c.score2 != c.score2 else f"{c.score2:.3f}, {c.ic2:.1f}"
            L.append(f"| {c.name} | {c.kind} | {c.k} | {c.score:.3f} | {c.ic:.1f} | {two} | "
                     f"{'yes' if c.accepted else 'no'} | "
                     + ", ".join(f"{k}={v:.4g}" for k, v in c.params.items())
                     + f" | {c.description or c.onboard} |")
    else:
        L += ["", "## Ranking (penalised held-out score, 1.0 = baseline)", "",
              "| effect | k | score | penalised | accepted | parameters | onboard |", "|---|---|---|---|---|---|---|"]
        for c in res.ranked:
            L.append(f"| {c.name} | {c.k} | {c.score:.3f} | {c.penalised:.3f} | {'yes' if c.accepted else 'no'} | "
                     + ", ".join(f"{k}={v:.4g}" for k, v in c.params.items()) + f" | {c.onboard} |")
    for n, why in res.skipped:
        L.append(f"| {n} | - | - | - | - | - | skipped | {why} | |" if res.search else
                 f"| {n} | - | - | - | skipped | {why} | |")
    k = getattr(res, "correction", None)
    if k is not None:
        L += ["", "## Non-parametric correction (no physical effect identified)", "",
              k.summary() + ".", "",
              "It is a smooth function of the two channels most correlated with the residual, fitted to the "
              "residual (loop/correction.py); it names no effect and does not extrapolate beyond the "
              "training range of its channels." + (" update.json carries it." if k.useful else "")]
    L += ["", "## Evidence: residual dependence (baseline residual)", ""]
    for o in ds.outputs:
        L.append(f"- {o}: lag-1 autocorrelation {res.structure[o]:.2f}; strongest: "
                 + ", ".join(f"{n} (r={r:+.2f}, rank r={rr:+.2f})" for n, r, rr in res.dependence[o][:6]))
    L += [""] + [f"![{os.path.basename(p)}]({os.path.basename(p)})" for p in figs]
    path = os.path.join(outdir, f"{prefix}report.md")
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")
    return path, upd
