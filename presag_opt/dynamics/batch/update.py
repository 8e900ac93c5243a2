"""One batch run's Newton iterate after a correction, and the end of its step (numba).

After each Woodbury correction (:mod:`presag_opt.dynamics.batch.woodbury`) the new iterate
δ = δ_lin − s Z φ is formed only where the nonlinear forces read it (:func:`iterate_kinematics`),
and its forces and residual s (f − φ) on the set follow (:func:`iterate_residual`; together
:func:`update_iterate`). A run whose iteration fails stops (:func:`fail_run`). At the step's end
(:func:`close_run_step`) φ's catenary part goes to sweep 3 of :mod:`presag_opt.dynamics.batch.kernel`
(:func:`hand_phi_to_sweep`), the pantographs take their new state (:func:`update_pantographs`), the
final residual joins the right-hand side (:func:`join_residual`), and a run that converged at its
predictor gets the right-hand side that makes sweep 3 exact (:func:`converged_at_predictor`, from
sweep 1's C ṽ + K ũ). The arrays are the named tuples of :mod:`presag_opt.dynamics.batch.kernel_data`.
"""

from __future__ import annotations

import numpy as np

from presag_opt.dynamics import assembly
from presag_opt.dynamics.batch.forces import enter_set, nonlinear_forces
from presag_opt.dynamics.batch.kernel_data import STATUS_NOT_CONVERGED, STATUS_NOT_FINITE
from presag_opt.dynamics.batch.woodbury import influence
from presag_opt.native.jit import kernel_part

newmark_update = kernel_part(assembly.newmark_update)


@kernel_part
def iterate_kinematics(b, step, n_phi, scalars, shared, runs, state, work, scratch, pan, drop):
    """The iterate δ = δ_lin − s Z φ where the forces read it: displacement ``scratch.u_of`` [m]
    and velocity ``scratch.v_of`` [m/s] at the contact nodes and the pantograph DOFs, every
    dropper's ``scratch.stretch`` [m] and ``scratch.rate`` [m/s].

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    n_phi : int
        Entries of φ from the last correction (0 if none). [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors.
    drop : DropperStep
        Run ``b``'s droppers at the predictor.
    scalars, shared, runs, state, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    s, a1 = scalars.scheme.s, scalars.scheme.a1
    column_of, columns, pantograph_inverse = shared.column_of, shared.columns, shared.pantograph_inverse
    stretch_influence, path_nodes, u_pred, v_pred, delta = (shared.stretch_influence, runs.path_nodes, state.u, state.v,
                                                            work.delta)
    u_of, v_of, stretch, rate = scratch.u_of, scratch.v_of, scratch.stretch, scratch.rate
    phi_dofs, phi = scratch.phi_dofs, scratch.phi
    n = shared.mass.shape[0]
    for p in range(shared.head_dof.shape[0]):
        for e in range(2):
            j = path_nodes[b, p, step, e]
            dj = delta[j, b]
            for k in range(n_phi):
                dj -= s * influence(j, phi_dofs[k], n, column_of, columns, pantograph_inverse) * phi[k]
            u_of[j] = u_pred[j, b] + dj
            v_of[j] = v_pred[j, b] + a1 * dj
    p_pred, pv_pred, p_delta_lin = pan.u_pred, pan.v_pred, pan.delta_lin
    for i in range(p_pred.shape[0]):
        di = p_delta_lin[i]
        for k in range(n_phi):
            if phi_dofs[k] >= n:
                di -= s * pantograph_inverse[i, phi_dofs[k] - n] * phi[k]
        u_of[n + i] = p_pred[i] + di
        v_of[n + i] = pv_pred[i] + a1 * di
    base_stretch, base_rate, linear_stretch = drop.stretch, drop.rate, drop.linear
    n_d = linear_stretch.shape[0]
    for d in range(n_d):
        stretch[d] = linear_stretch[d]
    for k in range(n_phi):
        m = phi_dofs[k]
        if m < n:
            row = column_of[m]
            f = s * phi[k]
            for d in range(n_d):
                stretch[d] -= f * stretch_influence[row, d]
    for d in range(n_d):
        rate[d] = base_rate[d] + a1 * stretch[d]
        stretch[d] = base_stretch[d] + stretch[d]


@kernel_part
def iterate_residual(b, step, n_phi, scalars, shared, runs, scratch):
    """The nonlinear forces at the iterate (the DOFs of φ joined to the set) and the residual
    s (f − φ) on the set in ``scratch.residual`` [N]. Returns (set size, recorded droppers slack,
    largest |residual| [N]).

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    n_phi : int
        Entries of φ from the last correction (0 if none). [-]
    scalars, shared, runs, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    s = scalars.scheme.s
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    phi_dofs, phi, residual = scratch.phi_dofs, scratch.phi, scratch.residual
    count, slack = nonlinear_forces(b, step, scalars.scheme.a1, scalars, shared, runs, scratch)
    for k in range(n_phi):
        _, count = enter_set(phi_dofs[k], set_dofs, set_force, tangent, position, count)
    for i in range(count):
        residual[i] = s * set_force[i]
    for k in range(n_phi):
        residual[position[phi_dofs[k]]] -= s * phi[k]
    largest = 0.0
    for i in range(count):
        largest = max(largest, abs(residual[i]))
    return count, slack, largest


@kernel_part
def update_iterate(b, step, n_phi, scalars, shared, runs, state, work, scratch, pan, drop):
    """The new iterate δ = δ_lin − s Z φ where the forces read it, its nonlinear forces, and the
    residual s (f − φ) on the set. Returns (set size, recorded droppers slack, largest |residual| [N]).

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    n_phi : int
        Entries of φ from the last correction. [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors (:func:`~presag_opt.dynamics.batch.predictor.pantograph_predictor`).
    drop : DropperStep
        Run ``b``'s droppers at the predictor (:func:`~presag_opt.dynamics.batch.predictor.predictor_state`).
    scalars, shared, runs, state, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    iterate_kinematics(b, step, n_phi, scalars, shared, runs, state, work, scratch, pan, drop)
    return iterate_residual(b, step, n_phi, scalars, shared, runs, scratch)


@kernel_part
def fail_run(b, step, largest, count, taken, out, scratch):
    """Stop run ``b``: its status, step and last residual [N]; the set cleared.

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    largest : float
        Largest absolute residual at the last iterate. [N]
    count : int
        Size of the set: DOFs that carry nonlinear forces at the iterate. [-]
    taken : int
        Newton corrections taken in this step so far. [-]
    out, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    out.status[b] = STATUS_NOT_CONVERGED if np.isfinite(largest) else STATUS_NOT_FINITE
    out.fail_step[b] = step
    out.fail_residual[b] = largest
    for i in range(count):
        scratch.position[scratch.set_dofs[i]] = -1
    out.iterations[b] += taken


@kernel_part
def converged_at_predictor(b, count, scalars, shared, state, work, scratch, pan):
    """A run that converged at its predictor: δ = 0, and R = s f0 − g everywhere gives
    r_(n+1) = C ṽ + K ũ + f0. Sweep 3 forms (rhs + R − M a)/s, so rhs becomes s (C ṽ + K ũ) and
    R = s f0 on the set; the pantographs' δ_lin becomes 0.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    count : int
        Size of the set: DOFs that carry nonlinear forces at the iterate. [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors.
    scalars, shared, state, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    s = scalars.scheme.s
    rhs, delta, linear, delta_lin = state.r, work.delta, work.linear, pan.delta_lin
    set_force, residual = scratch.set_force, scratch.residual
    for j in range(shared.mass.shape[0]):
        rhs[j, b] = s * linear[j, b]  # C ṽ + K ũ from sweep 1
        delta[j, b] = 0.0
    for i in range(delta_lin.shape[0]):
        delta_lin[i] = 0.0
    for i in range(count):
        residual[i] = s * set_force[i]


@kernel_part
def hand_phi_to_sweep(b, n_phi, s, shared, work, scratch, pan):
    """φ's catenary part to ``work`` for sweep 3 (columns and coefficients s φ); its pantograph
    part taken into the pantographs' δ here.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    n_phi : int
        Entries of φ from the last correction (0 if none). [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors.
    s : float
        1 + α of the HHT-α scheme. [-]
    shared, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    column_of, inverse = shared.column_of, shared.pantograph_inverse
    phi_dofs, phi, delta_lin = scratch.phi_dofs, scratch.phi, pan.delta_lin
    n = shared.mass.shape[0]
    e = 0
    for k in range(n_phi):
        m = phi_dofs[k]
        if m < n:
            work.phi_column[b, e] = column_of[m]
            work.phi_coefficient[b, e] = s * phi[k]
            e += 1
        else:
            for i in range(delta_lin.shape[0]):
                delta_lin[i] -= s * inverse[i, m - n] * phi[k]
    work.phi_count[b] = e


@kernel_part
def update_pantographs(b, taken, scalars, shared, state, pan):
    """The pantographs' new displacement [m], velocity [m/s], acceleration [m/s²] and internal
    force r_(n+1) = (rhs − M a)/s before the residual joins [N] (C ṽ + K ũ at the predictor).

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    taken : int
        Newton corrections taken in this step. [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors.
    scalars, shared, state : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    c = scalars.scheme
    pantograph_mass, pantograph_r = shared.pantograph_mass, state.pantograph_r
    u_pred, v_pred, p_rhs, p_linear, delta_lin = pan.u_pred, pan.v_pred, pan.rhs, pan.linear, pan.delta_lin
    for i in range(pantograph_mass.shape[0]):
        ai, state.pantograph_v[i, b] = newmark_update(delta_lin[i], v_pred[i], c)
        state.pantograph_u[i, b] = u_pred[i] + delta_lin[i]
        state.pantograph_a[i, b] = ai
        if taken == 0:
            pantograph_r[i, b] = p_linear[i]
        else:
            pantograph_r[i, b] = (p_rhs[i] - pantograph_mass[i] * ai) / c.s


@kernel_part
def join_residual(b, step, count, slack, s, shared, state, out, scratch):
    """HHT's r_(n+1) = (rhs + R − M a)/s: the final residual R joins the catenary's right-hand side
    on the set (for sweep 3) or the pantographs' r directly; the set cleared, the step's contact
    forces [N] and slack droppers recorded.

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    count : int
        Size of the set: DOFs that carry nonlinear forces at the iterate. [-]
    slack : int
        Recorded droppers slack at the iterate. [-]
    s : float
        1 + α of the HHT-α scheme. [-]
    shared, state, out, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    set_dofs, position, residual, contact_now = scratch.set_dofs, scratch.position, scratch.residual, scratch.contact_now
    rhs, pantograph_r = state.r, state.pantograph_r
    n = shared.mass.shape[0]
    for i in range(count):
        j = set_dofs[i]
        position[j] = -1
        if j < n:
            rhs[j, b] += residual[i]
        else:
            pantograph_r[j - n, b] += residual[i] / s
    for p in range(shared.head_dof.shape[0]):
        out.contact_force[b, p, step] = contact_now[p]
    out.slack_max[b] = max(out.slack_max[b], slack)


@kernel_part
def close_run_step(b, step, taken, count, n_phi, slack, scalars, shared, state, out, work, scratch, pan):
    """The end of run ``b``'s step: φ's catenary part to ``work`` for sweep 3, the pantographs' new
    state, the final residual R joined to the right-hand side, and the step's records.

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    taken : int
        Newton corrections taken in this step. [-]
    count : int
        Size of the set: DOFs that carry nonlinear forces at the iterate. [-]
    n_phi : int
        Entries of φ from the last correction (0 if none was taken). [-]
    slack : int
        Recorded droppers slack at the iterate. [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors (:func:`~presag_opt.dynamics.batch.predictor.pantograph_predictor`).
    scalars, shared, state, out, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    s = scalars.scheme.s
    if taken == 0:
        converged_at_predictor(b, count, scalars, shared, state, work, scratch, pan)
    hand_phi_to_sweep(b, n_phi, s, shared, work, scratch, pan)
    update_pantographs(b, taken, scalars, shared, state, pan)
    join_residual(b, step, count, slack, s, shared, state, out, scratch)
