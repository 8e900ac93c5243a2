"""One call per job: the functions the ``presag`` commands call, with their parameters and defaults.

==============================  ==================================  ==============================================================
job                             command                             returns
==============================  ==================================  ==============================================================
:func:`recommend`               ``presag recommend``                :class:`~presag_opt.pipeline.band.BandAnswer`
:func:`robust_design`           ``presag robust``                   :class:`~presag_opt.pipeline.band.BandAnswer`
:func:`dynamic_robust_design`   ``presag robust --dynamic``         :class:`~presag_opt.pipeline.band.BandAnswer`
:func:`design_line`             ``presag design``                   :class:`~presag_opt.pipeline.line.LineAnswer`
:func:`sensitivity_study`       ``presag sensitivity``              :class:`~presag_opt.sensitivity.analysis.SensitivityResult`
:func:`tolerance`               ``presag tolerance --monte-carlo``  :class:`~presag_opt.robust.monte_carlo.MonteCarloResult`
:func:`validity`                ``presag validity``                 :class:`~presag_opt.studies.validity_results.ValidityResult`
:func:`simulate`                ``presag simulate``                 :class:`~presag_opt.dynamics.simulate.SimulationResult`
==============================  ==================================  ==============================================================

Every job takes the designer's units at its boundary — km/h, mm, %, N and N/(km/h)² (an operating band
from :meth:`~presag_opt.design.band.OperatingBand.from_kmh`) — and works in SI inside; the defaults are
those of the command line (:mod:`presag_opt.jobs.options`). The results render themselves in a notebook
and give their tables as pandas data frames (``to_frame``).
"""

from __future__ import annotations

from presag_opt.jobs.band import dynamic_robust_design, recommend, robust_design
from presag_opt.jobs.line import design_line
from presag_opt.jobs.studies import sensitivity_study, simulate, tolerance, validity

__all__ = ["design_line", "dynamic_robust_design", "recommend", "robust_design", "sensitivity_study", "simulate",
           "tolerance", "validity"]
