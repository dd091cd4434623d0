"""The `grip-tire` command-line program (port/linux/grip_tire.c) against the
Python references: its .tir reader against tools/grip_tools/reference/tir.py (values
and error messages), its forces against tools/grip_tools/reference/mf.py, and its CSV
handling (passthrough columns, malformed rows, exit codes).

The binary: $GRIP_TIRE_BIN, default build/float-gcc/bin/grip-tire. Tests
are skipped, with the reason, when it is absent.

Tolerances (docs/tools.md): float build |err| <= 1e-4 * Fz for Fx, Fy and
1e-4 * Fz * R0 for Mz; fixed build 2e-3 * Fz and 2e-3 * Fz * R0 (the library's
documented fixed-point error is the bound; these are the end-to-end
checks of the tool, not of the model). The --outputs channels: |err| <=
tol * (scale + |want|), tol 1e-4 float / 2e-3 fixed, with the channel's
scale of tests/unit/test_mf_ext.c (R0, FNOMIN, FNOMIN R0, the file's
stiffness, 1; Omega (1 + |kappa|) 1 m/s / R0); an empty field exactly
where the reference has no value.
"""
import csv
import glob
import io
import os
import subprocess
import unittest

import numpy as np

from grip_tools.golden import mf as golden_mf
from grip_tools.reference import tir
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
BIN = os.environ.get("GRIP_TIRE_BIN", os.path.join(ROOT, "build", "float-gcc", "bin", "grip-tire"))
SHARED = golden_mf.shared_data_dir()
FIXTURES = os.path.join(ROOT, "tests", "data", "tir")

try:
    from grip_tools.reference import mf
except ImportError:          # the reference model is not there yet
    mf = None

TOL_REL = {"float": 1e-4, "fixed": 2e-3}


def shared_tirs():
    return sorted(glob.glob(os.path.join(SHARED, "chrono-tir", "*.tir")) +
                  glob.glob(os.path.join(SHARED, "mfeval-tir", "*.tir")))


def run(args, stdin_text=""):
    p = subprocess.run([BIN] + args, input=stdin_text.encode(), capture_output=True, timeout=120)
    return p.returncode, p.stdout.decode(), p.stderr.decode()


def build_arith():
    rc, out, _ = run(["--help"])
    if "Build: fixed" in out:
        return "fixed"
    return "float"


def stored(v, fmt, arith):
    """The value as the build stores it (tir.py's SI double -> grip_real_t -> double)."""
    if arith == "float":
        return float(np.float32(v))
    scale = 256.0 if fmt == "QL" else 65536.0
    x = v * scale
    r = np.floor(x + 0.5) if x >= 0 else -np.floor(-x + 0.5)
    return r / scale


def dump(path):
    rc, out, err = run(["--tir", path, "--dump-params"])
    if rc != 0:
        raise AssertionError(f"grip-tire --dump-params {path}: exit {rc}: {err}")
    vals = {}
    for line in out.splitlines():
        k, v = line.split("=")
        vals[k.strip()] = float(v)
    return vals


def parse_out(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


@unittest.skipUnless(os.path.exists(BIN), f"grip-tire not built ({BIN}); set GRIP_TIRE_BIN or build it")
class TirReaderAgreesWithPython(unittest.TestCase):
    """The C reader (through --dump-params) and tools/grip_tools/reference/tir.py read
    every file to the same values and reject every bad fixture with the
    same message."""

    GOOD = ("minimal.tir", "units.tir", "crlf_bar.tir", "fittyp_from_format.tir", "fittyp_52.tir", "use_mode_ok.tir")

    def fixtures(self):
        """(valid, with warnings, refused) fixtures of tests/data/tir."""
        every = sorted(glob.glob(os.path.join(FIXTURES, "*.tir")))
        good = [f for f in every if os.path.basename(f) in self.GOOD]
        warn = [f for f in every if os.path.basename(f).startswith("warn_")]
        bad = [f for f in every if f not in good and f not in warn]
        return good, warn, bad

    def test_values_equal(self):
        arith = build_arith()
        good, warn, _ = self.fixtures()
        files = shared_tirs() + good + warn
        self.assertGreaterEqual(len(files), 19, "shared .tir files not found")
        quiet = tir.set_warning_handler(lambda w: None)
        try:
            for path in files:
                t = tir.read_tir(path)
                got = dump(path)
                self.assertEqual(int(got["FITTYP"]), t.fittyp, path)
                self.assertEqual(int(got["TYRESIDE"]), t.tyreside, path)
                differ = [c.key for c in tir.coefficients()
                          if got[c.key] != stored(t.values[c.key], c.fmt, arith)]
                self.assertEqual(differ, [], f"{path}: C and Python disagree on {differ[:5]}")
        finally:
            tir.set_warning_handler(quiet)
        print(f"\n# {len(files)} files: C reader == tir.py on all "
              f"{len(tir.coefficients())} coefficients ({arith} build)")

    def python_messages(self, path, **kw):
        """tir.py's warnings and error, as grip-tire prints them."""
        lines = []
        old = tir.set_warning_handler(lambda w: lines.append(f"grip-tire: warning: {w}"))
        try:
            tir.read_tir(path, **kw)
            ok = True
        except tir.TirError as e:
            lines.append(f"grip-tire: {e}")
            ok = False
        finally:
            tir.set_warning_handler(old)
        return ok, lines

    def test_messages_equal(self):
        """Every fixture, plain and --strict: the same warnings and the same
        error, word for word (and exit 3 exactly when tir.py refuses)."""
        good, warn, bad = self.fixtures()
        self.assertGreaterEqual(len(bad), 31)
        self.assertGreaterEqual(len(warn), 3)
        n = 0
        for path in good + warn + bad + [os.path.join(FIXTURES, "no_such_file.tir")]:
            for strict in (False, True):
                ok, want = self.python_messages(path, strict=strict)
                rc, out, err = run(["--tir", path, "--dump-params"] + (["--strict"] if strict else []))
                self.assertEqual(rc, 0 if ok else 3, f"{path} strict={strict}: exit {rc}: {err}")
                if not ok:
                    self.assertEqual(out, "")
                self.assertEqual(err.strip().splitlines(), want, f"{path} strict={strict}")
                n += 1
            if path in bad:
                self.assertFalse(self.python_messages(path)[0], path)
            if path in warn:
                self.assertTrue(self.python_messages(path)[1], f"{path}: no warning")
                self.assertFalse(self.python_messages(path, strict=True)[0], f"{path}: accepted under --strict")
        print(f"\n# {n} reads (plain and --strict): C reader and tir.py give the same warnings and errors")

    def test_overrides(self):
        """--no-range-check reads a value outside its plausible range as
        given; --pure accepts USE_MODE 13 (uncombined forces)."""
        path = os.path.join(FIXTURES, "range_pdy1.tir")
        self.assertEqual(run(["--tir", path, "--dump-params"])[0], 3)
        rc, out, err = run(["--tir", path, "--dump-params", "--no-range-check"])
        self.assertEqual(rc, 0, err)
        self.assertIn("PDY1 = 30000\n", out)
        self.assertEqual(tir.read_tir(path, range_check=False).values["PDY1"], 30000.0)
        path = os.path.join(FIXTURES, "use_mode_uncombined.tir")
        self.assertEqual(run(["--tir", path, "--dump-params"])[0], 3)
        rc, out, err = run(["--tir", path, "--dump-params", "--pure"])
        self.assertEqual(rc, 0, err)
        self.assertEqual(tir.read_tir(path, pure_slip=True).use_mode, 13)


@unittest.skipUnless(os.path.exists(BIN), f"grip-tire not built ({BIN}); set GRIP_TIRE_BIN or build it")
class CsvHandling(unittest.TestCase):
    TIR = os.path.join(FIXTURES, "minimal.tir")
    HEAD = "kappa,alpha,gamma,fz,p,vx"

    def test_passthrough_and_column_order(self):
        text = ('id,vx,note,alpha,kappa,fz,gamma,p,extra\r\n'
                '1,20,"left, front",0.05,0.02,4000,0.01,220000,x\n'
                '2,15,plain,-0.1,-0.05,3000,0,200000,"say ""hi"""\n')
        rc, out, err = run(["--tir", self.TIR], text)
        self.assertEqual(rc, 0, err)
        lines = out.splitlines()
        self.assertEqual(lines[0], "id,vx,note,alpha,kappa,fz,gamma,p,extra,fx,fy,mz,status")
        # every input line comes back byte for byte, the results appended
        self.assertTrue(lines[1].startswith('1,20,"left, front",0.05,0.02,4000,0.01,220000,x,'))
        self.assertTrue(lines[2].startswith('2,15,plain,-0.1,-0.05,3000,0,200000,"say ""hi""",'))
        head, rows = parse_out(out)
        self.assertEqual(rows[1][8], "say \"hi\"")
        for r in rows:
            self.assertEqual(r[-1], "0")
            self.assertTrue(all(np.isfinite(float(v)) for v in r[-4:-1]))

    def test_options_no_status_and_prefix(self):
        text = self.HEAD + ",fx\n0.1,0,0,4000,220000,20,123\n"
        rc, out, err = run(["--tir", self.TIR], text)
        self.assertEqual(rc, 4)
        self.assertIn("already has a column 'fx'", err)
        rc, out, err = run(["--tir", self.TIR, "--prefix", "model_", "--no-status"], text)
        self.assertEqual(rc, 0, err)
        self.assertEqual(out.splitlines()[0], self.HEAD + ",fx,model_fx,model_fy,model_mz")
        self.assertEqual(len(out.splitlines()[1].split(",")), 10)

    def test_malformed_rows(self):
        text = (self.HEAD + "\n"
                "0.1,0,0,4000,220000,20\n"          # line 2: fine
                "0.1,abc,0,4000,220000,20\n"        # line 3: not a number
                "0.1,0,0,4000\n"                    # line 4: too few fields
                "\n"                                # line 5: blank, skipped
                "0.1,0,0,4000,220000,20,9\n"        # line 6: too many fields
                "0.1,nan,0,4000,220000,20\n"        # line 7: not finite
                '0.1,"0,0,4000,220000,20\n'         # line 8: open quote
                "-0.1,0.02,0,4000,220000,20\n")     # line 9: fine
        rc, out, err = run(["--tir", self.TIR], text)
        self.assertEqual(rc, 1)
        # the malformed rows are echoed as they came (one has an open
        # quote), so split off the four appended fields by hand
        rows = [line.rsplit(",", 4)[1:] for line in out.splitlines()[1:]]
        self.assertEqual(len(rows), 7, "one output row per non-blank input row")
        status = [r[-1] for r in rows]
        self.assertEqual(status, ["0", "-100", "-100", "-100", "-100", "-100", "0"])
        for frag in ("<stdin>:3: column 'alpha': 'abc' is not a finite number",
                     "<stdin>:4: malformed row: 4 fields, the header has 6",
                     "<stdin>:6: malformed row: 7 fields, the header has 6",
                     "<stdin>:7: column 'alpha': 'nan' is not a finite number",
                     "<stdin>:8: malformed row: unterminated quoted field",
                     "7 rows: 5 malformed"):
            self.assertIn(frag, err)
        self.assertEqual(rows[1][-4:-1], ["", "", ""], "nothing computed for a malformed row")

    def test_header_errors(self):
        rc, out, err = run(["--tir", self.TIR], "kappa,alpha,gamma,fz,vx\n0,0,0,1,1\n")
        self.assertEqual(rc, 4)
        self.assertIn("missing column 'p'", err)
        rc, out, err = run(["--tir", self.TIR], "")
        self.assertEqual(rc, 4)
        self.assertIn("empty input", err)
        rc, out, err = run(["--tir", self.TIR], "kappa,alpha,gamma,fz,p,vx,ALPHA\n")
        self.assertEqual(rc, 4)
        self.assertIn("'alpha' appears twice", err)

    def test_usage_and_model_errors(self):
        self.assertEqual(run(["--model", "nosuch", "--tir", self.TIR])[0], 2)
        self.assertEqual(run(["--bogus"])[0], 2)
        self.assertEqual(run(["--side", "up", "--tir", self.TIR])[0], 2)
        rc, out, err = run([], self.HEAD + "\n")
        self.assertEqual(rc, 3)
        self.assertIn("--tir", err)
        rc, out, err = run(["--tir", os.path.join(FIXTURES, "bad_fittyp.tir")], self.HEAD + "\n")
        self.assertEqual(rc, 3)
        self.assertIn("bad_fittyp.tir:12: FITTYP:", err)

    def test_rejected_input_keeps_row(self):
        # a slip ratio beyond the fixed-point range is reported, not wrapped
        # (--no-unit-check: without it the unit check refuses it first)
        text = self.HEAD + "\n1e9,0,0,4000,220000,20\n0,0,0,4000,220000,20\n"
        rc, out, err = run(["--tir", self.TIR, "--no-unit-check"], text)
        head, rows = parse_out(out)
        self.assertEqual(len(rows), 2)
        self.assertEqual(rows[1][-1], "0")
        st = int(rows[0][-1])
        # float: the model clamps (warning) or rejects; fixed: not representable
        self.assertNotEqual(st, -100)
        if st < 0:
            self.assertEqual(rc, 1)
            self.assertIn("<stdin>:2:", err)

    def test_units_implausible(self):
        # a slip angle in degrees: the row is refused (-101, no forces), exit 4
        text = self.HEAD + "\n0,0.02,0,4000,220000,20\n0,5,0,4000,220000,20\n"
        rc, out, err = run(["--tir", self.TIR], text)
        head, rows = parse_out(out)
        self.assertEqual(rc, 4)
        self.assertEqual([r[-1] for r in rows], ["0", "-101"])
        self.assertEqual(rows[1][-4:-1], ["", "", ""])
        self.assertIn("<stdin>:3: column 'alpha': 5 rad is outside the plausible range", err)
        self.assertIn("(degrees?)", err)
        # loads in kN: every row is evaluated, then the column is refused
        fnomin = tir.read_tir(self.TIR).params()["fnomin"]
        text = self.HEAD + "\n0,0.02,0,3.5,220000,20\n0,0.02,0,4.2,220000,20\n0,0.02,0,-0.1,220000,20\n"
        rc, out, err = run(["--tir", self.TIR], text)
        self.assertEqual(rc, 4)
        self.assertEqual(len(parse_out(out)[1]), 3)
        self.assertIn(f"<stdin>:3: column 'fz': the largest load is 4.2 N, below a tenth of the tyre's "
                      f"FNOMIN = {fnomin:g} N: a load in kN labelled N?", err)
        # just above a tenth of FNOMIN is a light load, not a unit error
        light = 0.1 * fnomin + 1.0
        rc, out, err = run(["--tir", self.TIR], self.HEAD + f"\n0,0.02,0,{light},220000,20\n")
        self.assertEqual(rc, 0, err)
        # in the SAE axes a load is negative: the same rule on -fz
        rc, out, err = run(["--tir", self.TIR, "--sae"], self.HEAD + "\n0,0.02,0,-4.2,220000,20\n")
        self.assertEqual(rc, 4)
        self.assertIn("the largest load is 4.2 N", err)
        rc, out, err = run(["--tir", self.TIR, "--sae"], self.HEAD + "\n0,0.02,0,-4000,220000,20\n")
        self.assertEqual(rc, 0, err)
        # a pressure in bar; p <= 0 is the nominal pressure, not a unit error
        rc, out, err = run(["--tir", self.TIR], self.HEAD + "\n0,0.02,0,4000,2.2,20\n")
        self.assertEqual(rc, 4)
        self.assertIn("<stdin>:2: column 'p': the largest pressure is 2.2 Pa", err)
        rc, out, err = run(["--tir", self.TIR], self.HEAD + "\n0,0.02,0,4000,-1,20\n")
        self.assertEqual(rc, 0, err)
        # the override evaluates them as given
        rc, out, err = run(["--tir", self.TIR, "--no-unit-check"], self.HEAD + "\n0,5,0,4.2,2.2,20\n")
        self.assertIn(rc, (0, 1))
        self.assertNotEqual(parse_out(out)[1][0][-1], "-101")

    def test_units_declared(self):
        ok = "kappa[-],alpha[rad],gamma[rad],fz[N],p[Pa],vx[m/s]\n0,0.02,0,4000,220000,20\n"
        rc, out, err = run(["--tir", self.TIR], ok)
        self.assertEqual(rc, 0, err)
        self.assertEqual(parse_out(out)[0][:6], ok.splitlines()[0].split(","))
        rc, out, err = run(["--tir", self.TIR], ok.replace("fz[N]", "fz[kN]"))
        self.assertEqual(rc, 4)
        self.assertIn("<stdin>:1: header: column 4 'fz[kN]': unit [kN], but grip-tire reads fz in [N]", err)
        rc, out, err = run(["--tir", self.TIR, "--no-unit-check"], ok.replace("alpha[rad]", "ALPHA [deg]"))
        self.assertEqual(rc, 4)   # a declared unit is never overridden
        self.assertIn("column 2 'ALPHA [deg]': unit [deg]", err)
        rc, out, err = run(["--tir", self.TIR], ok.replace("fz[N]", "fz[N],FZ"))
        self.assertEqual(rc, 4)
        self.assertIn("'fz' appears twice", err)


def grid(params, n, seed):
    rng = np.random.default_rng(seed)
    fz0 = params["fnomin"]
    p0 = params["nompres"] or params["inflpres"] or 2e5
    return {
        "kappa": rng.uniform(-0.3, 0.3, n),
        "alpha": rng.uniform(-0.3, 0.3, n),
        "gamma": rng.uniform(-0.08, 0.08, n),
        "fz": rng.uniform(0.3, 1.8, n) * fz0,
        "p": rng.uniform(0.85, 1.15, n) * p0,
        "vx": rng.uniform(5.0, 30.0, n),
    }


def to_csv(cols, sign_fz=1.0):
    lines = ["kappa,alpha,gamma,fz,p,vx"]
    for i in range(len(cols["kappa"])):
        lines.append(",".join(repr(float(cols[k][i]) * (sign_fz if k == "fz" else 1.0))
                              for k in ("kappa", "alpha", "gamma", "fz", "p", "vx")))
    return "\n".join(lines) + "\n"


@unittest.skipUnless(os.path.exists(BIN), f"grip-tire not built ({BIN}); set GRIP_TIRE_BIN or build it")
@unittest.skipIf(mf is None, "tools/grip_tools/reference/mf.py (the reference model) is not there yet")
class ForcesAgreeWithReference(unittest.TestCase):
    N = 400

    def compare(self, path, args, ref_kw, pure=False, sign_fz=1.0, seed=1):
        arith = build_arith()
        t = tir.read_tir(path)
        params = t.params()
        cols = grid(params, self.N, seed)
        rc, out, err = run(["--tir", path] + args, to_csv(cols, sign_fz))
        self.assertIn(rc, (0,), f"{path} {args}: exit {rc}: {err[-500:]}")
        head, rows = parse_out(out)
        got = np.array([[float(v) for v in r[-4:-1]] for r in rows])
        status = np.array([int(r[-1]) for r in rows])
        ref = mf.evaluate(params, cols["kappa"], cols["alpha"], cols["gamma"], cols["fz"] * sign_fz,
                          cols["p"], cols["vx"], **ref_kw)
        keys = ("fx0", "fy0", "mz0") if pure else ("fx", "fy", "mz")
        want = np.stack([ref[k] for k in keys], axis=1)
        fz = np.abs(cols["fz"])
        r0 = params["unloaded_radius"]
        scale = np.stack([fz, fz, fz * r0], axis=1)
        err_rel = np.abs(got - want) / scale
        worst = err_rel.max(axis=0)
        print(f"\n# {os.path.basename(path)} {' '.join(args) or '(defaults)'}: max |err|/Fz "
              f"fx {worst[0]:.2e} fy {worst[1]:.2e}, |err|/(Fz R0) mz {worst[2]:.2e} "
              f"({arith}, tol {TOL_REL[arith]:.0e}; {np.sum(status != 0)} rows with warnings)")
        self.assertTrue(np.all(status >= 0), f"status {sorted(set(status))}")
        self.assertLessEqual(worst.max(), TOL_REL[arith])

    def test_every_shared_file_combined(self):
        for i, path in enumerate(shared_tirs()):
            with self.subTest(path=os.path.basename(path)):
                self.compare(path, [], {}, seed=10 + i)

    def test_pure(self):
        path = os.path.join(SHARED, "mfeval-tir", "MagicFormula61_Paramerters.tir")
        self.compare(path, ["--pure"], {}, pure=True)

    def test_sae_and_kappa_braking(self):
        path = os.path.join(SHARED, "mfeval-tir", "MagicFormula62_Paramerters.tir")
        self.compare(path, ["--sae"], {"convention": "sae"}, sign_fz=-1.0)
        self.compare(path, ["--kappa-braking"], {"kappa_braking": True})

    def test_mz52_svyk_camber(self):
        path = os.path.join(SHARED, "mfeval-tir", "MagicFormula52_Paramerters.tir")
        self.compare(path, ["--mz52-svyk-camber"], {"mz52_svyk_camber": True})

    def test_outputs_all_channels(self):
        arith = build_arith()
        worst = {}
        for i, path in enumerate(shared_tirs()):
            params = tir.read_tir(path).params()
            cols = grid(params, 150, 40 + i)
            rc, out, err = run(["--tir", path, "--outputs", "all"], to_csv(cols))
            self.assertEqual(rc, 0, f"{path}: {err[-300:]}")
            head, rows = parse_out(out)
            units = {"N m": "Nm"}
            names = [f"{n}[{units.get(u, u)}]" for n, u, _m, _s in mf.EXT_CHANNELS]
            self.assertEqual(head[-len(names) - 1:], names + ["status"])
            ref = mf.evaluate_ext(params, cols["kappa"], cols["alpha"], cols["gamma"], cols["fz"], cols["p"],
                                  cols["vx"])
            r0, fn = params["unloaded_radius"], params["fnomin"]
            scale = {"re": r0, "rl": r0, "rho": r0, "2a": r0, "2b": r0, "t": r0, "sigmax": r0, "sigmay": r0,
                     "cz": params["vertical_stiffness"], "cx": params["longitudinal_stiffness"],
                     "cy": params["lateral_stiffness"], "mzr": fn * r0, "mx": fn * r0, "my": fn * r0,
                     "kxk": fn, "kya": fn, "mux": 1.0, "muy": 1.0}
            for j, (name, _u, _m, _s) in enumerate(mf.EXT_CHANNELS):
                field = [r[len(head) - len(names) - 1 + j] for r in rows]
                want = ref[name]
                self.assertEqual([f == "" for f in field], list(np.isnan(want)), f"{path} {name}")
                got = np.array([float(f) if f else np.nan for f in field])
                sc = scale.get(name, (1.0 + np.abs(cols["kappa"])) / r0)
                e = np.abs(got - want) / (sc + np.abs(want))
                e = e[~np.isnan(want)]
                if e.size:
                    worst[name] = max(worst.get(name, 0.0), float(e.max()))
                    self.assertLessEqual(float(e.max()), TOL_REL[arith], f"{os.path.basename(path)} {name}")
        print(f"\n# --outputs all ({arith}): worst |err| / (scale + |want|): "
              + ", ".join(f"{k} {v:.1e}" for k, v in sorted(worst.items(), key=lambda kv: -kv[1])[:6]))

    def test_outputs_subset_and_errors(self):
        path = os.path.join(SHARED, "chrono-tir", "335_65R22_5_G275MSA_60psi.tir")
        cols = grid(tir.read_tir(path).params(), 5, 3)
        rc, out, err = run(["--tir", path, "--outputs", "my,cx,re", "--prefix", "m_"], to_csv(cols))
        self.assertEqual(rc, 0, err)
        head, rows = parse_out(out)
        self.assertEqual(head[-7:], ["m_fx", "m_fy", "m_mz", "m_my[Nm]", "m_cx[N/m]", "m_re[m]", "m_status"])
        self.assertTrue(all(r[-3] == "" and r[-2] != "" for r in rows))   # no LONGITUDINAL_STIFFNESS
        for args in (["--outputs", "re,nope"], ["--outputs", "re,re"], ["--outputs", ""],
                     ["--outputs", "re", "--pure"]):
            rc, out, err = run(["--tir", path] + args, to_csv(cols))
            self.assertEqual(rc, 2, f"{args}: {err}")
            self.assertIn("--outputs", err)
        rc, out, err = run(["--tir", path, "--outputs", "re"], "kappa,alpha,gamma,fz,p,vx,re[m]\n")
        self.assertEqual(rc, 4, err)

    def test_use_modes_and_turn_slip(self):
        # --use-mode 211 / 212 / --turn-slip [--ts-camber], with the columns
        # phit and omega (a third of the rows with a given spin), against the
        # reference; the extended channels with turn slip too
        arith = build_arith()
        worst = {}
        runs = ((["--use-mode", "211"], dict(limits=False)),
                (["--use-mode", "111", "--outputs", "re,omega,t,mzr,kya"], {}),
                (["--turn-slip", "--outputs", "re,omega,t,mzr,kya,muy"], dict(turn_slip=True)),
                (["--use-mode", "212"], dict(turn_slip=True, limits=False)),
                (["--turn-slip", "--ts-camber"], dict(turn_slip=True, ts_camber=True)))
        for i, path in enumerate(shared_tirs()):
            params = tir.read_tir(path).params()
            cols = grid(params, 120, 70 + i)
            rng = np.random.default_rng(i)
            cols["phit"] = rng.uniform(-3.0, 3.0, cols["kappa"].size)
            om = (1.0 + cols["kappa"]) * cols["vx"] / params["unloaded_radius"]
            cols["omega"] = np.where(rng.uniform(0, 1, om.size) < 0.3, om, 0.0)
            text = "kappa,alpha,gamma,fz,p,vx,phit,omega\n" + "".join(
                ",".join(repr(float(cols[k][j])) for k in ("kappa", "alpha", "gamma", "fz", "p", "vx", "phit", "omega"))
                + "\n" for j in range(om.size))
            for args, kw in runs:
                if kw.get("turn_slip") and not mf.turn_slip_usable(params):
                    rc, out, err = run(["--tir", path] + args, text)
                    self.assertEqual(rc, 3, f"{path} {args}: {err}")
                    self.assertIn("TURNSLIP_COEFFICIENTS", err)
                    continue
                rc, out, err = run(["--tir", path] + args, text)
                self.assertEqual(rc, 0, f"{path} {args}: {err[-300:]}")
                head, rows = parse_out(out)
                ref = mf.evaluate_ext(params, cols["kappa"], cols["alpha"], cols["gamma"], cols["fz"], cols["p"],
                                      cols["vx"], phit=cols["phit"], omega=cols["omega"], **kw)
                r0, fn = params["unloaded_radius"], params["fnomin"]
                names = ["fx", "fy", "mz"] + [h.split("[")[0] for h in head[head.index("mz") + 1:-1]]
                for j, name in enumerate(names):
                    field = [r[head.index("fx") + j] for r in rows]
                    want = ref[name]
                    got = np.array([float(f) if f else np.nan for f in field])
                    sc = {"fx": cols["fz"], "fy": cols["fz"], "mz": cols["fz"] * r0, "mzr": fn * r0, "kya": fn,
                          "muy": 1.0, "omega": (1.0 + np.abs(cols["kappa"])) / r0}.get(name, r0)
                    e = np.abs(got - want) / (sc + (0.0 if name in ("fx", "fy", "mz") else np.abs(want)))
                    key = f"{' '.join(args[:2])} {name}"
                    worst[key] = max(worst.get(key, 0.0), float(np.nanmax(e)))
                    self.assertLessEqual(float(np.nanmax(e)), TOL_REL[arith], f"{os.path.basename(path)} {args} {name}")
        print(f"\n# use modes / turn slip ({arith}): worst |err| / scale: "
              + ", ".join(f"{k} {v:.1e}" for k, v in sorted(worst.items(), key=lambda kv: -kv[1])[:6]))

    def test_use_mode_errors(self):
        path = os.path.join(SHARED, "mfeval-tir", "MagicFormula61_Paramerters.tir")
        cols = grid(tir.read_tir(path).params(), 3, 5)
        for args in (["--use-mode", "121"], ["--use-mode", "113"], ["--use-mode", "11"], ["--turn-slip", "--pure"],
                     ["--lanes", "--outputs", "re"], ["--lanes", "--turn-slip"], ["--lanes", "--use-mode", "211"]):
            rc, out, err = run(["--tir", path] + args, to_csv(cols))
            self.assertEqual(rc, 2, f"{args}: {err}")
        rc, out, err = run(["--tir", path, "--use-mode", "121"], to_csv(cols))
        self.assertIn("alpha* = tan(alpha)", err)
        rc, out, err = run(["--tir", path, "--turn-slip"], to_csv(cols))   # no phit column
        self.assertEqual(rc, 4, err)
        self.assertIn("phit", err)

    def test_mount_side(self):
        # the file is a RIGHT tyre: mounted right it is used as fitted,
        # mounted left it is mirrored
        path = os.path.join(SHARED, "mfeval-tir", "MagicFormula61_Paramerters.tir")
        self.compare(path, ["--side", "right"], {"mirror": False})
        self.compare(path, ["--side", "left"], {"mirror": True})


if __name__ == "__main__":
    unittest.main()
