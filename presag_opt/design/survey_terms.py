"""A section's failure in the survey's terms: mast ids and rows instead of the model's numbering.

The static model numbers the masts and spans of a section from 1 (``mast 10``, ``span 3``); a surveyor
knows the line by mast id and by the row of the table. :func:`in_survey_terms` rewrites an error of a
section's model so that every mast and span it names is the survey's (``mast M22 (line.csv, row 23)``,
``span M21–M22``), and names the survey column to look at where the failure points to one.
"""

from __future__ import annotations

import re

from presag_opt.errors import ConvergenceError, PresagError
from presag_opt.system.survey import SurveySection

_MAST = re.compile(r"\bmast (\d+)(?: \(of \d+\))?")
_SPAN = re.compile(r"\bspan (\d+)\b")

COLUMNS_TO_CHECK = (
    ("steady arm at mast", "stagger_mm"),
    ("push-off arm", "steady_arm"),
    ("messenger wire sags", "system_height_m"),
    ("shorter than settings.min_dropper_length", "system_height_m"),
)
"""Which survey column a failure points to, by a phrase of its message."""


def in_survey_terms(error: PresagError, section: SurveySection) -> PresagError:
    """The same error, its message naming the survey's masts, rows and the column to check.

    Parameters
    ----------
    error : PresagError
        An error of the section's model (its masts and spans numbered from 1).
    section : SurveySection
        The surveyed masts of that section.
    """
    masts = section.masts

    def mast(match: re.Match) -> str:
        i = int(match.group(1)) - 1
        if not 0 <= i < len(masts):
            return match.group(0)
        return f"mast {masts[i].mast}" + (f" ({masts[i].row})" if masts[i].row else "")

    def span(match: re.Match) -> str:
        i = int(match.group(1)) - 1
        if not 0 <= i < len(masts) - 1:
            return match.group(0)
        return f"span {masts[i].mast}–{masts[i + 1].mast}"

    message = _SPAN.sub(span, _MAST.sub(mast, str(error)))
    column = next((c for phrase, c in COLUMNS_TO_CHECK if phrase in message), None)
    if column:
        message += f" (survey column {column!r})"
    if message == str(error):
        return error
    out = ConvergenceError(message, error.stats) if isinstance(error, ConvergenceError) else type(error)(message)
    out.__cause__ = error
    return out
