"""Compiled time stepping of many runs on one catenary (numba), the batch index innermost.

The sweeps over all DOFs live here; each run's Newton iteration on its nonlinear DOFs is
:mod:`presag_opt.dynamics.batch_newton`'s.

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

from presag_opt.dynamics.batch_newton import (
    STATUS_OK,
    STATUS_RUNNING,
    newton_step,
    nonlinear_forces,
)
from presag_opt.native.banded_numba import backward_substitution

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
    n_runs = runs[0].shape[0]
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
        count, slack = nonlinear_forces(b, 0, 0.0, rayleigh_beta, friction_velocity, u_of, v_of, stretch, rate, shared,
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
    rhs − s (C ṽ + K ũ) and the forward substitution of K_eff δ_lin = g (:func:`forward_sweep`);
    (2) the backward substitution; then each run's Newton iteration on its few nonlinear DOFs;
    (3) δ = δ_lin − s Z φ, the new state (u, a, v and r_(n+1) = (rhs + R − M a)/s) and from it the
    next step's predictors (:func:`update_sweep`). The step's force scale and residual at the
    predictor are collected in sweep (1) over the rows no nonlinear force can reach, and completed
    run by run on the others (:func:`~presag_opt.dynamics.batch_newton.newton_step`).
    :func:`presag_opt.dynamics.native_sweeps.advance` is this loop with the sweeps in compiled C.
    """
    factor_band = shared[1]
    delta = work[0]
    for step in range(first_step, last_step + 1):
        active = start_step(step, runs, out, work)
        if active == 0:
            break
        forward_sweep(scalars, shared, state, work, active)
        backward_substitution(factor_band, delta, active)
        newton_steps(step, active, scalars, shared, runs, state, out, work, scratch)
        update_sweep(step, scalars, shared, runs, state, out, work, active)
        finish_step(step, active, runs, out)


@njit(cache=True)
def start_step(step, runs, out, work):
    """The number of leading runs the step must sweep (0: all have stopped), their force scale and
    residual at the predictor reset."""
    n_steps, status = runs[0], out[3]
    scale, first_residual = work[3], work[4]
    active = 0
    for b in range(n_steps.shape[0]):
        if n_steps[b] >= step and status[b] == STATUS_RUNNING:
            active = b + 1
    for b in range(active):
        scale[b] = 0.0
        first_residual[b] = 0.0
    return active


@njit(cache=True)
def newton_steps(step, active, scalars, shared, runs, state, out, work, scratch):
    """Each running run's Newton iteration on its nonlinear DOFs (no φ for the others)."""
    n_steps, status, phi_count = runs[0], out[3], work[5]
    for b in range(active):
        phi_count[b] = 0
        if status[b] == STATUS_RUNNING and n_steps[b] >= step:
            newton_step(b, step, scalars, shared, runs, state, out, work, scratch)


@njit(cache=True)
def finish_step(step, active, runs, out):
    """Mark the runs whose last step this was as finished."""
    n_steps, status = runs[0], out[3]
    for b in range(active):
        if status[b] == STATUS_RUNNING and n_steps[b] == step:
            status[b] = STATUS_OK


@njit(cache=True)
def forward_sweep(scalars, shared, state, work, active):
    """Sweep 1 of a step for the first ``active`` runs: C ṽ + K ũ row by row from the window of q,
    g = rhs − s (C ṽ + K ũ) (kept on the candidate rows), the force scale and residual at the
    predictor on the other rows, and the forward substitution of K_eff δ_lin = g."""
    rayleigh_alpha, hht_alpha = scalars[0], scalars[3]
    stiffness_band, factor_band, mass, candidate_index = shared[0], shared[1], shared[2], shared[21]
    v, q, r = state[1], state[2], state[3]
    delta, g, linear, scale, first_residual = work[0], work[1], work[2], work[3], work[4]
    n, width = factor_band.shape
    bw = width - 1
    s = 1.0 + hht_alpha
    acc = np.empty(active)
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


@njit(cache=True)
def update_constants(scalars):
    """The constants of the state update: s = 1 + α, a0 = 1/(β Δt²) [1/s²], Δt (1 − γ) [s],
    Δt² (1/2 − β) [s²] and γ Δt [s]."""
    dt, hht_alpha, newmark_beta, newmark_gamma = scalars[2], scalars[3], scalars[4], scalars[5]
    return (1.0 + hht_alpha, 1.0 / (newmark_beta * dt * dt), dt * (1.0 - newmark_gamma),
            dt * dt * (0.5 - newmark_beta), newmark_gamma * dt)


@njit(cache=True)
def update_sweep(step, scalars, shared, runs, state, out, work, active):
    """Sweep 3 of a step for the first ``active`` runs: δ = δ_lin − s Z φ, the converged state, the
    support uplift of the runs still going, and the next step's predictors."""
    rayleigh_beta, dt, hht_alpha = scalars[1], scalars[2], scalars[3]
    mass, columns, support_row = shared[2], shared[8], shared[23]
    n_steps = runs[0]
    u, v, q, r = state[0], state[1], state[2], state[3]
    uplift_max, status = out[1], out[3]
    delta, phi_count, phi_column, phi_coefficient = work[0], work[5], work[6], work[7]
    n = mass.shape[0]
    s, a0, c_v, c_a, c_g = update_constants(scalars)
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


def make_work(shared, n_runs, lanes=None):
    """Per-step work arrays of a batch: δ (n, lanes); C ṽ + K ũ and g on the candidate rows; force
    scale and residual at the predictor; φ (count, columns, s φ). ``lanes`` (default ``n_runs``) is
    the run dimension of the arrays the sweeps read, padded for the compiled sweeps."""
    lanes = n_runs if lanes is None else lanes
    n = shared[2].shape[0]
    n_candidates = shared[22].shape[0]
    size = 3 * shared[9].shape[0] + 2 * shared[3].shape[0] + 6 * shared[16].shape[0] + 1
    return (
        np.zeros((n, lanes)), np.zeros((n_candidates, lanes)), np.zeros((n_candidates, lanes)),
        np.zeros(lanes), np.zeros(lanes),
        np.zeros(n_runs, dtype=np.int64), np.zeros((n_runs, size), dtype=np.int64), np.zeros((n_runs, size)),
    )
