"""A batch run's iterate after a correction and the end of its step, on the synthetic batch (``conftest``)."""

from __future__ import annotations

import numpy as np


def _with_phi(batch, dofs, phi):
    sc = batch.scratch
    sc.phi_dofs[: len(dofs)] = dofs
    sc.phi[: len(dofs)] = phi
    return len(dofs)


def test_the_iterate_where_the_forces_read_it(plain_parts, synthetic_batch):
    batch = synthetic_batch()
    sh, st, sc, w = batch.shared, batch.state, batch.scratch, batch.work
    plain_parts.predictor.pantograph_predictor(0, batch.scalars, sh, batch.runs, st, batch.scratch)
    pan = batch.scratch.pantograph  # filled in place
    plain_parts.predictor.predictor_state(0, 1, sh, batch.runs, st, w, sc, pan)
    drop = sc.droppers  # filled in place
    n_phi = _with_phi(batch, [2, 6], [30.0, -20.0])
    plain_parts.update.iterate_kinematics(0, 1, n_phi, batch.scalars, sh, batch.runs, st, w, sc, pan, drop)
    s, a1 = batch.scalars.scheme.s, batch.scalars.scheme.a1
    delta = w.delta[:, 0] - s * 30.0 * sh.columns[2]  # δ = δ_lin − s Z φ
    delta_p = pan.delta_lin - s * sh.pantograph_inverse[:, 0] * -20.0
    np.testing.assert_allclose(sc.u_of[[2, 3]], st.u[[2, 3], 0] + delta[[2, 3]], rtol=1e-13)
    np.testing.assert_allclose(sc.v_of[[2, 3]], st.v[[2, 3], 0] + a1 * delta[[2, 3]], rtol=1e-13)
    np.testing.assert_allclose(sc.u_of[6:], pan.u_pred + delta_p, rtol=1e-13)
    g = sh.dropper_gradient[0]
    np.testing.assert_allclose(sc.stretch, [g @ (st.u[:, 0] + delta)], rtol=1e-12)
    np.testing.assert_allclose(sc.rate, [g @ (st.v[:, 0] + a1 * delta)], rtol=1e-12)


def test_the_residual_is_s_times_f_minus_phi_on_the_set(plain_parts, synthetic_batch):
    batch = synthetic_batch(head_height=-1e-3)  # in a gap: only friction (DOFs 6, 7) carries force
    sc = batch.scratch
    sc.position[:] = -1
    sc.u_of[:], sc.v_of[:], sc.stretch[:], sc.rate[:] = 0.0, 0.0, 1.0, 0.0
    n_phi = _with_phi(batch, [1, 6], [4.0, 3.0])
    count, slack, largest = plain_parts.update.iterate_residual(0, 1, n_phi, batch.scalars, batch.shared, batch.runs, sc)
    s = batch.scalars.scheme.s
    assert count == 5 and slack == 0  # nodes 2, 3, the head, the frame, and φ's DOF 1
    residual = dict(zip(sc.set_dofs[:count].tolist(), sc.residual[:count].tolist()))
    assert residual[1] == -s * 4.0 and residual[6] == s * (0.0 - 3.0) and residual[2] == 0.0
    assert largest == max(abs(r) for r in residual.values())


def test_the_end_of_the_step(plain_parts, synthetic_batch):
    """φ's catenary part to sweep 3, its pantograph part into the pantographs' new state, the
    residual joined to the right-hand side and the records written."""
    batch = synthetic_batch()
    sh, st, sc, w, out = batch.shared, batch.state, batch.scratch, batch.work, batch.out
    c = batch.scalars.scheme
    plain_parts.predictor.pantograph_predictor(0, batch.scalars, sh, batch.runs, st, batch.scratch)
    pan = batch.scratch.pantograph  # filled in place
    delta_lin_p = pan.delta_lin.copy()
    n_phi = _with_phi(batch, [4, 7], [10.0, 5.0])
    sc.position[:] = -1
    sc.set_dofs[:2], sc.residual[:2], sc.contact_now[0] = [4, 7], [0.25, 0.5], 77.0
    sc.position[[4, 7]] = [0, 1]
    rhs_before, slack_before = st.r[4, 0], out.slack_max[0]
    plain_parts.update.close_run_step(0, 2, 1, 2, n_phi, 3, batch.scalars, sh, st, out, w, sc, pan)
    assert w.phi_count[0] == 1 and w.phi_column[0, 0] == 4 and w.phi_coefficient[0, 0] == c.s * 10.0
    delta_p = delta_lin_p - c.s * sh.pantograph_inverse[:, 1] * 5.0
    np.testing.assert_allclose(st.pantograph_u[:, 0], pan.u_pred + delta_p, rtol=1e-14)
    np.testing.assert_allclose(st.pantograph_a[:, 0], c.a0 * delta_p, rtol=1e-14)
    np.testing.assert_allclose(st.pantograph_v[:, 0], pan.v_pred + c.velocity_update * c.a0 * delta_p, rtol=1e-14)
    r_p = (pan.rhs - sh.pantograph_mass * c.a0 * delta_p) / c.s
    r_p[1] += 0.5 / c.s
    np.testing.assert_allclose(st.pantograph_r[:, 0], r_p, rtol=1e-13)
    assert st.r[4, 0] == rhs_before + 0.25 and np.all(sc.position == -1)
    assert out.contact_force[0, 0, 2] == 77.0 and out.slack_max[0] == max(slack_before, 3)


def test_a_run_converged_at_its_predictor_takes_sweep_ones_c_v_plus_k_u_as_its_right_hand_side(plain_parts, synthetic_batch):
    """δ = 0 everywhere, rhs = s (C ṽ + K ũ) on every row from sweep 1's ``linear``, R = s f0 on the set,
    the pantographs' δ_lin zero; the other runs' columns untouched."""
    batch = synthetic_batch()
    sh, st, w, sc, c = batch.shared, batch.state, batch.work, batch.scratch, batch.scalars.scheme
    w.linear[:, 0] = np.linspace(-30.0, 40.0, batch.n)
    sc.set_force[:2] = [12.0, -3.0]
    plain_parts.predictor.pantograph_predictor(0, batch.scalars, sh, batch.runs, st, batch.scratch)
    pan = batch.scratch.pantograph  # filled in place
    pan.delta_lin[:] = [1e-3, -2e-3]
    plain_parts.update.converged_at_predictor(0, 2, batch.scalars, sh, st, w, sc, pan)
    assert np.array_equal(st.r[:, 0], c.s * w.linear[:, 0]) and np.all(w.delta[:, 0] == 0.0)
    assert np.all(pan.delta_lin == 0.0) and np.array_equal(sc.residual[:2], c.s * np.array([12.0, -3.0]))


def test_a_failed_run_keeps_its_reason(plain_parts, synthetic_batch):
    batch = synthetic_batch()
    sc = batch.scratch
    sc.position[:] = -1
    sc.set_dofs[0], sc.position[3] = 3, 0
    plain_parts.update.fail_run(0, 2, np.inf, 1, 4, batch.out, sc)
    assert batch.out.status[0] == plain_parts.update.STATUS_NOT_FINITE and batch.out.fail_step[0] == 2
    assert batch.out.iterations[0] == 4 and sc.position[3] == -1
