"""robust/surrogate.py: band statistics interpolated from simulated contact-force histories,
against synthetic histories whose statistics are known in closed form."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.robust.band_evaluation import BandEvaluation, BandStatistics
from presag_opt.robust.surrogate import HistorySurrogate

TIME = np.linspace(0.0, 2.0, 2001)
F0 = 100.0 + 12.0 * np.sin(2 * np.pi * 3.0 * TIME)          # [N]
F1 = 4000.0 * np.sin(2 * np.pi * 5.0 * TIME + 0.3)          # [N] per unit S_rel


def _evaluation(presag_rel: float, history) -> BandEvaluation:
    """One 'simulated' pre-sag with one operating point and the given force history."""
    force = history(presag_rel)
    stats = BandStatistics(presag_rel=presag_rel, mean_force=np.array([force.mean()]), sigma=np.array([force.std()]),
                           uplift_max=np.array([0.05 + presag_rel]))
    return BandEvaluation(statistics=stats, histories=(force,), loss_of_contact=np.zeros(1), wall_time=0.0)


def test_an_affine_model_is_exact_from_two_pre_sags():
    def affine(s):
        return F0 + s * F1

    surrogate = HistorySurrogate([_evaluation(0.5e-3, affine), _evaluation(1.0e-3, affine)])
    for s in (0.2e-3, 0.75e-3, 1.6e-3):  # inside and (affine) extrapolation on both sides
        got = surrogate.at(s)
        force = affine(s)
        assert not got.simulated
        assert got.mean_force[0] == pytest.approx(force.mean(), rel=1e-12)
        assert got.sigma[0] == pytest.approx(force.std(), rel=1e-9)
        assert got.uplift_max[0] == pytest.approx(0.05 + s, rel=1e-12)


def test_a_quadratic_model_is_exact_inside_three_pre_sags_and_simulated_points_are_returned():
    def quadratic(s):
        return F0 + s * F1 + (s * 1e3) ** 2 * 3.0 * np.cos(2 * np.pi * 7.0 * TIME)

    evaluations = [_evaluation(s, quadratic) for s in (0.4e-3, 0.8e-3, 1.2e-3, 1.6e-3)]
    surrogate = HistorySurrogate(evaluations)
    assert surrogate.at(0.8e-3) is evaluations[1].statistics
    index, w = surrogate.weights(1.0e-3)
    assert w.sum() == pytest.approx(1.0, abs=1e-12) and len(index) == 3
    assert surrogate.at(1.0e-3).sigma[0] == pytest.approx(quadratic(1.0e-3).std(), rel=1e-9)


def test_stencils_take_the_neighbours_and_the_nearer_next_one():
    def flat(s):
        return F0

    surrogate = HistorySurrogate([_evaluation(s, flat) for s in (1e-4, 2e-4, 3e-4, 5e-4)])
    assert surrogate.stencil(0.5e-4).tolist() == [0, 1]        # below: the two nearest
    assert surrogate.stencil(6e-4).tolist() == [2, 3]          # above
    assert surrogate.stencil(2.4e-4).tolist() == [0, 1, 2]     # 1e-4 nearer than 5e-4
    assert surrogate.stencil(2.9e-4).tolist() == [0, 1, 2]     # 1.9e-4 from 1e-4 against 2.1e-4 from 5e-4
    assert surrogate.stencil(3.5e-4).tolist() == [1, 2, 3]     # the last interval: only one outer neighbour
    with pytest.raises(ModelError, match="at least two different simulated pre-sags"):
        HistorySurrogate([_evaluation(1e-4, flat)])
