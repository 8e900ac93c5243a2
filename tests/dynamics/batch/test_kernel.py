"""The batch kernel's sweeps over all DOFs, on the synthetic batch (``conftest``), against dense NumPy."""

from __future__ import annotations

import numpy as np

from presag_opt.dynamics.batch import kernel, kernel_data


def _dense(band):
    n = band.shape[0]
    a = np.diag(band[:, 0])
    for k in range(1, band.shape[1]):
        a += np.diag(band[: n - k, k], -k) + np.diag(band[: n - k, k], k)
    return a


def test_the_banded_product(synthetic_batch):
    shared = synthetic_batch().shared
    band = shared.stiffness_band
    x = np.random.default_rng(0).normal(size=(6, 3))
    out = np.zeros((6, 3))
    kernel.band_matvec(band, shared.stiffness_rows, x, out, 2)  # the first two columns only
    np.testing.assert_allclose(out[:, :2], _dense(band) @ x[:, :2], rtol=1e-14, atol=1e-9)
    assert np.all(out[:, 2] == 0.0)


def test_sweeps_one_and_two_give_delta_lin_and_the_residual_at_the_predictor(synthetic_batch):
    batch = synthetic_batch()
    sh = batch.shared._replace(candidate_index=np.array([0, 1, -1, -1, -1, -1], dtype=np.int64))
    st, w, sc = batch.state, batch.work, batch.scalars
    rng = np.random.default_rng(1)
    st.q[:, 0] = 1e-4 * rng.normal(size=6)
    w.scale[0] = w.first_residual[0] = 0.0
    kernel.forward_sweep(sc, sh, st, w, 1)
    kernel.backward_sweep(sh, w, 1)
    s = sc.scheme.s
    linear = _dense(sh.stiffness_band) @ st.q[:, 0] + sc.rayleigh_alpha * sh.mass * st.v[:, 0]
    g = st.r[:, 0] - s * linear
    np.testing.assert_allclose(batch.k_cat @ w.delta[:, 0], g, rtol=0, atol=1e-10 * np.max(np.abs(g)))
    np.testing.assert_allclose(w.g[:2, 0], g[:2], rtol=1e-13)  # kept on the candidate rows
    np.testing.assert_allclose(w.linear[:, 0], linear, rtol=1e-13)  # C ṽ + K ũ kept on every row
    others = slice(2, 6)  # the force scale and the residual at the predictor on the other rows
    assert np.isclose(w.first_residual[0], np.max(np.abs(g[others])), rtol=1e-13)
    assert np.isclose(w.scale[0], max(np.max(np.abs(s * linear[others])), np.max(np.abs(st.r[others, 0]))),
                      rtol=1e-13)


def test_the_update_sweep_is_the_newmark_update(synthetic_batch):
    batch = synthetic_batch()
    sh, st, w, out, sc = batch.shared, batch.state, batch.work, batch.out, batch.scalars
    c = sc.scheme
    u, v, r, delta = st.u[:, 0].copy(), st.v[:, 0].copy(), st.r[:, 0].copy(), w.delta[:, 0].copy()
    w.phi_count[0], w.phi_column[0, 0], w.phi_coefficient[0, 0] = 1, 3, 2.5
    out.uplift_max[0] = -np.inf
    kernel.update_sweep(1, sc, sh, batch.runs, st, out, w, 1)
    d = delta - 2.5 * sh.columns[3]
    a = c.a0 * d
    u1, v1 = u + d, v + c.velocity_update * a
    np.testing.assert_allclose(st.u[:, 0], u1 + c.time_step * v1 + c.displacement_predictor * a, rtol=1e-13)
    np.testing.assert_allclose(st.v[:, 0], v1 + c.velocity_predictor * a, rtol=1e-13)
    np.testing.assert_allclose(st.r[:, 0], c.alpha * (r - sh.mass * a) / c.s, rtol=1e-13)
    np.testing.assert_allclose(st.q[:, 0], st.u[:, 0] + sc.rayleigh_beta * st.v[:, 0], rtol=1e-14)
    assert out.uplift_max[0] == u1[0]  # DOF 0 is the support of the analysed section


def test_runs_stop_at_their_last_step():
    runs = kernel_data.Runs(n_steps=np.array([5, 3, 3]), path_nodes=np.zeros((3, 1, 1, 2), np.int64),
                            path_weights=np.zeros((3, 1, 1, 2)), path_compliance=np.zeros((3, 1, 1)),
                            head_height=np.zeros((3, 1)), uplift=np.zeros(3),
                            cw_height=np.zeros((3, 1)), dropper_preload=np.zeros((3, 1)))
    status = np.full(3, kernel_data.STATUS_RUNNING, dtype=np.int64)
    out = kernel_data.Records(np.zeros((3, 1, 6)), np.zeros(3), np.zeros(3, np.int64), status,
                              np.zeros(3, np.int64), np.zeros(3), np.zeros(3, np.int64))
    work = kernel_data.Work(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros((1, 3)), np.ones(3), np.ones(3),
                            np.zeros(3, np.int64), np.zeros((3, 1), np.int64), np.zeros((3, 1)))
    assert kernel.start_step(3, runs, out, work) == 3 and np.all(work.scale == 0.0)
    kernel.mark_finished_runs(3, 3, runs, out)
    assert list(status) == [kernel_data.STATUS_RUNNING, kernel_data.STATUS_OK, kernel_data.STATUS_OK]
    assert kernel.start_step(4, runs, out, work) == 1
    status[0] = kernel_data.STATUS_NOT_CONVERGED
    assert kernel.start_step(4, runs, out, work) == 0  # all stopped
