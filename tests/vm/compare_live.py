"""Checks the results of the VM test (run_vcan_test.sh): grip-replay -i vcan0
inside a VM, with canplayer replaying the RAV4 log onto vcan0.

Prints "# ..." detail lines and one "RESULT ok|fail TEXT" line per check:

1. frames: the dump of what grip-replay received holds exactly the log's
   frames of the table's ids (same ids, payloads, order), no other id passed
   the kernel filter, and the summary reports 0 drops, 0 truncated reads and
   0 decode errors;
2. identity: grip-replay replaying that dump as a file writes exactly the
   live CSV (every step up to the last frame);
3. agreement with the file replay of the original log. The live frames carry
   the VM's receive times t'_j; the log, its own times t_j. With
   offset = median(t'_j - t_j) and the jitter J = max |t'_j - t_j - offset|,
   the file replay with --time-offset-us offset runs on the same step grid.
   A step at time T holds the newest frame at or before T; jitter can only
   change which frame that is among those within +-J of T. So each live
   value must equal (to the decode tolerance) the value of a frame whose
   shifted log time lies within [T - J, T + J], or of the newest frame before
   T - J; the file replay's value is one of the same candidate frames, so
   the numeric difference at that step is at most tol(J) = the spread of
   that input over its candidate frames (the frames within +-J of T and the
   newest one before; the largest such spread is reported per input), and
   validity can only differ if 2J can push an age across the staleness
   limit.
"""
import argparse
import bisect
import csv
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools"))

from grip_tools.can import dbc  # noqa: E402
from grip_tools.golden import can as golden_can  # noqa: E402

MAP = os.path.join(ROOT, "tests", "data", "comma2k19-rav4", "rav4_map.toml")
STALE_PERIODS = 3


def result(ok, text):
    print(f"RESULT {'ok' if ok else 'fail'} {text}", flush=True)
    return ok


def t_us(s):
    sec, _, frac = s.partition(".")
    neg = sec.startswith("-")
    v = abs(int(sec)) * 1000000 + int((frac + "000000")[:6])
    return -v if neg else v


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def replay(binary, log, extra=()):
    r = subprocess.run([binary, log, "-q", *extra], capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        raise SystemExit(f"grip-replay {log} failed ({r.returncode}): {r.stderr}")
    return r.stdout


def summary_number(text, label):
    for line in text.splitlines():
        if label in line:
            return line
    return ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--log", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    ok_all = True

    table, _, mp = dbc.table_from_map(MAP)
    db = golden_can.reference_db(mp["dbc"])   # cantools: the independent reference decode
    ids = {m.id for m in table.messages}
    orig = golden_can.read_candump(args.log)
    live = golden_can.read_candump(os.path.join(args.out, "live.log"))
    want = [(t, i, d) for t, i, d in orig if i in ids]
    same = len(want) == len(live) and all(a[1:] == b[1:] for a, b in zip(want, live))
    first_diff = next((k for k, (a, b) in enumerate(zip(want, live)) if a[1:] != b[1:]), None)
    others = sum(1 for _, i, _ in live if i not in ids)
    print(f"# frames: log {len(orig)} ({len(want)} of the table's {len(ids)} ids), received {len(live)}, "
          f"other ids received {others}" + (f", first difference at frame {first_diff}" if first_diff else ""))
    with open(os.path.join(args.out, "replay.err")) as f:
        err = f.read()
    sock = summary_number(err, "socket ")
    dec = summary_number(err, "decode errors")
    drops0 = " 0 drops" in sock and " 0 truncated reads" in sock
    dec0 = "decode errors  0 " in dec
    ok_all &= result(same and others == 0,
                     f"every frame of the table's ids arrived: {len(live)}/{len(want)}, same ids, payloads and "
                     f"order, no other id")
    ok_all &= result(drops0 and dec0, f"zero drops, truncated reads and decode errors ({sock.strip()}; "
                                      f"{dec.strip()})")

    # 2. identity of the live and file paths
    live_header, live_rows = read_csv(os.path.join(args.out, "live.csv"))
    last_t = max(t for t, _, _ in live) if live else 0
    live_rows = [r for r in live_rows if t_us(r[0]) <= last_t]
    dump_csv = replay(args.bin, os.path.join(args.out, "live.log")).splitlines()
    dump_rows = list(csv.reader(dump_csv[1:]))
    identical = dump_csv[0].split(",") == live_header and dump_rows == live_rows
    print(f"# identity: {len(live_rows)} live steps, {len(dump_rows)} steps from the file replay of the dump")
    ok_all &= result(identical, f"file replay of the received frames reproduces the live CSV exactly "
                                f"({len(live_rows)} steps)")

    # 3. live vs the file replay of the original log
    if not same or not live:
        result(False, "live vs file replay: skipped, the frames differ")
        return 1
    d = [b[0] - a[0] for a, b in zip(want, live)]
    offset = int(round(statistics.median(d)))
    jitter = max(abs(x - offset) for x in d)
    file_csv = replay(args.bin, args.log, ("--time-offset-us", str(offset))).splitlines()
    file_rows = {r[0]: r for r in csv.reader(file_csv[1:])}
    col = {name: k for k, name in enumerate(live_header)}
    # per-frame reference values (cantools) on the shifted time axis
    by_id = {m.id: m for m in table.messages}
    series = {}
    for t, i, data in want:
        for inp, (v, f) in golden_can.reference_inputs(table, db, by_id[i], data).items():
            series.setdefault(inp, []).append((t + offset, v, f))
    period = {t.input: m.period_us for m in table.messages for t in m.terms}
    dev = sorted(abs(x - offset) for x in d)
    pct = {p: dev[min(len(dev) - 1, int(p / 100 * len(dev)))] for p in (50, 95, 99, 99.9)}
    print(f"# timing: offset {offset} us (VM clock - log clock), jitter J = max |t' - t - offset| = {jitter} us "
          f"over {len(d)} frames (50/95/99/99.9 %: {pct[50]}/{pct[95]}/{pct[99]}/{pct[99.9]} us)")
    common = [r for r in live_rows if r[0] in file_rows]
    print(f"# {len(common)} steps on the common grid")
    all_member = True
    all_within = True
    validity_ok = True
    for inp, s in sorted(series.items()):
        name = dbc.INPUTS[inp][0]
        times = [x[0] for x in s]
        vals = [x[1] for x in s]
        tol = 0.0          # largest per-step tolerance used (reported)
        n_beyond = 0       # steps where |live - file| exceeds that step's tolerance
        gmax = max(b - a for a, b in zip(times, times[1:]))
        limit = STALE_PERIODS * period[inp]
        n_mem = n_valid = flips = n_diff = 0
        max_diff = 0.0
        for r in common:
            T = t_us(r[0])
            lv, lf = r[col[name]], r[col[name + "_fault"]]
            fr = file_rows[r[0]]
            fv, ff = fr[col[name]], fr[col[name + "_fault"]]
            if (lf == "ok") != (ff == "ok"):
                flips += 1
                continue
            if lf != "ok":
                continue
            n_valid += 1
            x = float(lv)
            dtol = abs(x) * 2.0**-23 + 2.0**-16
            max_diff = max(max_diff, abs(x - float(fv)))
            n_diff += x != float(fv)
            hi = bisect.bisect_right(times, T + jitter)
            lo_k = bisect.bisect_left(times, T - jitter)
            cand = range(max(lo_k - 1, 0), hi)
            if any(s[k][2] == 0 and abs(vals[k] - x) <= dtol for k in cand):
                n_mem += 1
            # tolerance from the jitter at this step: the spread over the candidates
            spread = max(vals[k] for k in cand) - min(vals[k] for k in cand) if len(cand) else 0.0
            tol = max(tol, spread)
            n_beyond += abs(x - float(fv)) > spread + dtol + 2.0**-15
        member = n_mem == n_valid
        within = n_beyond == 0
        flips_possible = gmax + 2 * jitter > limit
        all_member &= member
        all_within &= within
        validity_ok &= flips == 0 or flips_possible
        print(f"# {name:15s} valid {n_valid:5d}, differ {n_diff:4d}, frame value within +-J {n_mem:5d}, max |live - file| "
              f"{max_diff:.6g}, tol(J) {tol:.6g}, validity differs {flips} (longest gap {gmax / 1000:.1f} ms, "
              f"stale after {limit / 1000:.0f} ms)")
    ok_all &= result(all_member, f"every live value is the value of a frame within +-J = {jitter / 1000:.3f} ms "
                                 f"of its step")
    ok_all &= result(all_within and validity_ok,
                     "live and file replay agree within the jitter-derived tolerance tol(J), same validity")
    return 0 if ok_all else 1


if __name__ == "__main__":
    sys.exit(main())
