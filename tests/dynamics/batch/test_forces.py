"""The batch kernel's nonlinear force sets on the synthetic one-run batch (``conftest``).

Forces against the laws of :mod:`presag_opt.dynamics.laws` called plainly; tangents against central
differences of the set's forces (an independent check of every written entry).
"""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics import laws


def _forces(plain_parts, batch, a1=0.0):
    """The set as a dense map DOF -> force, and the dense tangent on the extended DOFs."""
    sc = batch.scratch
    sc.position[:] = -1
    count, slack = plain_parts.forces.nonlinear_forces(0, 1, a1, batch.scalars, batch.shared, batch.runs, sc)
    size = batch.n + batch.n_p
    force, tangent = np.zeros(size), np.zeros((size, size))
    dofs = sc.set_dofs[:count]
    force[dofs] = sc.set_force[:count]
    tangent[np.ix_(dofs, dofs)] = sc.tangent[:count, :count]
    sc.position[dofs] = -1
    return force, tangent, count, slack


def _set_state(batch, u, v, stretch, rate):
    sc = batch.scratch
    sc.u_of[:], sc.v_of[:], sc.stretch[:], sc.rate[:] = u, v, stretch, rate


def test_enter_set_adds_a_dof_once(plain_parts, synthetic_batch):
    sc = synthetic_batch().scratch
    sc.position[:] = -1
    sc.tangent[:] = 7.0  # stale entries must be cleared on entry
    p, count = plain_parts.forces.enter_set(4, sc.set_dofs, sc.set_force, sc.tangent, sc.position, 0)
    q, count = plain_parts.forces.enter_set(6, sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
    again, count = plain_parts.forces.enter_set(4, sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
    assert (p, q, again, count) == (0, 1, 0, 2)
    assert list(sc.set_dofs[:2]) == [4, 6] and sc.position[4] == 0 and sc.position[6] == 1
    assert np.all(sc.tangent[:2, :2] == 0.0) and np.all(sc.set_force[:2] == 0.0)


def test_the_contact_force_is_the_law_on_the_chord(plain_parts, synthetic_batch):
    batch = synthetic_batch(head_height=2e-3)
    u = np.zeros(8)
    u[[2, 3, 6]] = [1e-4, 3e-4, -5e-4]
    _set_state(batch, u, np.zeros(8), np.full(1, 1.0), np.zeros(1))  # dropper taut: contact and friction only
    force, _, _, _ = _forces(plain_parts, batch)
    k = laws.contact_stiffness(5e4, 1e-6)
    penetration = 2e-3 - 5e-4 - 0.5 * (1e-4 + 3e-4)
    expected = laws.contact_force(k, penetration)
    assert batch.scratch.contact_now[0] == expected and expected > 0.0
    np.testing.assert_allclose(force[[2, 3]], [-0.5 * expected, -0.5 * expected], rtol=1e-15)
    assert force[6] == pytest.approx(expected + laws.friction(5.0, 0.0, 0.01, 0.0)[0], rel=1e-15)


def test_a_head_in_a_gap_carries_no_force_but_its_dofs_enter(plain_parts, synthetic_batch):
    batch = synthetic_batch(head_height=-1e-3)
    _set_state(batch, np.zeros(8), np.zeros(8), np.full(1, 1.0), np.zeros(1))
    force, tangent, count, _ = _forces(plain_parts, batch)
    assert batch.scratch.contact_now[0] == 0.0 and force[2] == 0.0 and force[3] == 0.0
    assert count == 4  # nodes 2, 3, the head 6 and the frame 7 (friction)
    assert np.all(tangent[np.ix_([2, 3], [2, 3])] == 0.0)


def test_friction_acts_on_both_stages_with_the_law(plain_parts, synthetic_batch):
    batch = synthetic_batch(head_height=-1e-3)
    v = np.zeros(8)
    v[6], v[7] = 0.004, -0.003
    _set_state(batch, np.zeros(8), v, np.full(1, 1.0), np.zeros(1))
    force, _, _, _ = _forces(plain_parts, batch, a1=2000.0)
    upper = laws.friction(5.0, v[6] - v[7], 0.01, 2000.0)[0]
    lower = laws.friction(10.0, -0.003, 0.01, 2000.0)[0]
    # numba's tanh (libm's) and NumPy's may differ in the last bit: 2 ulp
    assert force[6] == pytest.approx(upper, rel=5e-16) and force[7] == pytest.approx(-upper + lower, rel=5e-16)


def test_a_slack_dropper_removes_its_axial_force_and_is_counted(plain_parts, synthetic_batch):
    batch = synthetic_batch(head_height=-1e-3)
    stretch, rate = -2e-3, 0.5  # N = 100 − 200 + 1e-4·1e5·0.5 = −95 N: slack
    _set_state(batch, np.zeros(8), np.zeros(8), np.full(1, stretch), np.full(1, rate))
    force, _, count, slack = _forces(plain_parts, batch)
    axial = laws.dropper_axial_force(100.0, 1e5, stretch, rate, 1e-4)
    assert axial == pytest.approx(-95.0, rel=1e-12) and slack == 1
    np.testing.assert_allclose(force[[0, 1, 4, 5]], -axial * batch.shared.dropper_gradient[0, [0, 1, 4, 5]],
                               rtol=1e-15)
    _set_state(batch, np.zeros(8), np.zeros(8), np.full(1, 0.0), np.zeros(1))
    assert _forces(plain_parts, batch)[3] == 0  # taut at its preload


def test_the_tangent_is_the_derivative_of_the_forces(plain_parts, synthetic_batch):
    """∂f/∂u + a1 ∂f/∂v by central differences, u and v moved together as in a step (v = a1 u)."""
    batch = synthetic_batch(head_height=2e-3)
    a1 = 2000.0
    rng = np.random.default_rng(3)
    u, v = 1e-4 * rng.normal(size=8), 1e-3 * rng.normal(size=8)
    g = batch.shared.dropper_gradient[0]
    stretch = lambda uu: -2e-3 + g @ uu[:6]  # noqa: E731 - slack dropper throughout
    _set_state(batch, u, v, np.full(1, stretch(u)), np.full(1, g @ v[:6]))
    _, tangent, _, _ = _forces(plain_parts, batch, a1)
    h = 1e-8  # [m]: the forces are smooth here (contact kept, dropper slack), central differences O(h²)
    numeric = np.zeros((8, 8))
    for j in range(8):
        e = np.zeros(8)
        e[j] = h
        plus = [u + e, v + a1 * e]
        minus = [u - e, v - a1 * e]
        _set_state(batch, *plus, np.full(1, stretch(plus[0])), np.full(1, g @ plus[1][:6]))
        fp = _forces(plain_parts, batch, a1)[0]
        _set_state(batch, *minus, np.full(1, stretch(minus[0])), np.full(1, g @ minus[1][:6]))
        fm = _forces(plain_parts, batch, a1)[0]
        numeric[:, j] = (fp - fm) / (2 * h)
    # the largest entries are ~5e4 N/m; differences of forces ~1e2 N at h = 1e-8 lose ~1e-6 relative
    np.testing.assert_allclose(tangent, numeric, rtol=0, atol=1e-4 * np.max(np.abs(tangent)))
