"""How the binding was built: the library objects are compiled with the
Makefile's command for lib/ (the recipe of its -fPIC objects, `make shlib`,
less -Werror; every source, every flag, the per-file flags of
lib/mf/mf_lanes.c included), and their machine code is the
Makefile's: the largest sources of each module are compiled here with the
recipe `make -n` prints, and the code and read-only data of the two objects
are compared byte for byte (objdump). Also: the
struct table the extensions carry is the headers' (cffi checked the
offsets when it built them)."""
import os
import shlex
import shutil
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor

import grip
from . import common
from .common import ARITHS, ROOT


def make_recipe(arith, src):
    """The Makefile's command for the -fPIC object of src, as a list."""
    rel = os.path.relpath(src, ROOT)
    obj = f"build/{arith}-gcc/pic/{os.path.splitext(rel)[0]}.o"
    p = subprocess.run(["make", "--no-print-directory", "-n", "-B", f"ARITH={arith}", "CC=gcc", obj], cwd=ROOT,
                       capture_output=True, text=True, timeout=120)
    if p.returncode != 0:
        raise AssertionError(p.stderr)
    for line in p.stdout.splitlines():
        if f"-c {rel} " in line + " ":
            return shlex.split(line)
    raise AssertionError(f"no compile command for {rel} in:\n{p.stdout}")


SAMPLE = ("lib/mf/mf_eval.c", "lib/mf/mf_lanes.c", "lib/est/est_step.c", "lib/arith/q16.c", "lib/brush/neofiala.c",
          "lib/monitor/monitor.c", "lib/calib/calib.c")
SECTIONS = (".text", ".text.unlikely", ".text.startup", ".rodata", ".rodata.cst4", ".rodata.cst8", ".rodata.cst16",
            ".rodata.str1.1", ".rodata.str1.8", ".data", ".data.rel.ro", ".data.rel.ro.local")


def code_of(obj):
    args = ["objdump", "-d", "-r", "-s"] + [x for s in SECTIONS for x in ("-j", s)] + [obj]
    p = subprocess.run(args, capture_output=True, text=True, timeout=120)
    # the first lines name the file
    return [ln for ln in p.stdout.splitlines()[2:] if not ln.startswith(obj)]


class TestBuild(common.BindingTest):
    def test_flags_are_the_makefiles(self):
        if shutil.which("make") is None:
            self.skipTest("make not installed")
        for arith in ARITHS:
            info = grip.build_info(arith)
            src = os.path.join(ROOT, "lib", "core", "status.c")
            cmd = make_recipe(arith, src)
            flags = [f for f in cmd[1:cmd.index("-c")] if f != "-Werror"]
            norm = [("-I" + os.path.abspath(os.path.join(ROOT, f[2:]))) if f.startswith("-I") else f for f in flags]
            self.assertEqual(norm, info["lib_cflags"], arith)
            self.assertEqual(sorted(info["lib_sources"]),
                             sorted(os.path.relpath(os.path.join(d, f), ROOT)
                                    for d, _, fs in os.walk(os.path.join(ROOT, "lib")) for f in fs if f.endswith(".c")))

    def test_machine_code_is_the_makefiles(self):
        if shutil.which("make") is None or shutil.which("objdump") is None:
            self.skipTest("make or objdump not installed")
        for arith in ARITHS:
            info = grip.build_info(arith)
            if not os.path.isdir(info["objects"]):
                self.skipTest(f"the binding's objects are gone ({info['objects']})")
            if os.path.basename(info["compiler"][-1]) not in ("gcc", "cc"):
                self.skipTest(f"the binding was built with {info['compiler']}, the Makefile's default is gcc")
            with tempfile.TemporaryDirectory() as d:
                def one(rel):
                    cmd = make_recipe(arith, os.path.join(ROOT, rel))
                    out = os.path.join(d, rel.replace("/", "_") + ".o")
                    cmd[cmd.index("-o") + 1] = out
                    subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, timeout=300)
                    mine = os.path.join(info["objects"], os.path.splitext(rel)[0] + ".o")
                    return rel, code_of(out) == code_of(mine), len(code_of(out))

                with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
                    results = list(pool.map(one, SAMPLE))
            differ = [rel for rel, same, _ in results if not same]
            self.assertEqual(differ, [], arith)
            self.assertTrue(all(n > 10 for _, _, n in results))

    def test_struct_table_is_the_headers(self):
        import sys
        sys.path.insert(0, os.path.join(ROOT, "tools", "grip"))
        try:
            import _build
        finally:
            sys.path.pop(0)
        table = _build.struct_table()
        for arith in ARITHS:
            be = grip._core.backend(arith)
            self.assertEqual({k: [tuple(f) for f in v] for k, v in be.structs.items()},
                             {k: [(a, b, list(c), d, e) for a, b, c, d, e in v] for k, v in table.items()})
            for name in table:
                self.assertEqual(be.dtype(name).itemsize, be.ffi.sizeof(name))
