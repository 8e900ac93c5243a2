"""Pre-sag design: the empirical and quasi-static rules, sections, validity, the recommendation.

Modules: :mod:`~presag_opt.design.empirical` (eq. 1–3), :mod:`~presag_opt.design.band` (operating
band, eq. 4, force levels), :mod:`~presag_opt.design.quasi_static` (eq. 2 and 5 on one curve,
interpolation between force levels), :mod:`~presag_opt.design.section` (ideal and mixed sections),
:mod:`~presag_opt.design.speed_range` (speed ratio, steady-arm uplift) and
:mod:`~presag_opt.design.recommendation` (the case study); :mod:`~presag_opt.design.layouts` (mixed
against ideal spans, curved track) is used from its module. The names below are the public API.
"""

from presag_opt.design.band import (
    CASE_STUDY_BAND,
    FORCE_LEVEL_SPACING,
    KMH,
    OperatingBand,
    check_levels_cover,
    force_levels_for_band,
    mean_contact_force,
    mean_force_grid,
)
from presag_opt.design.empirical import E_MAST_RATIOS, EMPIRICAL_K, EmpiricalPresag, mid_span_elasticity_empirical
from presag_opt.design.quasi_static import (
    PRESAG_METHODS,
    check_method,
    elasticity_difference,
    interpolate_elasticity,
    presag_quasi_static,
)
from presag_opt.design.recommendation import (
    CASE_STUDY_MODELS,
    CASE_STUDY_SPAN_LENGTH,
    LayoutRecommendation,
    Recommendation,
    layout_recommendation,
    recommend,
)
from presag_opt.design.section import (
    SectionElasticity,
    SectionPresag,
    check_elasticity_method,
    default_spans,
    layout_kind,
    section_elasticity,
    tension_label,
)
from presag_opt.design.speed_range import (
    QUASI_STATIC_BETA_LIMIT,
    STEADY_ARM_UPLIFT_LIMIT,
    SpeedContext,
    StaticSteadyArmUplift,
    speed_context,
)

__all__ = [
    "CASE_STUDY_BAND",
    "CASE_STUDY_MODELS",
    "CASE_STUDY_SPAN_LENGTH",
    "EMPIRICAL_K",
    "E_MAST_RATIOS",
    "FORCE_LEVEL_SPACING",
    "KMH",
    "PRESAG_METHODS",
    "QUASI_STATIC_BETA_LIMIT",
    "STEADY_ARM_UPLIFT_LIMIT",
    "EmpiricalPresag",
    "LayoutRecommendation",
    "OperatingBand",
    "Recommendation",
    "SectionElasticity",
    "SectionPresag",
    "SpeedContext",
    "StaticSteadyArmUplift",
    "check_elasticity_method",
    "check_levels_cover",
    "check_method",
    "default_spans",
    "elasticity_difference",
    "force_levels_for_band",
    "interpolate_elasticity",
    "layout_kind",
    "layout_recommendation",
    "mean_contact_force",
    "mean_force_grid",
    "mid_span_elasticity_empirical",
    "presag_quasi_static",
    "recommend",
    "section_elasticity",
    "speed_context",
    "tension_label",
]
