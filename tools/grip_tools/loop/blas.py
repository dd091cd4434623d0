"""One BLAS thread while the loop computes.

The loop's matrix products are small (a few hundred driver columns times
the training rows), and its parallelism is processes (the refinement's
pool, the benchmark's sets). OpenBLAS's own threads make these products
slower, not faster, and on a machine shared with other jobs they spin
waiting for each other: a 60 000-row analysis took 50 s of screening with
the default threads on a loaded 2-core machine and 5 s with one
(docs/measured-data-loop.md, "Time"). single_thread() limits every
OpenBLAS the process has loaded (numpy's and scipy's) to one thread and
restores the previous count on exit; threadpoolctl is used when it is
installed, the libraries' own set/get functions otherwise. Where neither
is found it does nothing.
"""
import contextlib
import ctypes

# the set/get functions of the OpenBLAS builds numpy and scipy ship
# (scipy-openblas: 64-bit integer and 32-bit integer variants) and of a
# system OpenBLAS
_NAMES = (("scipy_openblas_set_num_threads64_", "scipy_openblas_get_num_threads64_"),
          ("scipy_openblas_set_num_threads", "scipy_openblas_get_num_threads"),
          ("openblas_set_num_threads64_", "openblas_get_num_threads64_"),
          ("openblas_set_num_threads", "openblas_get_num_threads"))


def _openblas_libs():
    """(set, get) function pairs of every OpenBLAS loaded into this process."""
    paths = set()
    try:
        with open("/proc/self/maps") as f:
            for line in f:
                p = line.split()[-1] if line.strip() else ""
                if "openblas" in p.lower() and ".so" in p:
                    paths.add(p)
    except OSError:
        return []
    out = []
    for p in sorted(paths):
        try:
            lib = ctypes.CDLL(p)
        except OSError:
            continue
        for s, g in _NAMES:
            if hasattr(lib, s) and hasattr(lib, g):
                fs, fg = getattr(lib, s), getattr(lib, g)
                fs.argtypes, fs.restype, fg.restype = [ctypes.c_int], None, ctypes.c_int
                out.append((fs, fg))
                break
    return out


@contextlib.contextmanager
def single_thread():
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        threadpool_limits = None
    if threadpool_limits is not None:
        with threadpool_limits(limits=1, user_api="blas"):
            yield
        return
    # only the libraries not at one thread already (a nested call, or a
    # process started with OPENBLAS_NUM_THREADS=1, changes nothing)
    libs = [(fs, n) for fs, fg in _openblas_libs() for n in (int(fg()),) if n != 1]
    for fs, _ in libs:
        fs(1)
    try:
        yield
    finally:
        for fs, n in libs:
            fs(max(n, 1))
