"""Installation tolerance: the interval of parabolic pre-sag within a stated loss of the optimum.

Holds :func:`tolerance_band` (the sublevel interval of the parabolic designs' worst-case waviness,
found exactly by :class:`presag_opt.robust.parabola.ParabolaObjective`) and its result. The minimax
optimum it refers to is :func:`presag_opt.robust.lp.robust_presag`'s parabola (the same search).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.robust.lp import check_forces
from presag_opt.robust.parabola import ParabolaObjective
from presag_opt.robust.path import PathModel
from presag_opt.robust.scenarios import ForceScenarios, Risk


@dataclass(frozen=True, kw_only=True)
class ToleranceBand:
    """Interval of parabolic pre-sag whose objective stays within a share of the best.

    Attributes
    ----------
    low, high : float
        Ends of the interval of S_rel. [-]
    best : float
        S_rel at the optimum. [-]
    best_objective : float
        The optimum of the objective (worst-case R over the forces considered). [m]
    within : float
        Allowed loss relative to ``best_objective``. [-]
    forces : ndarray
        Forces the objective covers. [N]
    """

    low: float
    high: float
    best: float
    best_objective: float
    within: float
    forces: np.ndarray


def check_within(within: float) -> float:
    """The allowed loss of a tolerance interval, checked (one line naming it, in %, with its range).

    Parameters
    ----------
    within : float
        Allowed relative loss over the optimum, e.g. 0.10 for 10 %. [-]

    Raises
    ------
    ModelError
        Outside (0, 2], i.e. (0, 200] %.
    """
    if not 0.0 < within <= 2.0:
        raise ModelError(f"within = {within * 100:g} % is outside the valid range (0, 200] %")
    return within


def tolerance_band(
    path: PathModel, scenarios: ForceScenarios, within: float = 0.10
) -> ToleranceBand:
    """Interval of parabolic S_rel whose worst-case waviness stays within ``within`` of the best.

    The set {S_rel ≥ 0 : max_k R(S_rel, F_k) ≤ (1 + within)·R*}, R* the minimax optimum. The
    worst-case waviness is convex in S_rel, so the set is one interval; its ends are found by
    bisection on the exact waviness (:meth:`~presag_opt.robust.parabola.ParabolaObjective.sublevel_interval`).

    Parameters
    ----------
    path : PathModel
        Path model.
    scenarios : ForceScenarios
        Forces covered (a single force gives the tolerance of a design for that force alone).
    within : float
        Allowed relative loss, e.g. 0.10 for 10 %. [-]
    """
    check_within(within)
    check_forces(path, scenarios)
    objective = ParabolaObjective.of(path, scenarios, Risk())
    best, worst = objective.minimum()
    low, high = objective.sublevel_interval(best, (1.0 + within) * worst)
    return ToleranceBand(low=low, high=high, best=best, best_objective=worst, within=within,
                         forces=scenarios.forces)
