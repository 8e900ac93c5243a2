"""The per-run part of the batch kernel: nonlinear forces and each run's Newton iteration (numba).

:func:`newton_step` solves one run's step on its few nonlinear DOFs once the sweeps of
:mod:`presag_opt.dynamics.kernel` have formed the linear solution δ_lin of all runs: contact, slack
droppers and the pantographs' friction (:func:`nonlinear_forces`, with the laws of
:mod:`presag_opt.dynamics.laws` compiled inline), Woodbury corrections from the cached columns of
K_eff⁻¹ (:func:`influence`), and the integrator's residual test. Its parts, in order: the
pantographs' predictor (:func:`pantograph_predictor`), the state at the predictor
(:func:`predictor_state`), the residual there (:func:`residual_at_predictor`), the Woodbury correction
(:func:`woodbury_correction`), the new iterate and its residual (:func:`update_iterate`), and the
step's end (:func:`finish_step`). The arrays are the named tuples of
:mod:`presag_opt.dynamics.kernel_data`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from presag_opt.dynamics import laws
from presag_opt.native.jit import inline, kernel_function

STATUS_RUNNING = -1
STATUS_OK = 0
STATUS_NOT_CONVERGED = 1
STATUS_NOT_FINITE = 2

contact_stiffness = inline(laws.contact_stiffness)
contact_force = inline(laws.contact_force)
contact_tangent = inline(laws.contact_tangent)
friction = inline(laws.friction)
dropper_axial_force = inline(laws.dropper_axial_force)
dropper_slack = inline(laws.dropper_slack)
dropper_tension = inline(laws.dropper_tension)


class PantographStep(NamedTuple):
    """One run's pantograph quantities of a step: predictors ũ [m], ṽ [m/s]; right-hand side α r_n
    plus the uplift on the heads, C ṽ + K ũ, g = rhs − s (C ṽ + K ũ) [N]; δ_lin = K_eff⁻¹ g [m]."""

    u_pred: np.ndarray
    v_pred: np.ndarray
    rhs: np.ndarray
    linear: np.ndarray
    g: np.ndarray
    delta_lin: np.ndarray


class DropperStep(NamedTuple):
    """One run's dropper stretches of a step: at the predictor [m], its rate [m/s], and the stretch
    δ_lin adds [m]."""

    stretch: np.ndarray
    rate: np.ndarray
    linear: np.ndarray


@kernel_function
def influence(j, m, n, column_of, columns, pantograph_inverse):
    """Entry (j, m) of K_eff⁻¹ on the extended DOFs. [m/N]

    Parameters
    ----------
    j : int
        Row, an extended DOF. [-]
    m : int
        Column, an extended DOF of the set. [-]
    n : int
        Number of catenary DOFs (the pantograph DOFs follow). [-]
    column_of : ndarray of int
        Column of ``columns`` holding each catenary DOF's influence column (-1: none). [-]
    columns : ndarray, shape (n_columns, n)
        Influence columns K_eff⁻¹ e_m of the candidate DOFs. [m/N]
    pantograph_inverse : ndarray, shape (n_p, n_p)
        Inverse of the pantographs' effective stiffness. [m/N]
    """
    if j < n and m < n:
        return columns[column_of[m], j]
    if j >= n and m >= n:
        return pantograph_inverse[j - n, m - n]
    return 0.0


@kernel_function
def enter_set(dof, set_dofs, set_force, tangent, position, count):
    """Position of ``dof`` in the current nonlinear set, adding it (zero force and tangent) if new.

    Parameters
    ----------
    dof : int
        Degree of freedom (extended: pantograph DOFs after the catenary's). [-]
    set_dofs : ndarray of int
        DOFs of the set, in order of entry. [-]
    set_force : ndarray
        Nonlinear force on each DOF of the set. [N]
    tangent : ndarray, shape (m, m)
        Dense Newton tangent on the set. [N/m]
    position : ndarray of int
        Position of each DOF in the set (-1: not in it). [-]
    count : int
        Current size of the set. [-]
    """
    p = position[dof]
    if p >= 0:
        return p, count
    position[dof] = count
    set_dofs[count] = dof
    set_force[count] = 0.0
    for i in range(count + 1):
        tangent[count, i] = 0.0
        tangent[i, count] = 0.0
    return count, count + 1


@kernel_function
def nonlinear_forces(b, step, a1, scalars, shared, runs, scratch):
    """Nonlinear forces and Newton tangent ∂f/∂u + a1 ∂f/∂v of run ``b`` at record ``step``.

    Reads the full displacement ``scratch.u_of`` [m] and velocity ``scratch.v_of`` [m/s] at the
    contact nodes and the pantograph DOFs, and every dropper's stretch ``scratch.stretch`` [m] and
    rate ``scratch.rate`` [m/s]. Writes the set's DOFs, forces [N], dense tangent [N/m] and each
    contact force [N] into ``scratch``; returns (set size, recorded droppers slack).

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    step : int
        Record (time step) being computed. [-]
    a1 : float
        Velocity coefficient of the scheme (∂v/∂u within the step; 0 at rest). [1/s]
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        Arrays shared by every run (catenary, factor, pantographs).
    runs : Runs
        Per-run inputs (contact paths, step counts, head heights).
    scratch : Scratch
        Scratch arrays of the run being iterated.
    """
    head_dof, contact_stiffness_, cw_height = shared.head_dof, shared.contact_stiffness, shared.cw_height
    friction_dofs, friction_levels = shared.friction_dofs, shared.friction_levels
    dropper_dofs, dropper_gradient, dropper_stiffness = shared.dropper_dofs, shared.dropper_gradient, shared.dropper_stiffness
    dropper_preload, dropper_recorded = shared.dropper_preload, shared.dropper_recorded
    path_nodes, path_weights, path_compliance, head_height = (runs.path_nodes, runs.path_weights, runs.path_compliance,
                                                              runs.head_height)
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    contact_now, u_of, v_of, stretch, rate = scratch.contact_now, scratch.u_of, scratch.v_of, scratch.stretch, scratch.rate
    friction_velocity, rayleigh_beta = scalars.friction_velocity, scalars.rayleigh_beta
    count = 0
    for p in range(head_dof.shape[0]):
        n1, n2 = path_nodes[b, p, step, 0], path_nodes[b, p, step, 1]
        w1, w2 = path_weights[b, p, step, 0], path_weights[b, p, step, 1]
        stiffness = contact_stiffness(contact_stiffness_[p], path_compliance[b, p, step])
        head = head_dof[p]
        wire = w1 * (cw_height[n1] + u_of[n1]) + w2 * (cw_height[n2] + u_of[n2])
        penetration = head_height[b, p] + u_of[head] - wire
        q1, count = enter_set(n1, set_dofs, set_force, tangent, position, count)
        q2, count = enter_set(n2, set_dofs, set_force, tangent, position, count)
        qh, count = enter_set(head, set_dofs, set_force, tangent, position, count)
        force = contact_force(stiffness, penetration)
        k = contact_tangent(stiffness, penetration)
        contact_now[p] = force
        if k != 0.0:
            set_force[q1] -= w1 * force
            set_force[q2] -= w2 * force
            set_force[qh] += force
            tangent[q1, q1] += k * w1 * w1
            tangent[q1, q2] += k * w1 * w2
            tangent[q1, qh] -= k * w1
            tangent[q2, q1] += k * w2 * w1
            tangent[q2, q2] += k * w2 * w2
            tangent[q2, qh] -= k * w2
            tangent[qh, q1] -= k * w1
            tangent[qh, q2] -= k * w2
            tangent[qh, qh] += k
    for e in range(friction_levels.shape[0]):
        upper, lower = friction_dofs[e, 0], friction_dofs[e, 1]
        relative = v_of[upper] - (v_of[lower] if lower >= 0 else 0.0)
        force, slope = friction(friction_levels[e], relative, friction_velocity, a1)
        qu, count = enter_set(upper, set_dofs, set_force, tangent, position, count)
        set_force[qu] += force
        tangent[qu, qu] += slope
        if lower >= 0:
            ql, count = enter_set(lower, set_dofs, set_force, tangent, position, count)
            set_force[ql] -= force
            tangent[ql, ql] += slope
            tangent[qu, ql] -= slope
            tangent[ql, qu] -= slope
    slack_recorded = 0
    q = scratch.dropper_set
    for d in range(dropper_preload.shape[0]):
        axial = dropper_axial_force(dropper_preload[d], dropper_stiffness[d], stretch[d], rate[d], rayleigh_beta)
        if dropper_tension(axial) <= 0.0 and dropper_recorded[d]:
            slack_recorded += 1
        if dropper_slack(axial):
            for c in range(6):
                q[c], count = enter_set(dropper_dofs[d, c], set_dofs, set_force, tangent, position, count)
            k = -dropper_stiffness[d] * (1.0 + a1 * rayleigh_beta)
            for i in range(6):
                set_force[q[i]] += -axial * dropper_gradient[d, i]
                for c in range(6):
                    tangent[q[i], q[c]] += k * dropper_gradient[d, i] * dropper_gradient[d, c]
    return count, slack_recorded


@inline
def pantograph_predictor(b, scalars, shared, runs, state):
    """Run ``b``'s pantograph predictors, right-hand side (uplift on the heads), C ṽ + K ũ, g and
    δ_lin (a :class:`PantographStep`).

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        What the runs of the batch share.
    runs : Runs
        What differs between the runs.
    state : RunState
        The runs' state.
    """
    c = scalars.scheme
    head_dof, damping, stiffness, inverse = (shared.head_dof, shared.pantograph_damping, shared.pantograph_stiffness,
                                             shared.pantograph_inverse)
    pantograph_u, pv, pa, pantograph_r = state.pantograph_u, state.pantograph_v, state.pantograph_a, state.pantograph_r
    n = shared.mass.shape[0]
    n_p = shared.pantograph_mass.shape[0]
    u_pred, v_pred, rhs, linear, g, delta_lin = (np.empty(n_p), np.empty(n_p), np.empty(n_p), np.empty(n_p),
                                                 np.empty(n_p), np.empty(n_p))
    for i in range(n_p):
        u_pred[i] = pantograph_u[i, b] + c.time_step * pv[i, b] + c.displacement_predictor * pa[i, b]
        v_pred[i] = pv[i, b] + c.velocity_predictor * pa[i, b]
    for i in range(n_p):
        rhs[i] = c.alpha * pantograph_r[i, b]
    for p in range(head_dof.shape[0]):
        rhs[head_dof[p] - n] += runs.uplift[b]
    for i in range(n_p):
        lin = 0.0
        for k in range(n_p):
            lin += damping[i, k] * v_pred[k] + stiffness[i, k] * u_pred[k]
        linear[i] = lin
        g[i] = rhs[i] - c.s * lin
    for i in range(n_p):
        acc = 0.0
        for k in range(n_p):
            acc += inverse[i, k] * g[k]
        delta_lin[i] = acc
    pan = PantographStep(u_pred, v_pred, rhs, linear, g, delta_lin)
    return pan


@inline
def predictor_state(b, step, shared, runs, state, work, scratch, pan):
    """Run ``b``'s droppers at the predictor (a :class:`DropperStep`; ``scratch.stretch`` and
    ``.rate`` set too) and its contact nodes and pantograph DOFs at the predictor in ``scratch``.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    step : int
        Record (time step) being computed. [-]
    shared : Shared
        What the runs of the batch share.
    runs : Runs
        What differs between the runs.
    state : RunState
        The runs' state.
    work : Work
        Per-step work arrays of the batch.
    scratch : Scratch
        Scratch arrays of the run being iterated.
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    """
    dropper_dofs, dropper_gradient, path_nodes = shared.dropper_dofs, shared.dropper_gradient, runs.path_nodes
    u_pred, v_pred, delta = state.u, state.v, work.delta
    u_of, v_of, stretch, rate = scratch.u_of, scratch.v_of, scratch.stretch, scratch.rate
    n = shared.mass.shape[0]
    n_d = dropper_dofs.shape[0]
    base_stretch, base_rate, linear_stretch = np.empty(n_d), np.empty(n_d), np.empty(n_d)
    for d in range(n_d):
        su = 0.0
        sv = 0.0
        sd = 0.0
        for c in range(6):
            j = dropper_dofs[d, c]
            gd = dropper_gradient[d, c]
            su += gd * u_pred[j, b]
            sv += gd * v_pred[j, b]
            sd += gd * delta[j, b]
        base_stretch[d] = su
        base_rate[d] = sv
        linear_stretch[d] = sd
        stretch[d] = su
        rate[d] = sv
    for p in range(shared.head_dof.shape[0]):
        for c in range(2):
            j = path_nodes[b, p, step, c]
            u_of[j] = u_pred[j, b]
            v_of[j] = v_pred[j, b]
    p_pred, pv_pred = pan.u_pred, pan.v_pred
    for i in range(p_pred.shape[0]):
        u_of[n + i] = p_pred[i]
        v_of[n + i] = pv_pred[i]
    return DropperStep(base_stretch, base_rate, linear_stretch)


@inline
def residual_at_predictor(b, s, shared, state, work, scratch, pan):
    """The integrator's force scale and largest residual at the predictor of run ``b`` [N], the
    sweep's values completed on the rows the nonlinear forces can reach.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    s : float
        1 + α of the HHT-α scheme. [-]
    shared : Shared
        What the runs of the batch share.
    state : RunState
        The runs' state.
    work : Work
        Per-step work arrays of the batch.
    scratch : Scratch
        Scratch arrays of the run being iterated.
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    """
    set_force, position, candidate_rows = scratch.set_force, scratch.position, shared.candidate_rows
    linear, g, rhs = work.linear, work.g, state.r
    n = shared.mass.shape[0]
    largest_term = work.scale[b]
    largest = work.first_residual[b]
    for i in range(candidate_rows.shape[0]):
        j = candidate_rows[i]
        f0 = set_force[position[j]] if position[j] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (linear[i, b] + f0)), abs(rhs[j, b]))
        largest = max(largest, abs(s * f0 - g[i, b]))
    p_linear, p_rhs, p_g = pan.linear, pan.rhs, pan.g
    for i in range(p_linear.shape[0]):
        f0 = set_force[position[n + i]] if position[n + i] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (p_linear[i] + f0)), abs(p_rhs[i]))
        largest = max(largest, abs(s * f0 - p_g[i]))
    return largest_term, largest


@inline
def woodbury_correction(b, s, count, n_phi, taken, shared, work, scratch, pan):
    """The Woodbury correction from the current iterate δ (0 at the predictor): x_S = (δ_lin − s Z f)_S
    − δ_S, y = (I + s T Z_SS)⁻¹ s T x_S; the new δ = δ_lin − s Z φ with φ = f + y/s, left in
    ``scratch.phi``. Returns the size of φ.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    s : float
        1 + α of the HHT-α scheme. [-]
    count : int
        Size of the set: DOFs that carry nonlinear forces at the iterate. [-]
    n_phi : int
        Entries of φ from the last correction (0 before the first). [-]
    taken : int
        Newton corrections taken in this step so far. [-]
    shared : Shared
        What the runs of the batch share.
    work : Work
        Per-step work arrays of the batch.
    scratch : Scratch
        Scratch arrays of the run being iterated.
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    """
    column_of, columns, pantograph_inverse = shared.column_of, shared.columns, shared.pantograph_inverse
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    phi_dofs, phi, delta, delta_lin = scratch.phi_dofs, scratch.phi, work.delta, pan.delta_lin
    n = shared.mass.shape[0]
    x = np.empty(count)
    for i in range(count):
        j = set_dofs[i]
        lin = delta[j, b] if j < n else delta_lin[j - n]
        acc = lin
        for k in range(count):
            acc -= s * influence(j, set_dofs[k], n, column_of, columns, pantograph_inverse) * set_force[k]
        if taken > 0:
            current = lin
            for k in range(n_phi):
                current -= s * influence(j, phi_dofs[k], n, column_of, columns, pantograph_inverse) * phi[k]
            acc -= current
        x[i] = acc
    capacitance = np.eye(count)
    small = np.zeros(count)
    for i in range(count):
        for k in range(count):
            t = s * tangent[i, k]
            if t != 0.0:
                small[i] += t * x[k]
                for m in range(count):
                    capacitance[i, m] += t * influence(set_dofs[k], set_dofs[m], n, column_of, columns,
                                                       pantograph_inverse)
    y = np.linalg.solve(capacitance, small)
    for i in range(count):
        phi_dofs[i] = set_dofs[i]
        phi[i] = set_force[i] + y[i] / s
        position[set_dofs[i]] = -1
    return count


@inline
def update_iterate(b, step, n_phi, scalars, shared, runs, state, work, scratch, pan, drop):
    """The new iterate δ = δ_lin − s Z φ where the forces read it, its nonlinear forces, and the
    residual s (f − φ) on the set. Returns (set size, recorded droppers slack, largest |residual| [N]).

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    step : int
        Record (time step) being computed. [-]
    n_phi : int
        Entries of φ from the last correction (0 before the first). [-]
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        What the runs of the batch share.
    runs : Runs
        What differs between the runs.
    state : RunState
        The runs' state.
    work : Work
        Per-step work arrays of the batch.
    scratch : Scratch
        Scratch arrays of the run being iterated.
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    drop : DropperStep
        Run ``b``'s droppers at the predictor (``predictor_state``).
    """
    s, a1 = scalars.scheme.s, scalars.scheme.a1
    column_of, columns, pantograph_inverse = shared.column_of, shared.columns, shared.pantograph_inverse
    stretch_influence, path_nodes, u_pred, v_pred, delta = (shared.stretch_influence, runs.path_nodes, state.u, state.v,
                                                            work.delta)
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    u_of, v_of, stretch, rate = scratch.u_of, scratch.v_of, scratch.stretch, scratch.rate
    phi_dofs, phi, residual = scratch.phi_dofs, scratch.phi, scratch.residual
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
    base_stretch, base_rate, linear_stretch = drop.stretch, drop.rate, drop.linear
    for i in range(p_pred.shape[0]):
        di = p_delta_lin[i]
        for k in range(n_phi):
            if phi_dofs[k] >= n:
                di -= s * pantograph_inverse[i, phi_dofs[k] - n] * phi[k]
        u_of[n + i] = p_pred[i] + di
        v_of[n + i] = pv_pred[i] + a1 * di
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
    count, slack = nonlinear_forces(b, step, a1, scalars, shared, runs, scratch)
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


@inline
def fail_run(b, step, largest, count, taken, out, scratch):
    """Stop run ``b``: its status, step and last residual [N]; the set cleared.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    step : int
        Record (time step) being computed. [-]
    largest : float
        Largest absolute residual at the last iterate. [N]
    count : int
        Size of the set: DOFs that carry nonlinear forces at the iterate. [-]
    taken : int
        Newton corrections taken in this step so far. [-]
    out : Records
        The records being written.
    scratch : Scratch
        Scratch arrays of the run being iterated.
    """
    out.status[b] = STATUS_NOT_CONVERGED if np.isfinite(largest) else STATUS_NOT_FINITE
    out.fail_step[b] = step
    out.fail_residual[b] = largest
    for i in range(count):
        scratch.position[scratch.set_dofs[i]] = -1
    out.iterations[b] += taken


@inline
def finish_step(b, step, taken, count, n_phi, slack, scalars, shared, state, out, work, scratch, pan):
    """The end of run ``b``'s step: φ's catenary part to ``work`` for sweep 3, the pantographs' new
    state, the final residual R joined to the right-hand side, and the step's records.

    HHT's r_(n+1) = (rhs + R − M a)/s: R joins the catenary's right-hand side on the set (for sweep
    3) or the pantographs' r directly. A run that converged at its predictor has δ = 0, and
    R = s f0 − g everywhere gives r_(n+1) = C ṽ + K ũ + f0: sweep 3 forms (rhs + R − M a)/s, so rhs
    becomes s (C ṽ + K ũ) here and R = s f0 on the set.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    step : int
        Record (time step) being computed. [-]
    taken : int
        Newton corrections taken in this step so far. [-]
    count : int
        Size of the set: DOFs that carry nonlinear forces at the iterate. [-]
    n_phi : int
        Entries of φ from the last correction (0 before the first). [-]
    slack : int
        Recorded droppers slack at the iterate. [-]
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        What the runs of the batch share.
    state : RunState
        The runs' state.
    out : Records
        The records being written.
    work : Work
        Per-step work arrays of the batch.
    scratch : Scratch
        Scratch arrays of the run being iterated.
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    """
    c = scalars.scheme
    s = c.s
    column_of, inverse, pantograph_mass = shared.column_of, shared.pantograph_inverse, shared.pantograph_mass
    set_dofs, set_force, position, residual = scratch.set_dofs, scratch.set_force, scratch.position, scratch.residual
    phi_dofs, phi, contact_now = scratch.phi_dofs, scratch.phi, scratch.contact_now
    rhs, delta, pantograph_r = state.r, work.delta, state.pantograph_r
    u_pred, v_pred, p_rhs, p_linear, delta_lin = pan.u_pred, pan.v_pred, pan.rhs, pan.linear, pan.delta_lin
    n = shared.mass.shape[0]
    n_p = pantograph_mass.shape[0]
    if taken == 0:
        linear_column(b, scalars, shared, state, delta)
        for j in range(n):
            rhs[j, b] = s * delta[j, b]
            delta[j, b] = 0.0
        for i in range(n_p):
            delta_lin[i] = 0.0
        for i in range(count):
            residual[i] = s * set_force[i]
    e = 0
    for k in range(n_phi):
        m = phi_dofs[k]
        if m < n:
            work.phi_column[b, e] = column_of[m]
            work.phi_coefficient[b, e] = s * phi[k]
            e += 1
        else:
            for i in range(n_p):
                delta_lin[i] -= s * inverse[i, m - n] * phi[k]
    work.phi_count[b] = e
    for i in range(n_p):
        ai = c.a0 * delta_lin[i]
        state.pantograph_u[i, b] = u_pred[i] + delta_lin[i]
        state.pantograph_a[i, b] = ai
        state.pantograph_v[i, b] = v_pred[i] + c.velocity_update * ai
        if taken == 0:
            pantograph_r[i, b] = p_linear[i]
        else:
            pantograph_r[i, b] = (p_rhs[i] - pantograph_mass[i] * ai) / s
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


@kernel_function
def newton_step(b, step, scalars, shared, runs, state, out, work, scratch):
    """Newton iteration of run ``b`` for record ``step`` (see the module notes).

    Between the sweeps the catenary's ``state.u``, ``.v`` and ``.r`` hold the step's ũ, ṽ and α r_n
    and ``work.delta`` holds δ_lin. Leaves φ's catenary part in ``work`` (columns and coefficients
    s φ) for the state update, the pantographs' new state in ``state``, and stops a run whose
    iteration fails.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    step : int
        Record (time step) being computed. [-]
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        Arrays shared by every run (catenary, factor, pantographs).
    runs : Runs
        Per-run inputs (contact paths, step counts, head heights).
    state : RunState
        State arrays of the batch (catenary and pantographs).
    out : Records
        The records being written.
    work : Work
        Work arrays of the sweeps.
    scratch : Scratch
        Scratch arrays of the run being iterated.
    """
    s, a1 = scalars.scheme.s, scalars.scheme.a1
    pan = pantograph_predictor(b, scalars, shared, runs, state)
    drop = predictor_state(b, step, shared, runs, state, work, scratch, pan)
    count, slack = nonlinear_forces(b, step, a1, scalars, shared, runs, scratch)
    largest_term, largest = residual_at_predictor(b, s, shared, state, work, scratch, pan)
    limit = scalars.tolerance * largest_term
    n_phi = 0
    taken = 0
    while largest > limit:
        if taken == scalars.max_iterations or not np.isfinite(largest):
            fail_run(b, step, largest, count, taken, out, scratch)
            return
        n_phi = woodbury_correction(b, s, count, n_phi, taken, shared, work, scratch, pan)
        taken += 1
        count, slack, largest = update_iterate(b, step, n_phi, scalars, shared, runs, state, work, scratch, pan, drop)
    out.iterations[b] += taken
    finish_step(b, step, taken, count, n_phi, slack, scalars, shared, state, out, work, scratch, pan)


@kernel_function
def linear_column(b, scalars, shared, state, out):
    """out[:, b] = C ṽ + K ũ of run ``b`` (α_R M ṽ + K q), for a run that converged at its predictor. [N]

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        Arrays shared by every run (catenary, factor, pantographs).
    state : RunState
        State arrays of the batch (catenary and pantographs).
    out : ndarray, shape (n, n_runs)
        Array receiving the column. [N]
    """
    band, mass, v, q = shared.stiffness_band, shared.mass, state.v, state.q
    n, width = band.shape
    bw = width - 1
    for j in range(n):
        acc = band[j, 0] * q[j, b] + scalars.rayleigh_alpha * mass[j] * v[j, b]
        for k in range(1, min(bw, n - 1 - j) + 1):
            acc += band[j, k] * q[j + k, b]
        for k in range(1, min(bw, j) + 1):
            acc += band[j - k, k] * q[j - k, b]
        out[j, b] = acc
