"""Run the Python tests (stdlib unittest) and print TAP lines, so the
top-level runner counts them with the C tests."""
import os
import sys
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
TESTS = os.path.dirname(HERE)
# The test packages are named after the tool packages (can, loop, ...):
# import them as python.<name> from tests/, never as top-level names from
# this folder, where `can` would hide the python-can package cantools needs.
sys.path[:] = [p for p in sys.path if os.path.abspath(p or ".") != HERE]
# The tools of this clone, also when the environment has them installed.
sys.path.insert(0, os.path.join(TESTS, "..", "tools"))


# a test that takes this long [s] gets a "# slow test" line with its time
SLOW_TEST_S = 10.0


class TapResult(unittest.TextTestResult):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.n = 0

    def startTest(self, test):
        super().startTest(test)
        self._t0 = time.monotonic()

    def _line(self, ok, test, note=""):
        self.n += 1
        print(f"{'ok' if ok else 'not ok'} {self.n} - {test.id()}{note}", flush=True)
        # a class or module fixture's error comes without startTest: no time
        t0, self._t0 = getattr(self, "_t0", None), None
        took = 0.0 if t0 is None else time.monotonic() - t0
        if took >= SLOW_TEST_S:   # for the check's time budget
            print(f"# slow test {test.id()}: {took:.1f} s", flush=True)

    def addSuccess(self, test):
        super().addSuccess(test)
        self._line(True, test)

    def addFailure(self, test, err):
        super().addFailure(test, err)
        self._line(False, test)
        print("# " + self._exc_info_to_string(err, test).replace("\n", "\n# "))

    def addError(self, test, err):
        super().addError(test, err)
        self._line(False, test)
        print("# " + self._exc_info_to_string(err, test).replace("\n", "\n# "))

    def addSubTest(self, test, subtest, err):
        super().addSubTest(test, subtest, err)
        if err is not None:          # a failing subtest fails its test: say so in TAP
            self._line(False, subtest)
            print("# " + self._exc_info_to_string(err, test).replace("\n", "\n# "))

    def addUnexpectedSuccess(self, test):
        super().addUnexpectedSuccess(test)
        self._line(False, test, " # unexpected success")

    def addSkip(self, test, reason):
        super().addSkip(test, reason)
        self._line(True, test, f" # SKIP {reason}")


def iter_tests(suite):
    for t in suite:
        if isinstance(t, unittest.TestSuite):
            yield from iter_tests(t)
        else:
            yield t


# Modules whose tests run as one job per test class (no module-level
# fixtures): the estimator reference's takes most of the step's time alone.
SPLIT_BY_CLASS = ("python.reference.test_est",)
# The longest jobs, measured by the "# module" lines of a check's log,
# started first (the rest follow in name order).
LONG_FIRST = ("python.reference.test_est", "python.reference.test_est_integrity", "python.sim.test_independent",
              "python.loop.test_benchmark", "python.loop.test_attribution", "python.sim.test_model",
              "python.loop.test_grammar", "python.fleet.test_fleet", "python.loop.test_vehicle")


def run_module(item):
    """Worker: run one test module's tests; return its TAP lines and outcome
    (everything it printed, in order)."""
    import contextlib
    import io
    import time
    name, tests = item
    buf = io.StringIO()
    t0 = time.monotonic()
    with contextlib.redirect_stdout(buf):
        runner = unittest.TextTestRunner(resultclass=TapResult, stream=open(os.devnull, "w"), verbosity=0)
        result = runner.run(unittest.TestSuite(tests))
        # each module's wall time, for the schedule of the check's budget
        print(f"# module {name}: {time.monotonic() - t0:.1f} s wall")
    return name, buf.getvalue(), result.testsRun, result.wasSuccessful()


def main():
    # optional arguments: a file pattern (e.g. 'test_grip_tire*.py') and a
    # sub-folder (e.g. reference); the test packages mirror tools/grip_tools/.
    # GRIP_TEST_JOBS=N runs whole modules in N processes (output per module,
    # in module order, numbered as one TAP stream).
    pattern = sys.argv[1] if len(sys.argv) > 1 else "test_*.py"
    start = os.path.join(HERE, sys.argv[2]) if len(sys.argv) > 2 else HERE
    suite = unittest.defaultTestLoader.discover(start, pattern=pattern, top_level_dir=TESTS)
    jobs = int(os.environ.get("GRIP_TEST_JOBS", "1"))
    if jobs <= 1:
        runner = unittest.TextTestRunner(resultclass=TapResult, stream=open(os.devnull, "w"), verbosity=0)
        result = runner.run(suite)
        print(f"1..{result.testsRun}")
        return 0 if result.wasSuccessful() else 1
    import concurrent.futures
    import multiprocessing
    modules = {}
    for t in iter_tests(suite):
        key = type(t).__module__
        if key in SPLIT_BY_CLASS:
            key = f"{key}.{type(t).__name__}"
        modules.setdefault(key, []).append(t)
    items = sorted(modules.items())
    # the longest first, so that no worker is left alone with one at the end
    def rank(item):
        for i, name in enumerate(LONG_FIRST):
            if item[0] == name or item[0].startswith(name + "."):
                return i
        return len(LONG_FIRST)
    order = sorted(items, key=rank)
    # ProcessPoolExecutor's workers are not daemonic, so a test may start
    # processes of its own (a Dask LocalCluster, a multiprocessing pool)
    with concurrent.futures.ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context("fork")) as pool:
        done = {name: (text, n, ok) for name, text, n, ok in pool.map(run_module, order)}
    total, all_ok = 0, True
    for name, _ in items:
        text, n, ok = done[name]
        all_ok = all_ok and ok
        for line in text.splitlines():
            # renumber the module's TAP lines into one stream
            for head in ("ok ", "not ok "):
                if line.startswith(head) and line[len(head):].split(" ", 1)[0].isdigit():
                    total += 1
                    line = f"{head}{total} " + line[len(head):].split(" ", 1)[1]
                    break
            print(line)
    print(f"1..{total}")
    return 0 if all_ok else 1


if __name__ == "__main__":
    sys.exit(main())
