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
:mod:`~presag_opt.robust.dynamic_study` (the job behind ``presag robust --dynamic``). Importing this
package imports cvxpy. The names below are the public API.
"""

from presag_opt.robust.band_evaluation import BandEvaluation, BandEvaluator, BandStatistics, simulate_band
from presag_opt.robust.buildability import Buildability
from presag_opt.robust.dynamic_check import DynamicCheck, DynamicRun, design_catenary, dynamic_check
from presag_opt.robust.dynamic_design import (
    DynamicObjective,
    DynamicRobustDesign,
    DynamicTolerance,
    SearchSettings,
    band_curve,
    dynamic_robust_presag,
    dynamic_tolerance,
)
from presag_opt.robust.dynamic_study import DynamicRobustStudy, MethodResult, dynamic_robust_study
from presag_opt.robust.lp import SHAPES, RobustDesign, evaluate_design, robust_presag
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.robust.path import PathModel, build_path_model
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
    "DynamicCheck",
    "DynamicObjective",
    "DynamicRobustDesign",
    "DynamicRobustStudy",
    "DynamicRun",
    "DynamicTolerance",
    "ForceScenarios",
    "HistorySurrogate",
    "MethodResult",
    "OperatingGrid",
    "PathModel",
    "Risk",
    "RobustDesign",
    "RobustStudy",
    "SearchSettings",
    "ToleranceBand",
    "band_curve",
    "build_path_model",
    "design_catenary",
    "dynamic_check",
    "dynamic_robust_presag",
    "dynamic_robust_study",
    "dynamic_tolerance",
    "evaluate_design",
    "robust_presag",
    "robust_study",
    "simulate_band",
    "tolerance_band",
]
