"""The validity sweep of a decision: a stored study read, or a reduced sweep run for a report.

:func:`stored_sweep` reads a study store (``presag sweep``) and :func:`reduced_sweep` runs a few
pre-sags × speeds × static forces around the recommendation on the first model, in this process
(:mod:`presag_opt.studies.reduced`). Both return a :class:`ValidityRange`: the study's statistics,
their analysis and the :class:`~presag_opt.design.evidence.ValiditySweep` record the decision reads.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from presag_opt.design.band import OperatingBand
from presag_opt.design.evidence import ValiditySweep
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.studies.definition import load_study
from presag_opt.studies.reduced import REDUCED_SPANS, central_spans, reduced_study, run_in_process
from presag_opt.studies.store import open_store
from presag_opt.studies.validity_analysis import validity_analysis
from presag_opt.studies.validity_evidence import validity_sweep
from presag_opt.studies.validity_results import ValidityResult
from presag_opt.system.catenary import Catenary
from presag_opt.units import KMH

BASE_STUDY = "paper_grid_st98"
"""Study whose numerics, analysis window and uplift limit a reduced sweep starts from."""

SWEEP_BETAS = (0.2, 0.3, 0.4, 0.5, 0.6)
"""Speed ratios of a reduced sweep, besides the top speed of the band. [-]"""

SWEEP_PRESAG_FACTORS = (0.5, 1.0, 1.5)
"""Pre-sags of a reduced sweep, as multiples of the recommended one. [-]"""


@dataclass(frozen=True, kw_only=True)
class ValidityRange:
    """A validity sweep with its analysis and its record.

    Attributes
    ----------
    source : str
        The stored study file, or a description of the reduced sweep.
    dataset : xarray.Dataset
        The study's statistics.
    result : ValidityResult
        Its analysis.
    record : ValiditySweep
        What the decision reads from it.
    """

    source: str
    dataset: xr.Dataset
    result: ValidityResult
    record: ValiditySweep

    def uplift_up_to(self, speed: float) -> float | None:
        """Largest steady-arm uplift of the runs at or below a speed (None if no run there). [m]

        Parameters
        ----------
        speed : float
            Highest speed of the runs taken. [m/s]
        """
        speeds = self.dataset["speed"].values
        values = self.dataset["uplift_max"].values[:, speeds <= speed * (1 + 1e-9), :]
        finite = values[values == values]
        return float(finite.max()) if finite.size else None


def stored_sweep(path: str | Path, band: OperatingBand, line_wave_speed: float) -> ValidityRange:
    """A stored study (``presag sweep``) as the decision's validity sweep.

    Parameters
    ----------
    path : str or Path
        The study store.
    band : OperatingBand
        The band decided for (its top speed bounds the uplift taken). [m/s]
    line_wave_speed : float
        Contact-wire wave speed of the line decided for. [m/s]
    """
    dataset = open_store(path)
    result = validity_analysis(dataset)
    name = f"the validity study {Path(path).name}"
    record = validity_sweep(dataset, result, kind="study", name=name, speed_high=band.speed_high,
                            line_wave_speed=line_wave_speed)
    return ValidityRange(source=str(path), dataset=dataset, result=result, record=record)


def sweep_grid(catenary: Catenary, band: OperatingBand, presag_rel: float, quick: bool) -> dict:
    """Grid of a reduced sweep: pre-sags around ``presag_rel``, speeds from the band's top to β = 0.6,
    the band's static forces (a quick sweep: two of each).

    Parameters
    ----------
    catenary : Catenary
        The system swept.
    band : OperatingBand
        The band decided for. [N], [m/s]
    presag_rel : float
        The pre-sag the sweep is centred on. [-]
    quick : bool
        Two pre-sags, speeds and forces only.
    """
    c_kmh = catenary.contact_wire.wave_speed / KMH
    top = band.speed_high / KMH
    speeds = sorted({round(top)} | {10 * round(b * c_kmh / 10) for b in SWEEP_BETAS})
    speeds = [v for v in speeds if 0 < v < 0.9 * c_kmh]
    presag = presag_rel * max(central_spans(catenary, REDUCED_SPANS).layout.span_lengths)  # the swept section's
    factors = SWEEP_PRESAG_FACTORS
    forces = [band.static_force_low, 0.5 * (band.static_force_low + band.static_force_high), band.static_force_high]
    if quick:
        speeds, factors, forces = [round(top), speeds[-1]], (factors[0], factors[-1]), [forces[0], forces[-1]]
    return {
        "presags": tuple(round(f * presag, 3) for f in factors),
        "speeds": tuple(v * KMH for v in sorted(set(speeds))),
        "static_forces": tuple(sorted(set(forces))),
    }


def reduced_sweep(catenary: Catenary, pantograph: Pantograph, band: OperatingBand, presag_rel: float, *,
                  quick: bool, element_length: float, time_step: float,
                  progress: Callable[[str], None] | None = None) -> ValidityRange:
    """Run a reduced sweep around a pre-sag, in this process, as the decision's validity sweep.

    Parameters
    ----------
    catenary : Catenary
        The system swept (five central spans of it).
    pantograph : Pantograph
        The pantograph.
    band : OperatingBand
        The band decided for. [N], [m/s]
    presag_rel : float
        The pre-sag the sweep is centred on (the Δe rule's). [-]
    quick : bool
        Two pre-sags, speeds and forces (:func:`sweep_grid`).
    element_length : float
        Longest element. [m]
    time_step : float
        Integration time step. [s]
    progress : callable, optional
        Called with a short message before each batch.
    """
    definition = reduced_study(load_study(BASE_STUDY), catenary=catenary, pantograph=pantograph,
                               aero_coefficient=band.aero_coefficient, element_length=element_length,
                               time_step=time_step, **sweep_grid(catenary, band, presag_rel, quick))
    dataset = run_in_process(definition, progress=progress)
    result = validity_analysis(dataset)
    source = f"reduced sweep run for this decision: {definition.description}"
    record = validity_sweep(dataset, result, kind="reduced", name="the reduced sweep", speed_high=band.speed_high,
                            line_wave_speed=catenary.contact_wire.wave_speed)
    return ValidityRange(source=source, dataset=dataset, result=result, record=record)
