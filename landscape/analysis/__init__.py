"""Analyses of trial databases (statistics and tables; no click, no plotting): they join the numerics and
:mod:`sim`. :mod:`landscape.analysis.trials` holds the source paper's analyses, :mod:`landscape.analysis.bench`
times the numerics."""
