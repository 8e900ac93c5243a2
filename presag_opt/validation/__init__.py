"""Validation against published results: the paper's numbers and the EN 50318 reference ranges.

Modules: :mod:`~presag_opt.validation.paper` (Table 1, Table 2, the recommendation and Fig. 5b as
printed), :mod:`~presag_opt.validation.single_curve` (the Fig. 5b study),
:mod:`~presag_opt.validation.comparison` (our numbers beside the paper's) and
:mod:`~presag_opt.validation.en50318` (reference ranges of the EN 50318 case, a verdict per
statistic); :mod:`~presag_opt.validation.dynamic_model` (the simulator against crawling speed, a moving
force on a string and convergence) is used from its module. The names below are the public API.
"""

from presag_opt.validation.comparison import (
    ComparisonRow,
    PaperComparison,
    Table2Row,
    compare_with_paper,
    comparison_rows,
    table2_row,
)
from presag_opt.validation.en50318 import EN50318_RANGES, Verdict, en50318_ranges, en50318_verdicts
from presag_opt.validation.paper import (
    PAPER_RECOMMENDATION,
    PAPER_SINGLE_CURVE_ERROR,
    PAPER_TABLE1,
    PAPER_TABLE1_SPAN_LENGTH,
    PAPER_TABLE1_STATIC_FORCE,
    PAPER_TABLE2_FORCE,
    PAPER_TABLE2_MM,
    PAPER_TABLE2_MODELS,
    SINGLE_CURVE_MAX_FORCE,
    SINGLE_CURVE_MODEL,
)
from presag_opt.validation.single_curve import SingleCurveError, single_curve_error

__all__ = [
    "EN50318_RANGES",
    "PAPER_RECOMMENDATION",
    "PAPER_SINGLE_CURVE_ERROR",
    "PAPER_TABLE1",
    "PAPER_TABLE1_SPAN_LENGTH",
    "PAPER_TABLE1_STATIC_FORCE",
    "PAPER_TABLE2_FORCE",
    "PAPER_TABLE2_MM",
    "PAPER_TABLE2_MODELS",
    "SINGLE_CURVE_MAX_FORCE",
    "SINGLE_CURVE_MODEL",
    "ComparisonRow",
    "PaperComparison",
    "SingleCurveError",
    "Table2Row",
    "Verdict",
    "compare_with_paper",
    "comparison_rows",
    "en50318_ranges",
    "en50318_verdicts",
    "single_curve_error",
    "table2_row",
]
