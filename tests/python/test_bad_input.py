"""Bad input to the Python tools: every case ends with a non-zero exit and one
line naming file, line and field (grip_tools.errors, grip_tools.channels),
never a traceback and never exit 0. Plus a seeded mutation fuzzer of the
measured-data CSV reader: any mutation either reads or raises DataError."""
import contextlib
import io
import os
import random
import tempfile
import unittest

from grip_tools import channels, cli
from grip_tools.errors import DataError
from grip_tools.paths import TEST_DATA

MF61 = os.path.join(TEST_DATA, "mfeval-tir", "MagicFormula61_Paramerters.tir")

GOOD_FY = "fz[N],alpha[rad],gamma[rad],fy[N]\n" + "".join(
    f"{fz},{a / 100:.3f},0,{-fz * a / 20:.1f}\n" for fz in (2000, 4000, 6000) for a in range(-20, 21, 2))

GOOD_T = "t[s],alpha[rad],fz[N],fy[N]\n" + "".join(f"{i * 0.01:.2f},0.01,4000,-500\n" for i in range(50))


def replace_line(text, n, new):
    lines = text.splitlines(keepends=True)
    lines[n - 1] = new
    return "".join(lines)


# (name, file bytes, command args after the file, exit code, words the message must contain)
CASES = [
    ("empty", b"", ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["{f}:1:", "empty file"]),
    ("header only", b"fz,alpha,fy\n", ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["no data rows"]),
    ("nan cell", replace_line(GOOD_FY, 5, "4000,nan,0,100\n").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["{f}:5:", "alpha", "not a finite number"]),
    ("inf cell", replace_line(GOOD_FY, 7, "4000,0.1,0,inf\n").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["{f}:7:", "fy", "not a finite number"]),
    ("text cell", replace_line(GOOD_FY, 3, "4000,abc,0,100\n").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["{f}:3:", "alpha", "'abc' is not a number"]),
    ("short row", replace_line(GOOD_FY, 4, "4000,0.1\n").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["{f}:4:", "2 fields, the header has 4"]),
    ("three rows", GOOD_FY.encode()[:GOOD_FY.encode().index(b"\n", 60)], ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["free coefficients", "needed"]),
    ("kN labelled N", ("fz[N],alpha[rad],gamma[rad],fy[N]\n" + "".join(
        f"{fz},{a / 100:.3f},0,{-fz * a * 50:.1f}\n" for fz in (2, 4, 6) for a in range(-20, 21, 2))).encode(),
     ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["fz", "kN labelled N"]),
    ("degrees labelled rad", GOOD_FY.replace(",0.200,", ",20.0,").encode(),
     ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["alpha", "degrees?"]),
    ("negative load", GOOD_FY.replace("2000,", "-2000,").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["fz", "-2000"]),
    ("unit deg", GOOD_FY.replace("alpha[rad]", "alpha[deg]").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["{f}:1:", "alpha", "unit [deg]"]),
    ("header typo", GOOD_FY.replace("alpha[rad]", "alpah[rad]").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["alpha", "required column missing", "'alpah'"]),
    ("header typo, no unit", GOOD_FY.replace("alpha[rad]", "alpah").encode(),
     ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["alpah", "did you mean 'alpha'"]),
    ("unknown column", GOOD_FY.replace("gamma[rad]", "camber").encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["camber", "unknown column"]),
    ("duplicate column", GOOD_FY.replace("gamma[rad]", "alpha[rad]").encode(),
     ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["alpha", "duplicate column"]),
    ("NUL byte", replace_line(GOOD_FY, 6, "\0" + "4000,0.1,0,100\n").encode(),
     ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["{f}:6:", "NUL byte"]),
    ("latin-1 byte", replace_line(GOOD_FY, 2, "2000,0.1,0,100\xe9\n").encode("latin-1"),
     ["fit-mf", "{f}", "--model", "fy", "--tir", MF61], 3, ["{f}:2:", "not UTF-8"]),
    ("long line", b"fz,alpha,fy\n" + b"1" * 20000 + b"\n", ["fit-mf", "{f}", "--model", "fy", "--tir", MF61],
     3, ["{f}:2:", "cap"]),
    ("missing file", None, ["fit-mf", "/nonexistent/x.csv", "--model", "fy"], 2, ["cannot open", "/nonexistent/x.csv"]),
    ("brush-verify over no case", None, ["brush-verify", "--cases", "0"], 2, ["--cases: 0", "at least 1"]),
    ("brush-verify bad study", None, ["brush-verify", "--study", "1", "--iters", "4,x"], 2, ["--iters"]),
    ("simulate unknown surface", None, ["simulate", "-s", "ice", "-o", "/tmp/grip-bad-input-sim"], 2,
     ["--surface: 'ice'"]),
    ("est-eval option of another mode", None, ["est-eval", "--manoeuvres", "step-steer", "--out",
                                                "/tmp/grip-bad-input-est"], 2, ["--manoeuvres: only with"]),
    ("analyze unknown generated set", None, ["analyze", "--generate", "3"], 2, ["--generate 3", "one of"]),
    ("analyze benchmark of no set", None, ["analyze", "--benchmark", "0"], 2, ["--benchmark: at least one set"]),
    ("analyze rate 0", None, ["analyze", "--benchmark", "1", "--rate", "0"], 2, ["--rate 0.0"]),
    ("analyze bad holdout", None, ["analyze", "--generate", "load", "--holdout", "blocks:x"], 2, ["--holdout"]),
    ("fit-mf NaN noise", None, ["fit-mf", "--model", "fy", "--synthetic", "/tmp/grip-bad-input-s.csv", "--tir", MF61,
                                "--noise", "nan"], 2, ["--noise nan"]),
    ("comma2k19 bus out of range", None, ["comma2k19", "--bus", "-1", "-o", "/tmp/grip-bad-input-c.log"], 2,
     ["--bus -1"]),
    ("comma2k19 interface name with a space", None, ["comma2k19", "--iface", "can 0", "-o",
                                                     "/tmp/grip-bad-input-c.log"], 2, ["--iface 'can 0'"]),
    ("comma2k19 missing segment", None, ["comma2k19", "--data", "/no/such/segment", "-o",
                                         "/tmp/grip-bad-input-c.log"], 2, ["cannot read", "/no/such/segment"]),
    ("fit-brush text in a number cell", b"kappa,alpha,gamma,fz,vx,fx,fy,mz\n0,0.1,0,4000,20,0,x,1\n",
     ["fit-brush", "--csv", "{f}", "--out", "/tmp/grip-bad-input-fb"], 3, ["{f}:2:", "fy", "not a number"]),
    ("fit-brush missing column", b"kappa,alpha\n0,0.1\n", ["fit-brush", "--csv", "{f}", "--out",
                                                            "/tmp/grip-bad-input-fb"], 3, ["{f}:1:", "missing column"]),
    ("fit-brush exponent out of range", None, ["fit-brush", "--g275", "--n", "0"], 2, ["--n '0'"]),
    ("mf89 three coefficients", None, ["mf89", "--params", "1,2,3"], 2, ["--params '1,2,3'", "18"]),
    ("mf89 reversed load range", None, ["mf89", "--fz-range", "10,2"], 2, ["--fz-range '10,2'"]),
    ("stack malformed expression", None, ["stack", "build", "--public", "("], 2, ["--public '('"]),
    ("missing AV-21 log", None, ["est-eval", "--av21", "/nonexistent/av21.csv", "--out", "/tmp/grip-bad-input-av21"], 2,
     ["cannot open", "/nonexistent/av21.csv"]),
    ("missing tir", GOOD_FY.encode(), ["fit-mf", "{f}", "--model", "fy", "--tir", "/nonexistent/x.tir"], 3,
     ["/nonexistent/x.tir", "cannot open"]),
    ("analyze empty", b"", ["analyze", "{f}", "--tir", MF61], 3, ["{f}:1:", "empty file"]),
    ("analyze no time", GOOD_FY.encode(), ["analyze", "{f}", "--tir", MF61], 3, ["t", "required column missing"]),
    ("analyze time back", replace_line(GOOD_T, 11, "0.05,0.01,4000,-500\n").encode(), ["analyze", "{f}", "--tir", MF61],
     3, ["{f}:11:", "time does not increase"]),
    ("analyze kN", GOOD_T.replace(",4000,", ",4,").encode(), ["analyze", "{f}", "--tir", MF61], 3, ["kN labelled N"]),
    ("analyze degrees", GOOD_T.replace(",0.01,", ",5.0,").encode(), ["analyze", "{f}", "--tir", MF61], 3,
     ["alpha", "degrees?"]),
    ("analyze no output", "t[s],alpha[rad],fz[N]\n0,0.01,4000\n0.01,0.01,4000\n".encode(),
     ["analyze", "{f}", "--tir", MF61], 3, ["no measured output column"]),
    ("analyze unitless extra", GOOD_T.replace("fy[N]", "fy[N]").replace("t[s],", "t[s],temp,", 1)
     .replace(",0.01,4000,", ",20,0.01,4000,").encode(), ["analyze", "{f}", "--tir", MF61], 3,
     ["temp", "needs its unit"]),
    ("est-axle bad judge file", b'{"configs": \n', ["est-axle", "--judge", "{f}", "--runs-dir", "/nonexistent"], 3,
     ["{f}:2:", "not JSON"]),
    ("est-axle missing judge file", None, ["est-axle", "--judge", "/nonexistent/independent.json"], 2,
     ["cannot open", "/nonexistent/independent.json"]),
    ("tir2c missing", None, ["tir2c", "/nonexistent/a.tir", "--name", "t", "-o", "/tmp/x.c"], 3, ["cannot open"]),
    ("unknown command", None, ["no-such-command"], 2, ["unknown command"]),
]


class BadInputCorpus(unittest.TestCase):
    def run_grip(self, args):
        """The grip command in this process (as `grip ARGS`): (exit code, stderr)."""
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                code = cli.main(list(args))
            except SystemExit as e:       # argparse's usage errors
                code = e.code
        return code, err.getvalue()

    def test_corpus(self):
        failures = []
        with tempfile.TemporaryDirectory() as d:
            for i, (name, content, args, code, words) in enumerate(CASES):
                f = os.path.join(d, f"case{i}.csv")
                if content is not None:
                    with open(f, "wb") as fh:
                        fh.write(content)
                argv = [a.replace("{f}", f) for a in args]
                try:
                    rc, stderr = self.run_grip(argv)
                except Exception as e:  # noqa: BLE001 - an escaping exception is the failure reported
                    rc, stderr = None, f"{type(e).__name__}: {e} (escaped the command)"
                problems = []
                if rc != code:
                    problems.append(f"exit {rc}, expected {code}")
                for w in words:
                    if w.replace("{f}", f) not in stderr:
                        problems.append(f"no '{w.replace('{f}', f)}' in the message")
                if problems:
                    failures.append(f"{name}: {'; '.join(problems)}: {stderr.strip()[-300:]}")
        print(f"\n# bad-input corpus (Python tools): {len(CASES) - len(failures)} of {len(CASES)} refused as expected")
        self.assertEqual(failures, [])

    def test_help_states_the_exit_codes(self):
        for command in ("fit-mf", "analyze", "tir2c"):
            out = io.StringIO()
            with contextlib.redirect_stdout(out), self.assertRaises(SystemExit) as cm:
                cli.main([command, "--help"])
            self.assertEqual(cm.exception.code, 0)
            text = " ".join(out.getvalue().split())
            for words in ("exit status:", "2 usage", "3 data"):
                self.assertIn(words, text, command)


class ReaderMutationFuzz(unittest.TestCase):
    """Seeded mutations of a valid file: the reader returns a table or raises
    DataError (a ValueError naming file and line); nothing else escapes."""

    def test_mutations(self):
        rng = random.Random(20261126)
        base = GOOD_T.encode()
        alphabet = b"0123456789.,-+eE\n\r\t #[]\0\xff\xe9nainf"
        n_ok = n_refused = 0
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "m.csv")
            for _ in range(400):
                b = bytearray(base)
                for _ in range(rng.randint(1, 6)):
                    op = rng.randrange(3)
                    pos = rng.randrange(len(b) + 1)
                    if op == 0 and b:
                        del b[min(pos, len(b) - 1)]
                    elif op == 1:
                        b.insert(pos, rng.choice(alphabet))
                    elif b:
                        b[min(pos, len(b) - 1)] = rng.choice(alphabet)
                with open(path, "wb") as fh:
                    fh.write(bytes(b))
                try:
                    t = channels.read_table(path, quiet=True)
                    for v in t.columns.values():
                        self.assertTrue(all(map(lambda x: x == x and abs(x) != float("inf"), v)))
                    n_ok += 1
                except DataError as e:
                    self.assertIn(path, str(e))
                    n_refused += 1
        print(f"\n# reader mutation fuzz: 400 mutations, {n_ok} read, {n_refused} refused with file and line")


if __name__ == "__main__":
    unittest.main()
