"""Residual analysis, effect attribution and model update from measured data
(issue 7). Method and limits: docs/measured-data-loop.md.

    io.py          CSV schema (units in the header) -> Dataset
    candidates.py  derived channels (slip speed, friction power, ...)
    effects.py     candidate effects: parametric model terms with fit()
    attribution.py held-out (contiguous time blocks) ranking with a penalty
    report.py      Markdown + PNG report, updated parameter set (JSON)
    cli.py         `grip analyze`
"""
