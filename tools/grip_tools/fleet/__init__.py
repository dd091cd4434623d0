"""Fleet scale: the estimator over many logs on Dask (docs/fleet.md).

    manifest.py  which logs: folder, glob, manifest; input hashes
    backend.py   the replay adapter (grip-replay subprocess; a binding can replace it)
    summary.py   one log's summary, residual bands, accuracy (est_eval), attribution (loop)
    store.py     the results folder: Parquet tables, journal, resume
    cluster.py   LocalCluster / scheduler address / no Dask; progress bar
    run.py       grip fleet run
    analyze.py   grip fleet analyze: pooled residuals, effects across logs
    report.py    grip fleet report: Markdown + PNG, regressions against an earlier run
    simfleet.py  grip sim-fleet: logs with truth from the reference simulator
    cli.py       grip fleet {run,analyze,report}
"""
