"""grip - the C library itself, from Python.

The C sources of lib/ are compiled into two extensions when the tools are
installed (cffi, API mode): grip._grip_f32 (float build) and grip._grip_q16
(fixed build, Q15.16 / Q23.8), with the Makefile's flags for lib/. Every
function here takes numpy arrays, converts them to the build's number
format, and calls the library once per point or sample in a C loop.

    import grip
    tyre = grip.mf.load("tests/data/mfeval-tir/PacejkaBook_Defaults.tir")
    r = grip.mf.evaluate(tyre, kappa, alpha, 0.0, 4000.0, arith="fixed")

Modules: mf (Magic Formula), brush (FIALA, brush, Sakai, Neo-FIALA),
signals (the estimator's input samples), est (estimator), monitor (sensor
plausibility), calib (sensor calibration). docs/python-binding.md is the
manual.
"""
from grip._core import (ARITHS, ERR_DOMAIN, ERR_INPUT, ERR_NULL, ERR_PARAM, ERR_STATE, OK, STATUS_NAMES,
                        WARN_CLAMPED, GripError, build_info, status_name, status_str)
from grip import mf, brush, signals, est, monitor, calib  # noqa: E402

__all__ = ["ARITHS", "GripError", "build_info", "status_str", "status_name", "STATUS_NAMES", "OK",
           "WARN_CLAMPED", "ERR_NULL", "ERR_PARAM", "ERR_INPUT", "ERR_STATE", "ERR_DOMAIN", "mf", "brush",
           "signals", "est", "monitor", "calib", "version"]


def version():
    """The C library's version (grip_version.h) the extensions were built from."""
    from grip._core import backend
    return backend("float").version
