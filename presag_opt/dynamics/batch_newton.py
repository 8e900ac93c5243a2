"""The per-run part of the batch kernel: nonlinear forces and each run's Newton iteration (numba).

:func:`newton_step` solves one run's step on its few nonlinear DOFs once
:func:`presag_opt.dynamics.kernel.advance` has formed the linear solution δ_lin of all runs:
contact (penalty, in series with the element's compliance), slack droppers (tension only) and the
pantographs' regularised friction (:func:`nonlinear_forces`), Woodbury corrections from the
cached columns of K_eff⁻¹ (:func:`influence`), and the integrator's residual test. The shared
arrays and the sweeps over all DOFs are :mod:`presag_opt.dynamics.kernel`'s.
"""

from __future__ import annotations

import numpy as np
from numba import njit

STATUS_RUNNING = -1
STATUS_OK = 0
STATUS_NOT_CONVERGED = 1
STATUS_NOT_FINITE = 2


@njit(cache=True)
def influence(j, m, n, column_of, columns, pantograph_inverse):
    """Entry (j, m) of K_eff⁻¹ on the extended DOFs. [m/N]"""
    if j < n and m < n:
        return columns[column_of[m], j]
    if j >= n and m >= n:
        return pantograph_inverse[j - n, m - n]
    return 0.0


@njit(cache=True)
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


@njit(cache=True)
def nonlinear_forces(b, step, a1, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared, runs, scratch):
    """Nonlinear forces and Newton tangent ∂f/∂u + a1 ∂f/∂v of run ``b`` at record ``step``.

    ``u_of`` [m] and ``v_of`` [m/s] hold the full displacement and velocity at the contact nodes and
    the pantograph DOFs; ``stretch`` [m] and ``rate`` [m/s] the stretch of every dropper from the
    equilibrium and its rate. Writes the set's DOFs, forces [N], dense tangent [N/m] and each
    contact force [N] into ``scratch``; returns (set size, recorded droppers slack).
    """
    head_dof, contact_stiffness, friction_dofs, friction_levels = shared[9], shared[10], shared[11], shared[12]
    dropper_dofs, dropper_gradient, dropper_stiffness, dropper_preload = shared[13], shared[14], shared[15], shared[16]
    dropper_recorded, cw_height = shared[17], shared[19]
    path_nodes, path_weights, path_compliance, head_height = runs[1], runs[2], runs[3], runs[4]
    set_dofs, set_force, tangent, position, contact_now = scratch[0], scratch[1], scratch[2], scratch[3], scratch[4]
    count = 0
    for p in range(head_dof.shape[0]):
        n1 = path_nodes[b, p, step, 0]
        n2 = path_nodes[b, p, step, 1]
        w1 = path_weights[b, p, step, 0]
        w2 = path_weights[b, p, step, 1]
        stiffness = 1.0 / (1.0 / contact_stiffness[p] + path_compliance[b, p, step])
        head = head_dof[p]
        wire = w1 * (cw_height[n1] + u_of[n1]) + w2 * (cw_height[n2] + u_of[n2])
        penetration = head_height[b, p] + u_of[head] - wire
        q1, count = enter_set(n1, set_dofs, set_force, tangent, position, count)
        q2, count = enter_set(n2, set_dofs, set_force, tangent, position, count)
        qh, count = enter_set(head, set_dofs, set_force, tangent, position, count)
        contact_now[p] = 0.0
        if penetration > 0.0:
            force = stiffness * penetration
            contact_now[p] = force
            set_force[q1] -= w1 * force
            set_force[q2] -= w2 * force
            set_force[qh] += force
            tangent[q1, q1] += stiffness * w1 * w1
            tangent[q1, q2] += stiffness * w1 * w2
            tangent[q1, qh] -= stiffness * w1
            tangent[q2, q1] += stiffness * w2 * w1
            tangent[q2, q2] += stiffness * w2 * w2
            tangent[q2, qh] -= stiffness * w2
            tangent[qh, q1] -= stiffness * w1
            tangent[qh, q2] -= stiffness * w2
            tangent[qh, qh] += stiffness
    for e in range(friction_levels.shape[0]):
        upper = friction_dofs[e, 0]
        lower = friction_dofs[e, 1]
        relative = v_of[upper] - (v_of[lower] if lower >= 0 else 0.0)
        th = np.tanh(relative / friction_velocity)
        force = friction_levels[e] * th
        slope = a1 * friction_levels[e] / friction_velocity * (1.0 - th * th)
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
    q = scratch[5]
    for d in range(dropper_preload.shape[0]):
        axial = dropper_preload[d] + dropper_stiffness[d] * stretch[d]
        if rayleigh_beta != 0.0:
            axial += rayleigh_beta * dropper_stiffness[d] * rate[d]
        if axial <= 0.0 and dropper_recorded[d]:
            slack_recorded += 1
        if axial < 0.0:
            for c in range(6):
                q[c], count = enter_set(dropper_dofs[d, c], set_dofs, set_force, tangent, position, count)
            k = -dropper_stiffness[d] * (1.0 + a1 * rayleigh_beta)
            for i in range(6):
                set_force[q[i]] += -axial * dropper_gradient[d, i]
                for c in range(6):
                    tangent[q[i], q[c]] += k * dropper_gradient[d, i] * dropper_gradient[d, c]
    return count, slack_recorded


@njit(cache=True)
def make_scratch(shared):
    """Scratch arrays of the per-run Newton solve, allocated once per batch."""
    n = shared[2].shape[0]
    n_p = shared[3].shape[0]
    n_pan = shared[9].shape[0]
    n_d = shared[16].shape[0]
    size = 3 * n_pan + 2 * n_p + 6 * n_d + 1
    return (
        np.empty(size, dtype=np.int64),  # 0 set DOFs
        np.empty(size),  # 1 set forces [N]
        np.empty((size, size)),  # 2 tangent [N/m]
        np.full(n + n_p, -1, dtype=np.int64),  # 3 DOF -> position in the set
        np.zeros(n_pan),  # 4 contact forces [N]
        np.empty(6, dtype=np.int64),  # 5 a dropper's set positions
        np.zeros(n + n_p),  # 6 full displacement at the DOFs read [m]
        np.zeros(n + n_p),  # 7 full velocity at the DOFs read [m/s]
        np.zeros(n_d),  # 8 dropper stretch [m]
        np.zeros(n_d),  # 9 dropper stretch rate [m/s]
        np.empty(size, dtype=np.int64),  # 10 φ DOFs
        np.empty(size),  # 11 φ [N]
        np.empty(size),  # 12 residual [N]
    )


@njit(cache=True)
def newton_step(b, step, scalars, shared, runs, state, out, work, scratch):
    """Newton iteration of run ``b`` for record ``step`` (see module notes).

    Leaves φ's catenary part in ``work`` (columns and coefficients s φ) for the state update, the
    pantographs' new state in ``state``, and the final set with its residual in ``scratch``.
    """
    rayleigh_beta, dt, hht_alpha, newmark_beta, newmark_gamma = scalars[1], scalars[2], scalars[3], scalars[4], scalars[5]
    tolerance, max_iterations, friction_velocity = scalars[6], int(scalars[7]), scalars[8]
    mass, pantograph_mass, pantograph_damping, pantograph_stiffness = shared[2], shared[3], shared[4], shared[5]
    pantograph_inverse, column_of, columns, head_dof = shared[6], shared[7], shared[8], shared[9]
    dropper_dofs, dropper_gradient, stretch_influence = shared[13], shared[14], shared[20]
    path_nodes, uplift = runs[1], runs[5]
    pantograph_u, pv, pa, pantograph_r = state[4], state[5], state[6], state[7]
    status, fail_step, fail_residual, iterations = out[3], out[4], out[5], out[6]
    u_pred, v_pred, rhs = state[0], state[1], state[3]  # during the step: ũ, ṽ and α r_n
    delta, g, linear, scale, first_residual = work[0], work[1], work[2], work[3], work[4]
    phi_count, phi_column, phi_coefficient = work[5], work[6], work[7]
    candidate_rows = shared[22]
    set_dofs, set_force, tangent, position = scratch[0], scratch[1], scratch[2], scratch[3]
    u_of, v_of, stretch, rate = scratch[6], scratch[7], scratch[8], scratch[9]
    phi_dofs, phi, residual = scratch[10], scratch[11], scratch[12]
    n = mass.shape[0]
    n_p = pantograph_mass.shape[0]
    n_pan = head_dof.shape[0]
    n_d = dropper_dofs.shape[0]
    s = 1.0 + hht_alpha
    a0 = 1.0 / (newmark_beta * dt * dt)
    a1 = newmark_gamma / (newmark_beta * dt)
    c_v = dt * (1.0 - newmark_gamma)
    c_a = dt * dt * (0.5 - newmark_beta)

    # Pantographs: predictors, right-hand side (uplift on the heads), C ṽ + K ũ, g and δ_lin.
    p_pred = np.empty(n_p)
    pv_pred = np.empty(n_p)
    p_rhs = np.empty(n_p)
    p_linear = np.empty(n_p)
    p_delta_lin = np.empty(n_p)
    p_g = np.empty(n_p)
    for i in range(n_p):
        p_pred[i] = pantograph_u[i, b] + dt * pv[i, b] + c_a * pa[i, b]
        pv_pred[i] = pv[i, b] + c_v * pa[i, b]
    for i in range(n_p):
        p_rhs[i] = hht_alpha * pantograph_r[i, b]
    for p in range(n_pan):
        p_rhs[head_dof[p] - n] += uplift[b]
    for i in range(n_p):
        lin = 0.0
        for k in range(n_p):
            lin += pantograph_damping[i, k] * pv_pred[k] + pantograph_stiffness[i, k] * p_pred[k]
        p_linear[i] = lin
        p_g[i] = p_rhs[i] - s * lin
    for i in range(n_p):
        acc = 0.0
        for k in range(n_p):
            acc += pantograph_inverse[i, k] * p_g[k]
        p_delta_lin[i] = acc

    # Droppers: stretch and rate at the predictor, and the stretch δ_lin adds.
    base_stretch = np.empty(n_d)
    base_rate = np.empty(n_d)
    linear_stretch = np.empty(n_d)
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
    # Contact nodes and pantograph DOFs at the predictor.
    for p in range(n_pan):
        for c in range(2):
            j = path_nodes[b, p, step, c]
            u_of[j] = u_pred[j, b]
            v_of[j] = v_pred[j, b]
    for i in range(n_p):
        u_of[n + i] = p_pred[i]
        v_of[n + i] = pv_pred[i]

    count, slack = nonlinear_forces(b, step, a1, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared,
                             runs, scratch)
    # The integrator's force scale and residual at the predictor, completed on the rows the
    # nonlinear forces can reach.
    largest_term = scale[b]
    largest = first_residual[b]
    for i in range(candidate_rows.shape[0]):
        j = candidate_rows[i]
        f0 = set_force[position[j]] if position[j] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (linear[i, b] + f0)), abs(rhs[j, b]))
        largest = max(largest, abs(s * f0 - g[i, b]))
    for i in range(n_p):
        f0 = set_force[position[n + i]] if position[n + i] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (p_linear[i] + f0)), abs(p_rhs[i]))
        largest = max(largest, abs(s * f0 - p_g[i]))
    limit = tolerance * largest_term
    n_phi = 0
    taken = 0
    while largest > limit:
        if taken == max_iterations or not np.isfinite(largest):
            status[b] = STATUS_NOT_CONVERGED if np.isfinite(largest) else STATUS_NOT_FINITE
            fail_step[b] = step
            fail_residual[b] = largest
            for i in range(count):
                position[set_dofs[i]] = -1
            iterations[b] += taken
            return
        # Woodbury correction from the current iterate δ (0 at the predictor):
        # x_S = (δ_lin − s Z f)_S − δ_S, y = (I + s T Z_SS)⁻¹ s T x_S, new δ = δ_lin − s Z φ, φ = f + y/s.
        x = np.empty(count)
        for i in range(count):
            j = set_dofs[i]
            lin = delta[j, b] if j < n else p_delta_lin[j - n]
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
        n_phi = count
        for i in range(count):
            phi_dofs[i] = set_dofs[i]
            phi[i] = set_force[i] + y[i] / s
            position[set_dofs[i]] = -1
        taken += 1
        # The new iterate where the forces read it, its forces, and the residual s (f − φ).
        for p in range(n_pan):
            for c in range(2):
                j = path_nodes[b, p, step, c]
                dj = delta[j, b]
                for k in range(n_phi):
                    dj -= s * influence(j, phi_dofs[k], n, column_of, columns, pantograph_inverse) * phi[k]
                u_of[j] = u_pred[j, b] + dj
                v_of[j] = v_pred[j, b] + a1 * dj
        for i in range(n_p):
            di = p_delta_lin[i]
            for k in range(n_phi):
                if phi_dofs[k] >= n:
                    di -= s * pantograph_inverse[i, phi_dofs[k] - n] * phi[k]
            u_of[n + i] = p_pred[i] + di
            v_of[n + i] = pv_pred[i] + a1 * di
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
        count, slack = nonlinear_forces(b, step, a1, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared,
                                 runs, scratch)
        for k in range(n_phi):
            q, count = enter_set(phi_dofs[k], set_dofs, set_force, tangent, position, count)
        for i in range(count):
            residual[i] = s * set_force[i]
        for k in range(n_phi):
            residual[position[phi_dofs[k]]] -= s * phi[k]
        largest = 0.0
        for i in range(count):
            largest = max(largest, abs(residual[i]))
    iterations[b] += taken
    if taken == 0:
        # Converged at the predictor: δ = 0, and R = s f0 − g everywhere gives
        # r_(n+1) = C ṽ + K ũ + f0; sweep 3 forms (rhs + R − M a)/s, so rhs becomes s (C ṽ + K ũ)
        # here and R = s f0 on the set.
        linear_column(b, scalars, shared, state, delta)
        for j in range(n):
            rhs[j, b] = s * delta[j, b]
            delta[j, b] = 0.0
        for i in range(n_p):
            p_delta_lin[i] = 0.0
        for i in range(count):
            residual[i] = s * set_force[i]
    # φ's catenary part goes to sweep 3; the pantographs are updated here.
    c = 0
    for k in range(n_phi):
        m = phi_dofs[k]
        if m < n:
            phi_column[b, c] = column_of[m]
            phi_coefficient[b, c] = s * phi[k]
            c += 1
        else:
            for i in range(n_p):
                p_delta_lin[i] -= s * pantograph_inverse[i, m - n] * phi[k]
    phi_count[b] = c
    for i in range(n_p):
        ai = a0 * p_delta_lin[i]
        pantograph_u[i, b] = p_pred[i] + p_delta_lin[i]
        pa[i, b] = ai
        pv[i, b] = pv_pred[i] + newmark_gamma * dt * ai
        if taken == 0:
            pantograph_r[i, b] = p_linear[i]
        else:
            pantograph_r[i, b] = (p_rhs[i] - pantograph_mass[i] * ai) / s
    # HHT's r_(n+1) = (rhs + R − M a)/s: the final residual R joins the right-hand side on the set
    # (the catenary's, for sweep 3) or the pantographs' r directly.
    for i in range(count):
        j = set_dofs[i]
        position[j] = -1
        if j < n:
            rhs[j, b] += residual[i]
        else:
            pantograph_r[j - n, b] += residual[i] / s
    for p in range(n_pan):
        out[0][b, p, step] = scratch[4][p]
    out[2][b] = max(out[2][b], slack)


@njit(cache=True)
def linear_column(b, scalars, shared, state, out):
    """out[:, b] = C ṽ + K ũ of run ``b`` (α_R M ṽ + K q), for a run that converged at its predictor."""
    rayleigh_alpha = scalars[0]
    stiffness_band, mass = shared[0], shared[2]
    v, q = state[1], state[2]
    n, width = stiffness_band.shape
    bw = width - 1
    for j in range(n):
        acc = stiffness_band[j, 0] * q[j, b] + rayleigh_alpha * mass[j] * v[j, b]
        for k in range(1, min(bw, n - 1 - j) + 1):
            acc += stiffness_band[j, k] * q[j + k, b]
        for k in range(1, min(bw, j) + 1):
            acc += stiffness_band[j - k, k] * q[j - k, b]
        out[j, b] = acc
