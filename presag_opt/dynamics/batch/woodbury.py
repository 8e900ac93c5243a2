"""The batch kernel's Woodbury correction of one run's Newton iterate (numba).

Every Newton iterate of a batch run is δ = δ_lin − s Z φ: δ_lin = K_eff⁻¹ g from the sweeps, Z the
cached columns of K_eff⁻¹ at the DOFs a nonlinear force can reach (:func:`influence`), and φ a short
vector on the nonlinear set. A correction from the iterate δ (0 at the predictor) is Woodbury's
identity on that set S: the target x_S = (δ_lin − s Z f)_S − δ_S (:func:`woodbury_target`), the small
system y = (I + s T Z_SS)⁻¹ s T x_S, and the new φ = f + y/s (:func:`woodbury_correction`).

It is the correction of the single-run integrator
(:meth:`presag_opt.dynamics.step_solvers.FactorisedSolver.correction`, whose Woodbury step is
:func:`presag_opt.static.woodbury.woodbury_update`) written for φ instead of the full δ, and it is
not that function compiled, for three reasons: the batch never forms δ on all DOFs (sweep 3 of
:mod:`presag_opt.dynamics.batch.kernel` does, for all runs at once), it reads Z entry by entry from the
cached columns instead of gathering a dense Z_SS, and it forms s T Z_SS by loops over the nonzero
tangent entries in a fixed order, where the integrator's matrix products go through BLAS. The loops
make every run's arithmetic the same IEEE operations whatever the lanes (C and numba sweeps equal to
the last bit); calling the NumPy function would round differently, and allocate, in every
iteration. The two stay equal to round-off (``tests/dynamics/batch/test_simulation.py`` holds the batch to the
single-run path).

References
----------
W. W. Hager, "Updating the inverse of a matrix", SIAM Review 31 (1989) 221–239,
doi:10.1137/1031049 (Woodbury identity).
"""

from __future__ import annotations

import numpy as np

from presag_opt.native.jit import kernel_part
from presag_opt.native.lapack import solve_by_columns


@kernel_part
def influence(j, m, n, column_of, columns, pantograph_inverse):
    """Entry (j, m) of K_eff⁻¹ on the extended DOFs (catenary and pantographs are uncoupled in
    K_eff: 0 between them). [m/N]

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


@kernel_part
def woodbury_target(b, s, count, n_phi, taken, shared, work, scratch, pan):
    """x_S = (δ_lin − s Z f)_S − δ_S on the set, with δ = δ_lin − s Z φ the current iterate (δ = 0
    before the first correction), into ``scratch.target``. [m]

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
    pan : PantographStep
        Run ``b``'s pantograph predictors (its δ_lin).
    shared, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    column_of, columns, pantograph_inverse = shared.column_of, shared.columns, shared.pantograph_inverse
    set_dofs, set_force, phi_dofs, phi = scratch.set_dofs, scratch.set_force, scratch.phi_dofs, scratch.phi
    delta, delta_lin = work.delta, pan.delta_lin
    n = shared.mass.shape[0]
    x = scratch.target
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


@kernel_part
def woodbury_correction(b, s, count, n_phi, taken, shared, work, scratch, pan):
    """The Woodbury correction from the current iterate: y = (I + s T Z_SS)⁻¹ s T x_S with x_S of
    :func:`woodbury_target`; the new δ = δ_lin − s Z φ with φ = f + y/s, left in ``scratch.phi``
    (its DOFs in ``scratch.phi_dofs``; the set's positions cleared); ``work.delta`` holds δ_lin.
    Returns the size of φ.

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
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    shared, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    column_of, columns, pantograph_inverse = shared.column_of, shared.columns, shared.pantograph_inverse
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    phi_dofs, phi = scratch.phi_dofs, scratch.phi
    n = shared.mass.shape[0]
    woodbury_target(b, s, count, n_phi, taken, shared, work, scratch, pan)
    x, y = scratch.target, scratch.correction
    # I + ..., by columns as LAPACK takes it: capacitance[m, i] is entry (i, m)
    capacitance = scratch.capacitance[:count * count].reshape((count, count))
    capacitance[:, :] = 0.0
    for i in range(count):
        capacitance[i, i] = 1.0
    y[:count] = 0.0
    for i in range(count):
        for k in range(count):
            t = s * tangent[i, k]
            if t != 0.0:
                y[i] += t * x[k]
                for m in range(count):
                    capacitance[m, i] += t * influence(set_dofs[k], set_dofs[m], n, column_of, columns,
                                                       pantograph_inverse)
    if solve_by_columns(capacitance, y[:count], scratch.pivots, scratch.lapack_integers) != 0:
        y[:count] = np.nan  # singular: the run stops on its non-finite residual
    for i in range(count):
        phi_dofs[i] = set_dofs[i]
        phi[i] = set_force[i] + y[i] / s
        position[set_dofs[i]] = -1
    return count
