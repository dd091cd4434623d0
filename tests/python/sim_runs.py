"""Reference-simulator runs for the tests, each simulated once per test run.

Many estimator tests judge a switch on the same run (a sine with dwell on
snow, say): the simulator takes 15-40 s a run, the estimator 1 s. run()
keeps each run's output folder under build/test-cache/sim/, named by the
simulator's arguments and by a hash of every source file that can change
its output (the Python tools and the tire files), and copies it into the
caller's folder. A changed simulator, tire model or sensor model is a new
name, so a stale run is never used; `make check` starts from a clean
build/ anyway. GRIP_TEST_SIM_CACHE=0 simulates every time.
"""
import hashlib
import os
import shutil
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
CACHE = os.path.join(REPO, "build", "test-cache", "sim")
# what the simulator's output depends on: its code, the reference models it
# calls, and the tire files it reads
SOURCES = (os.path.join(REPO, "tools", "grip_tools"), os.path.join(REPO, "tests", "data"))
SOURCE_TYPES = (".py", ".tir")

_source_hash = None


def source_hash():
    """sha256 over the path and content of every file the runs depend on."""
    global _source_hash
    if _source_hash is None:
        h = hashlib.sha256()
        for top in SOURCES:
            for d, dirs, files in os.walk(top):
                dirs.sort()
                for f in sorted(files):
                    if f.endswith(SOURCE_TYPES):
                        p = os.path.join(d, f)
                        h.update(os.path.relpath(p, REPO).encode() + b"\0")
                        with open(p, "rb") as fh:
                            h.update(fh.read())
                        h.update(b"\0")
        _source_hash = h.hexdigest()
    return _source_hash


def run(args, out_dir):
    """The simulator's command line `args` (without -o) into out_dir, as
    `grip sim` writes it; from the cache when this source tree already ran it."""
    from grip_tools.sim import cli
    if os.environ.get("GRIP_TEST_SIM_CACHE", "1") == "0":
        cli.main(list(args) + ["-o", out_dir])
        return
    key = hashlib.sha256(("\0".join(args) + "\0" + source_hash()).encode()).hexdigest()[:20]
    cached = os.path.join(CACHE, key)
    if not os.path.isdir(cached):
        os.makedirs(CACHE, exist_ok=True)
        work = tempfile.mkdtemp(prefix=key + ".", dir=CACHE)
        cli.main(list(args) + ["-o", work])
        try:
            os.rename(work, cached)     # atomic: another process may have got there first
        except OSError:
            shutil.rmtree(work, ignore_errors=True)
    shutil.copytree(cached, out_dir, dirs_exist_ok=True)
