"""The start of a batch run's step on the synthetic batch (``conftest``), against NumPy formulas."""

from __future__ import annotations

import numpy as np


def test_the_pantograph_predictor_is_the_newmark_predictor(plain_parts, synthetic_batch):
    batch = synthetic_batch()
    c, st, sh = batch.scalars.scheme, batch.state, batch.shared
    plain_parts.predictor.pantograph_predictor(0, batch.scalars, sh, batch.runs, st, batch.scratch)
    pan = batch.scratch.pantograph  # filled in place
    pu, pv, pa = st.pantograph_u[:, 0], st.pantograph_v[:, 0], st.pantograph_a[:, 0]
    np.testing.assert_allclose(pan.u_pred, pu + c.time_step * pv + c.displacement_predictor * pa, rtol=1e-14)
    np.testing.assert_allclose(pan.v_pred, pv + c.velocity_predictor * pa, rtol=1e-14)
    rhs = c.alpha * st.pantograph_r[:, 0] + np.array([batch.runs.uplift[0], 0.0])  # the uplift on the head only
    np.testing.assert_allclose(pan.rhs, rhs, rtol=1e-14)
    linear = sh.pantograph_damping @ pan.v_pred + sh.pantograph_stiffness @ pan.u_pred
    np.testing.assert_allclose(pan.linear, linear, rtol=1e-12)
    np.testing.assert_allclose(pan.g, rhs - c.s * linear, rtol=1e-12)
    np.testing.assert_allclose(batch.k_pan @ pan.delta_lin, pan.g, rtol=1e-10)  # δ_lin = K_eff⁻¹ g


def test_the_state_at_the_predictor(plain_parts, synthetic_batch):
    batch = synthetic_batch()
    sh, st, sc = batch.shared, batch.state, batch.scratch
    plain_parts.predictor.pantograph_predictor(0, batch.scalars, sh, batch.runs, st, batch.scratch)
    pan = batch.scratch.pantograph  # filled in place
    plain_parts.predictor.predictor_state(0, 1, sh, batch.runs, st, batch.work, sc, pan)
    drop = sc.droppers  # filled in place
    g = sh.dropper_gradient[0]
    np.testing.assert_allclose(drop.stretch, [g @ st.u[:, 0]], rtol=1e-13)
    np.testing.assert_allclose(drop.rate, [g @ st.v[:, 0]], rtol=1e-13)
    np.testing.assert_allclose(drop.linear, [g @ batch.work.delta[:, 0]], rtol=1e-13)
    assert sc.stretch[0] == drop.stretch[0] and sc.rate[0] == drop.rate[0]
    np.testing.assert_array_equal(sc.u_of[[2, 3]], st.u[[2, 3], 0])  # the contact nodes
    np.testing.assert_array_equal(sc.u_of[6:], pan.u_pred)
    np.testing.assert_array_equal(sc.v_of[6:], pan.v_pred)


def test_the_residual_at_the_predictor_completes_the_sweeps(plain_parts, synthetic_batch):
    """max |s f0 − g| and the force scale over the candidate rows and the pantographs, from the
    sweeps' values on the other rows."""
    batch = synthetic_batch()
    sh, st, sc, w = batch.shared, batch.state, batch.scratch, batch.work
    plain_parts.predictor.pantograph_predictor(0, batch.scalars, sh, batch.runs, st, batch.scratch)
    pan = batch.scratch.pantograph  # filled in place
    s = batch.scalars.scheme.s
    w.linear[:, 0] = np.linspace(-30.0, 40.0, batch.n)
    w.scale[0], w.first_residual[0] = 5.0, 1.0
    sc.position[:] = -1
    sc.position[3], sc.set_force[0] = 0, 12.0  # one DOF of the set carries 12 N
    scale, largest = plain_parts.predictor.residual_at_predictor(0, s, sh, st, w, sc, pan)
    f0 = np.zeros(batch.n)
    f0[3] = 12.0
    expected_largest = max(1.0, np.max(np.abs(s * f0 - w.g[:, 0])), np.max(np.abs(pan.g)))
    expected_scale = max(5.0, np.max(np.abs(s * (w.linear[:, 0] + f0))), np.max(np.abs(st.r[:, 0])),
                         np.max(np.abs(s * pan.linear)), np.max(np.abs(pan.rhs)))
    assert largest == expected_largest and scale == expected_scale
