"""CAN tools: the DBC -> table generator (dbc.py), the comma2k19 converter,
and grip-replay's command-line behaviour (when a build is present)."""
import os
import random
import re
import subprocess
import tempfile
import unittest
from fractions import Fraction

import cantools

from grip_tools.logs import comma2k19
from grip_tools.can import dbc
from grip_tools.golden import can as golden_can
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
DATA = os.path.join(ROOT, "tests", "data", "comma2k19-rav4")
MAP = os.path.join(DATA, "rav4_map.toml")
LOG = os.path.join(DATA, "rav4_bus0.log")
SHARED = "/work/shared/data/comma2k19-rav4"


def replay_bin():
    cand = [os.environ.get("GRIP_REPLAY", "")] + \
        [os.path.join(ROOT, "build", v, "bin", "grip-replay") for v in ("float-gcc", "fixed-gcc")]
    for c in cand:
        if c and os.access(c, os.X_OK):
            return c
    return None


class GeneratedFilesTest(unittest.TestCase):
    def test_committed_table_matches_generator(self):
        table, _, mp = dbc.table_from_map(MAP)
        with open(os.path.join(ROOT, "lib", "can", "can_table_rav4.c")) as f:
            self.assertEqual(f.read(), dbc.render_c(table, "tests/data/comma2k19-rav4/rav4_map.toml", mp["dbc"]),
                             "lib/can/can_table_rav4.c is stale: python -m grip_tools can-table "
                             "tests/data/comma2k19-rav4/rav4_map.toml --c lib/can/can_table_rav4.c "
                             "--text tests/data/comma2k19-rav4/rav4.sigtab")
        with open(os.path.join(DATA, "rav4.sigtab")) as f:
            self.assertEqual(f.read(), dbc.render_text(table))

    def test_inputs_match_the_c_header(self):
        with open(os.path.join(ROOT, "include", "grip", "grip_signals.h")) as f:
            enum = re.findall(r"GRIP_IN_([A-Z_]+) = (\d+)", f.read())
        names = [(n.lower(), int(i)) for n, i in enum if n != "COUNT"]
        self.assertEqual(names, [(n, i) for i, (n, _, _) in enumerate(dbc.INPUTS)])


class ScalingTest(unittest.TestCase):
    def setUp(self):
        self.table, self.db, mp = dbc.table_from_map(MAP)
        self.ref = golden_can.reference_db(mp["dbc"])   # cantools, the reference decoder

    def test_integer_factors_within_half_a_unit(self):
        for t in self.table.signals:
            if t.role != "value":
                continue
            self.assertLessEqual(abs(Fraction(t.K, 2**t.shift) - t.k), Fraction(1, 2**(t.shift + 1)))
            self.assertLessEqual(abs(Fraction(t.C, 2**t.shift) - t.c), Fraction(1, 2**(t.shift + 1)))
            self.assertLess(abs(t.K), 2**30)
            self.assertLess(abs(t.C), 2**61)
            self.assertGreaterEqual(t.shift, 16)

    def test_exact_decimal_ranges(self):
        frac = next(t for t in self.table.signals if t.name == "STEER_FRACTION")
        # DBC [-0.7|0.7] with factor 0.1: raw -7 and 7 are in range (float64 -7*0.1 is not)
        self.assertEqual((frac.raw_min, frac.raw_max), (-7, 7))
        self.assertLess(-7 * 0.1, -0.7)
        yaw = next(t for t in self.table.signals if t.name == "YAW_RATE")
        lo, hi = yaw.si_exact(yaw.raw_min), yaw.si_exact(yaw.raw_max)
        self.assertTrue(-2 <= lo and hi <= 2)
        self.assertTrue(yaw.si_exact(yaw.raw_min - 1) < -2 and yaw.si_exact(yaw.raw_max + 1) > 2)

    def test_signs_and_units(self):
        ax = next(t for t in self.table.signals if t.name == "ACCEL_X")
        self.assertEqual(ax.k, Fraction("-0.03589"))           # gain -1 in the map
        ws = next(t for t in self.table.signals if t.name == "WHEEL_SPEED_FL")
        self.assertEqual(ws.k, Fraction("0.01") * Fraction(5, 18))   # km/h -> m/s exactly

    def test_extract_mirror_agrees_with_cantools(self):
        rng = random.Random(1)
        msg = self.ref.get_message_by_name("WHEEL_SPEEDS")
        for _ in range(200):
            data = bytes(rng.randrange(256) for _ in range(8))
            raw = msg.decode(data, scaling=False, decode_choices=False)
            for s in msg.signals:
                order = "intel" if s.byte_order == "little_endian" else "motorola"
                self.assertEqual(dbc.extract(data, s.start, s.length, order, int(s.is_signed)), raw[s.name])


class MapErrorTest(unittest.TestCase):
    def build(self, body):
        d = tempfile.mkdtemp()
        p = os.path.join(d, "m.toml")
        dbcs = ", ".join(f'"{os.path.join(DATA, "dbc", n)}"' for n in ("_toyota_2017.dbc", "toyota_new_mc_pt.dbc"))
        with open(p, "w") as f:
            f.write(f'name = "t"\ndbc = [{dbcs}]\n' + body)
        return dbc.table_from_map(p)

    def expect(self, body, text):
        with self.assertRaises(dbc.MapError) as cm:
            self.build(body)
        self.assertIn(text, str(cm.exception))

    def test_mismatches_name_both_sides(self):
        ok = '[messages.KINEMATICS]\nperiod_ms = 12\n'
        self.expect(ok + '[inputs.yaw_rate]\nsignals = "KINEMATIX.YAW_RATE"\n',
                    "DBC/map mismatch: message 'KINEMATIX' is not in the DBC")
        self.expect(ok + '[inputs.yaw_rate]\nsignals = "KINEMATICS.YAW"\n',
                    "DBC/map mismatch: message 'KINEMATICS' (0x24) has no signal 'YAW'")
        self.expect(ok + '[inputs.yaw_rate]\nsignals = "KINEMATICS.YAW_RATE"\nunit = "rad/s"\n',
                    "is in 'deg/s' in the DBC, the map says 'rad/s'")
        self.expect(ok + '[inputs.yaw]\nsignals = "KINEMATICS.YAW_RATE"\n', "unknown estimator input")
        self.expect(ok + '[inputs.ax]\nsignals = "KINEMATICS.YAW_RATE"\n', "input ax needs m/s^2")
        self.expect('[inputs.yaw_rate]\nsignals = "KINEMATICS.YAW_RATE"\nrange = [-2, 2]\n',
                    "no cycle time for KINEMATICS: set period_ms")
        self.expect(ok.replace("period_ms = 12", 'period_ms = 12\nchecksum = "toyota"') +
                    '[inputs.yaw_rate]\nsignals = "KINEMATICS.YAW_RATE"\n',
                    "checksum 'toyota' but KINEMATICS has no CHECKSUM signal")
        self.expect(ok + '[inputs.yaw_rate]\nsignals = ["KINEMATICS.YAW_RATE", "SPEED.SPEED"]\n',
                    "must be in one message")
        self.expect(ok + '[inputs.yaw_rate]\nsignals = "KINEMATICS.YAW_RATE"\nrange = [5, 6]\n',
                    "contains no raw value")
        self.expect(ok + '[messages.NOPE]\nperiod_ms = 1\n[inputs.yaw_rate]\nsignals = "KINEMATICS.YAW_RATE"\n',
                    "[messages.NOPE] is not in the DBC")

    def test_a_valid_small_map(self):
        table, _, _ = self.build('[messages.SPEED]\nperiod_ms = 24\nchecksum = "toyota"\n'
                                 '[inputs.vehicle_speed]\nsignals = "SPEED.SPEED"\n')
        self.assertEqual(len(table.messages), 1)
        self.assertEqual(table.messages[0].checksum_byte, 7)


class Comma2k19Test(unittest.TestCase):
    def test_log_frames_have_their_dbc_length_and_valid_checksums(self):
        db = dbc.load_dbc([os.path.join(DATA, "dbc", n) for n in ("_toyota_2017.dbc", "toyota_new_mc_pt.dbc")])
        lengths = {m.frame_id: m.length for m in db.messages}
        frames = golden_can.read_candump(LOG)
        self.assertEqual(len(frames), 53800)
        self.assertTrue(all(b[0] >= a[0] for a, b in zip(frames, frames[1:])), "log not in time order")
        bad_len = [(i, len(d)) for _, i, d in frames if i in lengths and len(d) < lengths[i]]
        self.assertEqual(bad_len, [])
        speed = [d for _, i, d in frames if i == 0xB4]
        self.assertEqual(len(speed), 2487)
        self.assertTrue(all(dbc.toyota_checksum(0xB4, d, 7) == d[7] for d in speed))

    @unittest.skipUnless(os.path.isdir(SHARED), "comma2k19 arrays not on this machine")
    def test_converter_reproduces_the_committed_log(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "x.log")
            n = comma2k19.convert(SHARED, out, 0, "vcan0", [os.path.join(DATA, "dbc", "_toyota_2017.dbc"),
                                                            os.path.join(DATA, "dbc", "toyota_new_mc_pt.dbc")])
            self.assertEqual(n, 53800)
            with open(out) as a, open(LOG) as b:
                self.assertEqual(a.read(), b.read())

    @unittest.skipUnless(os.path.isdir(SHARED), "comma2k19 arrays not on this machine")
    def test_decoded_log_matches_the_processed_arrays(self):
        # the README's check: processed wheel_speed == WHEEL_SPEEDS / 3.6
        import numpy as np
        db = golden_can.reference_db([os.path.join(DATA, "dbc", n) for n in ("_toyota_2017.dbc", "toyota_new_mc_pt.dbc")])
        ws = np.load(os.path.join(SHARED, "processed_log", "CAN", "wheel_speed", "value"))
        sa = np.load(os.path.join(SHARED, "processed_log", "CAN", "steering_angle", "value"))
        frames = golden_can.read_candump(LOG)
        wheel = [db.decode_message(0xAA, d) for _, i, d in frames if i == 0xAA]
        steer = [db.decode_message(0x25, d) for _, i, d in frames if i == 0x25]
        self.assertEqual(len(wheel), len(ws))
        got = np.array([[w["WHEEL_SPEED_FL"], w["WHEEL_SPEED_FR"], w["WHEEL_SPEED_RL"], w["WHEEL_SPEED_RR"]]
                        for w in wheel]) / 3.6
        self.assertLess(np.max(np.abs(got - ws)), 1e-9)
        # comma's steering angle is the coarse angle plus the fraction, as the map adds them
        self.assertLess(np.max(np.abs(np.array([s["STEER_ANGLE"] + s["STEER_FRACTION"] for s in steer]) - sa)),
                        1e-9)


@unittest.skipUnless(replay_bin(), "grip-replay not built (make progs)")
class ReplayCliTest(unittest.TestCase):
    def run_replay(self, *args, stdin=None):
        return subprocess.run([replay_bin(), *args], capture_output=True, text=True, input=stdin, timeout=60)

    def test_rav4_log(self):
        with tempfile.TemporaryDirectory() as d:
            csv = os.path.join(d, "out.csv")
            dump = os.path.join(d, "dump.log")
            r = self.run_replay(LOG, "-o", csv, "--dump", dump)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("53800 read", r.stderr)
            self.assertIn("17409 decoded", r.stderr)
            self.assertIn("decode errors  0", r.stderr)
            self.assertIn("5999 steps written", r.stderr)
            with open(csv) as f:
                rows = f.read().splitlines()
            self.assertEqual(len(rows), 6000)
            self.assertTrue(rows[0].startswith("t_s,step,wheel_speed_fl,wheel_speed_fl_fault"))
            # the dump of a replay is the log again, byte for byte
            with open(dump) as a, open(LOG) as b:
                self.assertEqual(a.read(), b.read())

    def test_time_offset_shifts_steps(self):
        r = self.run_replay(LOG, "-n", "200", "--time-offset-us", "-46408000000", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout.splitlines()[1].split(",")[0], "0.590000")

    def test_malformed_line_names_its_line(self):
        with tempfile.TemporaryDirectory() as d:
            p = os.path.join(d, "bad.log")
            with open(LOG) as f, open(p, "w") as g:
                lines = [next(f) for _ in range(10)]
                lines[6] = lines[6].replace("#", "#Z")
                g.writelines(lines)
            r = self.run_replay(p, "-o", os.devnull)
            self.assertEqual(r.returncode, 4)
            self.assertIn("bad.log:7: malformed candump line: data: not a hex digit", r.stderr)

    def test_unreadable_file_and_missing_interface(self):
        r = self.run_replay("/nonexistent/x.log")
        self.assertEqual(r.returncode, 4)
        self.assertIn("cannot open log file /nonexistent/x.log: No such file or directory", r.stderr)
        r = self.run_replay("-i", "nosuchcan0", "-d", "0.1")
        self.assertEqual(r.returncode, 4)
        self.assertIn("no CAN interface 'nosuchcan0'", r.stderr)

    def test_dbc_map_mismatch(self):
        other = "(0000000001.000000) vcan0 123#0011223344556677\n" * 50
        r = self.run_replay("-", stdin=other)
        self.assertEqual(r.returncode, 3)
        self.assertIn("DBC/map mismatch: none of the 50 frames", r.stderr)
        self.assertIn("0x024 0x025 0x0AA 0x0B4", r.stderr)
        with tempfile.TemporaryDirectory() as d:
            p = os.path.join(d, "t.sigtab")
            with open(os.path.join(DATA, "rav4.sigtab")) as f:
                text = f.read().replace("sig YAW_RATE yaw_rate", "sig YAW_RATE yaw_rte")
            with open(p, "w") as f:
                f.write(text)
            r = self.run_replay("-t", p, LOG)
            self.assertEqual(r.returncode, 3)
            self.assertRegex(r.stderr, r"t\.sigtab:\d+: sig line: unknown input name")

    def test_text_table_gives_the_same_csv(self):
        a = self.run_replay(LOG, "-q")
        b = self.run_replay(LOG, "-q", "-t", os.path.join(DATA, "rav4.sigtab"))
        self.assertEqual(a.returncode, 0)
        self.assertEqual(a.stdout, b.stdout)


if __name__ == "__main__":
    unittest.main()
