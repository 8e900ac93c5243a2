"""The parabolic design's one unknown: its risk objective as a convex function of S_rel, minimised exactly.

A parabolic pre-sag puts every dropper of the analysed spans at the depth S_rel·l·4t(1 − t), so the
path height at point x under the mean force F_k is an affine function of the one number S_rel
(:class:`presag_opt.robust.path.PathModel`):

.. math::

    h_k(x; S) = a_k(x) + b(x)\\,S, \\qquad
    R_k(S) = \\max_{\\text{spans}}\\bigl(\\max_{x} h_k - \\min_{x} h_k\\bigr).

Each R_k is the largest of a finite set of affine functions of S, hence convex and piecewise linear;
the minimax, mean and CVaR aggregations of :class:`~presag_opt.robust.scenarios.Risk` are convex,
non-decreasing in every R_k, so the objective J(S) is convex and piecewise linear in S ≥ 0. Its
minimum is found by a golden-section search on a bracket where J rises (exact to the floating-point
resolution of S, far below a millimetre of pre-sag), and the interval {S ≥ 0 : J(S) ≤ (1 + w)·J*} of
the installation tolerance by bisection on each side of the minimiser. Every evaluation of J is
exact (no solver tolerance), so the tolerance interval needs no safety margin; a per-dropper profile
has one unknown per dropper and stays a linear program (:mod:`presag_opt.robust.lp`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.robust.path import PathModel
from presag_opt.robust.scenarios import ForceScenarios, Risk

_GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0
FIRST_BRACKET = 1e-3
"""First upper end of the bracket searched for the minimum, 1 ‰; doubled until J rises. [-]"""
LARGEST_BRACKET = 0.1
"""S_rel beyond which no physical pre-sag lies (100 ‰): a J still falling there is refused. [-]"""
RESOLUTION = 1e-12
"""Width of the final bracket in S_rel (1e-12 · 60 m = 6e-11 m of pre-sag). [-]"""


@dataclass(frozen=True)
class ParabolaObjective:
    """The risk objective J(S_rel) of the parabolic designs of a path model over force scenarios.

    Attributes
    ----------
    offset : ndarray, shape (K, points)
        a_k(x): the path height at S_rel = 0 under each scenario force. [m]
    slope : ndarray, shape (points,)
        b(x): the path height per unit S_rel. [m]
    starts : ndarray of int
        Index of the first path point of each analysed span in ``offset``'s columns (points sorted by
        span). [-]
    weights : ndarray, shape (K,)
        Scenario probabilities. [-]
    risk : Risk
        Aggregation of the scenario losses.
    """

    offset: np.ndarray
    slope: np.ndarray
    starts: np.ndarray
    weights: np.ndarray
    risk: Risk

    @classmethod
    def of(cls, path: PathModel, scenarios: ForceScenarios, risk: Risk | None = None) -> ParabolaObjective:
        """The objective of ``path``'s parabolic designs over ``scenarios`` (uplift computed once).

        Parameters
        ----------
        path : PathModel
            Linear model of the contact path.
        scenarios : ForceScenarios
            Mean contact forces and their probabilities. [N]
        risk : Risk, optional
            Default minimax.
        """
        order = np.argsort(path.node_span, kind="stable")
        unit = path.parabola_depths(1.0)
        at_zero = path.base_height - path.sensitivity @ path.reference_depth
        offset = at_zero[None, :] + path.uplift(scenarios.forces)
        spans = path.node_span[order]
        starts = np.flatnonzero(np.r_[True, spans[1:] != spans[:-1]])
        return cls(offset=offset[:, order], slope=(path.sensitivity @ unit)[order], starts=starts,
                   weights=np.asarray(scenarios.weights, dtype=float), risk=risk or Risk())

    def waviness(self, presag_rel: float) -> np.ndarray:
        """R of every scenario and analysed span at S_rel (K × spans). [m]

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel. [-]
        """
        h = self.offset + presag_rel * self.slope
        return np.maximum.reduceat(h, self.starts, axis=1) - np.minimum.reduceat(h, self.starts, axis=1)

    def __call__(self, presag_rel: float) -> float:
        """J(S_rel): the risk measure of the worst span's waviness over the scenarios. [m]

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel. [-]
        """
        return self.risk.value(self.waviness(presag_rel).max(axis=1), self.weights)

    def minimum(self) -> tuple[float, float]:
        """The minimiser S* ≥ 0 of J and J(S*). ([-], [m])

        Raises
        ------
        ModelError
            J still falls at S_rel = 100 ‰ (no physical optimum: a path model without uplift).
        """
        high = FIRST_BRACKET
        while self(2.0 * high) < self(high):
            high *= 2.0
            if high > LARGEST_BRACKET:
                raise ModelError(f"the path waviness still falls at S_rel = {high * 1e3:g} ‰: no physical "
                                 "optimum of the parabolic pre-sag (check the force band and the elasticity)")
        low, high = 0.0, 2.0 * high
        left, right = high - _GOLDEN * (high - low), low + _GOLDEN * (high - low)
        j_left, j_right = self(left), self(right)
        while high - low > RESOLUTION:
            if j_left <= j_right:
                high, right, j_right = right, left, j_left
                left = high - _GOLDEN * (high - low)
                j_left = self(left)
            else:
                low, left, j_left = left, right, j_right
                right = low + _GOLDEN * (high - low)
                j_right = self(right)
        best = min((low, high, 0.5 * (low + high)), key=self)
        return best, self(best)

    def sublevel_interval(self, best: float, bound: float) -> tuple[float, float]:
        """The interval {S ≥ 0 : J(S) ≤ bound} around the minimiser ``best`` (J convex: one interval). [-]

        Parameters
        ----------
        best : float
            A minimiser of J (:meth:`minimum`). [-]
        bound : float
            The objective allowed, at least J(best). [m]
        """
        low = 0.0 if self(0.0) <= bound else self._crossing(0.0, best, bound)
        far = max(best, FIRST_BRACKET)
        while self(far) <= bound:
            far *= 2.0
            if far > LARGEST_BRACKET:
                raise ModelError(f"the path waviness stays within {bound * 1e3:.2f} mm up to S_rel = "
                                 f"{far * 1e3:g} ‰: no upper end of the tolerance interval")
        return low, self._crossing(far, best, bound)

    def _crossing(self, outside: float, inside: float, bound: float) -> float:
        """Bisection for J = bound between a point above it and one at or below it; returns the inner end. [-]"""
        while abs(outside - inside) > RESOLUTION:
            middle = 0.5 * (outside + inside)
            if self(middle) <= bound:
                inside = middle
            else:
                outside = middle
        return inside
