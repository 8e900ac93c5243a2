"""Band statistics at any pre-sag, interpolated from the contact-force histories of simulated pre-sags.

The runs of one operating point at different pre-sags share their time grid (the route, speed and
time step do not depend on S), so their filtered contact forces can be combined sample by sample.
:class:`HistorySurrogate` interpolates them in S with Lagrange weights w_i(S) over a stencil of
simulated pre-sags: F(t; S) ≈ Σ w_i F(t; S_i). Filtering and windowing are linear, so the statistics
of the interpolated force follow from those of the simulated ones:

    F_m(S) = Σ w_i m_i,        σ²(S) = wᵀ C w,

with m_i the window means and C their covariances. For a model that is linear in the pre-sag — the
pre-sag acts as an affine excitation, F(t; S) = F₀(t) + S·F₁(t) — two simulated pre-sags give σ(S)
exactly for every S; friction, slack droppers and loss of contact make it an approximation, exact at
the simulated pre-sags and better the closer they lie. The stencil is the two simulated pre-sags
around S and the nearer next one (quadratic interpolation); outside them, the two nearest (affine
extrapolation, σ² quadratic in S). The steady-arm uplift, a maximum over time, is interpolated as a
number with the same weights.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.robust.band_evaluation import BandEvaluation, BandStatistics


class HistorySurrogate:
    """Band statistics at any pre-sag from simulated ones (see the module notes).

    Parameters
    ----------
    evaluations : sequence of BandEvaluation
        At least two simulated pre-sags of the same operating grid.
    """

    def __init__(self, evaluations: Sequence[BandEvaluation]):
        ordered = sorted(evaluations, key=lambda e: e.statistics.presag_rel)
        self.presags = np.array([e.statistics.presag_rel for e in ordered])
        if len(ordered) < 2 or np.any(np.diff(self.presags) <= 0.0):
            raise ModelError("the history surrogate needs at least two different simulated pre-sags")
        self._statistics = [e.statistics for e in ordered]
        self._means = np.array([e.statistics.mean_force for e in ordered])  # (pre-sags, points)
        self._uplift = np.array([e.statistics.uplift_max for e in ordered])
        n_points = len(ordered[0].histories)
        self._covariance = []
        for k in range(n_points):
            centred = np.array([e.histories[k] - np.mean(e.histories[k]) for e in ordered])
            self._covariance.append(centred @ centred.T / centred.shape[1])

    def stencil(self, presag_rel: float) -> np.ndarray:
        """Indices of the simulated pre-sags the value at ``presag_rel`` is interpolated from.

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel (mid-span depth over span length). [-]
        """
        n = len(self.presags)
        right = int(np.searchsorted(self.presags, presag_rel))
        if right == 0:
            return np.array([0, 1])
        if right == n:
            return np.array([n - 2, n - 1])
        left = right - 1
        if n == 2:
            return np.array([left, right])
        outer = [i for i in (left - 1, right + 1) if 0 <= i < n]
        third = min(outer, key=lambda i: abs(self.presags[i] - presag_rel))
        return np.array(sorted((left, right, third)))

    def weights(self, presag_rel: float) -> tuple[np.ndarray, np.ndarray]:
        """Stencil indices and their Lagrange weights at ``presag_rel`` (they sum to 1). [-]

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel (mid-span depth over span length). [-]
        """
        index = self.stencil(presag_rel)
        nodes = self.presags[index]
        w = np.ones(len(index))
        for i in range(len(index)):
            for j in range(len(index)):
                if i != j:
                    w[i] *= (presag_rel - nodes[j]) / (nodes[i] - nodes[j])
        return index, w

    def at(self, presag_rel: float) -> BandStatistics:
        """Statistics at one pre-sag: the simulated ones where it was simulated, else interpolated.

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel. [-]
        """
        hit = np.flatnonzero(self.presags == presag_rel)
        if len(hit):
            return self._statistics[int(hit[0])]
        index, w = self.weights(presag_rel)
        variance = np.array([w @ c[np.ix_(index, index)] @ w for c in self._covariance])
        return BandStatistics(
            presag_rel=float(presag_rel),
            mean_force=w @ self._means[index],
            sigma=np.sqrt(np.maximum(variance, 0.0)),
            uplift_max=w @ self._uplift[index],
            simulated=False,
        )
