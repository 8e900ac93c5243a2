"""The job on a surveyed line: ``design_line``, what ``presag design`` runs."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand
from presag_opt.jobs.band import check_band_speed, decision_settings
from presag_opt.jobs.options import (
    ELEMENT_LENGTH,
    LINE_ELASTICITY_STEP,
    UPLIFT_LIMIT_MM,
    WITHIN_PERCENT,
    WORKERS,
    WORKING_WIDTH_MM,
)
from presag_opt.system.catenary import Catenary

if TYPE_CHECKING:
    from presag_opt.pipeline.line import LineAnswer
    from presag_opt.system.survey import Survey


def design_line(
    survey: str | Path | Survey,
    system: str | Path | Catenary,
    band: OperatingBand = CASE_STUDY_BAND,
    *,
    rule: str = "proportional",
    working_width_mm: float = WORKING_WIDTH_MM,
    within_percent: float = WITHIN_PERCENT,
    uplift_limit_mm: float = UPLIFT_LIMIT_MM,
    crew_tolerance_mm: float | None = None,
    study: str | Path | None = None,
    dynamic_check: bool = False,
    dynamic_robust: bool = False,
    step: float = LINE_ELASTICITY_STEP,
    element_length: float = ELEMENT_LENGTH,
    workers: int = WORKERS,
    allow_supercritical: bool = False,
    progress: Callable[[str], None] | None = None,
) -> LineAnswer:
    """Design a surveyed line: per-span pre-sag, a dropper schedule and one decision (``presag design``).

    Parameters
    ----------
    survey : str, Path or Survey
        The survey table (``.csv``, ``.xlsx`` or ``.toml``, one row per mast), or a loaded survey.
    system : str, Path or Catenary
        The system model (wires, tensions, droppers, supports); its layout and geometry are replaced
        by the survey's.
    band : OperatingBand
        Static forces, speeds and α_ae (:meth:`OperatingBand.from_kmh`). Default: the case study's.
    rule : {"proportional", "per-span", "robust"}
        Pre-sag per span: S = S_rel·l with the line's S_rel (Swedish practice), each span's own
        quasi-static S_rel, or each span's own quasi-static robust parabola.
    working_width_mm : float
        Half working width of the pantograph, the largest stagger accepted (a survey file only). [mm]
    within_percent : float
        Allowed loss of the tolerance intervals. [%]
    uplift_limit_mm : float
        Steady-arm uplift limit. [mm]
    crew_tolerance_mm : float, optional
        The crew's build tolerance of the mid-span pre-sag, ± (default: the assumed 2.5). [mm]
    study : str or Path, optional
        A stored validity study (``presag sweep``).
    dynamic_check : bool
        Simulate the band's worst points on the section with the largest static uplift, as built.
    dynamic_robust : bool
        Run the dynamic robust design of that section and decide with it.
    step : float
        Point spacing of the elasticity curves. [m]
    element_length : float
        Longest element of the static model. [m]
    workers : int
        Processes for the sections and the simulations. [-]
    allow_supercritical : bool
        Accept a top speed at or above β = 0.7 of the system's wave speed.
    progress : callable, optional
        Called with a short message as the work goes on.

    Returns
    -------
    LineAnswer
        The line as built (``answer.design``: spans, droppers, rules) and the decision; shows itself in
        a notebook, its tables by :meth:`~presag_opt.pipeline.line.LineAnswer.to_frame`.

    Examples
    --------
    Eight masts 50 m apart on straight track, the survey's columns in their table units (m, mm):

    >>> from presag_opt import design_line
    >>> from presag_opt.system.survey import survey_from_rows
    >>> rows = [(f"row {i}", {"mast": f"M{i}", "chainage_m": 50.0 * i, "stagger_mm": 300 if i % 2 else -300,
    ...                       "contact_wire_height_m": 5.5, "system_height_m": 1.2, "curve_radius_m": 0,
    ...                       "steady_arm": "pull-off"}) for i in range(8)]
    >>> answer = design_line(survey_from_rows(rows), "st_9.8_ideal")
    >>> print(answer.headline())
    Pre-sag to build (provisional): ...
    """
    from presag_opt.design.line import LineOptions
    from presag_opt.pipeline.band import DynamicOptions
    from presag_opt.pipeline.line import answer_line
    from presag_opt.system.loader import load_catenary
    from presag_opt.system.survey import load_survey

    if isinstance(survey, str | Path):
        survey = load_survey(survey, working_width=working_width_mm * 1e-3)
    base = system if isinstance(system, Catenary) else load_catenary(system)
    check_band_speed(band, [base], allow_supercritical)
    settings = decision_settings(within_percent, uplift_limit_mm, crew_tolerance_mm, study=study)
    return answer_line(survey, base, band, options=LineOptions(rule=rule, element_length=element_length, step=step,
                                                               workers=workers),
                       within=settings["within"], uplift_limit=settings["uplift_limit"], crew=settings["crew"],
                       study=study, check=dynamic_check,
                       dynamic=DynamicOptions(workers=workers) if dynamic_robust else None, progress=progress)
