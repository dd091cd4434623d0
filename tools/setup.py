"""Build of the C extensions of the `grip` binding (everything else of the
package is declared in pyproject.toml).

cffi generates the wrapper of each arithmetic from grip/_build.py; the
library objects it links are compiled here, with the Makefile's flags for
lib/ (grip/_build.py: lib_cflags), not with Python's CFLAGS, by the compiler
setuptools chose for the extension ($CC, else Python's). Build folders go
under the clone's build/python (ignored by git), as the Makefile's go under
build/.
"""
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

from setuptools import setup
from setuptools.command.build_ext import build_ext as _build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "grip"))
import _build as gb  # noqa: E402  (grip/_build.py, without importing the package)

sys.path.pop(0)


def _newer(target, deps):
    if not os.path.exists(target):
        return True
    t = os.path.getmtime(target)
    return any(os.path.getmtime(d) > t for d in deps)


class build_ext(_build_ext):
    def pre_run(self, ext, ffi):
        # cffi's hook, called with each extension and its FFI builder
        ext.grip_arith = getattr(ffi, "grip_arith", None)

    def _compiler_cmd(self):
        cmd = []
        for a in self.compiler.compiler_so:
            if a.startswith("-"):
                break
            cmd.append(a)
        return cmd or ["cc"]

    @staticmethod
    def _objects(arith, cc):
        """Where the library objects go: a fixed folder of the clone's build/
        (not setuptools' temporary one, which an editable install deletes),
        one per arithmetic and compiler, so that a test can compare them
        with the Makefile's and a reinstall recompiles only what changed."""
        return os.path.join(gb.REPO, "build", "python", "objects", f"{arith}-{os.path.basename(cc[-1])}")

    def _compile(self, arith, sources, flags, cc):
        headers = [os.path.join(d, f) for d in (gb.GRIP_INC, gb.ARITH_INC, gb.PORT)
                   for f in os.listdir(d) if f.endswith(".h")]
        headers += [os.path.join(r, f) for r, _, fs in os.walk(os.path.join(gb.REPO, "lib"))
                    for f in fs if f.endswith(".h")]
        jobs = []
        objs = []
        for src in sources:
            rel = os.path.relpath(src, gb.REPO)
            obj = os.path.join(self._objects(arith, cc), os.path.splitext(rel)[0] + ".o")
            objs.append(obj)
            if self.force or _newer(obj, [src] + headers):
                os.makedirs(os.path.dirname(obj), exist_ok=True)
                jobs.append(cc + flags + gb.file_cflags(rel) + ["-c", src, "-o", obj])

        def run(cmd):
            print(" ".join(cmd), flush=True)
            p = subprocess.run(cmd, cwd=gb.REPO, capture_output=True, text=True)
            if p.stderr:
                sys.stderr.write(p.stderr)
            if p.returncode != 0:
                raise RuntimeError(f"compiling {cmd[-3]} failed (exit {p.returncode})")

        with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            list(pool.map(run, jobs))
        return objs

    def build_extension(self, ext):
        arith = getattr(ext, "grip_arith", None)
        if arith is not None:
            gb.check_tree()
            cc = self._compiler_cmd()
            lib_objs = self._compile(arith, gb.lib_sources(), gb.lib_cflags(arith), cc)
            port_objs = self._compile(arith, gb.port_sources(), gb.port_cflags(arith), cc)
            ext.extra_objects = lib_objs + port_objs
            # relink when an object, or how they are built, changed
            ext.depends = list(ext.depends or []) + ext.extra_objects + [
                os.path.abspath(__file__), os.path.join(gb.HERE, "_build.py")]
            try:
                version = subprocess.run(cc + ["--version"], capture_output=True, text=True,
                                         timeout=60).stdout.splitlines()[0]
            except (OSError, IndexError, subprocess.SubprocessError):
                version = "?"
            info = {"arith": arith, "compiler": cc, "compiler_version": version,
                    "lib_cflags": gb.lib_cflags(arith), "port_cflags": gb.port_cflags(arith),
                    "lib_sources": [os.path.relpath(s, gb.REPO) for s in gb.lib_sources()],
                    "port_sources": [os.path.relpath(s, gb.REPO) for s in gb.port_sources()],
                    "objects": self._objects(arith, cc),
                    "repository": gb.REPO}
            ext.define_macros = [m for m in ext.define_macros if m[0] != "GRIP_PY_BUILD"]
            ext.define_macros.append(("GRIP_PY_BUILD", gb.c_string(json.dumps(info))))
        super().build_extension(ext)


setup(
    cffi_modules=["grip/_build.py:ffi_float", "grip/_build.py:ffi_fixed"],
    cmdclass={"build_ext": build_ext},
    options={"build": {"build_base": os.path.join(gb.REPO, "build", "python")}},
)
