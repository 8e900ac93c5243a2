"""Compiled time stepping of many runs on one catenary (numba), the batch index innermost.

The sweeps over all DOFs live here; each run's Newton iteration on its nonlinear DOFs is
:mod:`presag_opt.dynamics.batch.newton_step`'s (its parts: ``predictor``, ``forces``,
``woodbury``, ``update``).

This module holds the arithmetic of :func:`presag_opt.dynamics.batch.simulate_many`: banded
products and solves on arrays of shape (n_dofs, n_runs), over the bands' nonzero entries
(:mod:`presag_opt.dynamics.batch.band_rows`), and the HHT-α step of every run. Setting up
(matrices, orderings, contact paths, initial states) and the statistics are left to
:mod:`presag_opt.dynamics.batch.system` and :mod:`presag_opt.dynamics.batch.simulation`.

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

from presag_opt.dynamics.batch.forces import nonlinear_forces
from presag_opt.dynamics.batch.kernel_data import STATUS_OK, STATUS_RUNNING
from presag_opt.dynamics.batch.newton_step import newton_step
from presag_opt.dynamics.batch.predictor import newmark_predictor
from presag_opt.dynamics.batch.update import newmark_update
from presag_opt.native import sweeps as native
from presag_opt.native.jit import kernel_function, kernel_part, shared_kernel_function


@kernel_function
def band_matvec(band, rows, x, out, runs):
    """out[:, :runs] = A x[:, :runs]; A symmetric, its diagonal ``band[:, 0]`` and its off-diagonal
    nonzeros ``rows`` (:func:`~presag_opt.dynamics.batch.band_rows.symmetric_rows`).

    Row by row (each output row written once, its inputs read from a window of 2·bw + 1 rows that
    stays in cache), the runs innermost.

    Parameters
    ----------
    band : ndarray, shape (n, bw + 1)
        Lower band of the symmetric matrix A, by rows. [N/m]
    rows : BandRows
        A's off-diagonal nonzeros by rows. [N/m]
    x : ndarray, shape (n, n_runs)
        Vectors to multiply, one per column. [m]
    out : ndarray, shape (n, n_runs)
        Array receiving A x. [N]
    runs : int
        Number of leading columns to multiply. [-]
    """
    acc = np.empty(runs)
    for j in range(band.shape[0]):
        d = band[j, 0]
        for b in range(runs):
            acc[b] = d * x[j, b]
        add_row_product(j, rows, x, acc, runs, 1.0)
        for b in range(runs):
            out[j, b] = acc[b]


@kernel_part
def add_row_product(j, rows, x, acc, active, sign):
    """acc[:active] += Σ (sign · value) · x[column, :active] over row j's off-diagonal entries of
    ``rows``, in their order: the one band × vector of the kernel (:func:`band_matvec`, sweep 1's
    C ṽ + K ũ with sign 1, the substitutions' rows with sign −1: acc + (−v) x rounds as acc − v x).

    Parameters
    ----------
    j : int
        Row. [-]
    rows : BandRows
        The matrix's off-diagonal nonzeros by rows. [unit of the matrix]
    x : ndarray, shape (n, n_runs)
        The vectors, one per column. [unit of x]
    acc : ndarray, shape (active,)
        Row j's accumulator. [unit of the matrix · unit of x]
    active : int
        Number of leading columns. [-]
    sign : float
        1 or −1. [-]
    """
    start, column, value = rows
    for e in range(start[j], start[j + 1]):
        entry, i = sign * value[e], column[e]
        for b in range(active):
            acc[b] += entry * x[i, b]


@kernel_function
def initialise(scalars, shared, runs, state, out, scratch):
    """The static contact state at rest (t = 0), its records, and the predictors of step 1.

    r = K u + f_nl(u, 0) on the catenary and the pantographs, as the integrator's initial state;
    the contact forces, slack droppers and support uplifts of the first record. At rest the
    predictors of step 1 are ũ = u, ṽ = 0 (see :func:`advance` for what the arrays hold).

    Parameters
    ----------
    scalars, shared, runs, state, out, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    sh, sc = shared, scratch
    u, v, q, r = state.u, state.v, state.q, state.r
    n = sh.mass.shape[0]
    n_p = sh.pantograph_stiffness.shape[0]
    n_runs = runs.n_steps.shape[0]
    band_matvec(sh.stiffness_band, sh.stiffness_rows, u, r, n_runs)
    sc.rate[:] = 0.0
    sc.v_of[:] = 0.0
    for b in range(n_runs):
        for i in range(n_p):
            acc = 0.0
            for k in range(n_p):
                acc += sh.pantograph_stiffness[i, k] * state.pantograph_u[k, b]
            state.pantograph_r[i, b] = acc
            sc.u_of[n + i] = state.pantograph_u[i, b]
        for j in range(n):
            sc.u_of[j] = u[j, b]
        for d in range(sh.dropper_dofs.shape[0]):
            acc = 0.0
            for c in range(6):
                acc += sh.dropper_gradient[d, c] * u[sh.dropper_dofs[d, c], b]
            sc.stretch[d] = acc
        count, slack = nonlinear_forces(b, 0, 0.0, scalars, shared, runs, scratch)
        for i in range(count):
            j = sc.set_dofs[i]
            sc.position[j] = -1
            if j < n:
                r[j, b] += sc.set_force[i]
            else:
                state.pantograph_r[j - n, b] += sc.set_force[i]
        for p in range(sh.head_dof.shape[0]):
            out.contact_force[b, p, 0] = sc.contact_now[p]
        out.slack_max[b] = slack
        out.uplift_max[b] = -np.inf
        for i in range(sh.support_dofs.shape[0]):
            out.uplift_max[b] = max(out.uplift_max[b], u[sh.support_dofs[i], b])
        out.status[b] = STATUS_RUNNING
        out.iterations[b] = 0
    for j in range(n):
        for b in range(n_runs):
            v[j, b] = 0.0
            q[j, b] = u[j, b]
            r[j, b] = scalars.scheme.alpha * r[j, b]


@kernel_function
def advance(first_step, last_step, c_sweeps, scalars, shared, runs, state, out, work, scratch):
    """Advance every running run from record ``first_step − 1`` to record ``last_step``.

    Runs are sorted by step count, longest first, so the runs still going form a prefix of the
    batch; a run stops at its own last step or when its Newton iteration fails.

    Between steps the catenary arrays hold the next step's predictors: u = ũ, v = ṽ,
    q = ũ + β_R ṽ, and r = α r_n (the right-hand side; the uplift acts on the heads only). A step is
    three sweeps over the DOFs, each reading the arrays once: (1) C ṽ + K ũ = α_R M ṽ + K q, g =
    rhs − s (C ṽ + K ũ) and the forward substitution of K_eff δ_lin = g (:func:`forward_sweep`);
    (2) the backward substitution (:func:`backward_sweep`); then each run's Newton iteration on its few nonlinear DOFs;
    (3) δ = δ_lin − s Z φ, the new state (u, a, v and r_(n+1) = (rhs + R − M a)/s) and from it the
    next step's predictors (:func:`update_sweep`). The step's force scale and residual at the
    predictor are collected in sweep (1) over the rows no nonlinear force can reach, and completed
    run by run on the others (:func:`~presag_opt.dynamics.batch.newton_step.newton_step`).

    The sweeps are numba's (below) or the same sweeps in compiled C, the function pointers
    ``c_sweeps`` (:func:`presag_opt.native.sweeps.sweeps`; same arguments, same numbers to the last
    bit; the catenary's run arrays padded to whole blocks of lanes). numba prunes the branch that
    ``c_sweeps`` (None or not) rules out before typing it: each kind of call compiles only its own
    sweeps.

    Parameters
    ----------
    first_step : int
        First record to compute (from 1). [-]
    last_step : int
        Last record to compute. [-]
    c_sweeps : CSweeps or None
        Function pointers of the compiled sweeps; None: numba's sweeps.
    scalars, shared, runs, state, out, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    for step in range(first_step, last_step + 1):
        active = start_step(step, runs, out, work)
        if active == 0:
            break
        if c_sweeps is None:
            forward_sweep(scalars, shared, state, work, active)
            backward_sweep(shared, work, active)
        else:
            native.forward_sweep(c_sweeps, scalars, shared, state, work, active)
            native.backward_sweep(c_sweeps, shared, work, active)
        newton_steps(step, active, scalars, shared, runs, state, out, work, scratch)
        if c_sweeps is None:
            update_sweep(step, scalars, shared, runs, state, out, work, active)
        else:
            native.update_sweep(c_sweeps, step, scalars, shared, runs, state, out, work, active)
        mark_finished_runs(step, active, runs, out)


@kernel_function
def start_step(step, runs, out, work):
    """The number of leading runs the step must sweep (0: all have stopped), their force scale and
    residual at the predictor reset.

    Parameters
    ----------
    step : int
        Record (time step) being computed. [-]
    runs, out, work : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    n_steps, status, scale, first_residual = runs.n_steps, out.status, work.scale, work.first_residual
    active = 0
    for b in range(n_steps.shape[0]):
        if n_steps[b] >= step and status[b] == STATUS_RUNNING:
            active = b + 1
    for b in range(active):
        scale[b] = 0.0
        first_residual[b] = 0.0
    return active


@shared_kernel_function
def newton_steps(step, active, scalars, shared, runs, state, out, work, scratch):
    """Each running run's Newton iteration on its nonlinear DOFs (no φ for the others).

    Parameters
    ----------
    step : int
        Record (time step) being computed. [-]
    active : int
        Number of leading runs (columns) the sweep covers. [-]
    scalars, shared, runs, state, out, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    n_steps, status, phi_count = runs.n_steps, out.status, work.phi_count
    for b in range(active):
        phi_count[b] = 0
        if status[b] == STATUS_RUNNING and n_steps[b] >= step:
            newton_step(b, step, scalars, shared, runs, state, out, work, scratch)


@kernel_function
def mark_finished_runs(step, active, runs, out):
    """Mark the runs whose last step this was as finished.

    Parameters
    ----------
    step : int
        Record (time step) being computed. [-]
    active : int
        Number of leading runs swept in the step. [-]
    runs, out : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    n_steps, status = runs.n_steps, out.status
    for b in range(active):
        if status[b] == STATUS_RUNNING and n_steps[b] == step:
            status[b] = STATUS_OK


@kernel_function
def forward_sweep(scalars, shared, state, work, active):
    """Sweep 1 of a step for the first ``active`` runs: C ṽ + K ũ row by row from the window of q
    (kept on every row), g = rhs − s (C ṽ + K ũ) (kept on the candidate rows), the force scale and residual at the
    predictor on the other rows, and the forward substitution of K_eff δ_lin = g.

    Parameters
    ----------
    active : int
        Number of leading runs (columns) the sweep covers. [-]
    scalars, shared, state, work : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    stiffness_band, factor_band, mass, candidate_index = (shared.stiffness_band, shared.factor_band, shared.mass,
                                                          shared.candidate_index)
    v, q, r = state.v, state.q, state.r
    delta, g, linear, scale, first_residual = work.delta, work.g, work.linear, work.scale, work.first_residual
    rayleigh_alpha, s = scalars.rayleigh_alpha, scalars.scheme.s
    acc = np.empty(active)
    for j in range(factor_band.shape[0]):
        d = stiffness_band[j, 0]
        m = rayleigh_alpha * mass[j]
        for b in range(active):
            acc[b] = d * q[j, b] + m * v[j, b]
        add_row_product(j, shared.stiffness_rows, q, acc, active, 1.0)
        for b in range(active):
            linear[j, b] = acc[b]
        c = candidate_index[j]
        if c >= 0:
            for b in range(active):
                gj = r[j, b] - s * acc[b]
                g[c, b] = gj
                acc[b] = gj
        else:
            for b in range(active):
                lin = acc[b]
                gj = r[j, b] - s * lin
                scale[b] = max(scale[b], abs(s * lin), abs(r[j, b]))
                first_residual[b] = max(first_residual[b], abs(gj))
                acc[b] = gj
        substitute_row(j, shared.lower_rows, factor_band[j, 0], delta, acc, active)


@kernel_part
def substitute_row(j, rows, pivot, x, acc, active):
    """One row of a triangular substitution: x[j, :active] = (acc − Σ value · x[column]) / pivot over
    row j's entries of ``rows``, in their order.

    Parameters
    ----------
    j : int
        Row. [-]
    rows : BandRows
        The triangle's off-diagonal nonzeros by rows. [sqrt(N/m)]
    pivot : float
        The diagonal entry of row j. [sqrt(N/m)]
    x : ndarray, shape (n, n_runs)
        The solution so far (the rows the entries reach are done), row j written. [m·sqrt(N/m) or m]
    acc : ndarray, shape (active,)
        Row j's right-hand side, used as the accumulator. [unit of x · pivot]
    active : int
        Number of leading columns. [-]
    """
    add_row_product(j, rows, x, acc, active, -1.0)
    for b in range(active):
        x[j, b] = acc[b] / pivot


@kernel_function
def backward_sweep(shared, work, active):
    """Sweep 2 of a step for the first ``active`` runs: the backward substitution Lᵀ δ_lin = y in
    place (``work.delta`` holds y = L⁻¹ g in, δ_lin out), over the nonzeros of Lᵀ (``shared.upper_rows``).

    Parameters
    ----------
    active : int
        Number of leading runs (columns) the sweep covers. [-]
    shared, work : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    factor_band, delta = shared.factor_band, work.delta
    acc = np.empty(active)
    for j in range(factor_band.shape[0] - 1, -1, -1):
        for b in range(active):
            acc[b] = delta[j, b]
        substitute_row(j, shared.upper_rows, factor_band[j, 0], delta, acc, active)


@kernel_function
def update_sweep(step, scalars, shared, runs, state, out, work, active):
    """Sweep 3 of a step for the first ``active`` runs: δ = δ_lin − s Z φ, the converged state, the
    support uplift of the runs still going, and the next step's predictors.

    Parameters
    ----------
    step : int
        Record (time step) being computed. [-]
    active : int
        Number of leading runs (columns) the sweep covers. [-]
    scalars, shared, runs, state, out, work : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    c = scalars.scheme
    s, hht_alpha, rayleigh_beta = c.s, c.alpha, scalars.rayleigh_beta
    mass, columns, support_row, n_steps = shared.mass, shared.columns, shared.support_row, runs.n_steps
    u, v, q, r = state.u, state.v, state.q, state.r
    uplift_max, status = out.uplift_max, out.status
    delta, phi_count, phi_column, phi_coefficient = work.delta, work.phi_count, work.phi_column, work.phi_coefficient
    n = mass.shape[0]
    for j in range(n):
        for b in range(active):
            for k in range(phi_count[b]):
                delta[j, b] -= phi_coefficient[b, k] * columns[phi_column[b, k], j]
        m = mass[j]
        for b in range(active):
            dj = delta[j, b]
            aj, vj = newmark_update(dj, v[j, b], c)
            uj = u[j, b] + dj
            rj = (r[j, b] - m * aj) / s
            up, vp = newmark_predictor(uj, vj, aj, c)
            delta[j, b] = uj  # u_(n+1), kept for the support records below
            u[j, b] = up
            v[j, b] = vp
            q[j, b] = up + rayleigh_beta * vp
            r[j, b] = hht_alpha * rj
        if support_row[j]:
            for b in range(active):
                if status[b] == STATUS_RUNNING and n_steps[b] >= step:
                    uplift_max[b] = max(uplift_max[b], delta[j, b])
