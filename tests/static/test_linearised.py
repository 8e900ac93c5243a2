"""The linearised tension-only structure: its dropper law and its active set against enumeration.

:meth:`TensionOnlyStructure.slack_set` and :meth:`~TensionOnlyStructure.displacement` are checked on
a small synthetic structure (6 DOFs, 4 droppers; positive definite without its droppers, as a
catenary's wires under tension are) against an independent method: every one of the 16
candidate slack sets solved directly, (K − G_S D_S G_Sᵀ) q = p + G_S f0_S, and the one set whose
droppers' forces agree with it (slack where N < 0, taut elsewhere) kept.
"""

from __future__ import annotations

import itertools
from types import SimpleNamespace

import numpy as np
import pytest

from presag_opt.errors import ConvergenceError
from presag_opt.static.linearised import TensionOnlyStructure, dropper_axial_force, dropper_slack


class _Factor:
    def __init__(self, k):
        self._k = k

    def solve(self, b):
        return np.linalg.solve(self._k, b)


def _structure(seed: int = 0) -> tuple[TensionOnlyStructure, np.ndarray]:
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(6, 6))
    k = a @ a.T + 50.0 * np.eye(6)  # tangent stiffness [N/m]
    g = rng.normal(size=(6, 4))  # length gradients [-]
    # dropper stiffnesses [N/m]: G D Gᵀ well below K's eigenvalues (≥ 50), so the structure without any
    # dropper stays positive definite, the tension-only energy is convex and its active set unique
    d = np.array([0.5, 0.8, 0.6, 0.4])
    f0 = np.array([2.0, 0.5, 3.0, 1.0])  # preloads [N]
    state = SimpleNamespace(factorised_stiffness=lambda: _Factor(k))
    influence = np.linalg.solve(k, g)
    return TensionOnlyStructure(state=state, gradients=g, influence=influence, gram=g.T @ influence, preload=f0,
                                stiffness=d), k


def _enumerated(structure: TensionOnlyStructure, k: np.ndarray, load: np.ndarray):
    g, d, f0 = structure.gradients, structure.stiffness, structure.preload
    consistent = []
    for flags in itertools.product((False, True), repeat=len(f0)):
        slack = np.array(flags)
        gs = g[:, slack]
        q = np.linalg.solve(k - gs @ np.diag(d[slack]) @ gs.T, load + gs @ f0[slack])
        axial = f0 + d * (g.T @ q)
        if np.array_equal(axial < 0.0, slack):
            consistent.append((slack, q))
    return consistent


def test_the_dropper_law():
    """N = N0 + k e + β_R k ė; slack below zero, taut at zero."""
    assert dropper_axial_force(100.0, 2e4, -1e-3, 0.5, 0.0) == pytest.approx(80.0, rel=1e-15)
    assert dropper_axial_force(100.0, 2e4, -1e-3, 0.5, 1e-3) == pytest.approx(90.0, rel=1e-14)
    np.testing.assert_array_equal(dropper_slack(np.array([-1e-9, 0.0, 5.0])), [True, False, False])


@pytest.mark.parametrize("scale", [0.0, 1.0, 3.0, 10.0])
def test_the_active_set_is_the_one_consistent_set(scale):
    structure, k = _structure()
    load = scale * np.array([40.0, -30.0, 25.0, 10.0, -50.0, 35.0])  # [N]; 0 leaves every dropper taut
    consistent = _enumerated(structure, k, load)
    assert len(consistent) == 1
    expected_slack, expected_q = consistent[0]
    q, slack = structure.displacement(load)
    np.testing.assert_array_equal(slack, expected_slack)
    # two direct solves of a 6x6 system with condition below 100: agree to 1e-12 of |q|
    np.testing.assert_allclose(q, expected_q, rtol=0, atol=1e-12 * max(np.max(np.abs(expected_q)), 1e-30))
    if scale == 0.0:
        assert not slack.any()


def test_some_droppers_go_slack_under_the_large_load():
    """The loads above reach a mixed set (the enumeration is not trivially 'all taut')."""
    structure, k = _structure()
    _, slack = structure.displacement(10.0 * np.array([40.0, -30.0, 25.0, 10.0, -50.0, 35.0]))
    assert 0 < slack.sum() < 4


def test_the_correction_is_the_slack_droppers_force_change():
    """z = D_S G_Sᵀ q: the slack droppers' stiffness forces the removed springs no longer carry. [N]"""
    structure, k = _structure()
    load = 10.0 * np.array([40.0, -30.0, 25.0, 10.0, -50.0, 35.0])
    slack, z = structure.slack_set(structure.influence.T @ load)
    s = np.flatnonzero(slack)
    q, _ = structure.displacement(load)
    # (K − G_S D_S G_Sᵀ) q = p + G_S f0_S, so K q = p + G_S (f0_S + D_S G_Sᵀ q) = p + G_S (f0_S + z)
    np.testing.assert_allclose(z, structure.stiffness[s] * (structure.gradients[:, s].T @ q), rtol=1e-10)


def test_an_unsettled_set_raises():
    structure, _ = _structure()
    with pytest.raises(ConvergenceError, match="did not settle in 0 iterations"):
        structure.slack_set(np.full(4, -10.0), max_iterations=0)
