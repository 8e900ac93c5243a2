"""One batch run's Newton step on the synthetic batch (``conftest``) against the equation it solves.

The step must end with K_eff δ + s f_nl(ũ + δ, ṽ + a1 δ) = g on every extended DOF, to the
integrator's tolerance: the nonlinear forces are evaluated here in NumPy from the laws of
:mod:`presag_opt.dynamics.laws` (an independent evaluation of the residual), δ rebuilt from what
the step leaves for sweep 3 and from the pantographs' new state.

The step and its parts run as plain Python (the ``plain_parts`` fixture: the source the kernel
compiles, with numba's jit off), in milliseconds; the compiled step is checked end to end
(tests/dynamics/batch/test_simulation.py: the batch against the single-run engine).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from presag_opt.dynamics import laws
from presag_opt.dynamics.batch import kernel_data


def _nonlinear(batch, u, v):
    """f_nl on the extended DOFs at full displacement ``u`` and velocity ``v``. [N]"""
    sh, runs, sc = batch.shared, batch.runs, batch.scalars
    f = np.zeros(len(u))
    w = runs.path_weights[0, 0, 1]
    k = laws.contact_stiffness(sh.contact_stiffness[0], runs.path_compliance[0, 0, 1])
    force = laws.contact_force(k, runs.head_height[0, 0] + u[6] - (w[0] * u[2] + w[1] * u[3]))
    f[[2, 3, 6]] += [-w[0] * force, -w[1] * force, force]
    for (upper, lower), level in zip(sh.friction_dofs, sh.friction_levels):
        friction = laws.friction(level, v[upper] - (v[lower] if lower >= 0 else 0.0), sc.friction_velocity, 1.0)[0]
        f[upper] += friction
        if lower >= 0:
            f[lower] -= friction
    g = sh.dropper_gradient[0]
    axial = laws.dropper_axial_force(batch.runs.dropper_preload[0, 0], sh.dropper_stiffness[0], g @ u[:6], g @ v[:6],
                                     sc.rayleigh_beta)
    if laws.dropper_slack(axial):
        f[:6] -= axial * g
    return f


def _predictors(batch):
    c, st, sh = batch.scalars.scheme, batch.state, batch.shared
    pu, pv, pa = st.pantograph_u[:, 0], st.pantograph_v[:, 0], st.pantograph_a[:, 0]
    pu_pred = pu + c.time_step * pv + c.displacement_predictor * pa
    pv_pred = pv + c.velocity_predictor * pa
    rhs_p = c.alpha * st.pantograph_r[:, 0]
    rhs_p[sh.head_dof[0] - batch.n] += batch.runs.uplift[0]
    g_p = rhs_p - c.s * (sh.pantograph_damping @ pv_pred + sh.pantograph_stiffness @ pu_pred)
    u = np.concatenate([st.u[:, 0], pu_pred])
    v = np.concatenate([st.v[:, 0], pv_pred])
    return u, v, np.concatenate([batch.work.g[:, 0], g_p])


def test_the_step_solves_its_nonlinear_equation(plain_parts, synthetic_batch):
    batch = synthetic_batch(head_height=3e-3)
    u_pred, v_pred, g = _predictors(batch)
    delta_lin = batch.work.delta[:, 0].copy()
    plain_parts.newton_step.newton_step(0, 1, batch.scalars, batch.shared, batch.runs, batch.state, batch.out, batch.work,
                             batch.scratch)
    w, n = batch.work, batch.n
    assert batch.out.status[0] == kernel_data.STATUS_RUNNING and batch.out.iterations[0] >= 1
    delta_c = delta_lin - sum(w.phi_coefficient[0, k] * batch.shared.columns[w.phi_column[0, k]]
                              for k in range(w.phi_count[0]))
    delta = np.concatenate([delta_c, batch.state.pantograph_u[:, 0] - u_pred[n:]])
    s, a1 = batch.scalars.scheme.s, batch.scalars.scheme.a1
    k_ext = sla.block_diag(batch.k_cat, batch.k_pan)
    f = _nonlinear(batch, u_pred + delta, v_pred + a1 * delta)
    residual = k_ext @ delta + s * f - g
    # the kernel stops at |R| ≤ 1e-10 × its largest force term (~1e2 N): 1e-7 N leaves room for round-off
    assert np.max(np.abs(residual)) < 1e-7, residual
    u = u_pred + delta
    w8 = batch.runs.path_weights[0, 0, 1]
    k = laws.contact_stiffness(batch.shared.contact_stiffness[0], batch.runs.path_compliance[0, 0, 1])
    contact = laws.contact_force(k, batch.runs.head_height[0, 0] + u[6] - (w8[0] * u[2] + w8[1] * u[3]))
    # recorded at the last iterate, δ rebuilt here to round-off (~1e-16 m × 5e4 N/m)
    assert abs(batch.out.contact_force[0, 0, 1] - contact) < 1e-9 and contact > 10.0


def test_a_run_out_of_corrections_stops_with_its_reason(plain_parts, synthetic_batch):
    batch = synthetic_batch(head_height=3e-3, max_iterations=0)
    plain_parts.newton_step.newton_step(0, 1, batch.scalars, batch.shared, batch.runs, batch.state, batch.out, batch.work,
                             batch.scratch)
    assert batch.out.status[0] == plain_parts.newton_step.STATUS_NOT_CONVERGED
    assert batch.out.fail_step[0] == 1 and batch.out.fail_residual[0] > 0.0
    assert np.all(batch.scratch.position == -1)  # the set cleared for the next run


def test_the_statuses_are_distinct(plain_parts):
    statuses = {plain_parts.newton_step.STATUS_RUNNING, plain_parts.newton_step.STATUS_OK, plain_parts.newton_step.STATUS_NOT_CONVERGED,
                plain_parts.newton_step.STATUS_NOT_FINITE}
    assert len(statuses) == 4 and plain_parts.newton_step.STATUS_OK == kernel_data.STATUS_OK == 0
