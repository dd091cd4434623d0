"""The bad-input corpus (tests/badinput/cases.tsv): each case runs a program
on a malformed or hostile input and passes if the program exits with the
expected code (never 0) and its standard error holds every expected word
(the file, the line or row, the field). Prints TAP lines
(`ok N - id` / `not ok N - id`); exit status 0 if every case passed.

    python3 tests/badinput/run_badinput.py [--bin DIR] [--only PROGRAM] [--no-mem] [ID ...]

--bin: the directory of grip-replay and grip-tire (default
build/float-gcc/bin). --no-mem: skip (TAP SKIP) the cases run under the
64 MiB address-space limit, for sanitizer builds (ASan reserves far more
address space than that). --only grip runs the Python tools' cases (the
`grip` command, `python -m grip_tools` of this clone), which do not depend
on a build. Cases marked `todo=...` are known failures: printed as
`not ok ... # TODO ...` (TAP: expected to fail) and not counted in the exit
status; one that passes is reported as `ok ... # TODO ...`, so the mark can
be removed.

cases.tsv, one case a line, tab-separated, '#' comments:
    ID  EXIT  OPTIONS  ARGS  WORDS
ARGS are the program's arguments (split at blanks). Placeholders:
    {in:NAME}   tests/badinput/inputs/NAME (make_inputs.py writes them)
    {gen:NAME}  a file GENERATED[NAME] makes in a temporary directory
    {fix:NAME}  tests/data/tir/NAME (the .tir reader's fixtures)
    {tir} {log} {sigtab}   the bundled tire, RAV4 log and RAV4 signal table
    {tmp}       the temporary directory
OPTIONS, comma-separated ('-' for none):
    mem         run under an address-space limit of 64 MiB (RLIMIT_AS)
    stdin=ARG   standard input from ARG (a placeholder or a path)
    gone=ARG    ARG must not exist afterwards (an incomplete output removed)
    prog=NAME   the program (default grip-replay): grip-replay, grip-tire (in
                --bin) or grip (the Python tools: python -m grip_tools)
    todo=TEXT   a known failure (TAP TODO)
WORDS: ' | '-separated strings that must all appear in standard error.
"""
import argparse
import os
import random
import resource
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
MEM_LIMIT = 64 << 20
TIMEOUT = 20

GOOD_LOG = [f"({46408.5 + k * 0.0025:017.6f}) vcan0 024#01FE01D541F980BB\n".encode() for k in range(4)]
CSV_HEAD = b"t_s,wheel_speed_fl,wheel_speed_fr,wheel_speed_rl,wheel_speed_rr,steer_angle,yaw_rate,ax,ay"
CSV_ROW = b"%.2f,20,20,20,20,0.01,0.002,0.1,0.3"


def _csv(rows_before, bad_row, extra_col=b""):
    head = CSV_HEAD + (b",comment" if extra_col else b"") + b"\n"
    rows = [CSV_ROW % (k * 0.01) + (b",x" if extra_col else b"") + b"\n" for k in range(rows_before)]
    return head + b"".join(rows) + bad_row + b"\n"


# name -> bytes, or a callable(path) that makes the file
GENERATED = {
    "nul_1000.log": b"\0" * 1000,
    "nul_mid.log": b"".join(GOOD_LOG[:2]) + b"(0000046408.510000) vcan0 024#01FE\0" + b"1D541F980BB\n",
    "high_byte.log": b"".join(GOOD_LOG[:3]) + b"(0000046408.510000) vcan\xe9 024#01FE01D541F980BB\n",
    "control_byte.log": GOOD_LOG[0] + b"(0000046408.510000) vcan0 024#01FE\x01D541F980BB\n",
    "bom.log": b"\xef\xbb\xbf" + b"".join(GOOD_LOG),
    "random.bin": (lambda rng: bytes(rng.getrandbits(8) for _ in range(4096)))(random.Random(1)),
    "nul.csv": _csv(2, b"0.02,20,20,2\x000,20,0.01,0.002,0.1,0.3"),
    "bad_utf8.csv": _csv(2, b"0.02,20,20,20,20,0.01,0.002,0.1,0.3,caf\xff", extra_col=True),
    "overlong_utf8.csv": _csv(1, b"0.01,20,20,20,20,0.01,0.002,0.1,0.3,\xc0\xaf", extra_col=True),
    "surrogate_utf8.csv": _csv(1, b"0.01,20,20,20,20,0.01,0.002,0.1,0.3,\xed\xa0\x80", extra_col=True),
    "escape.csv": _csv(3, b"0.03,20,20,20,20,0.01,\x1b[0m,0.1,0.3"),
    "tire_nul_row.csv": b"kappa,alpha,gamma,fz,p,vx\n0,0.01,0,4000,0,10\n\0,0.02,0,4000,0,10\n0,0.03,0,4000,0,10\n",
    "tire_nul_mid.csv": b"kappa,alpha,gamma,fz,p,vx\n0,0.0\x001,0,4000,0,10\n0,0.03,0,4000,0,10\n",
    "tire_control.csv": b"kappa,alpha,gamma,fz,p,vx\n0,\x01.01,0,4000,0,10\n",
    "tire_bad_utf8.csv": b"kappa,alpha,gamma,fz,p,vx,note\n0,0.01,0,4000,0,10,caf\xff\n",
    "tire_escape.csv": b"kappa,alpha,gamma,fz,p,vx\n0,0.01,0,\x1b[0m4000,0,10\n",
    "tire_nul_header.csv": b"kappa\0,alpha,gamma,fz,p,vx\n0,0.01,0,4000,0,10\n",
    "tire_zeros.csv": b"kappa,alpha,gamma,fz,p,vx\n" + b"\0" * 100000,
    "tire_long_row.csv": b"kappa,alpha,gamma,fz,p,vx\n0,0.01,0,4000,0,10\n0,0.01,0,4000,0,10" + b"0" * 70000 + b"\n",
    "brush_nul.txt": b"model = fiala\nmu = 0.\x009\n",
    "many_keys.tir": b"[MODEL]\n" + b"".join(b"K%d = 1\n" % k for k in range(5000)),
    "many_rows.tir": b"[SHAPE]\n" + b"1.0 0.5\n" * 5000,
    "nul.sigtab": b"grip-can-table 1 rav4\nmsg KINEMATICS 0x24 8 12000\0 none 0 0 0 intel\n",
    "nul.veh": b"mass = 1600\niz = 26\x0000\n",
    "big_noline.bin": b"A" * (4 << 20),
    "many_frames.log": lambda p: _write(p, b"".join(b"(0000046408.500000) vcan0 024#01FE01D541F980BB\n"
                                                    for _ in range(70000))),
    "sparse_1g": lambda p: _sparse(p, 1 << 30),
    "big.tir": lambda p: _write(p, b"[MODEL]\n" + b"FITTYP = 61\n" * 400000),
}


def _write(path, data):
    with open(path, "wb") as f:
        f.write(data)


def _sparse(path, size):
    with open(path, "wb") as f:
        f.truncate(size)


def read_cases(path):
    cases = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            parts = line.split("\t")
            if len(parts) != 5:
                raise SystemExit(f"{path}:{n}: {len(parts)} tab-separated fields, expected 5")
            cid, code, opts, args, words = parts
            opt = {}
            if opts.strip() != "-":
                for o in opts.split(","):
                    k, _, v = o.partition("=")
                    opt[k.strip()] = v.strip() or True
            cases.append(dict(id=cid.strip(), exit=int(code), opts=opt, args=args.split(),
                              words=[w.strip() for w in words.split(" | ") if w.strip()], line=n))
    return cases


class Env:
    def __init__(self, tmp):
        self.tmp = tmp
        self.made = {}

    def gen(self, name):
        if name not in self.made:
            path = os.path.join(self.tmp, name)
            g = GENERATED[name]
            if callable(g):
                g(path)
            else:
                _write(path, g)
            self.made[name] = path
        return self.made[name]

    def expand(self, a):
        out = a
        while "{" in out:
            i = out.index("{")
            j = out.index("}", i)
            key = out[i + 1:j]
            if key.startswith("in:"):
                v = os.path.join(HERE, "inputs", key[3:])
            elif key.startswith("gen:"):
                v = self.gen(key[4:])
            elif key.startswith("fix:"):
                v = os.path.join(ROOT, "tests", "data", "tir", key[4:])
            elif key == "tir":
                v = os.path.join(ROOT, "tests", "data", "mfeval-tir", "PacejkaBook_Defaults.tir")
            elif key == "log":
                v = os.path.join(ROOT, "tests", "data", "comma2k19-rav4", "rav4_bus0.log")
            elif key == "sigtab":
                v = os.path.join(ROOT, "tests", "data", "comma2k19-rav4", "rav4.sigtab")
            elif key == "tmp":
                v = self.tmp
            else:
                raise SystemExit(f"unknown placeholder {{{key}}}")
            out = out[:i] + v + out[j + 1:]
        return out


def limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (MEM_LIMIT, MEM_LIMIT))


def command(prog, bindir):
    """The argv prefix of a case's program."""
    if prog == "grip":
        py = os.path.join(ROOT, ".venv", "bin", "python")
        return [py if os.path.exists(py) else sys.executable, "-m", "grip_tools"]
    return [os.path.join(bindir, prog)]


def run_case(c, env, bindir):
    prog = command(c["opts"].get("prog", "grip-replay"), bindir)
    args = [env.expand(a) for a in c["args"]]
    stdin = subprocess.DEVNULL
    if "stdin" in c["opts"]:
        stdin = open(env.expand(c["opts"]["stdin"]), "rb")
    gone = env.expand(c["opts"]["gone"]) if "gone" in c["opts"] else None
    t0 = time.monotonic()
    try:
        env_vars = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "tools"), PYTHONDONTWRITEBYTECODE="1")
        p = subprocess.run(prog + args, stdin=stdin, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                           timeout=TIMEOUT, preexec_fn=limit_memory if "mem" in c["opts"] else None, env=env_vars,
                           cwd=env.tmp)
        rc, err = p.returncode, p.stderr.decode("utf-8", "replace")
    except subprocess.TimeoutExpired as e:
        rc, err = "timeout", (e.stderr or b"").decode("utf-8", "replace")
    finally:
        if stdin is not subprocess.DEVNULL:
            stdin.close()
    dt = time.monotonic() - t0
    problems = []
    if rc != c["exit"]:
        problems.append(f"exit {rc}, expected {c['exit']}")
    if rc == 0:
        problems.append("exit 0 on bad input")
    missing = [w for w in c["words"] if w not in err]
    if missing:
        problems.append("message lacks " + ", ".join(repr(w) for w in missing))
    if not err.strip():
        problems.append("no message")
    if gone is not None and os.path.exists(gone):
        problems.append(f"{gone} left behind")
    return problems, err, dt


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "float-gcc", "bin"))
    ap.add_argument("--only", help="only the cases of these programs (comma-separated: grip-replay, grip-tire, grip)")
    ap.add_argument("--cases", default=os.path.join(HERE, "cases.tsv"))
    ap.add_argument("--no-mem", action="store_true", help="skip the memory-limited cases (sanitizer builds)")
    ap.add_argument("ids", nargs="*")
    a = ap.parse_args(argv)
    a.bin = os.path.abspath(a.bin)      # the cases run in a temporary directory
    cases = read_cases(a.cases)
    ids = [c["id"] for c in cases]
    dup = {i for i in ids if ids.count(i) > 1}
    if dup:
        raise SystemExit(f"{a.cases}: duplicate case ids {sorted(dup)}")
    if a.only:
        only = set(a.only.split(","))
        cases = [c for c in cases if c["opts"].get("prog", "grip-replay") in only]
    if a.ids:
        cases = [c for c in cases if c["id"] in a.ids]
    for prog in sorted({c["opts"].get("prog", "grip-replay") for c in cases} - {"grip"}):
        if not os.path.exists(os.path.join(a.bin, prog)):
            raise SystemExit(f"{os.path.join(a.bin, prog)} not built (make progs)")
    print(f"1..{len(cases)}")
    failed = 0
    t_all = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="grip-badinput-") as tmp:
        env = Env(tmp)
        for n, c in enumerate(cases, 1):
            if a.no_mem and "mem" in c["opts"]:
                print(f"ok {n} - {c['id']} # SKIP memory limit (--no-mem)")
                continue
            problems, err, dt = run_case(c, env, a.bin)
            todo = c["opts"].get("todo")
            note = f" # TODO {todo}" if todo else ""
            name = f"{c['id']} ({c['opts'].get('prog', 'grip-replay')}, exit {c['exit']})"
            if problems:
                print(f"not ok {n} - {name}{note}")
                print(f"#   cases.tsv:{c['line']}: " + "; ".join(problems))
                for l in err.strip().splitlines()[:4]:
                    print(f"#   stderr: {l[:300]}")
                failed += 0 if todo else 1
            else:
                print(f"ok {n} - {name}{note}")
            if dt > 5:
                print(f"#   slow: {dt:.1f} s")
    print(f"# {len(cases)} cases, {failed} failed, {time.monotonic() - t_all:.1f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
