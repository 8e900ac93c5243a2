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
from presag_opt.dynamics.jit import inline, kernel_function

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
    """Entry (j, m) of K_eff⁻¹ on the extended DOFs. [m/N]"""
    if j < n and m < n:
        return columns[column_of[m], j]
    if j >= n and m >= n:
        return pantograph_inverse[j - n, m - n]
    return 0.0


@kernel_function
def enter_set(dof, set_dofs, set_force, tangent, position, count):
    """Position of ``dof`` in the current nonlinear set, adding it (zero force and tangent) if new."""
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
    """
    sh, sc = shared, scratch
    count = 0
    for p in range(sh.head_dof.shape[0]):
        n1, n2 = runs.path_nodes[b, p, step, 0], runs.path_nodes[b, p, step, 1]
        w1, w2 = runs.path_weights[b, p, step, 0], runs.path_weights[b, p, step, 1]
        stiffness = contact_stiffness(sh.contact_stiffness[p], runs.path_compliance[b, p, step])
        head = sh.head_dof[p]
        wire = w1 * (sh.cw_height[n1] + sc.u_of[n1]) + w2 * (sh.cw_height[n2] + sc.u_of[n2])
        penetration = runs.head_height[b, p] + sc.u_of[head] - wire
        q1, count = enter_set(n1, sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
        q2, count = enter_set(n2, sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
        qh, count = enter_set(head, sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
        force = contact_force(stiffness, penetration)
        k = contact_tangent(stiffness, penetration)
        sc.contact_now[p] = force
        if k != 0.0:
            sc.set_force[q1] -= w1 * force
            sc.set_force[q2] -= w2 * force
            sc.set_force[qh] += force
            sc.tangent[q1, q1] += k * w1 * w1
            sc.tangent[q1, q2] += k * w1 * w2
            sc.tangent[q1, qh] -= k * w1
            sc.tangent[q2, q1] += k * w2 * w1
            sc.tangent[q2, q2] += k * w2 * w2
            sc.tangent[q2, qh] -= k * w2
            sc.tangent[qh, q1] -= k * w1
            sc.tangent[qh, q2] -= k * w2
            sc.tangent[qh, qh] += k
    for e in range(sh.friction_levels.shape[0]):
        upper, lower = sh.friction_dofs[e, 0], sh.friction_dofs[e, 1]
        relative = sc.v_of[upper] - (sc.v_of[lower] if lower >= 0 else 0.0)
        force, slope = friction(sh.friction_levels[e], relative, scalars.friction_velocity, a1)
        qu, count = enter_set(upper, sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
        sc.set_force[qu] += force
        sc.tangent[qu, qu] += slope
        if lower >= 0:
            ql, count = enter_set(lower, sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
            sc.set_force[ql] -= force
            sc.tangent[ql, ql] += slope
            sc.tangent[qu, ql] -= slope
            sc.tangent[ql, qu] -= slope
    slack_recorded = 0
    q = sc.dropper_set
    for d in range(sh.dropper_preload.shape[0]):
        axial = dropper_axial_force(sh.dropper_preload[d], sh.dropper_stiffness[d], sc.stretch[d], sc.rate[d],
                                    scalars.rayleigh_beta)
        if dropper_tension(axial) <= 0.0 and sh.dropper_recorded[d]:
            slack_recorded += 1
        if dropper_slack(axial):
            for c in range(6):
                q[c], count = enter_set(sh.dropper_dofs[d, c], sc.set_dofs, sc.set_force, sc.tangent, sc.position,
                                        count)
            k = -sh.dropper_stiffness[d] * (1.0 + a1 * scalars.rayleigh_beta)
            for i in range(6):
                sc.set_force[q[i]] += -axial * sh.dropper_gradient[d, i]
                for c in range(6):
                    sc.tangent[q[i], q[c]] += k * sh.dropper_gradient[d, i] * sh.dropper_gradient[d, c]
    return count, slack_recorded


@inline
def pantograph_predictor(b, scalars, shared, runs, state):
    """Run ``b``'s pantograph predictors, right-hand side (uplift on the heads), C ṽ + K ũ, g and
    δ_lin (a :class:`PantographStep`)."""
    c, sh = scalars.scheme, shared
    n = sh.mass.shape[0]
    n_p = sh.pantograph_mass.shape[0]
    pan = PantographStep(np.empty(n_p), np.empty(n_p), np.empty(n_p), np.empty(n_p), np.empty(n_p), np.empty(n_p))
    for i in range(n_p):
        pan.u_pred[i] = (state.pantograph_u[i, b] + c.time_step * state.pantograph_v[i, b]
                         + c.displacement_predictor * state.pantograph_a[i, b])
        pan.v_pred[i] = state.pantograph_v[i, b] + c.velocity_predictor * state.pantograph_a[i, b]
    for i in range(n_p):
        pan.rhs[i] = c.alpha * state.pantograph_r[i, b]
    for p in range(sh.head_dof.shape[0]):
        pan.rhs[sh.head_dof[p] - n] += runs.uplift[b]
    for i in range(n_p):
        lin = 0.0
        for k in range(n_p):
            lin += sh.pantograph_damping[i, k] * pan.v_pred[k] + sh.pantograph_stiffness[i, k] * pan.u_pred[k]
        pan.linear[i] = lin
        pan.g[i] = pan.rhs[i] - c.s * lin
    for i in range(n_p):
        acc = 0.0
        for k in range(n_p):
            acc += sh.pantograph_inverse[i, k] * pan.g[k]
        pan.delta_lin[i] = acc
    return pan


@inline
def predictor_state(b, step, shared, runs, state, work, scratch, pan):
    """Run ``b``'s droppers at the predictor (a :class:`DropperStep`; ``scratch.stretch`` and
    ``.rate`` set too) and its contact nodes and pantograph DOFs at the predictor in ``scratch``."""
    sh, sc = shared, scratch
    n = sh.mass.shape[0]
    n_d = sh.dropper_dofs.shape[0]
    drop = DropperStep(np.empty(n_d), np.empty(n_d), np.empty(n_d))
    for d in range(n_d):
        su = 0.0
        sv = 0.0
        sd = 0.0
        for c in range(6):
            j = sh.dropper_dofs[d, c]
            gd = sh.dropper_gradient[d, c]
            su += gd * state.u[j, b]
            sv += gd * state.v[j, b]
            sd += gd * work.delta[j, b]
        drop.stretch[d] = su
        drop.rate[d] = sv
        drop.linear[d] = sd
        sc.stretch[d] = su
        sc.rate[d] = sv
    for p in range(sh.head_dof.shape[0]):
        for c in range(2):
            j = runs.path_nodes[b, p, step, c]
            sc.u_of[j] = state.u[j, b]
            sc.v_of[j] = state.v[j, b]
    for i in range(pan.u_pred.shape[0]):
        sc.u_of[n + i] = pan.u_pred[i]
        sc.v_of[n + i] = pan.v_pred[i]
    return drop


@inline
def residual_at_predictor(b, s, shared, state, work, scratch, pan):
    """The integrator's force scale and largest residual at the predictor of run ``b`` [N], the
    sweep's values completed on the rows the nonlinear forces can reach."""
    sc = scratch
    n = shared.mass.shape[0]
    largest_term = work.scale[b]
    largest = work.first_residual[b]
    for i in range(shared.candidate_rows.shape[0]):
        j = shared.candidate_rows[i]
        f0 = sc.set_force[sc.position[j]] if sc.position[j] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (work.linear[i, b] + f0)), abs(state.r[j, b]))
        largest = max(largest, abs(s * f0 - work.g[i, b]))
    for i in range(pan.linear.shape[0]):
        f0 = sc.set_force[sc.position[n + i]] if sc.position[n + i] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (pan.linear[i] + f0)), abs(pan.rhs[i]))
        largest = max(largest, abs(s * f0 - pan.g[i]))
    return largest_term, largest


@inline
def woodbury_correction(b, s, count, n_phi, taken, shared, work, scratch, pan):
    """The Woodbury correction from the current iterate δ (0 at the predictor): x_S = (δ_lin − s Z f)_S
    − δ_S, y = (I + s T Z_SS)⁻¹ s T x_S; the new δ = δ_lin − s Z φ with φ = f + y/s, left in
    ``scratch.phi``. Returns the size of φ."""
    sh, sc = shared, scratch
    n = sh.mass.shape[0]
    x = np.empty(count)
    for i in range(count):
        j = sc.set_dofs[i]
        lin = work.delta[j, b] if j < n else pan.delta_lin[j - n]
        acc = lin
        for k in range(count):
            acc -= s * influence(j, sc.set_dofs[k], n, sh.column_of, sh.columns, sh.pantograph_inverse) * sc.set_force[k]
        if taken > 0:
            current = lin
            for k in range(n_phi):
                current -= s * influence(j, sc.phi_dofs[k], n, sh.column_of, sh.columns, sh.pantograph_inverse) * sc.phi[k]
            acc -= current
        x[i] = acc
    capacitance = np.eye(count)
    small = np.zeros(count)
    for i in range(count):
        for k in range(count):
            t = s * sc.tangent[i, k]
            if t != 0.0:
                small[i] += t * x[k]
                for m in range(count):
                    capacitance[i, m] += t * influence(sc.set_dofs[k], sc.set_dofs[m], n, sh.column_of, sh.columns,
                                                       sh.pantograph_inverse)
    y = np.linalg.solve(capacitance, small)
    for i in range(count):
        sc.phi_dofs[i] = sc.set_dofs[i]
        sc.phi[i] = sc.set_force[i] + y[i] / s
        sc.position[sc.set_dofs[i]] = -1
    return count


@inline
def update_iterate(b, step, n_phi, scalars, shared, runs, state, work, scratch, pan, drop):
    """The new iterate δ = δ_lin − s Z φ where the forces read it, its nonlinear forces, and the
    residual s (f − φ) on the set. Returns (set size, recorded droppers slack, largest |residual| [N])."""
    c, sh, sc = scalars.scheme, shared, scratch
    s, a1 = c.s, c.a1
    n = sh.mass.shape[0]
    for p in range(sh.head_dof.shape[0]):
        for e in range(2):
            j = runs.path_nodes[b, p, step, e]
            dj = work.delta[j, b]
            for k in range(n_phi):
                dj -= s * influence(j, sc.phi_dofs[k], n, sh.column_of, sh.columns, sh.pantograph_inverse) * sc.phi[k]
            sc.u_of[j] = state.u[j, b] + dj
            sc.v_of[j] = state.v[j, b] + a1 * dj
    for i in range(pan.u_pred.shape[0]):
        di = pan.delta_lin[i]
        for k in range(n_phi):
            if sc.phi_dofs[k] >= n:
                di -= s * sh.pantograph_inverse[i, sc.phi_dofs[k] - n] * sc.phi[k]
        sc.u_of[n + i] = pan.u_pred[i] + di
        sc.v_of[n + i] = pan.v_pred[i] + a1 * di
    n_d = drop.linear.shape[0]
    for d in range(n_d):
        sc.stretch[d] = drop.linear[d]
    for k in range(n_phi):
        m = sc.phi_dofs[k]
        if m < n:
            row = sh.column_of[m]
            f = s * sc.phi[k]
            for d in range(n_d):
                sc.stretch[d] -= f * sh.stretch_influence[row, d]
    for d in range(n_d):
        sc.rate[d] = drop.rate[d] + a1 * sc.stretch[d]
        sc.stretch[d] = drop.stretch[d] + sc.stretch[d]
    count, slack = nonlinear_forces(b, step, a1, scalars, shared, runs, scratch)
    for k in range(n_phi):
        _, count = enter_set(sc.phi_dofs[k], sc.set_dofs, sc.set_force, sc.tangent, sc.position, count)
    for i in range(count):
        sc.residual[i] = s * sc.set_force[i]
    for k in range(n_phi):
        sc.residual[sc.position[sc.phi_dofs[k]]] -= s * sc.phi[k]
    largest = 0.0
    for i in range(count):
        largest = max(largest, abs(sc.residual[i]))
    return count, slack, largest


@inline
def fail_run(b, step, largest, count, taken, out, scratch):
    """Stop run ``b``: its status, step and last residual [N]; the set cleared."""
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
    """
    c, sh, sc = scalars.scheme, shared, scratch
    s = c.s
    n = sh.mass.shape[0]
    n_p = sh.pantograph_mass.shape[0]
    if taken == 0:
        linear_column(b, scalars, shared, state, work.delta)
        for j in range(n):
            state.r[j, b] = s * work.delta[j, b]
            work.delta[j, b] = 0.0
        for i in range(n_p):
            pan.delta_lin[i] = 0.0
        for i in range(count):
            sc.residual[i] = s * sc.set_force[i]
    e = 0
    for k in range(n_phi):
        m = sc.phi_dofs[k]
        if m < n:
            work.phi_column[b, e] = sh.column_of[m]
            work.phi_coefficient[b, e] = s * sc.phi[k]
            e += 1
        else:
            for i in range(n_p):
                pan.delta_lin[i] -= s * sh.pantograph_inverse[i, m - n] * sc.phi[k]
    work.phi_count[b] = e
    for i in range(n_p):
        ai = c.a0 * pan.delta_lin[i]
        state.pantograph_u[i, b] = pan.u_pred[i] + pan.delta_lin[i]
        state.pantograph_a[i, b] = ai
        state.pantograph_v[i, b] = pan.v_pred[i] + c.velocity_update * ai
        if taken == 0:
            state.pantograph_r[i, b] = pan.linear[i]
        else:
            state.pantograph_r[i, b] = (pan.rhs[i] - sh.pantograph_mass[i] * ai) / s
    for i in range(count):
        j = sc.set_dofs[i]
        sc.position[j] = -1
        if j < n:
            state.r[j, b] += sc.residual[i]
        else:
            state.pantograph_r[j - n, b] += sc.residual[i] / s
    for p in range(sh.head_dof.shape[0]):
        out.contact_force[b, p, step] = sc.contact_now[p]
    out.slack_max[b] = max(out.slack_max[b], slack)


@kernel_function
def newton_step(b, step, scalars, shared, runs, state, out, work, scratch):
    """Newton iteration of run ``b`` for record ``step`` (see the module notes).

    Between the sweeps the catenary's ``state.u``, ``.v`` and ``.r`` hold the step's ũ, ṽ and α r_n
    and ``work.delta`` holds δ_lin. Leaves φ's catenary part in ``work`` (columns and coefficients
    s φ) for the state update, the pantographs' new state in ``state``, and stops a run whose
    iteration fails.
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
    """out[:, b] = C ṽ + K ũ of run ``b`` (α_R M ṽ + K q), for a run that converged at its predictor. [N]"""
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
