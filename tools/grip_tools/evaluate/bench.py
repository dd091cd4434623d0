"""`make bench`: ns per call on the host, instruction counts from callgrind,
and Cortex-M4F / M0+ instruction counts from qemu-system-arm.

Cortex-M counting: qemu runs the benchmark image (tests/bench/bench_target.c)
with one instruction per translation block and logs every block executed
(-singlestep -d exec,nochain); the instructions between two bench_mark()
calls are counted and the mean count of an empty case is subtracted. The
Fixed build's ARMv6-M code runs on the Cortex-M3 board (mps2-an385): the
instruction stream is that of a Cortex-M0+. Counts are instructions, not
cycles (a Cortex-M0+ takes 1-2 cycles for most, 32 for a multi-cycle multiply
variant; the M4F's FPU divide takes 14).

Writes build/bench/bench.csv and build/bench/bench.md and prints the table.
"""
import argparse
import bisect
import csv
import os
import re
import statistics
import subprocess
import sys
import tempfile

from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
TRACE_PC = re.compile(r"^Trace \d+: 0x[0-9a-f]+ \[[0-9a-f]+/([0-9a-f]+)/")


# the benchmark image of each --targets name and the qemu board it runs on
TARGET_IMAGES = {"m4f": ("m4f-float", "mps2-an386"), "m0p": ("m0p-fixed", "mps2-an385")}


def host_ns(arith):
    exe = os.path.join(ROOT, f"build/{arith}-gcc/bench/bench_host")
    out = subprocess.run([exe], check=True, capture_output=True, text=True).stdout
    return {row["case"]: float(row["ns_per_call"]) for row in csv.DictReader(out.splitlines())}


# The Q15.16 kernels: the functions behind r_sqrt ... r_log and the file-local
# helpers of lib/arith/q16.c they run in (gcc may suffix a local's clone: .isra.0,
# .part.0, ...), with q_mul_wide, the Cortex-M0+'s product, which only q16.c calls
# and which -Os leaves out of line there.
Q16_KERNEL_FN = (r"grip_q16_(sqrt|atan|atan2|sin|cos|sincos|exp|log)"
                 r"|horner_q30|horner_step|k_mul|q_mul_wide|sin_poly_q30|atan_poly_q30|exp2_poly_q30"
                 r"|q30_to_q16|msb64|atan_mag_q30|phase_q32|sin_of_phase")
# The math kernels of an evaluation: libm's functions (float build, GRIP_FLOAT_KERNELS
# 0; grip's float kernels are inlined into their callers and cannot be told apart) and
# the Q15.16 kernels (fixed build).
MATH_KERNEL_FN = re.compile(r"^(" + Q16_KERNEL_FN + r")(\.\w+)*$")
CG_NAME = re.compile(r"^\((\d+)\)(?: (.*))?$")


# Source files whose code is a math kernel wherever the compiler inlined it
# (the fixed build's Q15.16 kernels inline in the model where it optimizes
# for speed; grip's float kernels): counted through callgrind's inline file
# records (fi= / fe=), as the Cortex-M counts use the line table.
KERNEL_SOURCES = ("lib/arith/q16_math_inline.h", "lib/arith/f32_kernels.h")


def callgrind_split(lines):
    """Self cost (Ir) of a callgrind output file: (total, inside the math kernels:
    libm, the kernel functions, and code from KERNEL_SOURCES inlined elsewhere)."""
    obs, fns, fls = {}, {}, {}
    ob, fn, src = "", "", ""
    total = kern = 0
    skip = False

    def name(table, text):
        m = CG_NAME.match(text.strip())
        if not m:
            return text.strip()
        if m.group(2) is not None:
            table[m.group(1)] = m.group(2)
        return table.get(m.group(1), "")

    for line in lines:
        if skip:            # the inclusive cost of the call named on the line before
            skip = False
            continue
        if line.startswith("ob="):
            ob = name(obs, line[3:])
        elif line.startswith("cob="):
            name(obs, line[4:])
        elif line.startswith("fl="):
            src = name(fls, line[3:])
        elif line.startswith(("fi=", "fe=")):
            src = name(fls, line[3:])
        elif line.startswith(("cfi=", "cfl=")):
            name(fls, line[4:])
        elif line.startswith("fn="):
            fn = name(fns, line[3:])
        elif line.startswith("cfn="):
            name(fns, line[4:])
        elif line.startswith("calls="):
            skip = True
        elif line[:1] in "0123456789+-*":
            parts = line.split()
            if len(parts) >= 2:
                c = int(parts[1])
                total += c
                if ("libm" in os.path.basename(ob) or MATH_KERNEL_FN.match(fn)
                        or src.replace(os.sep, "/").endswith(KERNEL_SOURCES)):
                    kern += c
    return total, kern


def callgrind_ir(arith, case, n=1600):
    """Mean instructions per call: (total, inside the math kernels)."""
    exe = os.path.join(ROOT, f"build/{arith}-gcc/bench/bench_host")
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "cg.out")
        subprocess.run(["valgrind", "--tool=callgrind", "--instr-atstart=no",
                        f"--callgrind-out-file={out}", exe, case, str(n)],
                       check=True, capture_output=True)
        with open(out) as f:
            lines = f.readlines()
    totals = [int(l.split()[1]) for l in lines if l.startswith("totals:")]
    if not totals:
        raise RuntimeError("callgrind: no totals line in its output")
    total, kern = callgrind_split(lines)
    if total != totals[0]:
        raise RuntimeError(f"callgrind: self costs add up to {total}, totals line {totals[0]}")
    return totals[0] / n, kern / n


# The math kernels in a Cortex-M image: newlib's single-precision functions and their
# internal helpers (float), grip's Q15.16 functions and the helpers of lib/arith/q16.c
# (fixed). libgcc's helpers (__aeabi_*, __muldi3, ...) count where they are called
# from: with the function executed last before them that is not a libgcc helper.
M_KERNEL_FN = re.compile(r"^(atanf|atan2f|sinf|cosf|sincosf|expf|logf|sqrtf|fabsf|floorf|scalbnf|copysignf"
                         r"|__ieee754_\w+|__kernel_\w+|__math_\w+|__sin\w*|__cos\w*|__exp\w*|__log\w*"
                         r"|" + Q16_KERNEL_FN + r")(\.\w+)*$")
M_HELPER_FN = re.compile(r"^(__aeabi_\w+|__\w+(di|si)\d|__clz\w+|__ctz\w+|__gnu_\w+)$")


def symbol_classes(elf):
    """Sorted function starts and, per start, 1 kernel / 0 other / None libgcc helper."""
    syms = [(a, size, 1 if M_KERNEL_FN.match(n) else (None if M_HELPER_FN.match(n) else 0))
            for a, size, n in function_table(elf)]
    syms.sort(key=lambda x: (x[0], x[1], -1 if x[2] is None else x[2]))
    return [x[0] for x in syms], syms


# grip's float kernels (lib/arith/f32_kernels.h) are inlined into their callers:
# their instructions are found through the line table, as the addresses the
# compiler attributes to that header.
INLINE_KERNEL_SOURCES = ("lib/arith/f32_kernels.h",)


def inline_kernel_ranges(elf, sources=INLINE_KERNEL_SOURCES):
    """Sorted (start addresses, flags) of the line table's address ranges:
    flag 1 where the range's source is one of `sources`."""
    out = subprocess.run(["arm-none-eabi-objdump", "--dwarf=decodedline", elf], check=True,
                         capture_output=True, text=True).stdout
    return decodedline_ranges(out, sources)


def decodedline_ranges(text, sources=INLINE_KERNEL_SOURCES):
    """inline_kernel_ranges from objdump --dwarf=decodedline's text: a
    "path:" line names the source of the rows after it; a row is "file line
    address [view] [stmt]", line "-" ending a sequence."""
    rows, cur = [], None
    for line in text.splitlines():
        s = line.strip()
        if s.endswith(":") and " " not in s:
            cur = s[:-1]
            continue
        p = s.split()
        if len(p) >= 3 and p[2].startswith("0x"):
            end = p[1] == "-"
            rows.append((int(p[2], 16), 0 if end or cur is None else int(cur.endswith(sources))))
    rows.sort(key=lambda r: r[0])   # stable: of the rows at one address the last counts
    addrs, flags = [], []
    for a, f in rows:
        if addrs and addrs[-1] == a:
            flags[-1] = f
        else:
            addrs.append(a)
            flags.append(f)
    return addrs, flags


def _qemu_trace(target, machine, d):
    """Runs the target's benchmark image under qemu-system-arm with the
    block trace (one instruction per block) into directory d; returns (elf,
    trace log path, the case names in the image's order)."""
    elf = os.path.join(ROOT, f"build/{target}/grip-bench.elf")
    log = os.path.join(d, "trace.log")
    run = subprocess.run(["qemu-system-arm", "-M", machine, "-nographic", "-singlestep",
                          "-semihosting-config", "enable=on,target=native",
                          "-d", "exec,nochain", "-D", log, "-kernel", elf],
                         capture_output=True, text=True, timeout=600)
    if run.returncode != 0:
        raise RuntimeError(f"qemu {target}: exit {run.returncode}: {run.stdout[-500:]}")
    # semihosting SYS_WRITE0 output arrives on stderr
    names = [l[len("bench: "):] for l in (run.stdout + run.stderr).splitlines() if l.startswith("bench: ")]
    return elf, log, names


def _trace_pcs(log):
    """The program counters of a qemu block trace, in order."""
    with open(log) as f:
        for line in f:
            m = TRACE_PC.match(line)
            if m:
                yield int(m.group(1), 16)


def _mark_address(elf):
    nm = subprocess.run(["arm-none-eabi-nm", elf], check=True, capture_output=True, text=True).stdout
    return next(int(l.split()[0], 16) & ~1 for l in nm.splitlines() if l.endswith(" bench_mark"))


def mark_spans(pcs, mark):
    """The program counters of each call a benchmark case makes: bench_mark
    is called before and after every call, so the marks come in pairs (a
    call's start, its end); what runs between an end and the next start is
    the harness. Yields one list per call, in order."""
    span, n_marks = None, 0
    for pc in pcs:
        if pc == mark:
            if n_marks % 2 == 1:
                yield span
            span = [] if n_marks % 2 == 0 else None
            n_marks += 1
        elif span is not None:
            span.append(pc)


def qemu_counts(target, machine):
    """Per case: (mean, max, mean inside the math kernels) instructions per call."""
    with tempfile.TemporaryDirectory() as d:
        elf, log, names = _qemu_trace(target, machine, d)
        mark = _mark_address(elf)
        starts, syms = symbol_classes(elf)
        k_addrs, k_flags = inline_kernel_ranges(elf)
        spans, kspans = [], []
        cls_last = 0
        for span in mark_spans(_trace_pcs(log), mark):
            ksince = 0
            for pc in span:
                i = bisect.bisect_right(starts, pc) - 1
                if i >= 0 and pc < syms[i][0] + max(syms[i][1], 2):
                    if syms[i][2] is not None:
                        cls_last = syms[i][2]
                else:
                    cls_last = 0
                j = bisect.bisect_right(k_addrs, pc) - 1
                ksince += cls_last or (k_flags[j] if j >= 0 else 0)
            spans.append(len(span))
            kspans.append(ksince)
    per = len(spans) // len(names)
    out = {}
    empty = statistics.mean(spans[0:per])
    for k, name in enumerate(names[1:], start=1):
        vals = [v - empty for v in spans[k * per:(k + 1) * per]]
        out[name] = (statistics.mean(vals), max(vals), statistics.mean(kspans[k * per:(k + 1) * per]))
    return out


def function_table(elf):
    """Sorted (start, size, name) of the image's functions (nm -S)."""
    nm = subprocess.run(["arm-none-eabi-nm", "-S", "--defined-only", elf], check=True,
                        capture_output=True, text=True).stdout
    fns = []
    for l in nm.splitlines():
        p = l.split()
        if len(p) == 4 and p[2] in "tTwW":
            fns.append((int(p[0], 16) & ~1, int(p[1], 16), p[3]))
    fns.sort()
    return fns


def profile_spans(pcs, mark, fns, names, case_re):
    """Per case whose name matches case_re: {function: instructions per
    call}, each instruction counted in the function whose address range
    holds it ("?" outside every one). pcs: the trace's program counters;
    mark: bench_mark's address, called before and after every call of a
    case; fns: function_table's; names: the cases in the image's order, each
    run the same number of times."""
    starts = [f[0] for f in fns]
    spans = []
    for span in mark_spans(pcs, mark):
        cur = {}
        for pc in span:
            i = bisect.bisect_right(starts, pc) - 1
            name = fns[i][2] if i >= 0 and pc < fns[i][0] + max(fns[i][1], 2) else "?"
            cur[name] = cur.get(name, 0) + 1
        spans.append(cur)
    per = len(spans) // len(names) if names else 0
    out = {}
    for k, case in enumerate(names):
        if not per or not re.search(case_re, case):
            continue
        tot = {}
        for sp in spans[k * per:(k + 1) * per]:
            for fn, n in sp.items():
                tot[fn] = tot.get(fn, 0) + n
        out[case] = {fn: n / per for fn, n in tot.items()}
    return out


def qemu_profile(target, machine, case_re):
    """profile_spans of the target's benchmark image run under qemu."""
    with tempfile.TemporaryDirectory() as d:
        elf, log, names = _qemu_trace(target, machine, d)
        return profile_spans(_trace_pcs(log), _mark_address(elf), function_table(elf), names, case_re)


def profile_md(target, prof):
    """The profile of each case as a markdown table, the most expensive
    function first."""
    md = []
    for case, per_fn in prof.items():
        total = sum(per_fn.values())
        md += [f"### {case} ({target}): {total:.0f} instructions per call", "",
               "| function | instructions per call | share |", "|---|---|---|"]
        md += [f"| {fn} | {n:.1f} | {100 * n / total:.1f} % |"
               for fn, n in sorted(per_fn.items(), key=lambda x: (-x[1], x[0]))]
        md.append("")
    return "\n".join(md)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip bench", description=__doc__)
    ap.add_argument("--outdir", default=os.path.join(ROOT, "build/bench"))
    ap.add_argument("--cases", default="",
                    help="regular expression: only the matching cases (for quick measurements "
                         "while optimizing; the image still runs every case once)")
    ap.add_argument("--targets", default="m4f,m0p",
                    help="comma-separated Cortex-M images to run (m4f, m0p, or empty for none)")
    ap.add_argument("--profile", default=None, metavar="REGEX",
                    help="instead of the table: the Cortex-M instructions per call of each matching case "
                         "by function (--targets' images; writes <outdir>/profile_<target>.md)")
    args = ap.parse_args(argv)
    for opt, val in (("--cases", args.cases), ("--profile", args.profile)):
        try:
            re.compile(val or "")
        except re.error as e:
            ap.error(f"{opt} {val!r}: not a regular expression ({e})")
    unknown = [t for t in args.targets.split(",") if t and t not in ("m4f", "m0p")]
    if unknown:
        ap.error(f"--targets: {', '.join(unknown)}: unknown (have m4f, m0p, or empty for none)")
    os.makedirs(args.outdir, exist_ok=True)
    if args.profile is not None:
        targets = [t for t in args.targets.split(",") if t]
        if not targets:
            ap.error("--profile: needs a target (--targets m4f, m0p)")
        for t in targets:
            prof = qemu_profile(*TARGET_IMAGES[t], args.profile)
            if not prof:
                ap.error(f"--profile {args.profile!r}: no case of the {t} image matches")
            text = profile_md(t, prof)
            with open(os.path.join(args.outdir, f"profile_{t}.md"), "w") as f:
                f.write(text)
            print(text)
        return 0
    ns = {a: host_ns(a) for a in ("float", "fixed")}
    cases = [c for c in ns["float"] if re.search(args.cases, c)]
    ir = {a: {c: callgrind_ir(a, c) for c in cases} for a in ("float", "fixed")}
    targets = [t for t in args.targets.split(",") if t]
    none = {c: (float("nan"), float("nan"), float("nan")) for c in cases}
    m4f = qemu_counts(*TARGET_IMAGES["m4f"]) if "m4f" in targets else none
    m0p = qemu_counts(*TARGET_IMAGES["m0p"]) if "m0p" in targets else none
    header = ["case", "host ns float", "host ns fixed", "x86 instr float", "x86 instr fixed",
              "x86 float in kernels", "x86 fixed in kernels",
              "M4F instr mean", "M4F instr max", "M4F in kernels", "M0+ instr mean", "M0+ instr max",
              "M0+ in kernels"]
    rows = []
    for c in cases:
        rows.append([c, f"{ns['float'][c]:.1f}", f"{ns['fixed'][c]:.1f}",
                     f"{ir['float'][c][0]:.0f}", f"{ir['fixed'][c][0]:.0f}",
                     f"{ir['float'][c][1]:.0f}", f"{ir['fixed'][c][1]:.0f}",
                     f"{m4f[c][0]:.0f}", f"{m4f[c][1]:.0f}", f"{m4f[c][2]:.0f}",
                     f"{m0p[c][0]:.0f}", f"{m0p[c][1]:.0f}", f"{m0p[c][2]:.0f}"])
    with open(os.path.join(args.outdir, "bench.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    md = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    md += ["| " + " | ".join(r) + " |" for r in rows]
    text = "\n".join(md) + "\n"
    with open(os.path.join(args.outdir, "bench.md"), "w") as f:
        f.write(text)
    print(text)
    print("x86 instr: valgrind callgrind, mean over the 16 input sets; 'in kernels': the part of it in "
          "libm's functions (float) or grip_q16_sqrt/atan/atan2/sin/cos/exp/log (fixed), the rest is outside; "
          "M4F/M0+ instr: (in kernels: newlib's float functions, grip_q16_* and their helpers, libgcc "
          "counted with its caller, and the instructions the line table attributes to the inlined "
          "lib/arith/f32_kernels.h) "
          "qemu-system-arm trace, mean and max over the 16 input sets; host ns: median of 5 runs",
          file=sys.stderr)
    return 0
