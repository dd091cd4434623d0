"""Residual analysis, effect attribution and model update from measured data
(issue 7). Method and limits: docs/measured-data-loop.md.

    io.py          CSV schema (units in the header) -> Dataset
    candidates.py  derived channels (slip speed, friction power, ...)
    grammar.py     the candidate grammar (target x driver), its screening and refinement
    effects.py     the base tyre model and the named effects: parametric terms with fit()
    attribution.py held-out ranking with a complexity penalty (held-out BIC for tyre models)
    correction.py  the non-parametric correction when nothing physical is identified
    sanity.py      the base-model check (sign, side, unit, offset)
    report.py      Markdown + PNG report, updated parameter set (JSON)
    benchmark.py   the generality benchmark (generated rig sets, one undeclared effect each)
    blas.py        one BLAS thread while the loop computes (its parallelism is processes)
    cli.py         `grip analyze`
"""
