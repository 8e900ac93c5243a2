"""Installation tolerance: the interval of parabolic pre-sag within a stated loss of the optimum.

Holds :func:`tolerance_band` (two linear programs over the minimax constraints) and its result. The
minimax optimum it refers to comes from :func:`presag_opt.robust.lp.robust_presag`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.robust.lp import _peak_to_peak, _solve, robust_presag
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

    Two LPs over the same constraints: minimise and maximise S_rel subject to
    max_k R(S_rel, F_k) ≤ (1 + within)·R*, with R* the minimax optimum. The worst-case waviness is
    convex in S_rel, so the feasible set is exactly this interval.

    Parameters
    ----------
    path : PathModel
        Path model.
    scenarios : ForceScenarios
        Forces covered (a single force gives the tolerance of a design for that force alone).
    within : float
        Allowed relative loss, e.g. 0.10 for 10 %. [-]
    """
    import cvxpy as cp  # on first use: importing it takes about a second

    check_within(within)
    best = robust_presag(path, scenarios, shape="parabola", risk=Risk())

    def build():
        s = cp.Variable()
        uplift = cp.Parameter((len(scenarios.forces), len(path.node_span)))
        bound = cp.Parameter(nonneg=True)
        shape = path.sensitivity @ path.parabola_depths(1.0)
        z = path.base_height - path.sensitivity @ path.reference_depth + shape * s
        spread, bounds = _peak_to_peak(path, z, uplift)
        constraints = [*bounds, spread <= bound, s >= 0]
        return cp.Problem(cp.Minimize(s), constraints), cp.Problem(cp.Maximize(s), constraints), s, uplift, bound

    lower, upper, s, uplift, bound = path.problem("tolerance", len(scenarios.forces), build)
    uplift.value = path.uplift(scenarios.forces)
    # a hair above (1 + within)·R* so the optimum itself is always feasible despite solver tolerance
    bound.value = (1.0 + within) * best.worst_case_waviness * (1 + 1e-7) + 1e-9
    _solve(lower)
    low = float(s.value)
    _solve(upper)
    high = float(s.value)
    return ToleranceBand(low=low, high=high, best=best.presag_rel, best_objective=best.worst_case_waviness,
                         within=within, forces=scenarios.forces)
