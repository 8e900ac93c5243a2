"""The paper's published numbers: Table 1, Table 2, the case-study recommendation and Fig. 5b.

Data only, as printed, so that every comparison reads them from one place
(:mod:`presag_opt.validation.comparison` sets our numbers beside them; the tests check against them).
How our numbers are computed is left to :mod:`presag_opt.design`.

The paper's Table 2 S_rel column is not S/60 m of its own S column for three of the four entries
(96 mm → 1.69 ‰ printed, 1.60 ‰ computed; 118 → 1.96 vs 1.97; 58 → 0.96 vs 0.97); comparisons with
Table 2 therefore use S in mm only.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: Table 1, Table 2, Fig. 5b, section 5.2.
"""

from __future__ import annotations

PAPER_TABLE1_SPAN_LENGTH = 60.0
"""Span length of Table 1. [m]"""

PAPER_TABLE1_STATIC_FORCE = 140.0
"""Static contact force of Table 1. [N]"""


SINGLE_CURVE_MAX_FORCE = 179.0
"""Largest F_m of the Fig. 5b study (upper end of the EN 50367 range for 1,5 kV DC). [N]"""

PAPER_TABLE1 = {
    "7.1/7.1": {"e_mid_mm_per_N": 1.056, "presag_mm": (74, 104), "presag_rel_permille": (1.23, 1.73)},
    "9.8/9.8": {"e_mid_mm_per_N": 0.765, "presag_mm": (54, 75), "presag_rel_permille": (0.90, 1.25)},
}
"""Table 1 of the paper (F_stat = 140 N, l = 60 m), as printed."""

PAPER_TABLE2_MM = {
    "7.1/7.1": {"mid-mast": 96.0, "delta-e": 118.0},
    "9.8/9.8": {"mid-mast": 58.0, "delta-e": 79.0},
}
"""Table 2 of the paper: S in mm at F_m = 140 N from simulated elasticity (60 m spans)."""

PAPER_TABLE2_FORCE = 140.0
"""Mean contact force of Table 2. [N]"""

PAPER_RECOMMENDATION = {
    "fm_band_N": (70.0, 148.0),
    "presag_rel_range_permille": {"ideal": (0.68, 1.35), "mixed": (0.82, 1.62)},
    "presag_rel_permille": 1.12,
    "presag_mm": 67.0,
    "beta_max": 0.26,
}
"""The case-study recommendation of section 5.2 (S_rel ranges with the Δe rule)."""

PAPER_SINGLE_CURVE_ERROR = {0.030: 0.16, 0.070: 0.02}
"""Fig. 5b: relative error of using only the 100 N curve, at F_m = 179 N, by geometry pre-sag [m]."""


PAPER_TABLE2_MODELS = ("st_7.1_ideal", "st_9.8_ideal")
"""Built-in ideal-span models of the two systems of Table 2."""

SINGLE_CURVE_MODEL = "st_9.8_ideal"
"""Built-in model of the Fig. 5b study (homogeneous ST 9,8/9,8 spans)."""
