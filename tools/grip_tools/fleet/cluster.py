"""Where the fleet's tasks run: a Dask LocalCluster on this machine (the
default), any running Dask scheduler (--scheduler tcp://host:8786: the
same code on a cluster), or this process alone (--workers 0: no Dask,
for debugging and as the reference the tests compare with).

Also the terminal progress bar shown while results come back.
"""
import logging
import os
import sys
import time


def add_arguments(ap, default_memory="2GiB"):
    g = ap.add_argument_group("where the tasks run")
    g.add_argument("--scheduler", metavar="ADDR",
                   help="address of a running Dask scheduler (tcp://host:8786); default: a LocalCluster here")
    g.add_argument("--workers", type=int, default=None,
                   help="LocalCluster worker processes (default: the number of CPUs); 0 = no Dask, this process")
    g.add_argument("--memory-limit", default=default_memory,
                   help="LocalCluster memory per worker (default %(default)s; a worker above it is restarted "
                        "and its task retried)")
    g.add_argument("--dashboard", default=":8787", metavar="ADDR",
                   help="LocalCluster dashboard address (default %(default)s; 'none' = off)")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    return g


class Serial:
    """The no-Dask executor (--workers 0)."""
    dashboard_link = None
    n_workers = 0

    def close(self):
        pass


def open_client(a, quiet=False):
    """A dask.distributed Client per the arguments (or Serial()); prints the
    dashboard link."""
    if a.workers == 0 and not a.scheduler:
        return Serial()
    from dask.distributed import Client, LocalCluster
    if a.scheduler:
        client = Client(a.scheduler)
    else:
        n = a.workers or os.cpu_count() or 1
        dash = None if (a.dashboard or "").lower() in ("none", "off", "") else a.dashboard
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, memory_limit=a.memory_limit,
                               dashboard_address=dash, silence_logs=logging.ERROR)
        client = Client(cluster)
    client.n_workers = len(client.scheduler_info()["workers"])
    if not quiet:
        off = not a.scheduler and (a.dashboard or "").lower() in ("none", "off", "")
        link = "off" if off else (getattr(client, "dashboard_link", None) or "(none)")
        print(f"grip fleet: Dask scheduler {client.scheduler.address}, {client.n_workers} worker(s), "
              f"dashboard {link}", file=sys.stderr)
    return client


def close_client(client):
    cluster = getattr(client, "cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()


def _hms(s):
    s = int(round(s))
    return f"{s // 3600}h{s % 3600 // 60:02d}m" if s >= 3600 else f"{s // 60}m{s % 60:02d}s"


class Progress:
    """A one-line progress bar on stderr (a line per 10 % when stderr is not
    a terminal)."""

    def __init__(self, total, what="logs", enabled=True, stream=None):
        self.total, self.what = total, what
        self.stream = stream or sys.stderr
        self.enabled = enabled and total > 0
        self.tty = self.stream.isatty()
        self.t0 = time.time()
        self.done = self.errors = self.skipped = 0
        self._last = 0.0
        self._decile = -1

    def update(self, done=1, errors=0, skipped=0):
        self.done += done
        self.errors += errors
        self.skipped += skipped
        if not self.enabled:
            return
        now = time.time()
        if self.tty and now - self._last < 0.2 and self.done < self.total:
            return
        self._last = now
        el = now - self.t0
        rate = self.done / el if el > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else 0.0
        w = 30
        k = int(w * self.done / self.total)
        counts = f", {self.skipped} unchanged, {self.errors} errors" if self.what == "logs" else ""
        line = (f"[{'#' * k}{'.' * (w - k)}] {self.done}/{self.total} {self.what}{counts}, {rate:.2f}/s, "
                f"elapsed {_hms(el)}, eta {_hms(eta)}")
        if self.tty:
            self.stream.write("\r" + line + "\x1b[K")
            if self.done >= self.total:
                self.stream.write("\n")
            self.stream.flush()
        else:
            dec = 10 * self.done // self.total
            if dec != self._decile:
                self._decile = dec
                print(line, file=self.stream, flush=True)
