"""Robust pre-sag over a band of mean contact forces, installation tolerance, dynamic check.

Modules: :mod:`~presag_opt.robust.scenarios` (forces and risk measures),
:mod:`~presag_opt.robust.path` (the quasi-static path, affine in the dropper heights),
:mod:`~presag_opt.robust.buildability` (limits of a per-dropper profile), :mod:`~presag_opt.robust.lp`
(the linear programs), :mod:`~presag_opt.robust.rounding` (the construction step),
:mod:`~presag_opt.robust.tolerance` (the tolerance interval), :mod:`~presag_opt.robust.study` (the
job behind ``presag robust``) and :mod:`~presag_opt.robust.dynamic_check`. Importing this package
imports cvxpy. The names below are the public API.
"""

from presag_opt.robust.buildability import Buildability
from presag_opt.robust.dynamic_check import DynamicCheck, DynamicRun, dynamic_check
from presag_opt.robust.lp import SHAPES, RobustDesign, evaluate_design, robust_presag
from presag_opt.robust.path import PathModel, build_path_model
from presag_opt.robust.scenarios import ForceScenarios, Risk
from presag_opt.robust.study import RobustStudy, robust_study
from presag_opt.robust.tolerance import ToleranceBand, tolerance_band

__all__ = [
    "SHAPES",
    "Buildability",
    "DynamicCheck",
    "DynamicRun",
    "ForceScenarios",
    "PathModel",
    "Risk",
    "RobustDesign",
    "RobustStudy",
    "ToleranceBand",
    "build_path_model",
    "dynamic_check",
    "evaluate_design",
    "robust_presag",
    "robust_study",
    "tolerance_band",
]
