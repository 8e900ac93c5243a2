"""Validity studies: a grid of dynamic runs over pre-sag, speed and static force, and its analysis.

Modules: :mod:`~presag_opt.studies.definition` (study files and the validated definition),
:mod:`~presag_opt.studies.parameters` (extra swept parameters by dotted name),
:mod:`~presag_opt.studies.work` (work units and the pure worker function),
:mod:`~presag_opt.studies.store` (atomic unit files and the netCDF store),
:mod:`~presag_opt.studies.runner` (local processes or Dask, progress, resume),
:mod:`~presag_opt.studies.validity_analysis` (the paper's Fig. 6/7/8 criteria, β*, eq. 7 fit, uplift) with its
results in :mod:`~presag_opt.studies.validity_results`,
:mod:`~presag_opt.studies.plots` (figures), :mod:`~presag_opt.studies.reduced` (a small grid on a
short section, run in one process).
"""
