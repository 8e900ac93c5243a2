"""Compiled time stepping of many runs on one catenary (numba), the batch index innermost.

This module holds the arithmetic of :func:`presag_opt.dynamics.batch.simulate_many`: banded
products and solves on arrays of shape (n_dofs, n_runs), and the HHT-α step of every run. Setting up
(matrices, orderings, contact paths, initial states) and the statistics are left to
:mod:`presag_opt.dynamics.batch`.

The step is the one of :mod:`presag_opt.dynamics.integrator` (HHT-α; Newmark for α = 0), written
for δ = u_(n+1) − ũ, the displacement from the predictor. K_eff = a0 M + s (K + a1 C) is constant
and shared by all runs, so the linear part of every run is one banded solve, δ_lin = K_eff⁻¹ g with
g = rhs − s (C ṽ + K ũ). The nonlinear forces (contact, slack droppers, pantograph friction) act on
a few DOFs, so every Newton iterate is δ = δ_lin − s Z φ, with Z = K_eff⁻¹ E (columns computed once
for every DOF that can carry a nonlinear force) and a short vector φ. Each correction is the
integrator's Woodbury correction from the same iterate, with the same residual test
(max |R| ≤ tolerance × the largest force term of the step), so the batch follows the integrator's
iterates up to round-off.

The runs are independent: nothing is reduced across the batch, and every run's arithmetic is the
same sequence of IEEE operations whatever its neighbours (no fast-math, so no reassociation or
contraction that could differ between vector lanes and scalar remainders). A run's result does not
depend, to the last bit, on which other runs share its batch. A run whose Newton iteration fails
stops with its status; the others go on.

Extended DOF numbering: the catenary's DOFs in banded (reverse Cuthill–McKee) order, 0 … n − 1,
then the pantographs' DOFs, n … n + n_p − 1.
"""

from __future__ import annotations

import numpy as np
from numba import njit

SHARED = (
    "stiffness_band", "factor_band", "mass", "pantograph_mass", "pantograph_damping", "pantograph_stiffness",
    "pantograph_inverse", "column_of", "columns", "head_dof", "contact_stiffness", "friction_dofs",
    "friction_levels", "dropper_dofs", "dropper_gradient", "dropper_stiffness", "dropper_preload",
    "dropper_recorded", "support_dofs", "cw_height", "stretch_influence", "candidate_index", "candidate_rows",
    "support_row",
)
"""The arrays all runs share, in the order of the kernel's ``shared`` tuple (catenary DOFs in banded
order, pantograph DOFs after them): K and the Cholesky factor of K_eff by rows, band[j, k] = A[j + k, j]
[N/m, sqrt(N/m)]; lumped masses [kg]; the pantographs' M, C, K and K_eff⁻¹; the row of ``columns``
(K_eff⁻¹ e_j, [m/N]) for each DOF, −1 if none; each head's DOF and contact stiffness [N/m]; friction
elements (upper DOF, lower DOF or −1 for the car body) and levels [N]; dropper DOFs (6 each), stretch
gradients, axial stiffness [N/m], preload [N] and whether recorded; the supports of the analysed
section; static contact-wire height per DOF [m]; each dropper's stretch per unit force at each column
[m/N]; for each row, its place among the rows a nonlinear force can reach (−1 if none), and their
list; whether a row is a support of the analysed section."""

SCALARS = (
    "rayleigh_alpha", "rayleigh_beta", "time_step", "hht_alpha", "newmark_beta", "newmark_gamma", "tolerance",
    "max_iterations", "friction_velocity",
)
"""The kernel's ``scalars`` array: α_R [1/s], β_R [s], Δt [s], HHT α, Newmark β and γ, Newton tolerance,
iteration limit, friction regularisation velocity [m/s]."""

STATUS_RUNNING = -1
STATUS_OK = 0
STATUS_NOT_CONVERGED = 1
STATUS_NOT_FINITE = 2


@njit(cache=True)
def band_matvec(band, x, out, runs):
    """out[:, :runs] = A x[:, :runs]; A symmetric, stored by its lower band, band[j, k] = A[j + k, j].

    Row by row (each output row written once, its inputs read from a window of 2·bw + 1 rows that
    stays in cache), the runs innermost.
    """
    n, width = band.shape
    bw = width - 1
    acc = np.empty(runs)
    for j in range(n):
        d = band[j, 0]
        for b in range(runs):
            acc[b] = d * x[j, b]
        for k in range(1, min(bw, n - 1 - j) + 1):
            value = band[j, k]
            for b in range(runs):
                acc[b] += value * x[j + k, b]
        for k in range(1, min(bw, j) + 1):
            value = band[j - k, k]
            for b in range(runs):
                acc[b] += value * x[j - k, b]
        for b in range(runs):
            out[j, b] = acc[b]


@njit(cache=True)
def band_cholesky_solve(factor, x, runs):
    """Solve L Lᵀ y = x in place for the first ``runs`` columns; factor[j, k] = L[j + k, j].

    Forward and backward substitution in dot-product form (each row finished in one pass over the
    bw rows before or after it), the runs innermost.
    """
    n, width = factor.shape
    bw = width - 1
    acc = np.empty(runs)
    for j in range(n):
        for b in range(runs):
            acc[b] = x[j, b]
        for k in range(1, min(bw, j) + 1):
            value = factor[j - k, k]
            for b in range(runs):
                acc[b] -= value * x[j - k, b]
        d = factor[j, 0]
        for b in range(runs):
            x[j, b] = acc[b] / d
    for j in range(n - 1, -1, -1):
        for b in range(runs):
            acc[b] = x[j, b]
        for k in range(1, min(bw, n - 1 - j) + 1):
            value = factor[j, k]
            for b in range(runs):
                acc[b] -= value * x[j + k, b]
        d = factor[j, 0]
        for b in range(runs):
            x[j, b] = acc[b] / d


@njit(cache=True)
def _influence(j, m, n, column_of, columns, pantograph_inverse):
    """Entry (j, m) of K_eff⁻¹ on the extended DOFs. [m/N]"""
    if j < n and m < n:
        return columns[column_of[m], j]
    if j >= n and m >= n:
        return pantograph_inverse[j - n, m - n]
    return 0.0


@njit(cache=True)
def _enter(dof, set_dofs, set_force, tangent, position, count):
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
def _evaluate(b, step, a1, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared, runs, scratch):
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
        q1, count = _enter(n1, set_dofs, set_force, tangent, position, count)
        q2, count = _enter(n2, set_dofs, set_force, tangent, position, count)
        qh, count = _enter(head, set_dofs, set_force, tangent, position, count)
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
        qu, count = _enter(upper, set_dofs, set_force, tangent, position, count)
        set_force[qu] += force
        tangent[qu, qu] += slope
        if lower >= 0:
            ql, count = _enter(lower, set_dofs, set_force, tangent, position, count)
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
                q[c], count = _enter(dropper_dofs[d, c], set_dofs, set_force, tangent, position, count)
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
def initialise(scalars, shared, runs, state, out, scratch):
    """The static contact state at rest (t = 0), its records, and the predictors of step 1.

    r = K u + f_nl(u, 0) on the catenary and the pantographs, as the integrator's initial state;
    the contact forces, slack droppers and support uplifts of the first record. At rest the
    predictors of step 1 are ũ = u, ṽ = 0 (see :func:`advance` for what the arrays hold).
    """
    rayleigh_beta, hht_alpha, friction_velocity = scalars[1], scalars[3], scalars[8]
    stiffness_band, mass, pantograph_stiffness = shared[0], shared[2], shared[5]
    head_dof, dropper_dofs, dropper_gradient, support_dofs = shared[9], shared[13], shared[14], shared[18]
    u, v, q, r, pantograph_u, _, _, pantograph_r = state
    contact_force, uplift_max, slack_max, status, _, _, iterations = out
    set_dofs, set_force, position, contact_now = scratch[0], scratch[1], scratch[3], scratch[4]
    u_of, v_of, stretch, rate = scratch[6], scratch[7], scratch[8], scratch[9]
    n = mass.shape[0]
    n_p = pantograph_stiffness.shape[0]
    n_runs = u.shape[1]
    band_matvec(stiffness_band, u, r, n_runs)
    rate[:] = 0.0
    v_of[:] = 0.0
    for b in range(n_runs):
        for i in range(n_p):
            acc = 0.0
            for k in range(n_p):
                acc += pantograph_stiffness[i, k] * pantograph_u[k, b]
            pantograph_r[i, b] = acc
            u_of[n + i] = pantograph_u[i, b]
        for j in range(n):
            u_of[j] = u[j, b]
        for d in range(dropper_dofs.shape[0]):
            acc = 0.0
            for c in range(6):
                acc += dropper_gradient[d, c] * u[dropper_dofs[d, c], b]
            stretch[d] = acc
        count, slack = _evaluate(b, 0, 0.0, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared,
                                 runs, scratch)
        for i in range(count):
            j = set_dofs[i]
            position[j] = -1
            if j < n:
                r[j, b] += set_force[i]
            else:
                pantograph_r[j - n, b] += set_force[i]
        for p in range(head_dof.shape[0]):
            contact_force[b, p, 0] = contact_now[p]
        slack_max[b] = slack
        uplift_max[b] = -np.inf
        for i in range(support_dofs.shape[0]):
            uplift_max[b] = max(uplift_max[b], u[support_dofs[i], b])
        status[b] = STATUS_RUNNING
        iterations[b] = 0
    for j in range(n):
        for b in range(n_runs):
            v[j, b] = 0.0
            q[j, b] = u[j, b]
            r[j, b] = hht_alpha * r[j, b]


@njit(cache=True)
def advance(first_step, last_step, scalars, shared, runs, state, out, work, scratch):
    """Advance every running run from record ``first_step − 1`` to record ``last_step``.

    Runs are sorted by step count, longest first, so the runs still going form a prefix of the
    batch; a run stops at its own last step or when its Newton iteration fails.

    Between steps the catenary arrays hold the next step's predictors: u = ũ, v = ṽ,
    q = ũ + β_R ṽ, and r = α r_n (the right-hand side; the uplift acts on the heads only). A step is
    three sweeps over the DOFs, each reading the arrays once: (1) C ṽ + K ũ = α_R M ṽ + K q, g =
    rhs − s (C ṽ + K ũ) and the forward substitution of K_eff δ_lin = g; (2) the backward
    substitution; then each run's Newton iteration on its few nonlinear DOFs; (3) δ = δ_lin − s Z φ,
    the new state (u, a, v and r_(n+1) = (rhs + R − M a)/s) and from it the next step's predictors.
    The step's force scale and residual at the predictor are collected in sweep (1) over the rows
    no nonlinear force can reach, and completed run by run on the others (:func:`_newton`).
    """
    rayleigh_alpha, rayleigh_beta, dt, hht_alpha, newmark_beta, newmark_gamma = scalars[:6]
    stiffness_band, factor_band, mass, columns = shared[0], shared[1], shared[2], shared[8]
    candidate_index, support_row = shared[21], shared[23]
    n_steps = runs[0]
    u, v, q, r = state[0], state[1], state[2], state[3]
    uplift_max, status = out[1], out[3]
    delta, g, linear, scale, first_residual = work[0], work[1], work[2], work[3], work[4]
    phi_count, phi_column, phi_coefficient = work[5], work[6], work[7]
    n, width = factor_band.shape
    bw = width - 1
    n_runs = u.shape[1]
    s = 1.0 + hht_alpha
    a0 = 1.0 / (newmark_beta * dt * dt)
    c_v = dt * (1.0 - newmark_gamma)
    c_a = dt * dt * (0.5 - newmark_beta)
    c_g = newmark_gamma * dt
    acc = np.empty(n_runs)
    for step in range(first_step, last_step + 1):
        active = 0
        for b in range(n_runs):
            if n_steps[b] >= step and status[b] == STATUS_RUNNING:
                active = b + 1
        if active == 0:
            break
        for b in range(active):
            scale[b] = 0.0
            first_residual[b] = 0.0
        # Sweep 1: C ṽ + K ũ row by row from the window of q, g, and the forward substitution.
        for j in range(n):
            d = stiffness_band[j, 0]
            m = rayleigh_alpha * mass[j]
            for b in range(active):
                acc[b] = d * q[j, b] + m * v[j, b]
            for k in range(1, min(bw, n - 1 - j) + 1):
                value = stiffness_band[j, k]
                for b in range(active):
                    acc[b] += value * q[j + k, b]
            for k in range(1, min(bw, j) + 1):
                value = stiffness_band[j - k, k]
                for b in range(active):
                    acc[b] += value * q[j - k, b]
            c = candidate_index[j]
            if c >= 0:
                for b in range(active):
                    lin = acc[b]
                    gj = r[j, b] - s * lin
                    linear[c, b] = lin
                    g[c, b] = gj
                    acc[b] = gj
            else:
                for b in range(active):
                    lin = acc[b]
                    gj = r[j, b] - s * lin
                    scale[b] = max(scale[b], abs(s * lin), abs(r[j, b]))
                    first_residual[b] = max(first_residual[b], abs(gj))
                    acc[b] = gj
            for k in range(1, min(bw, j) + 1):
                value = factor_band[j - k, k]
                for b in range(active):
                    acc[b] -= value * delta[j - k, b]
            d = factor_band[j, 0]
            for b in range(active):
                delta[j, b] = acc[b] / d
        # Sweep 2: backward substitution.
        for j in range(n - 1, -1, -1):
            for b in range(active):
                acc[b] = delta[j, b]
            for k in range(1, min(bw, n - 1 - j) + 1):
                value = factor_band[j, k]
                for b in range(active):
                    acc[b] -= value * delta[j + k, b]
            d = factor_band[j, 0]
            for b in range(active):
                delta[j, b] = acc[b] / d
        for b in range(active):
            phi_count[b] = 0
            if status[b] == STATUS_RUNNING and n_steps[b] >= step:
                _newton(b, step, scalars, shared, runs, state, out, work, scratch)
        # Sweep 3: the converged state, the support uplift, and the next step's predictors.
        for j in range(n):
            for b in range(active):
                for k in range(phi_count[b]):
                    delta[j, b] -= phi_coefficient[b, k] * columns[phi_column[b, k], j]
            m = mass[j]
            for b in range(active):
                dj = delta[j, b]
                aj = a0 * dj
                uj = u[j, b] + dj
                vj = v[j, b] + c_g * aj
                rj = (r[j, b] - m * aj) / s
                up = uj + dt * vj + c_a * aj
                vp = vj + c_v * aj
                delta[j, b] = uj  # u_(n+1), kept for the support records below
                u[j, b] = up
                v[j, b] = vp
                q[j, b] = up + rayleigh_beta * vp
                r[j, b] = hht_alpha * rj
            if support_row[j]:
                for b in range(active):
                    if status[b] == STATUS_RUNNING and n_steps[b] >= step:
                        uplift_max[b] = max(uplift_max[b], delta[j, b])
        for b in range(active):
            if status[b] == STATUS_RUNNING and n_steps[b] == step:
                status[b] = STATUS_OK


@njit(cache=True)
def _newton(b, step, scalars, shared, runs, state, out, work, scratch):
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

    count, slack = _evaluate(b, step, a1, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared,
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
                acc -= s * _influence(j, set_dofs[k], n, column_of, columns, pantograph_inverse) * set_force[k]
            if taken > 0:
                current = lin
                for k in range(n_phi):
                    current -= s * _influence(j, phi_dofs[k], n, column_of, columns, pantograph_inverse) * phi[k]
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
                        capacitance[i, m] += t * _influence(set_dofs[k], set_dofs[m], n, column_of, columns,
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
                    dj -= s * _influence(j, phi_dofs[k], n, column_of, columns, pantograph_inverse) * phi[k]
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
        count, slack = _evaluate(b, step, a1, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared,
                                 runs, scratch)
        for k in range(n_phi):
            q, count = _enter(phi_dofs[k], set_dofs, set_force, tangent, position, count)
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
        _linear_column(b, scalars, shared, state, delta)
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
def _linear_column(b, scalars, shared, state, out):
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


def make_work(shared, n_runs):
    """Per-step work arrays of a batch: δ (n, runs); C ṽ + K ũ and g on the candidate rows; force
    scale and residual at the predictor; φ (count, columns, s φ)."""
    n = shared[2].shape[0]
    n_candidates = shared[22].shape[0]
    size = 3 * shared[9].shape[0] + 2 * shared[3].shape[0] + 6 * shared[16].shape[0] + 1
    return (
        np.zeros((n, n_runs)), np.zeros((n_candidates, n_runs)), np.zeros((n_candidates, n_runs)),
        np.zeros(n_runs), np.zeros(n_runs),
        np.zeros(n_runs, dtype=np.int64), np.zeros((n_runs, size), dtype=np.int64), np.zeros((n_runs, size)),
    )
