"""presag_opt: pre-sag design for simple railway overhead contact lines.

The jobs first, one call each, as the command line runs them (:mod:`presag_opt.jobs`): ``recommend``,
``robust_design``, ``dynamic_robust_design``, ``design_line``, ``sensitivity_study``, ``tolerance``,
``validity`` and ``simulate``, in the designer's units (km/h, mm, %, N/(km/h)²). Then the public API by name, from every layer: system models (:mod:`presag_opt.system`), the static model
(:mod:`presag_opt.static`), elasticity (:mod:`presag_opt.elasticity`), pre-sag design
(:mod:`presag_opt.design`), robust design (:mod:`presag_opt.robust`) and validation against published
results (:mod:`presag_opt.validation`); the dynamic simulation is used from :mod:`presag_opt.dynamics`.
A name is imported from its module on first use, so that ``import presag_opt`` loads neither CasADi nor
cvxpy nor the simulator (the command line relies on that to start quickly).
"""

from __future__ import annotations

from importlib import import_module

from presag_opt.version import VERSION

__version__ = VERSION

_API = {
    "presag_opt.jobs": (
        "design_line", "dynamic_robust_design", "recommend", "robust_design", "sensitivity_study", "simulate",
        "tolerance", "validity",
    ),
    "presag_opt.pipeline.band": (
        "BandAnswer",
    ),
    "presag_opt.pipeline.line": (
        "LineAnswer",
    ),
    "presag_opt.design.decision": (
        "Decision",
    ),
    "presag_opt.system.survey": (
        "Survey", "load_survey",
    ),
    "presag_opt.errors": (
        "ConvergenceError", "ModelError",
    ),
    "presag_opt.speed": (
        "doppler_factor", "speed_ratio", "wave_speed",
    ),
    "presag_opt.system.catenary": (
        "Catenary", "Damping", "Droppers", "PinSupport", "Provenance", "SpanLayout", "SpringSupport",
        "SteadyArm", "Wire",
    ),
    "presag_opt.system.loader": (
        "builtin_model_names", "load_catenary",
    ),
    "presag_opt.static.discretisation": (
        "StaticSettings",
    ),
    "presag_opt.static.equilibrium": (
        "EquilibriumState",
    ),
    "presag_opt.static.form_finding": (
        "dropper_height_sensitivity", "form_find",
    ),
    "presag_opt.static.linearised": (
        "TensionOnlyStructure",
    ),
    "presag_opt.elasticity": (
        "ElasticityCurve", "ElasticityStudy", "elasticity_study", "linear_elasticity", "nonlinear_elasticity",
    ),
    "presag_opt.design": (
        "CASE_STUDY_BAND", "CASE_STUDY_MODELS", "CASE_STUDY_SPAN_LENGTH", "EMPIRICAL_K", "E_MAST_RATIOS",
        "FORCE_LEVEL_SPACING", "KMH", "PRESAG_METHODS", "QUASI_STATIC_BETA_LIMIT", "STEADY_ARM_UPLIFT_LIMIT",
        "EmpiricalPresag", "LayoutRecommendation", "OperatingBand", "Recommendation", "SectionElasticity",
        "SectionPresag", "SpeedContext", "StaticSteadyArmUplift", "check_elasticity_method",
        "check_levels_cover", "check_method", "default_spans", "elasticity_difference",
        "force_levels_for_band", "interpolate_elasticity", "layout_kind", "layout_recommendation",
        "mean_contact_force", "mean_force_grid", "mid_span_elasticity_empirical", "presag_quasi_static",
        "section_elasticity", "speed_context", "tension_label",
    ),
    "presag_opt.robust": (
        "SHAPES", "BandEvaluation", "BandEvaluator", "BandStatistics", "Buildability", "DynamicCheck",
        "DynamicObjective", "DynamicRobustDesign", "DynamicRobustStudy", "DynamicRun", "DynamicTolerance",
        "ForceScenarios", "HistorySurrogate", "MethodResult", "OperatingGrid", "PathModel", "Risk",
        "RobustDesign", "RobustStudy", "SearchSettings", "ToleranceBand", "band_curve", "build_path_model",
        "design_catenary", "dynamic_check", "dynamic_robust_presag", "dynamic_robust_study", "dynamic_tolerance",
        "evaluate_design", "robust_presag", "robust_study", "simulate_band", "tolerance_band",
        "DropperTolerance", "DynamicMonteCarloResult", "FleetDesign", "FleetEvaluator", "FleetGrid",
        "InstallationErrors", "InstallationResponse", "InstallationSample", "MonteCarloResult",
        "QuasiStaticMonteCarlo", "check_realisation", "draw_installation_errors", "dynamic_monte_carlo",
        "fleet_robust_presag", "fleet_robust_study", "installation_response", "installed_state",
        "largest_dropper_tolerance", "percentile_summary",
    ),
    "presag_opt.validation": (
        "EN50318_RANGES", "PAPER_RECOMMENDATION", "PAPER_SINGLE_CURVE_ERROR", "PAPER_TABLE1",
        "PAPER_TABLE1_SPAN_LENGTH", "PAPER_TABLE1_STATIC_FORCE", "PAPER_TABLE2_FORCE", "PAPER_TABLE2_MM",
        "PAPER_TABLE2_MODELS", "SINGLE_CURVE_MAX_FORCE", "SINGLE_CURVE_MODEL", "ComparisonRow",
        "PaperComparison", "SingleCurveError", "Table2Row", "Verdict", "compare_with_paper", "en50318_ranges",
        "comparison_rows", "en50318_verdicts", "single_curve_error", "table2_row",
    ),
}
"""Public names by the module that defines or gathers them."""

_MODULE_OF = {name: module for module, names in _API.items() for name in names}

__all__ = sorted(_MODULE_OF)


def __getattr__(name: str) -> object:
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module 'presag_opt' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
