"""A validity sweep as evidence for a pre-sag decision: its limit reading and its uplift by pre-sag.

:func:`validity_sweep` turns a study's statistics (a stored ``presag sweep``, or a reduced sweep run
for a report) and their analysis (:func:`~presag_opt.studies.validity_analysis.validity_analysis`) into
the :class:`~presag_opt.design.evidence.ValiditySweep` record that the decision reads: β* with its
resolution and the verdict at each grid β (for :mod:`presag_opt.design.validity_limit`), and the
largest steady-arm uplift per swept pre-sag and static force over the speeds up to the band's top. A
study's pre-sags are those of the longest span of its catenary (:func:`sweep_reference_span`); the
record holds them relative to it.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from presag_opt.design.evidence import ValiditySweep
from presag_opt.design.validity_limit import SweepLimit
from presag_opt.errors import ModelError
from presag_opt.studies.validity_results import ValidityResult
from presag_opt.units import KMH


def sweep_wave_speed(dataset: xr.Dataset) -> float:
    """Contact-wire wave speed of a study's system, v/β of its runs. [m/s]

    Parameters
    ----------
    dataset : xarray.Dataset
        A study's statistics (coordinates ``speed``; variable ``beta``).
    """
    return float(dataset["speed"].values[0] / np.asarray(dataset["beta"].values).flat[0])


def sweep_reference_span(dataset: xr.Dataset) -> float:
    """The span a study's pre-sags are stated on: the longest span of its catenary. [m]

    Parameters
    ----------
    dataset : xarray.Dataset
        A study's statistics (its ``study_definition`` attribute holds the catenary).
    """
    return float(max(json.loads(dataset.attrs["study_definition"])["catenary"]["layout"]["span_lengths"]))


def validity_sweep(dataset: xr.Dataset, result: ValidityResult, *, kind: str, name: str, speed_high: float,
                   line_wave_speed: float) -> ValiditySweep:
    """The validity sweep's record (see the module docstring).

    Parameters
    ----------
    dataset : xarray.Dataset
        The study's statistics (coordinates ``presag`` [m], ``speed`` [m/s], ``static_force`` [N];
        variable ``uplift_max`` [m]).
    result : ValidityResult
        Its analysis.
    kind : {"study", "reduced"}
        A stored study, or a reduced sweep run for a report.
    name : str
        How the output names it.
    speed_high : float
        The band's top speed: the uplift is taken over the swept speeds up to it. [m/s]
    line_wave_speed : float
        Contact-wire wave speed of the line decided for (a study of another wire is noted). [m/s]

    Raises
    ------
    ModelError
        A study with no speed ratio verdicts (nothing analysed).
    """
    if not result.per_beta:
        raise ModelError(f"{name}: the validity analysis has no speed with a verdict; the sweep finished no run")
    uncertainty = result.beta_limit_uncertainty if result.beta_limit is not None else 0.0
    limit = SweepLimit(kind=kind, name=name, beta_star=result.beta_limit, resolution=float(uncertainty or 0.0),
                       grid_betas=tuple(v.beta for v in result.per_beta), holds_at=tuple(v.holds for v in result.per_beta))
    order = np.argsort(dataset["presag"].values)
    forces = np.argsort(dataset["static_force"].values)
    inside = dataset["speed"].values <= speed_high * (1 + 1e-9)
    values = np.asarray(dataset["uplift_max"].values, dtype=float)[:, inside, :]
    if values.shape[1]:
        finite = np.where(np.isfinite(values), values, -np.inf).max(axis=1)
        uplift = np.where(np.isneginf(finite), np.nan, finite)
    else:
        uplift = np.full((values.shape[0], values.shape[2]), np.nan)
    wave_speed = sweep_wave_speed(dataset)
    note = ("" if abs(wave_speed / line_wave_speed - 1.0) <= 0.01 else
            f"{name} is of a contact wire with wave speed {wave_speed / KMH:.0f} km/h, this line's is "
            f"{line_wave_speed / KMH:.0f} km/h: its speed ratios carry over, its speeds do not")
    reference_span = sweep_reference_span(dataset)
    return ValiditySweep(limit=limit, presag_rel=tuple(float(s) / reference_span for s in dataset["presag"].values[order]),
                         static_forces=tuple(float(f) for f in dataset["static_force"].values[forces]),
                         uplift=uplift[np.ix_(order, forces)], note=note)
