"""Bounded memory of the Python readers (docs/guarantees.md, "Limits"): each
reader of untrusted files, given /dev/zero, a 1 GiB sparse file and the
largest file of short lines it accepts, ends with its data error while a
resource limit allows it 64 MiB of address space more than the process had
after its imports (RLIMIT_AS in a child process: a reader that grew with
its input would end in MemoryError instead). The C readers' limits are
cases of the bad-input corpus (tests/badinput, option `mem`).

Readers: grip_tools.reference.tir.read_tir (.tir), grip_tools.channels.
read_table (measured-data CSV), grip_tools.reference.brush.read_params
(brush-model parameter files), grip_tools.can.dbc.load_map (CAN map files)
and grip_tools.can.dbcfile.load (DBC files).
"""
import os
import subprocess
import sys
import tempfile
import unittest

from grip_tools.paths import REPO_ROOT

MEM = 64 << 20

CHILD = r"""
import resource, sys
sys.path.insert(0, sys.argv[1])
import numpy
from grip_tools import channels
from grip_tools.can import dbc, dbcfile
from grip_tools.reference import brush, tir

READERS = {
    "tir": tir.read_tir,
    "csv": lambda p: channels.read_table(p, quiet=True),
    "brush": brush.read_params,
    "map": dbc.load_map,
    "dbc": lambda p: dbcfile.load([p]),
}


def vm_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    raise SystemExit("no VmSize")


reader, path, extra = READERS[sys.argv[2]], sys.argv[3], int(sys.argv[4])
tir.set_warning_handler(lambda w: None)
limit = vm_bytes() + extra
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
try:
    reader(path)
    print("ACCEPTED")
except MemoryError:
    print("MemoryError")
    sys.exit(9)
except Exception as e:  # noqa: BLE001 - the reader's data error is the expected outcome
    print(f"{type(e).__name__}: {e}"[:300])
"""


def run_reader(kind, path):
    p = subprocess.run([sys.executable, "-c", CHILD, os.path.join(REPO_ROOT, "tools"), kind, path, str(MEM)],
                       capture_output=True, text=True, timeout=300)
    return p.returncode, (p.stdout + p.stderr).strip()


class ReaderMemory(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        cls.sparse = os.path.join(d, "sparse_1g")
        with open(cls.sparse, "wb") as f:
            f.truncate(1 << 30)
        # the largest inputs each reader takes, of the shortest lines or cells
        cls.big = {}
        cls.big["tir"] = os.path.join(d, "big.tir")
        with open(cls.big["tir"], "w") as f:      # 4 MiB of one-character comment lines
            f.write("$\n" * ((4 << 20) // 2))
        cls.big["csv"] = os.path.join(d, "big.csv")
        with open(cls.big["csv"], "w") as f:      # 60 MB of one-digit cells
            f.write("a[-],b[-],c[-],d[-]\n")
            row = "0,0,0,0\n" * 4096
            for _ in range(60 * (1 << 20) // len(row)):
                f.write(row)
        cls.big["brush"] = os.path.join(d, "big.txt")
        with open(cls.big["brush"], "w") as f:
            f.write("#\n" * 499000)
        cls.big["map"] = os.path.join(d, "big.toml")
        with open(cls.big["map"], "w") as f:
            f.write("#\n" * ((1 << 20) // 2))
        cls.big["dbc"] = os.path.join(d, "big.dbc")
        with open(cls.big["dbc"], "w") as f:
            f.write("ab\n" * ((2 << 20) // 3))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_reader(self):
        out = []
        for kind in ("tir", "csv", "brush", "map", "dbc"):
            for name, path in (("/dev/zero", "/dev/zero"), ("1 GiB sparse", self.sparse), ("largest", self.big[kind])):
                with self.subTest(reader=kind, input=name):
                    rc, text = run_reader(kind, path)
                    self.assertNotIn("MemoryError", text, f"{kind} on {name}")
                    self.assertEqual(rc, 0, text)
                    out.append(f"{kind:5s} {name:13s} {text[:110]}")
        print("\n# under +64 MiB of address space:\n# " + "\n# ".join(out))


if __name__ == "__main__":
    unittest.main()
