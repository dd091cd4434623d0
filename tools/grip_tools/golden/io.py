"""Golden-vector file format shared by every generator.

A golden file is text: header lines start with '#' and record the
generator, its version, the reference it evaluates, its parameters and the
random seed; then one whitespace-separated row per vector. The C tests read
it with tests/support/golden.c.
"""
import hashlib
import inspect
import time

from grip_tools import __version__


def header(generator, reference, seed, columns, params=None):
    """Header lines. The hash of the reference source makes every change of
    the reference model visible in the vectors."""
    src = inspect.getsource(reference) if reference is not None else ""
    lines = [
        f"# grip golden vectors",
        f"# generator: {generator} (grip_tools {__version__})",
        f"# reference: {getattr(reference, '__name__', 'none')} sha256:{hashlib.sha256(src.encode()).hexdigest()[:16]}",
        f"# seed: {seed}",
        f"# created: {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}",
    ]
    for k, v in (params or {}).items():
        lines.append(f"# param {k}: {v}")
    lines.append("# columns: " + " ".join(columns))
    return "\n".join(lines) + "\n"
