"""A survey table written from a model: a hand-written section as a survey, and a survey as CSV rows.

For tests, notebooks and designers who start from a span list: :func:`survey_of_catenary` gives the
survey of a :class:`~presag_opt.system.catenary.Catenary` (one mast per support), and
:func:`write_survey_csv` a file that :func:`~presag_opt.system.survey.load_survey` reads back.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from presag_opt.system.catenary import Catenary
from presag_opt.system.survey import (
    COLUMNS,
    DEFAULT_SECTION,
    DEFAULT_WORKING_WIDTH,
    OPTIONAL_COLUMNS,
    Survey,
    SurveyMast,
)


def survey_of_catenary(catenary: Catenary, *, start_chainage: float = 0.0, section: str = DEFAULT_SECTION,
                       first_mast: int = 1) -> Survey:
    """The survey of a section written by hand (span list, one stagger and height): one mast per support.

    Parameters
    ----------
    catenary : Catenary
        The section; its per-mast stagger, heights and steady-arm types (alternating stagger, one
        height, pull-off arms without a :class:`~presag_opt.system.masts.MastGeometry`).
    start_chainage : float
        Chainage of the first mast. [m]
    section : str
        Section id of every mast.
    first_mast : int
        Number of the first mast (ids ``M<n>``). [-]
    """
    chainage = start_chainage + np.concatenate([[0.0], np.cumsum(catenary.layout.span_lengths)])
    radii = (*catenary.layout.radii, 0.0)
    masts = tuple(
        SurveyMast(mast=f"M{first_mast + i}", chainage=float(c), stagger=float(s), contact_wire_height=float(h),
                   system_height=float(sh), curve_radius=float(r), steady_arm="push-off" if p else "pull-off",
                   section=section, row=f"mast {i + 1}")
        for i, (c, s, h, sh, r, p) in enumerate(zip(chainage, catenary.mast_stagger(), catenary.mast_contact_wire_height(),
                                                    catenary.mast_system_height(), radii, catenary.mast_push_off()))
    )
    return Survey(masts=masts, source=f"<{catenary.name}>", working_width=max(DEFAULT_WORKING_WIDTH, catenary.stagger))


def survey_table(survey: Survey) -> list[dict[str, object]]:
    """The survey as table rows in table units (m, mm), columns :data:`COLUMNS`, ``section`` and ``stitched``
    (``yes``/``no``, empty where the survey does not say)."""
    return [
        {"mast": m.mast, "chainage_m": round(m.chainage, 6), "stagger_mm": round(m.stagger * 1e3, 6),
         "contact_wire_height_m": round(m.contact_wire_height, 6), "system_height_m": round(m.system_height, 6),
         "curve_radius_m": round(m.curve_radius, 6), "steady_arm": m.steady_arm, "section": m.section,
         "stitched": "" if m.stitched is None else "yes" if m.stitched else "no", "cant_mm": round(m.cant * 1e3, 3)}
        for m in survey.masts
    ]


def write_survey_csv(survey: Survey, path: str | Path) -> Path:
    """Write a survey as a CSV table that :func:`load_survey` reads back; return the path."""
    path = Path(path)
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=[*COLUMNS, *OPTIONAL_COLUMNS])
        writer.writeheader()
        writer.writerows(survey_table(survey))
    return path
