"""How much of two cores a machine gives right now, as a control for a
scaling measurement: the same CPU-bound work done by one process (two
units in a row) and by two processes (one unit each) at the same time.
On an idle 2-core machine the speed-up is about 2; on a shared one it is
what the other jobs leave (docs/fleet.md, Measured).

    python -m grip_tools.fleet.ceiling
"""
import multiprocessing as mp
import os
import time


def unit(_=None, n=40_000_000):
    x = 0
    for i in range(n):
        x += i * i % 7
    return x


def main():
    print("load before:", " ".join(f"{x:.2f}" for x in os.getloadavg()))
    t = time.time()
    unit()
    unit()
    one = time.time() - t
    t = time.time()
    with mp.get_context("spawn").Pool(2) as p:
        p.map(unit, [0, 1])
    two = time.time() - t
    print(f"1 process: {one:.2f} s, 2 processes: {two:.2f} s, speed-up {one / two:.2f}x; load after:",
          " ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
