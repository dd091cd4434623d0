"""Golden vectors of the Magic Formula reference (grip_tools.reference.mf) for every
shared .tir file, and the compiled-in parameter sets of those files.

Writes into outdir (build/golden):
  mf_<name>.txt  columns: kappa alpha gamma fz p vx fx0 fy0 mz0 fx fy mz
                 SI units, ISO-W, MF-Tyre forms, every tyre mounted on the
                 left (a RIGHT file is mirrored, as the emitted struct says),
                 so the golden vectors run the mirroring path too
  mf_ext_<name>.txt  the same input rows with the combined-slip outputs of
                 the other forms and channels: EXT_COLUMNS (mz_svyk_camber =
                 Mz with GRIP_MF_OPT_MZ52_SVYK_CAMBER, then MFeval's other
                 channels mf.EXT_NAMES in SI units; nan where a channel is not
                 available: its parameters are missing or it has no solution)
  mf_mode_<name>.txt  the use modes (docs/magic-formula.md section 10):
                 MODE_COLUMNS, mode = the GRIP_MF_OPT_* bits of the row
                 (64 turn slip, 128 no limits = MFeval 2xx, 256 the turn
                 slip's camber form), phit [1/m], omega [rad/s] (0:
                 estimated), then fx fy mz and the channels of mf_ext_;
                 rows without turn slip for every file (2xx, and 1xx with a
                 given omega), turn-slip rows for the files that have the
                 [TURNSLIP_COEFFICIENTS] (mf.turn_slip_usable)
  mf_params.c    static const grip_mf_params grip_tire_<name> = {...} per
                 file (tools/grip_tools/reference/tir.py emitter) and the table
                 grip_test_tires[] / grip_test_tire_count (tests/support/mf_params.h)

Rows per file (about 3000): pure kappa and alpha sweeps at five loads, an
alpha sweep at three cambers, a camber sweep, a combined kappa x alpha grid at
two loads and two cambers, a pressure sweep (MF 6.x), uniform random points
over the whole valid range (fixed seed per file) and low-speed rows with
0 <= vx <= 1.5 VXLOW (vx = 0 included). The valid range is the file's
*_RANGE sections: Fz FZMIN..FZMAX (0.1..2 FNOMIN when absent), kappa
KPUMIN..KPUMAX, alpha ALPMIN..ALPMAX, gamma CAMMIN..CAMMAX, p PRESMIN..PRESMAX
(0.8..1.2 NOMPRES when absent), each intersected with the library's input
domain (GRIP_MF_* in include/grip/grip_mf.h: |kappa| <= 1.5, |alpha| <= pi/2,
|gamma| <= 30 deg, Fz <= 4 FNOMIN, 0.5..2 NOMPRES), so that no golden row is
clamped by the C model. vx = LONGVL except in the low-speed rows. Every
input is a float32 value (representable): what a float build is given, so
that the rows measure the model rather than the rounding of its inputs.
Any .tir that fails validation makes the generation fail (TirError).
"""
import glob
import os
import re
import sys
import zlib

import numpy as np

from grip_tools.reference import mf, tir
from grip_tools.golden.all import write_if_changed
from grip_tools.golden.io import header

SEED = 20261123
COLUMNS = ["kappa", "alpha", "gamma", "fz", "p", "vx", "fx0", "fy0", "mz0", "fx", "fy", "mz"]
EXT_COLUMNS = COLUMNS[:6] + ["fx", "fy", "mz", "mz_svyk_camber"] + list(mf.EXT_NAMES)
MODE_COLUMNS = ["mode"] + COLUMNS[:6] + ["phit", "omega", "fx", "fy", "mz"] + list(mf.EXT_NAMES)
OPT_TURN_SLIP, OPT_NO_LIMITS, OPT_TS_CAMBER = 1 << 6, 1 << 7, 1 << 8   # include/grip/grip_mf.h
PHIT_MAX = 100.0     # GRIP_MF_PHIT_MAX: the rows stay inside the library's domain
SUBDIRS = ("chrono-tir", "mfeval-tir")


def shared_data_dir():
    """The test data folder: $GRIP_SHARED_DATA, else the copy bundled in tests/data."""
    env = os.environ.get("GRIP_SHARED_DATA")
    if env:
        return os.path.abspath(env)
    return os.path.join(tir.REPO_ROOT, "tests", "data")


def tir_files(root=None):
    root = root or shared_data_dir()
    files = []
    for sub in SUBDIRS:
        files += sorted(glob.glob(os.path.join(root, sub, "*.tir")))
    if not files:
        raise FileNotFoundError(f"no .tir files under {root}/{{{','.join(SUBDIRS)}}} "
                                "(set GRIP_SHARED_DATA)")
    return files


def tire_name(path):
    """C-identifier name: the file stem, leading size tokens dropped
    (335_65R22_5_G275MSA_60psi -> G275MSA_60psi)."""
    stem = os.path.splitext(os.path.basename(path))[0]
    tokens = [t for t in "".join(ch if ch.isalnum() else "_" for ch in stem).split("_") if t]
    while len(tokens) > 1 and not tokens[0][0].isalpha():
        tokens.pop(0)
    name = "_".join(tokens)
    if not name or not name[0].isalpha():
        name = "t_" + name
    return name


# The library's input domain (include/grip/grip_mf.h, GRIP_MF_*): golden
# rows stay inside it, so that the C side never clamps (a file's *_RANGE can
# be wider, e.g. PacejkaBook_Defaults PRESMIN = 10 kPa, ALPMAX = 1.5708).
DOMAIN_DEFAULTS = {"KAPPA_MAX": 1.5, "ALPHA_MAX": 1.5707963, "GAMMA_MAX": 0.5235988,
                   "FZ_MAX_REL": 4.0, "DPI_MIN": -0.5, "DPI_MAX": 1.0}


def lib_domain(header=os.path.join(tir.REPO_ROOT, "include", "grip", "grip_mf.h")):
    dom = dict(DOMAIN_DEFAULTS)
    try:
        with open(header) as f:
            text = f.read()
    except OSError:
        return dom
    for key in dom:
        m = re.search(r"#define\s+GRIP_MF_" + key + r"\s+\(?\s*([-+0-9.eE]+)\s*\)?", text)
        if m:
            dom[key] = float(m.group(1))
    return dom


def _clip(lo, hi, dlo, dhi):
    lo, hi = max(lo, dlo), min(hi, dhi)
    if not lo < hi:
        raise ValueError(f"empty range after intersecting with the library domain [{dlo}, {dhi}]")
    return lo, hi


def ranges(P):
    """Input ranges of the golden rows (SI): the file's *_RANGE values
    (defaults when absent) intersected with the library's input domain."""
    D = lib_domain()
    fnom = P["fnomin"]
    if P["fzmax"] > 0:
        fz = (P["fzmin"], P["fzmax"])
    else:
        fz = (0.1 * fnom, 2.0 * fnom)
    fz = _clip(*fz, 0.0, D["FZ_MAX_REL"] * fnom)
    pnom = P["inflpres"] if P["inflpres"] > 0 else P["nompres"]
    pr = None
    if P["fittyp"] in mf.MF6:
        nom = P["nompres"]
        pr = (P["presmin"], P["presmax"]) if P["presmax"] > 0 else (0.8 * nom, 1.2 * nom)
        pr = _clip(*pr, (1.0 + D["DPI_MIN"]) * nom, (1.0 + D["DPI_MAX"]) * nom)
    return dict(fz=fz,
                kappa=_clip(P["kpumin"], P["kpumax"], -D["KAPPA_MAX"], D["KAPPA_MAX"]),
                alpha=_clip(P["alpmin"], P["alpmax"], -D["ALPHA_MAX"], D["ALPHA_MAX"]),
                gamma=_clip(P["cammin"], P["cammax"], -D["GAMMA_MAX"], D["GAMMA_MAX"]),
                p=pr, pnom=pnom)


def inputs(P, rng):
    """The input rows (dict of equal-length arrays)."""
    R = ranges(P)
    fz_lo, fz_hi = R["fz"]
    fz_lo_sweep = fz_lo if fz_lo > 0 else 0.05 * P["fnomin"]
    loads = np.linspace(fz_lo_sweep, fz_hi, 5)
    fmid = min(max(P["fnomin"], fz_lo_sweep), fz_hi)
    klo, khi = R["kappa"]
    alo, ahi = R["alpha"]
    glo, ghi = R["gamma"]
    rows = []

    def add(k, a, g, f, p=None, v=None):
        k, a, g, f = np.broadcast_arrays(*(np.asarray(x, dtype=float).ravel() for x in (k, a, g, f)))
        n = k.size
        rows.append(dict(kappa=k, alpha=a, gamma=g, fz=f,
                         p=np.full(n, R["pnom"]) if p is None else np.broadcast_to(p, (n,)).astype(float),
                         vx=np.full(n, P["longvl"]) if v is None else np.broadcast_to(v, (n,)).astype(float)))

    ks = np.linspace(klo, khi, 101)
    als = np.linspace(alo, ahi, 101)
    for f in loads:                                   # pure sweeps
        add(ks, 0.0, 0.0, f)
        add(0.0, als, 0.0, f)
    for g in (glo, 0.5 * (glo + ghi), ghi):           # camber
        add(0.0, np.linspace(alo, ahi, 41), g, fmid)
    gs = np.linspace(glo, ghi, 41)
    add(0.0, 0.0, gs, fmid)
    add(0.25 * khi if khi > 0 else 0.25 * klo, 0.25 * ahi, gs, fmid)
    K, A = np.meshgrid(np.linspace(klo, khi, 17), np.linspace(alo, ahi, 17), indexing="ij")
    for f in (loads[1], loads[3]):                    # combined grid
        for g in (0.0, 0.5 * ghi):
            add(K, A, g, f)
    if R["p"] is not None:                            # pressure
        for p in np.linspace(R["p"][0], R["p"][1], 5):
            add(np.linspace(klo, khi, 21), 0.0, 0.0, fmid, p)
            add(0.0, np.linspace(alo, ahi, 21), 0.0, fmid, p)
    n = 600                                           # random over the range
    add(rng.uniform(klo, khi, n), rng.uniform(alo, ahi, n), rng.uniform(glo, ghi, n),
        rng.uniform(fz_lo, fz_hi, n),
        rng.uniform(*R["p"], n) if R["p"] is not None else None)
    n = 100                                           # low speed
    vx = rng.uniform(0.0, 1.5 * P["vxlow"], n)
    vx[:10] = 0.0
    vx[10:20] = np.linspace(0.05, 1.0, 10) * P["vxlow"]
    add(rng.uniform(klo, khi, n), rng.uniform(alo, ahi, n), rng.uniform(glo, ghi, n),
        rng.uniform(fz_lo_sweep, fz_hi, n), None, vx)
    x = {c: np.concatenate([r[c] for r in rows]) for c in COLUMNS[:6]}
    bounds = dict(R, fz=(fz_lo if fz_lo > 0 else 0.0, fz_hi), vx=(0.0, np.inf))
    return {c: representable(x[c], *(bounds[c] if bounds.get(c) is not None else (-np.inf, np.inf)))
            for c in COLUMNS[:6]}


def representable(x, lo, hi):
    """x rounded to the nearest float32 (the inputs a float build is given,
    so that the golden rows measure the model, not the rounding of its
    inputs: on FSAE_Defaults that rounding alone moves Fx by 2.7e-6 Fz), one
    step back towards x where rounding left the closed range [lo, hi]."""
    x = np.asarray(x, dtype=float)
    r = x.astype(np.float32)
    r64 = r.astype(float)            # compared in float64 (a float32 array would round lo and hi)
    above = (r64 > hi) & (x <= hi)
    below = (r64 < lo) & (x >= lo)
    r[above] = np.nextafter(r[above], np.float32(-np.inf))
    r[below] = np.nextafter(r[below], np.float32(np.inf))
    return r.astype(float)


def _ext_outputs(P, x, p):
    """The EXT_COLUMNS outputs on the input rows x."""
    alt = mf.evaluate(P, x["kappa"], x["alpha"], x["gamma"], x["fz"], p=p, vx=x["vx"],
                      mz52_svyk_camber=True)
    out = mf.evaluate_ext(P, x["kappa"], x["alpha"], x["gamma"], x["fz"], p=p, vx=x["vx"])
    out["mz_svyk_camber"] = alt["mz"]
    for k in ("fx", "fy", "mz", "mz_svyk_camber"):
        if not np.all(np.isfinite(out[k])):
            raise RuntimeError(f"non-finite {k} in the reference output")
    return out


def golden_texts(path, name, P):
    """(mf_<name>.txt, mf_ext_<name>.txt) texts."""
    seed = SEED + zlib.crc32(name.encode()) % 100000
    rng = np.random.default_rng(seed)
    x = inputs(P, rng)
    p = x["p"] if P["fittyp"] in mf.MF6 else None
    out = mf.evaluate(P, x["kappa"], x["alpha"], x["gamma"], x["fz"], p=p, vx=x["vx"])
    for k, v in out.items():
        if not np.all(np.isfinite(v)):
            raise RuntimeError(f"{path}: non-finite {k} in the reference output")
    ext = _ext_outputs(P, x, p)
    R = ranges(P)
    side = "RIGHT, mounted left -> mirrored" if P["tyreside"] == -1 else "LEFT/unknown, mounted left"
    hdr = header("grip_tools.golden.mf", mf, seed, COLUMNS, params={
        "tir": path,
        "name": name,
        "fittyp": P["fittyp"],
        "tyreside": side,
        "form": "mftyre (MF-Tyre forms)",
        "convention": "ISO-W, SI units (N, N m, rad, Pa, m/s); kappa > 0 driving",
        "fz range": f"{R['fz'][0]!r} .. {R['fz'][1]!r}",
        "kappa range": f"{R['kappa'][0]!r} .. {R['kappa'][1]!r}",
        "alpha range": f"{R['alpha'][0]!r} .. {R['alpha'][1]!r}",
        "gamma range": f"{R['gamma'][0]!r} .. {R['gamma'][1]!r}",
        "p": ("ignored (MF 5.2)" if R["p"] is None else f"{R['p'][0]!r} .. {R['p'][1]!r}"),
        "rows": x["kappa"].size,
    })
    cols = [x[c] for c in COLUMNS[:6]] + [out[c] for c in COLUMNS[6:]]
    body = np.column_stack(cols)
    lines = [" ".join(f"{v:.17g}" for v in row) for row in body]
    units = " ".join(f"{n}[{u}]" for n, u, _m, _s in mf.EXT_CHANNELS)
    ext_hdr = hdr.replace("# columns: " + " ".join(COLUMNS),
                          f"# param units: {units}\n# columns: " + " ".join(EXT_COLUMNS))
    ext_body = np.column_stack([x[c] for c in EXT_COLUMNS[:6]] + [ext[c] for c in EXT_COLUMNS[6:]])
    ext_lines = [" ".join(f"{v:.17g}" for v in row) for row in ext_body]
    return (hdr + "\n".join(lines) + "\n", ext_hdr + "\n".join(ext_lines) + "\n",
            mode_text(path, name, P, hdr))


def _mode_rows(P, x, rng):
    """The rows of mf_mode_<name>.txt: (mode, inputs with phit and omega)."""
    n = x["kappa"].size
    R0 = P["unloaded_radius"]
    blocks = []

    def take(idx, mode, phit=None, omega_frac=0.0):
        idx = np.asarray(idx)
        m = idx.size
        b = {c: x[c][idx].copy() for c in COLUMNS[:6]}
        b["mode"] = np.full(m, float(mode))
        b["phit"] = np.zeros(m) if phit is None else np.asarray(phit, dtype=float)
        # a given spin near free rolling on a share of the rows (0: estimated)
        om = (1.0 + b["kappa"]) * np.abs(b["vx"]) / R0 * rng.uniform(0.9, 1.1, m)
        b["omega"] = np.where(rng.uniform(0.0, 1.0, m) < omega_frac, om, 0.0)
        blocks.append(b)

    low = np.flatnonzero(x["vx"] != representable(P["longvl"], 0.0, np.inf))  # the low-speed rows
    every3 = np.arange(0, n, 3)
    # MFeval 2xx (no limits) on every file, and 1xx with a given omega
    take(np.union1d(every3, low), OPT_NO_LIMITS, omega_frac=0.3)
    take(rng.choice(n, 300, replace=False), 0, omega_frac=1.0)
    if mf.turn_slip_usable(P):
        R = ranges(P)
        glo, ghi = R["gamma"]
        fmid = min(max(P["fnomin"], R["fz"][0]), R["fz"][1])
        # phit sweeps at zero slip, two cambers, two loads: appended inputs
        sweep = np.linspace(-5.0, 5.0, 41)
        extra = []
        for f in (0.5 * fmid, fmid):
            for g in (0.0, 0.5 * ghi):
                for a in (0.0, 0.25 * R["alpha"][1]):
                    extra.append((sweep, a, g, f))
        base_n = n
        xs = {c: [x[c]] for c in COLUMNS[:6]}
        for ph, a, g, f in extra:
            m = ph.size
            xs["kappa"].append(np.zeros(m))
            xs["alpha"].append(np.full(m, a))
            xs["gamma"].append(np.full(m, g))
            xs["fz"].append(np.full(m, f))
            xs["p"].append(np.full(m, R["pnom"]))
            xs["vx"].append(np.full(m, P["longvl"]))
        for c in COLUMNS[:6]:
            x[c] = np.concatenate(xs[c])
        n = x["kappa"].size
        sweep_idx = np.arange(base_n, n)
        sweep_phit = np.tile(sweep, len(extra))
        # every base row with a random turn slip (a fifth at phit = 0: the
        # camber's spin alone; a tenth up to +-20 1/m), the sweeps
        ph = rng.uniform(-3.0, 3.0, base_n)
        ph[rng.uniform(0.0, 1.0, base_n) < 0.2] = 0.0
        big = rng.uniform(0.0, 1.0, base_n) < 0.1
        ph[big] = rng.uniform(-20.0, 20.0, int(big.sum()))
        take(np.arange(base_n), OPT_TURN_SLIP, ph, omega_frac=0.3)
        take(sweep_idx, OPT_TURN_SLIP, sweep_phit)
        sub = np.union1d(every3, low)
        take(sub, OPT_TURN_SLIP | OPT_NO_LIMITS, ph[sub], omega_frac=0.3)
        take(sub, OPT_TURN_SLIP | OPT_TS_CAMBER, ph[sub], omega_frac=0.3)
        take(sweep_idx, OPT_TURN_SLIP | OPT_TS_CAMBER, sweep_phit)
    rows = {c: np.concatenate([b[c] for b in blocks]) for c in MODE_COLUMNS[:9]}
    for c in MODE_COLUMNS[1:9]:      # the appended sweeps, phit and omega as well
        rows[c] = representable(rows[c], -np.inf, np.inf)
    if np.any(np.abs(rows["phit"]) > PHIT_MAX):
        raise RuntimeError("turn slip outside the library's domain")
    return rows


def mode_outputs(P, rows, p_used):
    """MODE_COLUMNS outputs of the rows (one reference call per mode)."""
    out = {c: np.full(rows["mode"].size, np.nan) for c in MODE_COLUMNS[9:]}
    for mode in np.unique(rows["mode"]):
        sel = rows["mode"] == mode
        m = int(mode)
        p = rows["p"][sel] if p_used else None
        o = mf.evaluate_ext(P, rows["kappa"][sel], rows["alpha"][sel], rows["gamma"][sel], rows["fz"][sel],
                            p=p, vx=rows["vx"][sel], limits=not (m & OPT_NO_LIMITS),
                            turn_slip=bool(m & OPT_TURN_SLIP), phit=rows["phit"][sel], omega=rows["omega"][sel],
                            ts_camber=bool(m & OPT_TS_CAMBER))
        for c in MODE_COLUMNS[9:]:
            out[c][sel] = o[c]
    for k in ("fx", "fy", "mz"):
        if not np.all(np.isfinite(out[k])):
            raise RuntimeError(f"non-finite {k} in the reference output (use modes)")
    return out


def mode_text(path, name, P, hdr):
    """mf_mode_<name>.txt, with the header of mf_<name>.txt."""
    seed = SEED + 7 + zlib.crc32(name.encode()) % 100000
    rng = np.random.default_rng(seed)
    x = inputs(P, rng)
    rows = _mode_rows(P, x, rng)
    out = mode_outputs(P, rows, P["fittyp"] in mf.MF6)
    units = " ".join(f"{n}[{u}]" for n, u, _m, _s in mf.EXT_CHANNELS)
    h = hdr.replace("# columns: " + " ".join(COLUMNS),
                    f"# param mode seed: {seed}\n"
                    f"# param modes: 0 = MFeval 111, {OPT_NO_LIMITS} = 211, {OPT_TURN_SLIP} = 112, "
                    f"{OPT_TURN_SLIP | OPT_NO_LIMITS} = 212, +{OPT_TS_CAMBER} = the turn slip's camber form\n"
                    f"# param units: phit[1/m] omega[rad/s] {units}\n"
                    "# columns: " + " ".join(MODE_COLUMNS))
    body = np.column_stack([rows[c] for c in MODE_COLUMNS[:9]] + [out[c] for c in MODE_COLUMNS[9:]])
    return h + "\n".join(" ".join(f"{v:.17g}" for v in row) for row in body) + "\n"


def _c_string(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def params_c(entries):
    parts = ["/* Generated by grip_tools.golden.mf (grip golden-all). Do not edit.\n"
             " * One grip_mf_params per shared .tir file, emitted by grip_tools.reference.tir. */\n",
             '#include "mf_params.h"\n']
    for name, path, P in entries:
        parts.append("\n" + tir.emit_definition(P, f"grip_tire_{name}", storage="static const"))
    parts.append("\nconst grip_test_tire grip_test_tires[] = {\n")
    for name, path, P in entries:
        parts.append(f"    {{ {_c_string(name)}, {_c_string(path)}, &grip_tire_{name}, "
                     f"{_c_string('mf_' + name + '.txt')} }},\n")
    parts.append("};\n")
    parts.append(f"const int grip_test_tire_count = {len(entries)};\n")
    parts.append("\nconst grip_mf_params *grip_test_tire_params(const char *name)\n{\n"
                 "    int k;\n"
                 "    for (k = 0; k < grip_test_tire_count; ++k) {\n"
                 "        const char *a = grip_test_tires[k].name, *b = name;\n"
                 "        while (*a != 0 && *a == *b) {\n"
                 "            ++a;\n"
                 "            ++b;\n"
                 "        }\n"
                 "        if (*a == 0 && *b == 0) {\n"
                 "            return grip_test_tires[k].params;\n"
                 "        }\n"
                 "    }\n"
                 "    return 0;\n}\n")
    return "".join(parts)


def _write_keep_stamp(path, text):
    """write_if_changed, ignoring the '# created:' header line."""
    if os.path.exists(path):
        with open(path) as f:
            old = f.read()
        strip = lambda t: [ln for ln in t.splitlines() if not ln.startswith("# created:")]
        if strip(old) == strip(text):
            return False
    write_if_changed(path, text)
    return True


def write_golden(outdir):
    os.makedirs(outdir, exist_ok=True)
    entries = []
    names = {}
    for path in tir_files():
        name = tire_name(path)
        if name in names:
            raise RuntimeError(f"{path}: name {name} already used by {names[name]}")
        names[name] = path
        P = tir.read_tir(path).params("left")     # TirError propagates: generation fails
        entries.append((name, path, P))
        main, ext, modes = golden_texts(path, name, P)
        _write_keep_stamp(os.path.join(outdir, f"mf_{name}.txt"), main)
        _write_keep_stamp(os.path.join(outdir, f"mf_ext_{name}.txt"), ext)
        _write_keep_stamp(os.path.join(outdir, f"mf_mode_{name}.txt"), modes)
    write_if_changed(os.path.join(outdir, "mf_params.c"), params_c(entries))
    print(f"golden_mf: {len(entries)} tyres -> {outdir}/mf_*.txt, mf_params.c", file=sys.stderr)
