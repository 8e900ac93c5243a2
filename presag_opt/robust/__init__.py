"""Robust pre-sag over a band of mean contact forces, installation tolerance, dynamic check, and the
dynamic robust pre-sag over a band of static forces × speeds.

Quasi-static modules: :mod:`~presag_opt.robust.scenarios` (forces and risk measures),
:mod:`~presag_opt.robust.path` (the quasi-static path, affine in the dropper heights),
:mod:`~presag_opt.robust.buildability` (limits of a per-dropper profile), :mod:`~presag_opt.robust.lp`
(the linear programs), :mod:`~presag_opt.robust.rounding` (the construction step),
:mod:`~presag_opt.robust.tolerance` (the tolerance interval), :mod:`~presag_opt.robust.study` (the
job behind ``presag robust``) and :mod:`~presag_opt.robust.dynamic_check` (designs, parabolic or
per-dropper, simulated over a grid). Dynamic modules: :mod:`~presag_opt.robust.operating_grid` (the
points simulated), :mod:`~presag_opt.robust.band_evaluation` (one pre-sag simulated over them),
:mod:`~presag_opt.robust.surrogate` (statistics between simulated pre-sags),
:mod:`~presag_opt.robust.dynamic_design` (search and tolerance) and
:mod:`~presag_opt.robust.dynamic_study` (the job behind ``presag robust --dynamic``),
:mod:`~presag_opt.robust.fleet` (the same over a fleet of pantographs). Installation errors:
:mod:`~presag_opt.robust.installation` (the error model and its draws),
:mod:`~presag_opt.robust.realisation` (the installed line, re-solved and linearised),
:mod:`~presag_opt.robust.monte_carlo` (quasi-static Monte Carlo and the largest dropper tolerance) and
:mod:`~presag_opt.robust.dynamic_monte_carlo` (realisations simulated over a grid). Importing this
package imports cvxpy. The names below are the public API.
"""

from presag_opt.robust.band_evaluation import (
    BandEvaluation,
    BandEvaluator,
    BandStatistics,
    simulate_band,
)
from presag_opt.robust.buildability import Buildability
from presag_opt.robust.dynamic_check import (
    DynamicCheck,
    DynamicRun,
    design_catenary,
    dynamic_check,
)
from presag_opt.robust.dynamic_design import (
    DynamicObjective,
    DynamicRobustDesign,
    DynamicTolerance,
    SearchSettings,
    band_curve,
    dynamic_robust_presag,
    dynamic_tolerance,
)
from presag_opt.robust.dynamic_monte_carlo import (
    DynamicMonteCarloResult,
    dynamic_monte_carlo,
)
from presag_opt.robust.dynamic_study import (
    DynamicRobustStudy,
    MethodResult,
    dynamic_robust_study,
)
from presag_opt.robust.fleet import (
    FleetDesign,
    FleetEvaluator,
    FleetGrid,
    fleet_robust_presag,
    fleet_robust_study,
)
from presag_opt.robust.installation import (
    InstallationErrors,
    InstallationSample,
    draw_installation_errors,
)
from presag_opt.robust.lp import SHAPES, RobustDesign, evaluate_design, robust_presag
from presag_opt.robust.monte_carlo import (
    DropperTolerance,
    MonteCarloResult,
    QuasiStaticMonteCarlo,
    largest_dropper_tolerance,
    percentile_summary,
)
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.robust.path import PathModel, build_path_model
from presag_opt.robust.realisation import (
    InstallationResponse,
    check_realisation,
    installation_response,
    installed_state,
)
from presag_opt.robust.scenarios import ForceScenarios, Risk
from presag_opt.robust.study import RobustStudy, robust_study
from presag_opt.robust.surrogate import HistorySurrogate
from presag_opt.robust.tolerance import ToleranceBand, tolerance_band

__all__ = [
    "SHAPES",
    "BandEvaluation",
    "BandEvaluator",
    "BandStatistics",
    "Buildability",
    "DropperTolerance",
    "DynamicCheck",
    "DynamicMonteCarloResult",
    "DynamicObjective",
    "DynamicRobustDesign",
    "DynamicRobustStudy",
    "DynamicRun",
    "DynamicTolerance",
    "FleetDesign",
    "FleetEvaluator",
    "FleetGrid",
    "ForceScenarios",
    "HistorySurrogate",
    "InstallationErrors",
    "InstallationResponse",
    "InstallationSample",
    "MethodResult",
    "MonteCarloResult",
    "OperatingGrid",
    "PathModel",
    "QuasiStaticMonteCarlo",
    "Risk",
    "RobustDesign",
    "RobustStudy",
    "SearchSettings",
    "ToleranceBand",
    "band_curve",
    "build_path_model",
    "check_realisation",
    "design_catenary",
    "draw_installation_errors",
    "dynamic_check",
    "dynamic_monte_carlo",
    "dynamic_robust_presag",
    "dynamic_robust_study",
    "dynamic_tolerance",
    "evaluate_design",
    "fleet_robust_presag",
    "fleet_robust_study",
    "installation_response",
    "installed_state",
    "largest_dropper_tolerance",
    "percentile_summary",
    "robust_presag",
    "robust_study",
    "simulate_band",
    "tolerance_band",
]
