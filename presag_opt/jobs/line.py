"""The job on a surveyed line: ``design_line``, what ``presag design`` runs."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand
from presag_opt.display import data_frame, html_summary
from presag_opt.errors import ModelError
from presag_opt.jobs.band import check_band_speed, decision_settings
from presag_opt.jobs.options import (
    ELEMENT_LENGTH,
    LINE_ELASTICITY_STEP,
    UPLIFT_LIMIT_MM,
    WITHIN_PERCENT,
    WORKERS,
    WORKING_WIDTH_MM,
)
from presag_opt.pipeline.band import JOB_OPTIONS
from presag_opt.pipeline.line import LineAnswer
from presag_opt.report.line_report import dropper_rows, rounding_rows, span_rows
from presag_opt.system.catenary import Catenary
from presag_opt.system.dropper_type import DEFAULT_DROPPER_TYPE

if TYPE_CHECKING:
    from presag_opt.system.dropper_type import DropperType
    from presag_opt.system.survey import Survey


@dataclass(frozen=True, kw_only=True)
class LineDesignAnswer(LineAnswer):
    """A designed line (:class:`~presag_opt.pipeline.line.LineAnswer`) that shows itself in a notebook and
    gives its tables: the rows of ``spans.csv``, ``droppers.csv`` and ``rounding.csv``
    (:mod:`presag_opt.report.line_report`) and the decision's answers."""

    def table(self, name: str = "spans") -> list[dict]:
        """A table as rows: ``spans``, ``droppers``, ``rounding`` (the line's CSV files, in table units) or
        ``answers`` (the decision's).

        Parameters
        ----------
        name : {"spans", "droppers", "rounding", "answers"}
            The table.
        """
        tables = {"spans": lambda: span_rows(self), "droppers": lambda: dropper_rows(self.design),
                  "rounding": lambda: rounding_rows(self.design), "answers": self.decision.table}
        if name not in tables:
            raise ModelError(f"table = {name!r} is not one of {', '.join(tables)}")
        return tables[name]()

    def to_frame(self, name: str = "spans"):
        """:meth:`table` as a pandas DataFrame.

        Parameters
        ----------
        name : {"spans", "droppers", "rounding", "answers"}
            The table.
        """
        return data_frame(self.table(name))

    def _repr_html_(self) -> str:
        def low_high(row: dict) -> str:
            low, high = row["presag_tolerance_low_mm"], row["presag_tolerance_high_mm"]
            return "" if low == "" else f"{low:.1f}–{high:.1f}"

        return html_summary(self.headline(), self.lines(JOB_OPTIONS)[1:],
                            [{"section": r["section"], "span": f"{r['from_mast']}–{r['to_mast']}", "l [m]": r["length_m"],
                              "S built [mm]": r["presag_mm"], "own tolerance [mm]": low_high(r), "flag": r["flag"]}
                             for r in self.table("spans")])


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
    round_mm: float = 0.0,
    dropper_type: str | Path | DropperType = DEFAULT_DROPPER_TYPE,
    step: float = LINE_ELASTICITY_STEP,
    element_length: float = ELEMENT_LENGTH,
    workers: int = WORKERS,
    allow_supercritical: bool = False,
    progress: Callable[[str], None] | None = None,
) -> LineDesignAnswer:
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
    round_mm : float
        The crew's cutting step the cut lengths are rounded to (0: exact); its error enters the installation
        tolerance. [mm]
    dropper_type : str, Path or DropperType
        The dropper type whose terminal and loop allowances make the cut length (built-in name, file or
        object).
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
    LineDesignAnswer
        The line as built (``answer.design``: spans, droppers, rules) and the decision; shows itself in
        a notebook, its tables by :meth:`LineDesignAnswer.to_frame`.

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
    from presag_opt.system.dropper_type import DropperType, check_step, load_dropper_type
    from presag_opt.system.loader import load_catenary
    from presag_opt.system.survey import load_survey

    round_step = check_step(round_mm * 1e-3)
    if not isinstance(dropper_type, DropperType):
        dropper_type = load_dropper_type(dropper_type)
    if isinstance(survey, str | Path):
        survey = load_survey(survey, working_width=working_width_mm * 1e-3)
    base = system if isinstance(system, Catenary) else load_catenary(system)
    check_band_speed(band, [base], allow_supercritical)
    settings = decision_settings(within_percent, uplift_limit_mm, crew_tolerance_mm, study=study)
    options = LineOptions(rule=rule, element_length=element_length, step=step, workers=workers, round_step=round_step,
                          dropper_type=dropper_type)
    answer = answer_line(survey, base, band, options=options, within=settings["within"],
                         uplift_limit=settings["uplift_limit"], crew=settings["crew"], study=study, check=dynamic_check,
                         dynamic=DynamicOptions(workers=workers) if dynamic_robust else None, progress=progress)
    return LineDesignAnswer(**{f.name: getattr(answer, f.name) for f in fields(answer)})
