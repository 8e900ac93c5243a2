"""Reduced validity studies: a small grid on a short section with coarse numerics, run in this process.

For a first look at a line (the HTML report, the notebooks' fast mode) the paper's 400-run grid on
ten spans at 0.5 m and 2 ms is more than needed. :func:`reduced_study` cuts a study to a few pre-sags,
speeds and static forces on the central spans of its section with coarser numerics, and
:func:`run_in_process` runs it here, without worker processes or files, and returns the same dataset
the store would hold, for :func:`presag_opt.studies.validity_analysis.validity_analysis`.

Coarse numerics change σ by tens of per cent against the paper's 0.5 m and 2 ms (the case study at
90 km/h: 14.8 N at 1 m and 4 ms against 11.2 N, measured), and the 4 ms step makes σ sensitive to
round-off: the case study at S = 50 mm with static forces 105 N · (1 + k·1e-12), k = 0…3, gave σ
spread by 2.0 % at 90 km/h and 1.3 % at 180 km/h at 1 m and 4 ms (0.6 % at 0.5 m and 4 ms), against
3e-12 at 90 km/h and 0.35 % at 180 km/h at 0.5 m and 2 ms (and 4e-11 at 1 m and 2 ms), measured. So a
reduced study locates the validity limit roughly, a verdict near its 5 % thresholds can turn on
round-off, and the full study (``presag sweep``) gives the numbers to quote.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import xarray as xr

from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.errors import ModelError
from presag_opt.studies.definition import StudyDefinition, StudyGrid
from presag_opt.studies.store import assemble
from presag_opt.studies.work import UnitRunner, all_units, task_groups
from presag_opt.system.catenary import Catenary, SpanLayout
from presag_opt.units import KMH

REDUCED_SPANS = 5
"""Spans of a reduced study's section: one lead-in, one analysed span and room to run out. [-]"""


def reduced_study(
    base: StudyDefinition,
    *,
    presags: Sequence[float],
    speeds: Sequence[float],
    static_forces: Sequence[float],
    catenary: Catenary | None = None,
    pantograph: Pantograph | None = None,
    aero_coefficient: float | None = None,
    span_count: int = REDUCED_SPANS,
    element_length: float = 1.0,
    time_step: float = 4e-3,
) -> StudyDefinition:
    """A small version of a study: fewer grid points, the central spans of the section, coarse numerics.

    Parameters
    ----------
    base : StudyDefinition
        The study to reduce (pantograph, aerodynamic coefficient, uplift limit, settings).
    presags : sequence of float
        Mid-span pre-sag of the longest span, increasing. [m]
    speeds : sequence of float
        Train speeds, increasing. [m/s]
    static_forces : sequence of float
        Static uplift forces, increasing. [N]
    catenary : Catenary, optional
        Another catenary to study (default: the base study's).
    pantograph : Pantograph, optional
        Another pantograph (default: the base study's).
    aero_coefficient : float, optional
        α_ae of F_m = F_stat + α_ae v² (default: the base study's). [N/(m/s)²]
    span_count : int
        Central spans kept, at least 4 (a lead-in span, the analysed span and the run-out). [-]
    element_length : float
        Longest element. [m]
    time_step : float
        Integration time step. [s]

    Returns
    -------
    StudyDefinition
        Checked like any study (every speed below the wave speed, the window inside the section).
    """
    if base.parameters:
        raise ModelError("reduced_study: the base study sweeps extra parameters; reduce a study without them")
    catenary = central_spans(catenary or base.catenary, span_count)
    kept = catenary.layout.span_lengths
    settings = dataclasses.replace(base.settings.with_fixed_numerics(element_length=element_length, time_step=time_step),
                                   analysed_spans=1, lead_in_spans=1)
    grid = StudyGrid(presags=tuple(presags), speeds=tuple(speeds), static_forces=tuple(static_forces),
                     aero_coefficient=base.grid.aero_coefficient if aero_coefficient is None else aero_coefficient)
    return dataclasses.replace(
        base, name=f"reduced: {catenary.name}", catenary=catenary,
        pantograph=pantograph or base.pantograph, grid=grid, settings=settings,
        description=f"{len(presags)} pre-sags x {len(speeds)} speeds x {len(static_forces)} static forces on "
                    f"{len(kept)} spans, {element_length:g} m elements, {time_step * 1e3:g} ms",
    )


def central_spans(catenary: Catenary, span_count: int = REDUCED_SPANS) -> Catenary:
    """The catenary cut to its ``span_count`` central spans (all of them if it has fewer).

    Parameters
    ----------
    catenary : Catenary
        The section.
    span_count : int
        Central spans kept, at least 4 (a lead-in span, the analysed span and the run-out). [-]
    """
    if span_count < 4:
        raise ModelError(f"span_count = {span_count} is below the smallest valid value 4")
    lengths = catenary.layout.span_lengths
    first = max(0, (len(lengths) - span_count) // 2)
    kept = lengths[first:first + span_count]
    radii = catenary.layout.radii[first:first + span_count]
    layout = SpanLayout(span_lengths=kept, curve_radii=radii if any(radii) else None,
                        label=f"{len(kept)} central spans of: {catenary.layout.label or catenary.name}")
    return catenary.with_layout(layout)


def run_in_process(definition: StudyDefinition, progress: Callable[[str], None] | None = None) -> xr.Dataset:
    """Run every unit of a (small) study in this process and return its dataset (nothing is written).

    Parameters
    ----------
    definition : StudyDefinition
        The study.
    progress : callable, optional
        Called with a short message before each batch (one pre-sag, up to four speeds).

    Returns
    -------
    xarray.Dataset
        As :func:`presag_opt.studies.store.open_store` would return it for this study.
    """
    results = []
    runner = UnitRunner()
    for group in task_groups(all_units(definition)):
        if progress:
            s = definition.grid.presags[group[0].presag_index]
            kmh = ", ".join(f"{definition.grid.speeds[u.speed_index] / KMH:g}" for u in group)
            progress(f"S = {s * 1e3:g} mm at {kmh} km/h")
        results += runner(definition, group)
    return assemble(definition, results)
