"""Golden vectors of the brush-model family (tools/grip_tools/reference/brush.py).

Writes brush_fiala.txt, brush_brush.txt, brush_sakai.txt and
brush_neofiala.txt into the golden folder, and parameter files of set 0 and of
the defaults of each model (brush_params_<model>[_default].txt) for the C
reader's test. Each vector file:

  P id <struct fields in C order and C units>     a parameter set (values on
                                                  the QS/QL grid of their
                                                  field, so both C builds
                                                  hold exactly these values)
  V id <inputs> fx fy mz rh                       valid range (status GRIP_OK)
  C id <inputs> fx fy mz rh                       out of range: expected outputs
                                                  at the clamped inputs, status
                                                  GRIP_WARN_CLAMPED
Inputs lie on the fixed-point grids (QS for slip, angles, speeds; QL for
loads). Expected values are the float64 closed forms with the adhesion
boundary solved to 1e-15 (brentq); tests/python/reference/test_brush.py proves these
equal the quadrature reference to 1e-9 for every supported n.

Inputs per model: fiala: alpha fz; brush: kappa fz vx; sakai: kappa alpha fz;
neofiala: kappa alpha gamma fz vx.
"""
import math
import os

import numpy as np

from grip_tools.reference import brush as B
from grip_tools.golden.io import header

SEED = 20260404


def qs(x):
    return float(np.round(float(x) * 65536.0) / 65536.0)


def ql(x):
    return float(np.round(float(x) * 256.0) / 256.0)


def _fmt(v):
    return repr(float(v))


FIRST_SETS = {}


def _prow(model, sid, p):
    if sid == 0:
        FIRST_SETS[model] = p
    vals = [v for _, v, _ in B.to_c_units(model, p)]
    return f"P {sid} " + " ".join(str(v) if isinstance(v, int) else _fmt(v) for v in vals)


def _checked(model, p):
    bad = B.validate(model, p)
    if bad:
        raise ValueError(f"golden_brush: {model} set outside the valid range: {bad}")
    return p


def _out(r):
    return " ".join(_fmt(r[k]) for k in ("fx", "fy", "mz", "rh"))


# ---------------------------------------------------------------------------
# parameter sets

def neofiala_sets(rng):
    sets = []
    # A passenger-car set in the spirit of seed Table 5.4 (235/50R18, ~5 kN)
    sets.append(B.NeoFiala(l=0.16, w=0.19, kx=95000.0, ky=72000.0, mu_s=1.15, mu_d0=0.95, a_v=0.003, n=4,
                           q0=0.05, c_q=1.0e-5, c_qm=0.0, c_xc=2.0e-6, xi=0.0, eps=2.0e-5, g_mz=15000.0,
                           a_x=2.0, c_gamma=0.15, h=0.02, g_my=200000.0, fz_min=500.0, fz_max=10000.0,
                           alpha_max=0.6, kappa_max=1.0, gamma_max=0.2, v_max=60.0))
    # pure-lateral variant of section 5.3: skew and centre shift from Mz
    sets.append(B.NeoFiala(l=0.16, w=0.19, kx=95000.0, ky=72000.0, mu_s=1.15, mu_d0=0.95, a_v=0.003, n=5,
                           q0=0.0, c_q=0.0, c_qm=1.0e-4, c_xc=0.0, xi=1.2e-6, eps=2.0e-5, g_mz=15000.0,
                           a_x=2.0, fz_min=500.0, fz_max=10000.0))
    for n in range(B.N_MIN, B.N_MAX + 1):
        sets.append(B.random_neofiala(rng, n, couplings=True))
    for n in (2, 5, 8):
        sets.append(B.random_neofiala(rng, n, couplings=False))
    return [_checked("neofiala", B.quantized("neofiala", p)) for p in sets]


KAPPAS = [-1.0, -0.6, -0.3, -0.15, -0.08, -0.04, -0.02, -0.01, -0.003, 0.0, 0.003, 0.01, 0.02, 0.04,
          0.08, 0.15, 0.3, 0.6, 1.0]
ALPHAS = [0.0, 0.002, 0.01, 0.03, 0.06, 0.1, 0.2, 0.35, 0.6]


def write_neofiala(path, rng):
    sets = neofiala_sets(rng)
    rows = []
    for sid, p in enumerate(sets):
        rows.append(_prow("neofiala", sid, p))
        pts = []
        for k in KAPPAS:
            for a in ALPHAS:
                a = a * rng.choice([-1.0, 1.0])
                g = rng.uniform(-p.gamma_max, p.gamma_max) if rng.uniform() < 0.5 else 0.0
                pts.append((k, a, g, rng.uniform(p.fz_min, p.fz_max), rng.uniform(0.0, 40.0)))
        for _ in range(150):
            pts.append(B.random_inputs(rng, p))
        for k, a, g, f, v in pts:
            k, a, g, f, v = qs(max(-1.0, min(k, p.kappa_max))), qs(a), qs(g), ql(f), qs(v)
            r = B.neofiala_cf(p, k, a, g, f, v)
            rows.append(f"V {sid} {_fmt(k)} {_fmt(a)} {_fmt(g)} {_fmt(f)} {_fmt(v)} {_out(r)}")
    p = sets[0]
    for k, a, g, f, v in [(0.05, 0.8, 0.0, 4000.0, 20.0), (-1.5, -0.1, 0.0, 4000.0, 20.0),
                          (2.0, 0.05, 0.0, 4000.0, 20.0), (-0.05, 0.05, 0.0, 100.0, 20.0),
                          (-0.05, 0.05, 0.0, 20000.0, 20.0), (0.0, 0.05, 0.3, 4000.0, 20.0),
                          (-0.1, 0.1, -0.3, 4000.0, 20.0), (-0.2, 0.05, 0.0, 4000.0, -90.0)]:
        k, a, g, f, v = qs(k), qs(a), qs(g), ql(f), qs(v)
        r = B.neofiala_cf(p, k, a, g, f, v)
        assert r["warn"]
        rows.append(f"C 0 {_fmt(k)} {_fmt(a)} {_fmt(g)} {_fmt(f)} {_fmt(v)} {_out(r)}")
    with open(path, "w") as fh:
        fh.write(header("golden_brush (neofiala)", B.nf_state, SEED,
                        ["tag", "id", "kappa", "alpha_rad", "gamma_rad", "fz_N", "vx_mps", "fx_N", "fy_N",
                         "mz_Nm", "rh"], {"param_fields": " ".join(n for n, _, _ in B.C_UNITS["neofiala"])}))
        fh.write("\n".join(rows) + "\n")
    return len(rows)


def write_fiala(path, rng):
    sets = [B.Fiala(), B.Fiala(ky=150000.0, mu=0.8, l=0.25, fz_min=1000.0, fz_max=30000.0, alpha_max=1.0)]
    sets = [_checked("fiala", B.quantized("fiala", p)) for p in sets]
    rows = []
    for sid, p in enumerate(sets):
        rows.append(_prow("fiala", sid, p))
        pts = [(s * a, f) for a in np.linspace(0.0, p.alpha_max, 61) for s in (-1.0, 1.0)
               for f in (p.fz_min, 0.5 * (p.fz_min + p.fz_max), p.fz_max)]
        pts += [(rng.uniform(-p.alpha_max, p.alpha_max), rng.uniform(p.fz_min, p.fz_max)) for _ in range(200)]
        for a, f in pts:
            a, f = qs(a), ql(f)
            r = B.fiala_cf(p, a, f)
            rows.append(f"V {sid} {_fmt(a)} {_fmt(f)} {_out(r)}")
    p = sets[0]
    for a, f in [(0.9, 4000.0), (-1.2, 4000.0), (0.05, 50.0), (0.05, 50000.0)]:
        a, f = qs(a), ql(f)
        r = B.fiala_cf(p, a, f)
        assert r["warn"]
        rows.append(f"C 0 {_fmt(a)} {_fmt(f)} {_out(r)}")
    with open(path, "w") as fh:
        fh.write(header("golden_brush (fiala)", B.fiala_cf, SEED,
                        ["tag", "id", "alpha_rad", "fz_N", "fx_N", "fy_N", "mz_Nm", "rh"],
                        {"param_fields": " ".join(n for n, _, _ in B.C_UNITS["fiala"])}))
        fh.write("\n".join(rows) + "\n")
    return len(rows)


def write_brush(path, rng):
    sets = []
    for n in range(B.N_MIN, B.N_MAX + 1):
        mu_s = rng.uniform(0.5, 1.4)
        sets.append(B.Brush(kx=rng.uniform(40000.0, 200000.0), mu_s=mu_s, mu_d0=mu_s * rng.uniform(0.6, 1.0),
                            a_v=rng.uniform(0.0, 0.01), n=n, fz_min=300.0, fz_max=12000.0, kappa_max=1.0,
                            v_max=60.0))
    sets = [_checked("brush", B.quantized("brush", p)) for p in sets]
    rows = []
    ks = sorted(set(KAPPAS + list(np.linspace(-1.0, 1.0, 81)) + list(np.linspace(-0.05, 0.05, 41))))
    for sid, p in enumerate(sets):
        rows.append(_prow("brush", sid, p))
        for k in ks:
            for f in (p.fz_min, 3000.0, p.fz_max):
                v = rng.uniform(0.0, 50.0)
                k2, f2, v2 = qs(k), ql(f), qs(v)
                r = B.brush_cf(p, k2, f2, v2)
                rows.append(f"V {sid} {_fmt(k2)} {_fmt(f2)} {_fmt(v2)} {_out(r)}")
    p = sets[0]
    for k, f, v in [(-2.0, 4000.0, 20.0), (3.0, 4000.0, 20.0), (-0.1, 10.0, 20.0), (-0.1, 4000.0, 200.0)]:
        k, f, v = qs(k), ql(f), qs(v)
        r = B.brush_cf(p, k, f, v)
        assert r["warn"]
        rows.append(f"C 0 {_fmt(k)} {_fmt(f)} {_fmt(v)} {_out(r)}")
    with open(path, "w") as fh:
        fh.write(header("golden_brush (brush)", B.brush_cf, SEED,
                        ["tag", "id", "kappa", "fz_N", "vx_mps", "fx_N", "fy_N", "mz_Nm", "rh"],
                        {"param_fields": " ".join(n for n, _, _ in B.C_UNITS["brush"])}))
        fh.write("\n".join(rows) + "\n")
    return len(rows)


def sakai_table21():
    """Seed Table 2.1 (Fz = 4000 N, K = 57,200, G_y = 250,000 N/m); mu_s, mu_d
    and l were lost in extraction and are chosen (docs/brush-models.md)."""
    return B.Sakai(k=57200.0, g_y=250000.0, mu_s=1.0, mu_d=0.8, l=0.18, fz_min=200.0, fz_max=10000.0,
                   alpha_max=0.6, kappa_max=1.0)


def write_sakai(path, rng):
    sets = [sakai_table21(), B.Sakai(k=120000.0, g_y=150000.0, mu_s=1.2, mu_d=0.9, l=0.22, fz_min=500.0,
                                     fz_max=12000.0, alpha_max=1.0, kappa_max=2.0)]
    sets = [_checked("sakai", B.quantized("sakai", p)) for p in sets]
    rows = []
    for sid, p in enumerate(sets):
        rows.append(_prow("sakai", sid, p))
        for k in KAPPAS:
            for a in ALPHAS:
                for f in ((4000.0,) if sid == 0 else (p.fz_min, 6000.0, p.fz_max)):
                    a2 = min(a, p.alpha_max) * rng.choice([-1.0, 1.0])
                    k2, a2, f2 = qs(k), qs(a2), ql(f)
                    r = B.sakai_cf(p, k2, a2, f2)
                    rows.append(f"V {sid} {_fmt(k2)} {_fmt(a2)} {_fmt(f2)} {_out(r)}")
        for _ in range(200):
            k2 = qs(rng.uniform(-1.0, p.kappa_max) * rng.choice([0.05, 0.3, 1.0]))
            a2 = qs(rng.uniform(-p.alpha_max, p.alpha_max) * rng.choice([0.05, 0.3, 1.0]))
            f2 = ql(rng.uniform(p.fz_min, p.fz_max))
            r = B.sakai_cf(p, k2, a2, f2)
            rows.append(f"V {sid} {_fmt(k2)} {_fmt(a2)} {_fmt(f2)} {_out(r)}")
    p = sets[0]
    for k, a, f in [(-1.5, 0.05, 4000.0), (2.0, 0.05, 4000.0), (-0.05, 0.9, 4000.0), (-0.05, 0.05, 20000.0)]:
        k, a, f = qs(k), qs(a), ql(f)
        r = B.sakai_cf(p, k, a, f)
        assert r["warn"]
        rows.append(f"C 0 {_fmt(k)} {_fmt(a)} {_fmt(f)} {_out(r)}")
    with open(path, "w") as fh:
        fh.write(header("golden_brush (sakai)", B.sakai_cf, SEED,
                        ["tag", "id", "kappa", "alpha_rad", "fz_N", "fx_N", "fy_N", "mz_Nm", "rh"],
                        {"param_fields": " ".join(n for n, _, _ in B.C_UNITS["sakai"])}))
        fh.write("\n".join(rows) + "\n")
    return len(rows)


def write_param_files(outdir, first_sets):
    """brush_params_<model>.txt: set 0 of each golden file as a parameter
    file (the C reader must reproduce its P row); brush_params_<model>_default.txt:
    the defaults written out in full (the C reader's defaults must match)."""
    for model, p in first_sets.items():
        B.write_params(os.path.join(outdir, f"brush_params_{model}.txt"), model, p,
                       comment="set 0 of the golden vectors (tools/grip_tools/golden/brush.py)")
        B.write_params(os.path.join(outdir, f"brush_params_{model}_default.txt"), model, B.MODELS[model](),
                       comment="defaults of tools/grip_tools/reference/brush.py")


def write_golden(outdir):
    rng = np.random.default_rng(SEED)
    write_fiala(os.path.join(outdir, "brush_fiala.txt"), rng)
    write_brush(os.path.join(outdir, "brush_brush.txt"), rng)
    write_sakai(os.path.join(outdir, "brush_sakai.txt"), rng)
    write_neofiala(os.path.join(outdir, "brush_neofiala.txt"), rng)
    write_param_files(outdir, FIRST_SETS)
    return 0


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="grip golden-brush", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--outdir", default="build/golden")
    args = ap.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    return write_golden(args.outdir)
