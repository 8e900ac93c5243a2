"""One call per job: the functions the ``presag`` commands call, with their parameters and defaults.

==============================  ==================================  ==============================================================
job                             command                             returns
==============================  ==================================  ==============================================================
:func:`recommend`               ``presag recommend``                :class:`~presag_opt.pipeline.band.BandAnswer`
:func:`robust_design`           ``presag robust``                   :class:`~presag_opt.pipeline.band.BandAnswer`
:func:`dynamic_robust_design`   ``presag robust --dynamic``         :class:`~presag_opt.pipeline.band.BandAnswer`
:func:`design_line`             ``presag design``                   :class:`~presag_opt.pipeline.line.LineAnswer`
:func:`sensitivity_study`       ``presag sensitivity``              :class:`~presag_opt.sensitivity.analysis.SensitivityResult`
:func:`tolerance`               ``presag tolerance``                :class:`~presag_opt.jobs.installation_tolerance.ToleranceAnswer`
:func:`validity`                ``presag validity``                 :class:`~presag_opt.studies.validity_results.ValidityResult`
:func:`simulate`                ``presag simulate``                 :class:`~presag_opt.jobs.simulation.SimulationAnswer`
==============================  ==================================  ==============================================================

Every job takes the designer's units at its boundary — km/h, mm, %, N and N/(km/h)² (an operating band
from :meth:`~presag_opt.design.band.OperatingBand.from_kmh`) — and works in SI inside; the defaults are
those of the command line (:mod:`presag_opt.jobs.options`). The results render themselves in a notebook
and give their tables as pandas data frames (``to_frame``).
"""

from __future__ import annotations

from importlib import import_module

_JOBS = {
    "recommend": "presag_opt.jobs.band", "robust_design": "presag_opt.jobs.band",
    "dynamic_robust_design": "presag_opt.jobs.band", "design_line": "presag_opt.jobs.line",
    "sensitivity_study": "presag_opt.jobs.studies", "tolerance": "presag_opt.jobs.installation_tolerance",
    "validity": "presag_opt.jobs.studies", "simulate": "presag_opt.jobs.simulation",
}
"""Each job by the module that defines it, imported on first use: the command line reads
:mod:`presag_opt.jobs.options` at start-up without loading the line design and its report."""

__all__ = sorted(_JOBS)


def __getattr__(name: str) -> object:
    module = _JOBS.get(name)
    if module is None:
        raise AttributeError(f"module 'presag_opt.jobs' has no attribute {name!r}")
    return getattr(import_module(module), name)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
