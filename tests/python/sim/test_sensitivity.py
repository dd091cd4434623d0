"""grip est-sensitivity (tools/grip_tools/evaluate/sensitivity.py): every
constant of lib/est/est_tuning.h has a class, the override hook changes the
one value asked for and nothing else, and a study build without overrides
is the product build bit for bit."""
import os
import subprocess
import tempfile
import unittest

import numpy as np

from grip_tools.evaluate import est_eval, sensitivity as sens
from grip_tools.golden import est as golden_est
from grip_tools.paths import REPO_ROOT
from grip_tools.reference import est as est_ref

from python.programs.test_grip_replay_csv import inputs, write_csv

PRODUCT = os.path.join(REPO_ROOT, "build", "float-gcc", "bin", "grip-replay")


class ClassTests(unittest.TestCase):
    def test_every_constant_has_a_class(self):
        consts = sens.constants()
        self.assertGreater(len(consts), 50)
        missing, extra = sens.check_classes(consts)
        self.assertEqual(missing, [], "constants of est_tuning.h without a class in sensitivity.CLASSES")
        self.assertEqual(extra, [], "classes of constants est_tuning.h no longer has")
        self.assertTrue(set(sens.CLASSES.values()) <= set(sens.CLASS_TEXT))

    def test_perturbed_constants_are_numbers(self):
        for n, v in sens.constants():
            if sens.CLASSES[n] in sens.PERTURBED:
                float(v)


class ConfigTests(unittest.TestCase):
    """The learners' and the bank observer's constants are studied with
    their part switched on: with it off they do nothing."""

    def test_each_constant_in_the_configuration_it_acts_in(self):
        self.assertEqual(sens.config_of("EST_K_HI"), "generic")
        self.assertEqual(sens.config_of("EST_STF_T"), "learned")
        self.assertEqual(sens.config_of("EST_KX_T"), "learned")
        self.assertEqual(sens.config_of("EST_ROAD_L"), "bank_est")
        for n, _ in sens.constants():
            self.assertIn(sens.config_of(n), sens.CONFIGS)


class OverrideTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def _value(self, name, override=None):
        """The constant as lib/est sees it, through a one-line program."""
        d = self.tmp.name
        src = os.path.join(d, "v.c")
        with open(src, "w") as f:
            f.write('#include <stdio.h>\n#include "est_tuning.h"\nint main(void) { printf("%.17g\\n", (double)('
                    + name + ')); return 0; }\n')
        args = ["gcc", "-std=c99", "-Wall", "-Werror", "-I" + os.path.join(REPO_ROOT, "lib", "est")]
        if override:
            hdr = os.path.join(d, "o.h")
            with open(hdr, "w") as f:
                f.write(override)
            args.append(f'-DGRIP_EST_TUNING_OVERRIDE="{hdr}"')
        exe = os.path.join(d, "v")
        subprocess.run(args + [src, "-o", exe], check=True, capture_output=True)
        return float(subprocess.run([exe], check=True, capture_output=True, text=True).stdout)

    def test_hook_replaces_one_value(self):
        self.assertEqual(self._value("EST_K_HI"), 5.0)
        o = "#undef EST_K_HI\n#define EST_K_HI (2.5)\n"
        self.assertEqual(self._value("EST_K_HI", o), 2.5)
        self.assertEqual(self._value("EST_K_MID", o), 1.5)   # a neighbour unchanged


class VariantBuildTests(unittest.TestCase):
    """A study build: lib/est recompiled, linked with the product's other
    objects."""

    @classmethod
    def setUpClass(cls):
        if not os.path.exists(PRODUCT):
            raise unittest.SkipTest(f"{PRODUCT} not built (make progs)")
        cls.tmp = tempfile.TemporaryDirectory()
        t, value, valid = inputs()
        cls.csv = os.path.join(cls.tmp.name, "in.csv")
        write_csv(cls.csv, t, value, valid)
        cls.base_obj = sens.prepare_base(cls.tmp.name)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def _run(self, exe):
        return est_eval.run_c(exe, golden_est.tire_path(), self.csv)

    def test_no_override_is_the_product(self):
        exe = sens.build_variant(self.tmp.name, self.base_obj, "baseline", {})
        a, b = self._run(exe), self._run(PRODUCT)
        for k in ("beta", "vx", "mu", "fyf", "valid"):
            self.assertTrue(np.array_equal(a[k], b[k], equal_nan=k != "valid"), k)

    def test_learner_constant_moves_the_estimate_in_its_configuration(self):
        # the stiffness learner's constants act only with stiff_est = 1: a
        # learner that never starts (EST_STF_V, its lowest speed, at 1000 m/s)
        # gives the product's output without it and a different one with it
        # (the 12 s drive of the golden sequences: the learner needs more
        # than the 5 s of the other tests to move)
        exe = sens.build_variant(self.tmp.name, self.base_obj, "stf_v", {"EST_STF_V": "1000.0"})
        csv = os.path.join(self.tmp.name, "drive12.csv")
        t, value, valid, _ = golden_est.bicycle_inputs(duration=12.0)
        write_csv(csv, t, value, valid)
        on = ["stiff_est = 1"]
        a_off, b_off = (est_eval.run_c(x, golden_est.tire_path(), csv) for x in (exe, PRODUCT))
        a_on, b_on = (est_eval.run_c(x, golden_est.tire_path(), csv, vehicle_lines=on) for x in (exe, PRODUCT))
        self.assertTrue(np.array_equal(a_off["beta"], b_off["beta"], equal_nan=True))
        d = float(np.nanmax(np.abs(a_on["beta"] - b_on["beta"])))
        print(f"\n  stiff_est = 1: beta moves up to {d:.2e} rad with the learner held off")
        self.assertGreater(d, 0.0)

    def test_override_moves_the_estimate(self):
        # the lateral observer starting at 30 m/s instead of 3 m/s never runs
        # on this slower drive: beta is never flagged valid
        exe = sens.build_variant(self.tmp.name, self.base_obj, "v_on", {"EST_V_ON": "30.0", "EST_V_OFF": "29.0"})
        a, b = self._run(exe), self._run(PRODUCT)
        vb = lambda r: int(np.sum((r["valid"] & est_ref.V_BETA) != 0))   # noqa: E731
        print(f"\n  beta valid steps: product {vb(b)}, EST_V_ON 30 m/s {vb(a)}")
        self.assertGreater(vb(b), 100)
        self.assertEqual(vb(a), 0)


if __name__ == "__main__":
    unittest.main()
