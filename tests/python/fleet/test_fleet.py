"""grip fleet on a small simulated fleet: a 2-worker LocalCluster gives the
same tables as a run in one process (bit for bit; both through the
in-process binding backend when it is built), a rerun does no work, a
changed log is recomputed, a corrupt log is an error row, a killed worker
loses no result; analyze and report read the results; the candump and
Parquet inputs; the binding and subprocess backends give the same rows bit
for bit on logs of every kind (and the same error message for corrupt
ones); the replay summary parser.

The fleet: grip sim-fleet 50 logs of 2.5 s from three simulated step
steers (dry, wet, snow: one simulator batch), 17 sensor variants each, plus
one corrupt log."""
import contextlib
import io
import os
import shutil
import signal
import tempfile
import time
import unittest

from grip_tools.paths import REPO_ROOT

BIN = {a: os.path.join(REPO_ROOT, "build", f"{a}-gcc", "bin", "grip-replay") for a in ("float", "fixed")}
RAV4_LOG = os.path.join(REPO_ROOT, "tests", "data", "comma2k19-rav4", "rav4_bus0.log")
N = 50

try:
    import dask  # noqa: F401
    import distributed  # noqa: F401
    import pandas  # noqa: F401
    import pyarrow  # noqa: F401
    HAVE_DEPS = True
except ImportError:
    HAVE_DEPS = False

_DIR = None
_CLIENT = None


def binding_missing():
    """Why the fleet's binding backend cannot run here (None: it can)."""
    if not HAVE_DEPS:
        return "no dask"
    from grip_tools.fleet import backend
    return backend.binding_available(("float", "fixed"))


# the backend of the cluster tests: the binding when it is built
BACKEND = ("--backend", "binding") if not binding_missing() else ("--backend", "subprocess")


def setUpModule():
    global _DIR
    if not HAVE_DEPS or not os.path.exists(BIN["float"]):
        return
    from grip_tools.fleet import simfleet
    _DIR = tempfile.mkdtemp(prefix="grip-fleet-test-")
    fleet = os.path.join(_DIR, "fleet")
    simfleet.main([str(N), "--out", fleet, "--duration", "2.5", "--variants", "17",
                   "--manoeuvres", "step-steer", "--workers", "0", "--no-progress"])
    with open(os.path.join(fleet, "logs", "corrupt.csv"), "w") as f:
        f.write("t_s,wheel_speed_fl,wheel_speed_fr\n0.0,12.0,12.0\n0.01,#!garbage,12.0\n")
    import pandas as pd
    m = pd.read_csv(os.path.join(fleet, "manifest.csv"))
    bad = m.iloc[[0]].copy()
    bad["log_id"], bad["path"], bad["truth"] = "corrupt", "logs/corrupt.csv", None
    pd.concat([m, bad]).to_csv(os.path.join(fleet, "manifest.csv"), index=False)


def tearDownModule():
    if _CLIENT is not None:
        from grip_tools.fleet import cluster
        cluster.close_client(_CLIENT)
    if _DIR:
        shutil.rmtree(_DIR, ignore_errors=True)


def client():
    """One 2-worker LocalCluster for the module (its start costs seconds)."""
    global _CLIENT
    if _CLIENT is None:
        from dask.distributed import Client, LocalCluster
        _CLIENT = Client(LocalCluster(n_workers=2, threads_per_worker=1, processes=True, memory_limit="2GiB",
                                      dashboard_address=None))
        _CLIENT.n_workers = 2
    return _CLIENT


def run(out, *extra, cl=None, on_result=None):
    from grip_tools.fleet import run as fr
    a = fr.parse_args([os.path.join(_DIR, "fleet"), "--out", out, "--no-progress", *extra])
    return fr.run_fleet(a, client=cl, on_result=on_result)


def bits_differ(a, b):
    """Where two tables differ bit for bit (schema, row count, then each
    column's validity and the bytes of every value, NaN included): None
    when they are the same, else the first difference in words (the column
    and the first differing row's values)."""
    import pyarrow as pa
    if a.schema != b.schema:
        return f"schema: {a.schema} / {b.schema}"
    if a.num_rows != b.num_rows:
        return f"rows: {a.num_rows} / {b.num_rows}"
    for n in a.column_names:
        x, y = a[n].combine_chunks(), b[n].combine_chunks()
        same = x.is_null().to_pylist() == y.is_null().to_pylist()
        if pa.types.is_floating(x.type):
            same = same and (x.to_numpy(zero_copy_only=False).tobytes() == y.to_numpy(zero_copy_only=False).tobytes())
        else:
            same = same and x.equals(y)
        if not same:
            xl, yl = x.to_pylist(), y.to_pylist()
            k = next((i for i in range(len(xl)) if repr(xl[i]) != repr(yl[i])), 0)
            ids = a["log_id"].to_pylist() if "log_id" in a.column_names else None
            return f"column {n}, row {k}{f' ({ids[k]})' if ids else ''}: {xl[k]!r} / {yl[k]!r}"
    return None


def same_bits(a, b):
    """Two tables equal bit for bit (bits_differ)."""
    return bits_differ(a, b) is None


def table(path, drop=("wall_s", "cpu_s", "rss_peak_mb")):
    import pyarrow.parquet as pq
    t = pq.read_table(path)
    return t.drop_columns([c for c in drop if c in t.column_names])


@unittest.skipUnless(HAVE_DEPS, "dask, distributed, pandas, pyarrow not installed")
@unittest.skipUnless(os.path.exists(BIN["float"]), "build/float-gcc/bin/grip-replay not built")
class FleetRunTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.serial = os.path.join(_DIR, "serial")
        cls.info_serial = run(cls.serial, "--workers", "0", "--steps", *BACKEND)
        cls.dask = os.path.join(_DIR, "dask")
        cls.info_dask = run(cls.dask, "--steps", *BACKEND, cl=client())

    def test_a_every_log_has_a_row(self):
        import pyarrow.parquet as pq
        t = pq.read_table(os.path.join(self.dask, "logs.parquet")).to_pandas()
        self.assertEqual(len(t), N + 1)
        self.assertEqual(list(t["log_id"]), sorted(t["log_id"]))
        ok = t[t["status"] == "ok"]
        self.assertEqual(len(ok), N)
        self.assertTrue(ok["has_truth"].all())
        self.assertTrue(ok["acc_beta_rms_deg"].notna().all())
        self.assertTrue((ok["steps"] == 251).all())
        # the loop's attribution ran on every log (2.5 s moving: enough samples)
        self.assertTrue(ok["attr_scores"].notna().all(), ok["attr_note"].unique())
        self.assertEqual(self.info_dask["computed"], N + 1)
        self.assertEqual(self.info_dask["backend"], "binding" if BACKEND[1] == "binding" else "grip-replay")

    def test_b_cluster_equals_one_process(self):
        """Bit for bit: the logs and bands tables (all columns but the task's
        wall and CPU time and its worker's peak memory)
        and every per-step table."""
        for name in ("logs.parquet", "bands.parquet"):
            s, d = table(os.path.join(self.serial, name)), table(os.path.join(self.dask, name))
            self.assertTrue(same_bits(s, d), name)
        import pyarrow.parquet as pq
        ids = sorted(os.listdir(os.path.join(self.serial, "steps", "arith=float")))
        self.assertEqual(len(ids), N)
        for i in ids:
            p = os.path.join("steps", "arith=float", i, "part-0.parquet")
            self.assertTrue(same_bits(pq.read_table(os.path.join(self.serial, p)),
                                      pq.read_table(os.path.join(self.dask, p))), i)

    def test_c_corrupt_log_is_an_error_row(self):
        import pyarrow.parquet as pq
        t = pq.read_table(os.path.join(self.dask, "logs.parquet")).to_pandas().set_index("log_id")
        r = t.loc["corrupt"]
        self.assertEqual(r["status"], "error")
        self.assertEqual(r["stage"], "decode")
        self.assertIn("not a number", r["error"])
        self.assertIn("#!garbage", r["error"])

    def test_d_rerun_does_no_work(self):
        before = table(os.path.join(self.dask, "logs.parquet"), drop=())
        info = run(self.dask, "--steps", *BACKEND, cl=client())
        self.assertEqual(info["computed"], 0)
        self.assertEqual(info["skipped"], N + 1)
        self.assertTrue(same_bits(before, table(os.path.join(self.dask, "logs.parquet"), drop=())))

    def test_e_changed_log_is_recomputed(self):
        out = os.path.join(_DIR, "changed")
        shutil.copytree(self.serial, out)
        path = os.path.join(_DIR, "fleet", "logs", "sim000007.csv")
        original = open(path).read()
        try:
            with open(path, "a") as f:
                f.write("# a comment: same inputs, other bytes\n")
            info = run(out, "--workers", "0", "--steps", *BACKEND)
        finally:
            with open(path, "w") as f:
                f.write(original)
        self.assertEqual(info["computed"], 1)
        # a different option (no per-step table) changes every hash
        info = run(out, "--workers", "0", "--no-attribution", *BACKEND)
        self.assertEqual(info["computed"], N + 1)

    def test_f_killed_worker_loses_no_result(self):
        out = os.path.join(_DIR, "killed")
        cl = client()
        killed = []

        def kill_one(_):
            if not killed:
                pids = cl.run(os.getpid)
                addr = sorted(pids)[0]
                os.kill(pids[addr], signal.SIGKILL)
                killed.append(addr)
        info = run(out, "--steps", *BACKEND, cl=cl, on_result=kill_one)
        self.assertTrue(killed)
        self.assertEqual(info["rows"], N + 1)
        self.assertIsNone(bits_differ(table(os.path.join(self.serial, "logs.parquet")),
                                      table(os.path.join(out, "logs.parquet"))))
        # the nanny restarts the worker
        deadline = time.time() + 60
        while len(cl.scheduler_info()["workers"]) < 2 and time.time() < deadline:
            time.sleep(0.5)

    def test_f2_stopped_run_keeps_its_rows(self):
        out = os.path.join(_DIR, "stopped")
        seen = []

        def stop(_):
            seen.append(1)
            if len(seen) == 10:
                raise KeyboardInterrupt
        with self.assertRaises(KeyboardInterrupt):
            run(out, "--workers", "0", "--steps", *BACKEND, on_result=stop)
        self.assertFalse(os.path.exists(os.path.join(out, "logs.parquet")))
        info = run(out, "--workers", "0", "--steps", *BACKEND)
        self.assertEqual((info["computed"], info["skipped"]), (N + 1 - 10, 10))
        self.assertFalse(os.path.exists(os.path.join(out, "_journal")))
        self.assertTrue(same_bits(table(os.path.join(self.serial, "logs.parquet")),
                                  table(os.path.join(out, "logs.parquet"))))

    def test_g_analyze_and_report(self):
        import json
        from grip_tools.fleet import analyze, report
        with contextlib.redirect_stdout(io.StringIO()):      # the Markdown it prints
            self.assertEqual(analyze.main([self.dask]), 0)
        a = os.path.join(self.dask, "analysis")
        for f in ("residuals.parquet", "effects.parquet", "analysis.md", "analysis.json"):
            self.assertTrue(os.path.exists(os.path.join(a, f)), f)
        import pandas as pd
        res = pd.read_parquet(os.path.join(a, "residuals.parquet"))
        self.assertEqual(set(res["grouping"]), {"vehicle", "surface", "band", "vehicle+surface+band"})
        self.assertIn("beta_err_deg", set(res["quantity"]))
        # the pooled count is every log's samples
        bands = pd.read_parquet(os.path.join(self.dask, "bands.parquet"))
        yaw = bands[(bands["quantity"] == "yaw_resid") & (bands["arith"] == "float")]
        row = res[(res["grouping"] == "vehicle") & (res["quantity"] == "yaw_resid")].iloc[0]
        self.assertEqual(row["n"], yaw["n"].sum())
        eff = json.load(open(os.path.join(a, "analysis.json")))["effects"]
        self.assertEqual({e["effect"] for e in eff}, {"sensor_bias", "sensor_scale", "sensor_delay"})
        self.assertEqual(report.main([self.dask, "--baseline", self.serial, "--fail-on-regression"]), 0)
        md = open(os.path.join(self.dask, "report", "report.md")).read()
        self.assertIn("**0 regressions**", md)
        for png in ("distributions.png", "accuracy.png"):
            self.assertTrue(os.path.getsize(os.path.join(self.dask, "report", png)) > 1000)

    def test_h_report_finds_a_regression(self):
        import pyarrow as pa
        import pyarrow.compute as pc
        import pyarrow.parquet as pq
        from grip_tools.fleet import report
        worse = os.path.join(_DIR, "worse")
        shutil.copytree(self.serial, worse)
        t = pq.read_table(os.path.join(worse, "logs.parquet"))
        i = t.column_names.index("acc_beta_rms_deg")
        t = t.set_column(i, "acc_beta_rms_deg", pc.add(t["acc_beta_rms_deg"], pa.scalar(1.0)))
        pq.write_table(t, os.path.join(worse, "logs.parquet"))
        self.assertEqual(report.main([worse, "--baseline", self.serial, "--fail-on-regression"]), 1)
        import pandas as pd
        reg = pd.read_csv(os.path.join(worse, "report", "regressions.csv"))
        self.assertEqual(int(((reg["kind"] == "regression") & (reg["metric"] == "acc_beta_rms_deg")).sum()), N)


@unittest.skipUnless(HAVE_DEPS, "dask, distributed, pandas, pyarrow not installed")
@unittest.skipUnless(os.path.exists(BIN["float"]) and os.path.exists(BIN["fixed"]), "grip-replay not built")
class SimFleetOptionsTests(unittest.TestCase):
    """grip sim-fleet refuses what the simulator cannot run with (exit 2,
    the option named) before it plans or writes anything."""

    def test_bad_options_are_refused(self):
        from grip_tools.cli import run_command
        for args, said in ((["--surfaces", "dry,ice"], "unknown surface 'ice'"), (["--surfaces", "0"], "'0'"),
                           (["--dt", "0"], "--dt: 0.0"), (["--duration", "-5"], "--duration: -5.0"),
                           (["--manoeuvres", "nope"], "unknown manoeuvre 'nope'")):
            err = io.StringIO()
            with tempfile.TemporaryDirectory() as d, contextlib.redirect_stderr(err):
                out = os.path.join(d, "fleet")
                code = run_command("sim-fleet", ["2", "--out", out] + args)
                self.assertFalse(os.path.exists(out), args)
            self.assertEqual(code, 2, args)
            self.assertIn(said, err.getvalue(), args)


    def test_a_friction_scale_is_a_surface(self):
        # "dry, wet, snow or numbers": a number written on the command line
        # plans a run on that friction (it raised a ValueError in plan)
        from grip_tools.fleet import simfleet
        runs, _ = simfleet.plan(2, 0, ["step-steer"], ["dry", "0.5"], 1)
        self.assertEqual([r["mu"] for r in runs], [1.0, 0.5])


class FleetRunOptionsTests(unittest.TestCase):
    """grip fleet run refuses what the whole run cannot go with before it
    reads a log (it once ran every log into an error row and exited 0)."""

    def test_bad_options_are_refused(self):
        from grip_tools.cli import run_command
        for args, said, code in ((["--step-ms", "0"], "--step-ms 0.0", 2), (["--step-ms", "nan"], "--step-ms nan", 2),
                                 (["--timeout", "-1"], "--timeout -1.0", 2), (["--retries", "-1"], "--retries -1", 2),
                                 (["--flush", "0"], "--flush 0", 2),
                                 (["--tir", "/no/such/file.tir"], "--tir /no/such/file.tir: cannot open", 2),
                                 (["--tir", os.path.join(REPO_ROOT, "README.md")], "README.md:1:", 3)):
            err = io.StringIO()
            with tempfile.TemporaryDirectory() as d, contextlib.redirect_stderr(err):
                out = os.path.join(d, "res")
                got = run_command("fleet", ["run", d, "--out", out] + args)
                self.assertFalse(os.path.exists(out), args)
            self.assertEqual(got, code, args)
            self.assertIn(said, err.getvalue(), args)


class FleetArithTests(unittest.TestCase):
    """fleet analyze / report of an arithmetic the run does not hold: exit 2
    (it wrote an analysis of 0 logs and exited 0)."""

    def test_missing_arithmetic_is_refused(self):
        import pandas as pd
        from grip_tools.errors import UsageError
        from grip_tools.fleet import analyze
        logs = pd.DataFrame({"arith": ["float", "float"]})
        self.assertEqual(analyze.pick_arith(logs, None), "float")
        self.assertEqual(analyze.pick_arith(logs, "float"), "float")
        with self.assertRaises(UsageError) as cm:
            analyze.pick_arith(logs, "fixed")
        self.assertIn("--arith fixed", str(cm.exception))


class FleetInputsTests(unittest.TestCase):
    def test_candump_and_parquet_and_both_arithmetics(self):
        import pandas as pd
        d = tempfile.mkdtemp(prefix="grip-fleet-inputs-", dir=_DIR)
        src = os.path.join(_DIR, "fleet", "logs", "sim000003.csv")
        inp = pd.read_csv(src)
        inp.to_parquet(os.path.join(d, "same.parquet"), index=False)
        shutil.copy(src, os.path.join(d, "same.csv"))
        shutil.copy(RAV4_LOG, os.path.join(d, "rav4.log"))
        pd.DataFrame({"log_id": ["pq", "csv", "rav4"], "path": ["same.parquet", "same.csv", "rav4.log"],
                      "preset": ["generic", "generic", "rav4"],
                      "vehicle_file": [os.path.join(_DIR, "fleet", "vehicle.txt")] * 2 + [None]}).to_csv(
            os.path.join(d, "manifest.csv"), index=False)
        from grip_tools.fleet import run as fr
        a = fr.parse_args([d, "--out", os.path.join(d, "out"), "--arith", "both", "--workers", "0",
                           "--no-progress"])
        fr.run_fleet(a)
        t = pd.read_parquet(os.path.join(d, "out", "logs.parquet")).set_index(["log_id", "arith"])
        self.assertTrue((t["status"] == "ok").all(), t["error"].dropna().tolist())
        # the Parquet log gives what its CSV gives
        skip = {"path", "format", "input_hash", "wall_s", "cpu_s", "rss_peak_mb"}
        for arith in ("float", "fixed"):
            p, c = t.loc[("pq", arith)], t.loc[("csv", arith)]
            for k in t.columns:
                if k not in skip:
                    self.assertTrue((p[k] == c[k]) or (pd.isna(p[k]) and pd.isna(c[k])), (arith, k, p[k], c[k]))
        r = t.loc[("rav4", "float")]
        self.assertEqual(r["frames_read"], 53800)
        self.assertEqual(r["decode_errors"], 0)
        self.assertEqual(r["steps"], 5999)
        fx = t.loc[("rav4", "fixed")]
        self.assertLess(fx["dev_beta_max_rad"], 1e-3)


@unittest.skipUnless(HAVE_DEPS, "dask, distributed, pandas, pyarrow not installed")
@unittest.skipUnless(os.path.exists(BIN["float"]) and os.path.exists(BIN["fixed"]), "grip-replay not built")
@unittest.skipIf(binding_missing(), f"the binding backend cannot run: {binding_missing()}")
class BackendsTests(unittest.TestCase):
    """The binding and the subprocess backend on logs of every kind, both
    arithmetics: the same logs, bands and per-step tables bit for bit (all
    columns but the backend's name and identity and the task's time and
    memory), the same error message for a corrupt log."""

    def test_binding_equals_subprocess(self):
        import pandas as pd
        import pyarrow.parquet as pq
        d = tempfile.mkdtemp(prefix="grip-fleet-backends-", dir=_DIR)
        fleet = os.path.join(_DIR, "fleet")
        src = os.path.join(fleet, "logs", "sim000003.csv")
        pd.read_csv(src).to_parquet(os.path.join(d, "sim3.parquet"), index=False)
        for i in ("000", "021", "042"):
            shutil.copy(os.path.join(fleet, "logs", f"sim000{i}.csv"), d)
        shutil.copy(RAV4_LOG, os.path.join(d, "rav4.log"))
        with open(src) as f:                                 # a bad cell on line 4
            text = f.read().replace("\n0.02,", "\n0.02,x", 1)
        with open(os.path.join(d, "bad.csv"), "w") as f:
            f.write(text)
        with open(RAV4_LOG) as f:                            # a malformed frame on line 5
            lines = f.readlines()[:400]
        lines[4] = "(1.0) can0 12#GG\n"
        with open(os.path.join(d, "bad.log"), "w") as f:
            f.writelines(lines)
        vf = os.path.join(fleet, "vehicle.txt")
        table = os.path.join(os.path.dirname(RAV4_LOG), "rav4.sigtab")
        rows = [("csv0", "sim000000.csv", "generic", vf, None), ("csv21", "sim000021.csv", "av21", None, None),
                ("csv42", "sim000042.csv", "rav4", vf, None), ("pq3", "sim3.parquet", "generic", vf, None),
                ("rav4", "rav4.log", "rav4", None, None), ("rav4tab", "rav4.log", "av21", None, table),
                ("badcsv", "bad.csv", "generic", vf, None), ("badlog", "bad.log", "rav4", None, None)]
        pd.DataFrame({"log_id": [r[0] for r in rows], "path": [r[1] for r in rows], "preset": [r[2] for r in rows],
                      "vehicle_file": [r[3] for r in rows], "table": [r[4] for r in rows]}).to_csv(
            os.path.join(d, "manifest.csv"), index=False)
        from grip_tools.fleet import run as fr
        out = {}
        for be in ("binding", "subprocess"):
            out[be] = os.path.join(d, be)
            a = fr.parse_args([d, "--out", out[be], "--arith", "both", "--workers", "0", "--no-progress", "--steps",
                               "--backend", be])
            fr.run_fleet(a)
        drop = ("wall_s", "cpu_s", "rss_peak_mb", "backend", "replay_id")
        for name in ("logs.parquet", "bands.parquet"):
            self.assertTrue(same_bits(table_of(out["binding"], name, drop), table_of(out["subprocess"], name, drop)),
                            name)
        t = pq.read_table(os.path.join(out["binding"], "logs.parquet")).to_pandas().set_index(["log_id", "arith"])
        self.assertEqual(len(t), 2 * len(rows))
        good = t.drop(index=["badcsv", "badlog"], level=0)
        self.assertTrue((good["status"] == "ok").all(), good["error"].dropna().tolist())
        self.assertEqual(set(t["backend"]), {"binding"})
        for arith in ("float", "fixed"):
            e = t.loc[("badcsv", arith)]
            self.assertEqual((e["status"], e["stage"]), ("error", "decode"))
            # the file's last message (the row's error column is the same in
            # both backends: compared above)
            self.assertRegex(e["error"], r"^grip-replay exit 4: .*bad\.csv:\d+: column ")
            e = t.loc[("badlog", arith)]
            self.assertEqual((e["status"], e["stage"]), ("error", "decode"))
            self.assertRegex(e["error"], r"^grip-replay exit 4: .*bad\.log:5: ")
        n = 0
        for arith in ("float", "fixed"):
            ids = sorted(os.listdir(os.path.join(out["subprocess"], "steps", f"arith={arith}")))
            self.assertEqual(ids, sorted(os.listdir(os.path.join(out["binding"], "steps", f"arith={arith}"))))
            for i in ids:
                p = os.path.join("steps", f"arith={arith}", i, "part-0.parquet")
                self.assertTrue(same_bits(pq.read_table(os.path.join(out["binding"], p)),
                                          pq.read_table(os.path.join(out["subprocess"], p))), p)
                n += 1
        self.assertEqual(n, 2 * (len(rows) - 2))

    def test_step_cap(self):
        """More steps than --max-steps: an error row, not a truncated log."""
        from grip_tools.fleet import backend
        from grip_tools.fleet.run import default_tir
        job = backend.ReplayJob(kind="csv", tir=default_tir(), path=os.path.join(_DIR, "fleet", "logs", "sim000000.csv"))
        self.assertEqual(len(backend.BindingReplay("float", max_steps=251).run(job).columns["t_s"]), 251)
        with self.assertRaisesRegex(backend.ReplayError, r"^grip-replay exit 5: more than 250 steps"):
            backend.BindingReplay("float", max_steps=250).run(job)

    def test_identity_differs_between_backends(self):
        from grip_tools.fleet import backend
        ids = {backend.BindingReplay("float").identity(), backend.BindingReplay("fixed").identity(),
               backend.SubprocessReplay(BIN["float"]).identity(), backend.SubprocessReplay(BIN["fixed"]).identity()}
        self.assertEqual(len(ids), 4)


def table_of(folder, name, drop):
    return table(os.path.join(folder, name), drop=drop)


class ReplayParserTests(unittest.TestCase):
    CANDUMP = """grip-replay: x.log, table rav4 (4 messages, 14 signals), step 10 ms, stale after 3 periods
  frames         53800 read (46408.584930 .. 46468.577630 s), 17409 decoded, 36391 other ids, 0 error frames, 0 remote requests
  decode errors  7 (dlc 1, checksum 2, counter frozen 0, out of range 4, sender fault 0), counter skips 3
  timing         5 reordered, 1 late, 0 too old, 2 timestamp jumps
  drops          0 (file replay)
  estimator      5999 steps, 0 errors; valid: beta 5999, yaw-rate reference 5999, mu 0; final mu 0.988
"""

    def test_summary(self):
        from grip_tools.fleet import backend
        c = backend.parse_summary(self.CANDUMP)
        self.assertEqual((c["frames_read"], c["frames_decoded"], c["decode_errors"], c["checksum_errors"],
                          c["out_of_range"], c["counter_skips"], c["reordered"], c["timestamp_jumps"],
                          c["est_steps"]), (53800, 17409, 7, 2, 4, 3, 5, 2, 5999))
        self.assertNotIn("rows_off_step", c)

    def test_error_line(self):
        from grip_tools.fleet import backend
        err = ("grip-replay: f.csv:2: column ax: not a number 'x'\n"
               "grip-replay: f.csv (CSV input), step 10 ms: 0 rows, 0 with a time step off by > 1 %\n"
               "  estimator      0 steps, 0 errors\n")
        self.assertEqual(backend.error_line(err), "grip-replay: f.csv:2: column ax: not a number 'x'")

    def test_output_columns(self):
        from grip_tools.fleet import backend
        text = ("t_s,step,yaw_rate,yaw_rate_fault,ay,ay_fault,est_status,est_valid,est_flags,vx,yaw_rate\n"
                "0.000000,0,0.5,ok,,missing,0,7,16,20.5,0.25\n")
        c = backend.parse_output(text)
        self.assertEqual(c["in_yaw_rate"][0], 0.5)
        self.assertEqual(c["yaw_rate"][0], 0.25)
        self.assertTrue(c["in_ay"][0] != c["in_ay"][0])
        self.assertEqual(c["in_ay_fault"][0], "missing")
        self.assertEqual(c["est_flags"].dtype.kind, "i")


if __name__ == "__main__":
    unittest.main()
