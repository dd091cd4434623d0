"""Worst-case stack per function from GCC's -fcallgraph-info=su output.

Reads the .ci files of a build (one per translation unit), joins them into
one call graph, and gives each public function the largest sum of frame
sizes along any call path below it. Recursion is an error (lib/ has none by
rule, and this proves it). Calls that leave the graph (libgcc and libm
helpers, whose frames GCC cannot see) are charged a stated allowance and
listed, so the figure is an honest bound with its assumptions named.
"""
import argparse
import glob
import re
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
FRAME = re.compile(r"(\d+) bytes \((static|dynamic|dynamic,bounded)\)")

# Frames of helpers outside lib/, in bytes. libgcc's integer helpers
# (__aeabi_lmul, __aeabi_ldivmod, __aeabi_uldivmod) use well under this;
# newlib's single-precision libm functions (sinf, atan2f, expf, ...) are
# charged more because their argument reduction keeps arrays on the stack.
EXTERNAL_ALLOWANCE = {"default": 64, "libm": 160}
LIBM = re.compile(r"^(sin|cos|tan|atan|atan2|exp|log|sqrt|pow|fabs)f?$|^__ieee754_|^__kernel_")


def load(paths):
    frames, kinds, edges = {}, {}, {}
    for path in paths:
        with open(path) as f:
            text = f.read()
        for name, label in NODE.findall(text):
            m = FRAME.search(label)
            if m:
                frames[name] = int(m.group(1))
                kinds[name] = m.group(2)
            else:
                frames.setdefault(name, None)
        for src, dst in EDGE.findall(text):
            edges.setdefault(src, set()).add(dst)
    return frames, kinds, edges


def worst_case(frames, edges):
    memo, externals = {}, {}

    def visit(name, stack):
        if name in memo:
            return memo[name]
        if name in stack:
            raise SystemExit(f"stack: recursion through {' -> '.join(stack + [name])}")
        own = frames.get(name)
        if own is None:
            own = EXTERNAL_ALLOWANCE["libm" if LIBM.match(name) else "default"]
            externals[name] = own
        deepest = 0
        for callee in sorted(edges.get(name, ())):
            deepest = max(deepest, visit(callee, stack + [name]))
        memo[name] = own + deepest
        return memo[name]

    for name in list(frames):
        visit(name, [])
    return memo, externals


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip stack", description=__doc__)
    ap.add_argument("builddir", help="folder searched recursively for .ci files")
    ap.add_argument("--public", default=r"^grip_", help="regex of the functions to report")
    ap.add_argument("--budget", type=int, default=0, help="fail if any reported function exceeds this (bytes)")
    args = ap.parse_args(argv)
    try:
        public = re.compile(args.public)
    except re.error as e:
        ap.error(f"--public {args.public!r}: not a regular expression ({e})")
    if args.budget < 0:
        ap.error(f"--budget {args.budget}: bytes >= 0 (0: no budget)")
    paths = sorted(glob.glob(f"{args.builddir}/**/*.ci", recursive=True))
    if not paths:
        print(f"stack: no .ci files under {args.builddir}", file=sys.stderr)
        return 2
    frames, kinds, edges = load(paths)
    total, externals = worst_case(frames, edges)
    rows = sorted((n for n in frames if public.search(n) and frames[n] is not None), key=lambda n: -total[n])
    dynamic = [n for n in kinds if kinds[n] != "static"]
    print(f"{'function':40s} {'frame':>6s} {'worst':>6s}  (bytes)")
    for n in rows:
        print(f"{n:40s} {frames[n]:6d} {total[n]:6d}")
    if externals:
        print("external calls charged an allowance: " +
              ", ".join(f"{n}={v}" for n, v in sorted(externals.items())))
    if dynamic:
        print("functions with dynamic frames: " + ", ".join(sorted(dynamic)))
    worst = max((total[n] for n in rows), default=0)
    print(f"worst public function: {worst} bytes" + (f" (budget {args.budget})" if args.budget else ""))
    if args.budget and (worst > args.budget or dynamic):
        print("stack: over budget or dynamic frame", file=sys.stderr)
        return 1
    return 0
