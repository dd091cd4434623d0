"""Tests of the .tir reader, validator and C emitter (grip_tools.reference.tir)."""
import glob
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

from grip_tools.golden import mf as golden_mf
from grip_tools.paths import REPO_ROOT as ROOT
from grip_tools.reference import tir

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data")


def shared_files():
    return golden_mf.tir_files()


def run_cli(*args):
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "tools"))
    return subprocess.run([sys.executable, "-m", "grip_tools", "tir2c", *args],
                          capture_output=True, text=True, env=env, cwd=ROOT)


class CoefficientList(unittest.TestCase):
    def test_parsed_from_header(self):
        coefs = tir.coefficients()
        with open(tir.COEFS_HEADER) as f:
            n_x = len(re.findall(r"^\s*X\(", f.read(), re.M))
        self.assertEqual(len(coefs), n_x)
        keys = [c.key for c in coefs]
        self.assertEqual(len(keys), len(set(keys)))
        by = {c.key: c for c in coefs}
        self.assertTrue(by["FNOMIN"].required)
        self.assertEqual(by["FNOMIN"].fmt, "QL")
        self.assertEqual(by["PKY4"].default, 2.0)
        self.assertEqual(by["LMUV"].default, 0.0)
        self.assertEqual(by["LFZO"].default, 1.0)


# MFeval 4.0's readTIR defaults (the values of Pacejka's book tyre) of every
# coefficient of the force and moment equations whose default is not 0: a
# key a file leaves out must take these, as MFeval and MF-Tyre evaluate it.
MFEVAL_DEFAULTS = {
    "LONGVL": 16.7, "VXLOW": 1.0, "PCX1": 1.65, "PDX1": 1.3, "PDX2": -0.15, "PKX1": 20.0,
    "RBX1": 20.0, "RBX2": 15.0, "RCX1": 1.0, "QSX4": 5.0, "QSX5": 1.0, "QSX6": 10.0, "QSX9": 0.4,
    "QSX11": 5.0, "PCY1": 1.3, "PDY1": 1.1, "PDY2": -0.15, "PKY1": -20.0, "PKY2": 1.0, "PKY4": 2.0,
    "PKY6": -1.0, "RBY1": 10.0, "RBY2": 10.0, "RCY1": 1.0, "RVY4": 20.0, "RVY5": 2.0, "RVY6": 10.0,
    "QSY1": 0.01, "QSY3": 4.0e-4, "QSY4": 4.0e-5, "QSY7": 0.85, "QSY8": -0.4, "QBZ1": 10.0, "QBZ9": 10.0,
    "QCZ1": 1.1, "QDZ1": 0.12, "QDZ8": -0.05, "Q_RE0": 1.0, "Q_FZ2": 1.0e-4, "BREFF": 8.4, "DREFF": 0.27,
    "FREFF": 0.07, "BOTTOM_OFFST": 0.01, "ASPECT_RATIO": 0.6, "Q_RA1": 0.5, "Q_RA2": 1.0, "Q_RB1": 1.0,
    "Q_RB2": -1.0,
}
# Keys whose default stays 0 = not given, with the reason (docs/tools.md):
# the book tyre's size, stiffnesses, limits and pressures would be wrong for
# any other tyre, and turn slip without the file's coefficients is refused.
GRIP_NOT_GIVEN = ("WIDTH", "RIM_RADIUS", "INFLPRES", "NOMPRES", "VERTICAL_STIFFNESS", "LONGITUDINAL_STIFFNESS",
                  "LATERAL_STIFFNESS", "PRESMIN", "PRESMAX", "FZMIN", "FZMAX")


class Defaults(unittest.TestCase):
    def test_defaults_are_mfevals(self):
        by = {c.key: c for c in tir.coefficients()}
        for key, want in MFEVAL_DEFAULTS.items():
            c = by[key]
            if not c.required:
                self.assertEqual(c.default, want, key)
        for c in tir.coefficients():
            if c.required or c.key in MFEVAL_DEFAULTS:
                continue
            if c.section == "SCALING_COEFFICIENTS":
                self.assertEqual(c.default, 0.0 if c.key == "LMUV" else 1.0, c.key)
            elif c.key in GRIP_NOT_GIVEN or c.section == "TURNSLIP_COEFFICIENTS" or c.section.endswith("_RANGE"):
                continue
            else:
                self.assertEqual(c.default, 0.0, f"{c.key}: MFeval's default is 0")

    def test_missing_pky2_keeps_the_cornering_stiffness(self):
        # minimal.tir gives only the required keys: before, PKY2 = 0 made
        # Kya = PKY1 Fz0 sin(PKY4 atan(Fz / 0)) = 0 and Fy 0.0003 N at 0.05 rad
        from grip_tools.reference import mf
        import numpy as np
        t = tir.read_tir(os.path.join(FIXTURES, "minimal.tir"))
        self.assertEqual(t.lines["PKY2"], 0)
        p = t.params()
        self.assertEqual(p["pky2"], 1.0)
        with open(os.path.join(FIXTURES, "minimal.tir")) as f:
            text = f.read()
        with tempfile.TemporaryDirectory() as d:
            q = os.path.join(d, "explicit.tir")
            with open(q, "w") as f:
                f.write(text.replace("PKY1 = -15.324", "PKY1 = -15.324\nPKY2 = 1"))
            explicit = tir.read_tir(q).params()
        args = (np.array([0.0]), np.array([0.05]), np.array([0.0]), np.array([4000.0]))
        fy = mf.evaluate(p, *args)["fy"][0]
        self.assertEqual(fy, mf.evaluate(explicit, *args)["fy"][0])
        self.assertGreater(abs(fy), 0.3 * 4000.0 * 0.05 * 15.324 * 0.5)


class SharedFiles(unittest.TestCase):
    def test_every_shared_file_both_line_endings(self):
        files = shared_files()
        self.assertGreaterEqual(len(files), 10)
        with tempfile.TemporaryDirectory() as d:
            for path in files:
                t = tir.read_tir(path)
                with open(path, "rb") as f:
                    data = f.read()
                lf = data.replace(b"\r\n", b"\n")
                crlf = lf.replace(b"\n", b"\r\n")
                for tag, blob in (("lf", lf), ("crlf", crlf)):
                    p = os.path.join(d, f"{tag}_{os.path.basename(path)}")
                    with open(p, "wb") as f:
                        f.write(blob)
                    u = tir.read_tir(p)
                    self.assertEqual(u.values, t.values, p)
                    self.assertEqual(u.lines, t.lines, p)
                    self.assertEqual((u.fittyp, u.tyreside), (t.fittyp, t.tyreside), p)
                self.assertIn(t.fittyp, tir.SUPPORTED_FITTYP)
                for c in tir.coefficients():
                    self.assertTrue(math.isfinite(t.values[c.key]))

    def test_known_values(self):
        root = golden_mf.shared_data_dir()
        t = tir.read_tir(os.path.join(root, "mfeval-tir", "MagicFormula61_Paramerters.tir"))
        self.assertEqual(t.fittyp, 61)
        self.assertEqual(t.tyreside, -1)
        self.assertEqual(t.values["FNOMIN"], 6752.0)
        self.assertEqual(t.values["PKY4"], -3.267949)
        self.assertEqual(t.values["NOMPRES"], 260000.0)
        self.assertEqual(t.lines["FITTYP"] if "FITTYP" in t.lines else 0, 0)
        # a section is kept even though grip does not use it
        self.assertIn("TURNSLIP_COEFFICIENTS", t.sections)
        self.assertEqual(t.get("TURNSLIP_COEFFICIENTS", "QDTP1"), 10.0)

    def test_tables_kept(self):
        root = golden_mf.shared_data_dir()
        t = tir.read_tir(os.path.join(root, "chrono-tir", "335_65R22_5_G275MSA_60psi.tir"))
        self.assertEqual(len(t.tables["SHAPE"]["rows"]), 10)
        self.assertEqual(t.tables["SHAPE"]["rows"][0], [1.0, 0.0])
        # this file repeats [DEFLECTION_LOAD_CURVE]: rows of both are kept
        self.assertEqual(len(t.tables["DEFLECTION_LOAD_CURVE"]["rows"]), 21 + 3)
        self.assertEqual(t.fittyp, 5)
        self.assertEqual(t.get("MODEL", "FE_METHOD"), "YES")

    def test_fittyp_inferred_from_property_file_format(self):
        root = golden_mf.shared_data_dir()
        t = tir.read_tir(os.path.join(root, "chrono-tir", "mf_185_80R14.tir"))
        self.assertEqual(t.fittyp, 6)
        self.assertTrue(t.fittyp_inferred)

    def test_tables_and_crlf_fixture(self):
        t = tir.read_tir(os.path.join(DATA, "good_tables_crlf.tir"))
        u = tir.read_tir(os.path.join(DATA, "good_min.tir"))
        self.assertEqual(t.values, u.values)
        self.assertEqual(t.tables["DEFLECTION_LOAD_CURVE"]["rows"][1], [0.005, 2004.057])
        self.assertEqual(t.tables["SHAPE"]["header"], "{radial width}")


class Units(unittest.TestCase):
    def test_conversion_to_si(self):
        t = tir.read_tir(os.path.join(DATA, "good_units.tir"))
        si = tir.read_tir(os.path.join(DATA, "good_min.tir"))
        close = lambda a, b: self.assertAlmostEqual(a, b, delta=1e-12 * max(1.0, abs(b)))
        close(t.values["UNLOADED_RADIUS"], 0.3135)            # mm
        close(t.values["FNOMIN"], 4000.0)                     # kN
        close(t.values["NOMPRES"], 220000.0)                  # bar
        close(t.values["VERTICAL_STIFFNESS"], 209651.0)       # kN/mm
        close(t.values["LONGVL"], 16.7)                       # mm/ms = m/s
        close(t.values["ALPMAX"], math.radians(30.0))         # deg
        close(t.values["ALPMIN"], -math.radians(30.0))
        # dimensionless MF coefficients are never scaled
        for key in ("PCX1", "PKX1", "PKY1", "QBZ1", "QDZ1", "KPUMIN"):
            self.assertEqual(t.values[key], si.values[key], key)

    def test_unit_tables(self):
        self.assertAlmostEqual(tir.LENGTH_UNITS["inch"], 0.0254)
        self.assertAlmostEqual(tir.LENGTH_UNITS["foot"], 0.3048)
        self.assertAlmostEqual(tir.LENGTH_UNITS["km"], 1000.0)
        self.assertAlmostEqual(tir.FORCE_UNITS["lbf"], 4.4482216152605)
        self.assertAlmostEqual(tir.FORCE_UNITS["kgf"], 9.80665)
        self.assertAlmostEqual(tir.MASS_UNITS["lb"], 0.45359237)
        self.assertAlmostEqual(tir.MASS_UNITS["tonne"], 1000.0)
        self.assertAlmostEqual(tir.TIME_UNITS["hour"], 3600.0)
        self.assertAlmostEqual(tir.PRESSURE_UNITS["psi"], 6894.757293168361)
        self.assertAlmostEqual(tir.PRESSURE_UNITS["kpa"], 1000.0)

    def test_pressure_from_force_and_length(self):
        with open(os.path.join(DATA, "good_min.tir")) as f:
            text = f.read()
        text = text.replace("FORCE = 'newton'", "FORCE = 'kN'").replace("NOMPRES = 220000", "NOMPRES = 220")
        text = text.replace("VERTICAL_STIFFNESS = 209651", "VERTICAL_STIFFNESS = 209.651")
        text = text.replace("FNOMIN = 4000", "FNOMIN = 4")      # 4 MN would be outside its range
        t = tir.validate(tir.parse_text(text, "mem.tir"))
        self.assertAlmostEqual(t.values["NOMPRES"], 220000.0)   # kN/m^2 = kPa


# (fixture, key, line, message fragment); a missing key is reported on its
# section header line (the last line of the file when the section is absent)
BAD = [
    ("bad_missing_key.tir", "FNOMIN", 16, "missing required key in [VERTICAL]"),
    ("bad_fittyp.tir", "FITTYP", 9, "unsupported Magic Formula version 7"),
    ("bad_number.tir", "PCX1", 23, "is not a number"),
    ("bad_unit.tir", "LENGTH", 3, "cannot be converted to SI"),
    ("bad_qs_range.tir", "PKX1", 25, "QS"),
    ("bad_ql_range.tir", "VERTICAL_STIFFNESS", 18, "QL"),
    ("bad_ql_after_units.tir", "NOMPRES", 15, "QL"),
    ("bad_fnomin.tir", "FNOMIN", 17, "must be > 0"),
    ("bad_radius.tir", "UNLOADED_RADIUS", 13, "must be > 0"),
    ("bad_nompres.tir", "NOMPRES", 15, "nominal pressure > 0"),
    ("bad_range.tir", "ALPMAX", 21, "must be greater than ALPMIN"),
    ("bad_syntax.tir", None, 24, "cannot read line"),
    ("bad_quote.tir", "TYRESIDE", 10, "unterminated quoted string"),
    ("bad_duplicate.tir", "PKY1", 30, "duplicate key (first on line 29)"),
    ("bad_outside.tir", "FILE_TYPE", 1, "outside any [SECTION]"),
    ("bad_tyreside.tir", "TYRESIDE", 10, "unknown tyre side"),
]


class Errors(unittest.TestCase):
    def test_every_error_class(self):
        for name, key, line, fragment in BAD:
            path = os.path.join(DATA, name)
            with self.subTest(name=name):
                with self.assertRaises(tir.TirError) as cm:
                    tir.read_tir(path)
                e = cm.exception
                self.assertEqual(e.file, path)
                self.assertEqual(e.line, line)
                self.assertEqual(e.key, key)
                self.assertIn(fragment, e.message)
                s = str(e)
                self.assertTrue(s.startswith(f"{path}:{line}: {key or '-'}: "), s)

    def test_cli_writes_nothing_on_error(self):
        with tempfile.TemporaryDirectory() as d:
            out_c = os.path.join(d, "out.c")
            out_h = os.path.join(d, "out.h")
            for name, key, line, _ in BAD:
                r = run_cli(os.path.join(DATA, name), "--name", "tyre", "-o", out_c, "--header", out_h)
                self.assertEqual(r.returncode, 3, name)       # a data error (file, line, key)
                self.assertIn(f"{name}:{line}: {key or '-'}:", r.stderr)
                self.assertEqual(os.listdir(d), [], name)
            # an existing output is left untouched by a failing run
            with open(out_c, "w") as f:
                f.write("old\n")
            r = run_cli(os.path.join(DATA, "bad_fittyp.tir"), "--name", "tyre", "-o", out_c)
            self.assertEqual(r.returncode, 3)
            with open(out_c) as f:
                self.assertEqual(f.read(), "old\n")
            self.assertEqual(sorted(os.listdir(d)), ["out.c"])

    def test_missing_file(self):
        with self.assertRaises(tir.TirError) as cm:
            tir.read_tir(os.path.join(DATA, "no_such_file.tir"))
        self.assertEqual(cm.exception.line, 0)


class Emitter(unittest.TestCase):
    def _emit(self, d, path, name="tyre", side=None):
        out_c = os.path.join(d, name + ".c")
        out_h = os.path.join(d, name + ".h")
        args = [path, "--name", name, "-o", out_c, "--header", out_h]
        if side:
            args += ["--side", side]
        r = run_cli(*args)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(out_c) as f:
            return f.read(), out_c, out_h

    def test_values_round_trip_and_designated_initializers(self):
        path = os.path.join(golden_mf.shared_data_dir(), "mfeval-tir", "MagicFormula61_Paramerters.tir")
        t = tir.read_tir(path)
        with tempfile.TemporaryDirectory() as d:
            text, _, _ = self._emit(d, path)
        self.assertIn("const grip_mf_params tyre = {", text)
        self.assertIn(".fittyp = 61,", text)
        self.assertIn(".tyreside = -1,", text)
        self.assertIn(".options = 8u,", text)          # mounted as fitted: GRIP_MF_OPT_RIGHT_SIDE
        found = dict(re.findall(r"\.(\w+) = GRIP_Q[SL]\(([^)]*)\)", text))
        coefs = tir.coefficients()
        self.assertEqual(len(found), len(coefs))
        for c in coefs:
            self.assertEqual(float(found[c.field]), t.values[c.key], c.key)   # repr precision
            self.assertIn(f".{c.field} = GRIP_{c.fmt}(", text)

    def test_mounting_side(self):
        # tyreside is always the file's; the mounting side is the options bit,
        # as fitted by default (a RIGHT file mounted right, nothing mirrored)
        path = os.path.join(golden_mf.shared_data_dir(), "mfeval-tir", "MagicFormula61_Paramerters.tir")
        with tempfile.TemporaryDirectory() as d:
            for side, tyreside, options, how in ((None, -1, 8, "as fitted"), ("left", -1, 0, "mirrored"),
                                                 ("right", -1, 8, "as fitted")):
                text = self._emit(d, path, side=side)[0]
                self.assertIn(f".tyreside = {tyreside},", text)
                self.assertIn(f".options = {options}u,", text)
                self.assertIn(how, text)
            path2 = os.path.join(DATA, "good_min.tir")
            for side, options, how in ((None, 0, "as fitted"), ("left", 0, "as fitted"), ("right", 8, "mirrored")):
                text = self._emit(d, path2, side=side)[0]
                self.assertIn(".tyreside = 1,", text)
                self.assertIn(f".options = {options}u,", text)
                self.assertIn(how, text)

    @unittest.skipIf(shutil.which("gcc") is None, "gcc not installed")
    def test_output_compiles_in_both_builds(self):
        with tempfile.TemporaryDirectory() as d:
            for path in shared_files()[:3] + [os.path.join(DATA, "good_units.tir")]:
                _, out_c, out_h = self._emit(d, path, name="tyre")
                for fixed in (0, 1):
                    r = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
                                        "-Wconversion", f"-DGRIP_ARITH_FIXED={fixed}",
                                        "-DGRIP_DEBUG_SATURATION=0", "-Iinclude", "-Itests/support",
                                        f"-I{d}", "-fsyntax-only", out_c],
                                       capture_output=True, text=True, cwd=ROOT)
                    self.assertEqual(r.returncode, 0, r.stderr)

    def test_bad_name(self):
        with tempfile.TemporaryDirectory() as d:
            for bad in ("1abc", "int", "__x", "_Tire", "grip_mf_params"):
                r = run_cli(os.path.join(DATA, "good_min.tir"), "--name", bad, "-o", os.path.join(d, "x.c"))
                self.assertEqual(r.returncode, 2, bad)
                self.assertIn("not a usable C identifier", r.stderr)
            self.assertEqual(os.listdir(d), [])

    def test_missing_output_folder(self):
        with tempfile.TemporaryDirectory() as d:
            r = run_cli(os.path.join(DATA, "good_min.tir"), "--name", "t", "-o", os.path.join(d, "no", "x.c"))
            self.assertEqual(r.returncode, 2)
            self.assertIn("does not exist", r.stderr)
            self.assertNotIn("Traceback", r.stderr)


FIXTURES = os.path.join(ROOT, "tests", "data", "tir")


def quiet_read(path, **kw):
    """read_tir with the warnings collected instead of printed: (Tir, [str])."""
    got = []
    old = tir.set_warning_handler(lambda w: got.append(str(w)))
    try:
        return tir.read_tir(path, **kw), got
    finally:
        tir.set_warning_handler(old)


class Validation(unittest.TestCase):
    """The validation layer (port/linux/tir_rules.h): unknown keys, empty
    values, FITTYP and USE_MODE as MF-Tyre and MFeval define them,
    plausibility ranges, bounds. The C reader gives the same messages
    (tests/python/programs/test_grip_tire.py compares them)."""

    def real_files(self):
        return shared_files() + sorted(glob.glob(os.path.join(ROOT, "docs", "estimator", "**", "*.tir"),
                                                 recursive=True))

    def test_every_real_file_passes_strict_with_no_warning(self):
        files = self.real_files()
        self.assertGreaterEqual(len(files), 14)
        for path in files:
            t, warns = quiet_read(path)
            self.assertEqual(warns, [], path)
            u = tir.read_tir(path, strict=True)
            v = tir.read_tir(path, range_check=False)
            # the checks never change a value read from a valid file
            self.assertEqual(t.values, u.values, path)
            self.assertEqual(t.values, v.values, path)

    def test_rules_cover_every_coefficient(self):
        r = tir.rules()
        self.assertEqual((r.line_max, r.size_max, r.keys_max, r.rows_max), (4096, 4 << 20, 4096, 4096))
        missing = [c.key for c in tir.coefficients() if tir.range_of(c.key) is None]
        self.assertEqual(missing, [], "coefficients without a plausibility range in tir_rules.h")
        for c in tir.coefficients():        # the defaults are plausible (a default is never checked)
            _, kind, lo, hi, _ = tir.range_of(c.key)
            ok = tir._in_range(c.default, kind, lo, hi) or (c.required and c.default == 0.0)
            self.assertTrue(ok, f"{c.key}: default {c.default} outside {kind} [{lo}, {hi}]")

    def test_issue_examples_refused(self):
        for name, key, words in (("range_pdy1.tir", "PDY1", "|v| in [0.05, 10]"),
                                 ("range_pcy1_zero.tir", "PCY1", "[0.1, 5]"),
                                 ("range_radius_mm.tir", "UNLOADED_RADIUS", "[0.01, 3]"),
                                 ("range_fnomin_kn.tir", "FNOMIN", "[20, 1e+06]"),
                                 ("range_alpmax_deg.tir", "ALPMIN", "[-3.2, 3.2]")):
            with self.subTest(name=name):
                path = os.path.join(FIXTURES, name)
                with self.assertRaises(tir.TirError) as cm:
                    tir.read_tir(path)
                self.assertEqual(cm.exception.key, key)
                self.assertIn("outside the plausible range " + words, cm.exception.message)
                self.assertIn("--no-range-check", cm.exception.message)
                tir.read_tir(path, range_check=False)       # the override reads it as given

    def test_unknown_and_misplaced_keys(self):
        t, warns = quiet_read(os.path.join(FIXTURES, "warn_unknown_key.tir"))
        self.assertEqual(len(warns), 2)
        self.assertIn(":29: RBX1X: unknown key in [LONGITUDINAL_COEFFICIENTS]: ignored (did you mean RBX1?)",
                      warns[0])
        self.assertEqual(t.lines["RBX1"], 31)            # ignored: RBX1 comes from its own line
        # the same misspelling in a file without RBX1 would lose its value
        # (RBX1 would take its default): refused, strict or not
        for strict in (False, True):
            with self.assertRaises(tir.TirError) as cm:
                quiet_read(os.path.join(FIXTURES, "typo_key.tir"), strict=strict)
            self.assertEqual((cm.exception.line, cm.exception.key), (29, "RBX1X"))
            self.assertIn("a misspelling of RBX1? The file does not give RBX1, which would take its default 20",
                          cm.exception.message)
        with self.assertRaises(tir.TirError) as cm:
            quiet_read(os.path.join(FIXTURES, "warn_unknown_key.tir"), strict=True)
        self.assertEqual((cm.exception.line, cm.exception.key), (29, "RBX1X"))
        self.assertIn("(refused: strict mode)", cm.exception.message)
        t, warns = quiet_read(os.path.join(FIXTURES, "warn_misplaced.tir"))
        self.assertEqual([w.split(": ", 2)[1] for w in warns], ["WIDTH", "QSX1", "LENGTH"])
        self.assertIn("not from the unknown section [OVERTURNING_COEFFICENTS]", warns[1])
        self.assertEqual(t.values["WIDTH"], 0.0)
        self.assertEqual(t.units["LENGTH"], 1.0)        # LENGTH = 'mm' in [HEADER] is not read
        self.assertEqual(tir.nearest_key("PDY11"), "PDY1")
        self.assertIsNone(tir.nearest_key("XYZ"))
        self.assertIsNone(tir.nearest_key("COMPLETELY_DIFFERENT"))

    def test_empty_values(self):
        t, warns = quiet_read(os.path.join(FIXTURES, "warn_empty.tir"))
        self.assertEqual(len(warns), 4)
        self.assertTrue(all("empty value" in w for w in warns))
        self.assertEqual(t.values["WIDTH"], 0.0)
        self.assertEqual(t.values["ASPECT_RATIO"], 0.6)   # the documented default
        self.assertIsNone(t.use_mode)
        text = "[MODEL]\nFITTYP =\nPROPERTY_FILE_FORMAT = 'MF_61'\n" + \
               open(os.path.join(FIXTURES, "minimal.tir")).read().split("[DIMENSION]", 1)[1].join(["[DIMENSION]", ""])
        old = tir.set_warning_handler(lambda w: None)
        try:
            t = tir.validate(tir.parse_text(text, "mem.tir"), strict=False)
        finally:
            tir.set_warning_handler(old)
        self.assertEqual((t.fittyp, len(t.warnings)), (61, 1))
        with self.assertRaises(tir.TirError) as cm:
            tir.read_tir(os.path.join(FIXTURES, "empty_required.tir"))
        self.assertIn("empty value for a required key", cm.exception.message)

    def test_fittyp_values(self):
        t = tir.read_tir(os.path.join(FIXTURES, "fittyp_52.tir"))
        self.assertEqual((t.fittyp, t.fittyp_file), (21, 52))
        self.assertEqual(t.params()["fittyp"], 21)
        with self.assertRaises(tir.TirError) as cm:
            tir.read_tir(os.path.join(FIXTURES, "fittyp_51.tir"))
        self.assertIn("supported: 5, 6, 21, 52", cm.exception.message)
        self.assertEqual(set(tir.FILE_FITTYP.values()), set(tir.SUPPORTED_FITTYP))

    def test_use_mode(self):
        for name, words in (("use_mode_turnslip.tir", "turn slip per call"), ("use_mode_negative.tir", "mirrors the tyre"),
                            ("use_mode_fy_only.tir", "Fy, Mx and Mz only"), ("use_mode_digit.tir", "tens digit 4"),
                            ("use_mode_uncombined.tir", "uncombined forces"), ("use_mode_text.tir", "not an integer")):
            with self.subTest(name=name):
                with self.assertRaises(tir.TirError) as cm:
                    tir.read_tir(os.path.join(FIXTURES, name))
                self.assertEqual(cm.exception.key, "USE_MODE")
                self.assertIn(words, cm.exception.message)
        t = tir.read_tir(os.path.join(FIXTURES, "use_mode_uncombined.tir"), pure_slip=True)
        self.assertEqual(t.use_mode, 13)
        t = tir.read_tir(os.path.join(FIXTURES, "use_mode_ok.tir"))
        self.assertEqual((t.use_mode, t.params()["tir_use_mode"]), (124, 124))
        uses = {tir.read_tir(p).use_mode for p in shared_files()}
        self.assertEqual(uses, {4, 14, 114, 124})

    def test_bounds(self):
        with tempfile.TemporaryDirectory() as d:
            big = os.path.join(d, "sparse.tir")
            with open(big, "wb") as f:
                f.truncate(1 << 30)
            with self.assertRaises(tir.TirError) as cm:
                tir.read_tir(big)
            self.assertEqual(cm.exception.line, 0)
            self.assertIn("larger than 4194304 bytes", cm.exception.message)
            with self.assertRaises(tir.TirError) as cm:
                tir.read_tir("/dev/zero")
            self.assertEqual(str(cm.exception),
                             "/dev/zero:1: -: NUL byte at byte offset 0 (byte 1 of the line): not a text .tir file")
            keys = os.path.join(d, "keys.tir")
            with open(keys, "w") as f:
                f.write("[MODEL]\n" + "".join(f"K{k} = 1\n" for k in range(5000)))
            with self.assertRaises(tir.TirError) as cm:
                tir.read_tir(keys)
            self.assertEqual(cm.exception.line, 4098)
            self.assertIn("more than 4096 keys", cm.exception.message)
            rows = os.path.join(d, "rows.tir")
            with open(rows, "w") as f:
                f.write("[SHAPE]\n" + "1 2\n" * 5000)
            with self.assertRaises(tir.TirError) as cm:
                tir.read_tir(rows)
            self.assertIn("more than 4096 table rows", cm.exception.message)
        with self.assertRaises(tir.TirError) as cm:
            tir.read_tir(os.path.join(FIXTURES, "long_line.tir"))
        self.assertIn("line longer than 4096 bytes (at byte offset", cm.exception.message)

    def test_cli_options(self):
        path = os.path.join(FIXTURES, "range_pdy1.tir")
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "t.c")
            r = run_cli(path, "--name", "t", "-o", out)
            self.assertEqual(r.returncode, 3)
            self.assertIn("outside the plausible range", r.stderr)
            r = run_cli(path, "--name", "t", "-o", out, "--no-range-check")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("GRIP_QS(30000.0)", open(out).read())
            warn = os.path.join(FIXTURES, "warn_unknown_key.tir")
            r = run_cli(warn, "--name", "t", "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("grip tir2c: warning: " + warn + ":29: RBX1X: unknown key", r.stderr)
            r = run_cli(warn, "--name", "t", "-o", out, "--strict")
            self.assertEqual(r.returncode, 3)
            self.assertIn("(refused: strict mode)", r.stderr)


if __name__ == "__main__":
    unittest.main()
