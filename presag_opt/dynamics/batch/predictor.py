"""The start of one batch run's Newton step: its pantographs, droppers and residual at the predictor (numba).

Once the sweeps of :mod:`presag_opt.dynamics.batch.kernel` have formed every run's linear solution
δ_lin on the catenary, :func:`~presag_opt.dynamics.batch.newton_step.newton_step` starts each run's
step here: the pantographs' predictors, right-hand side and δ_lin (:func:`pantograph_predictor`), the
droppers' stretch at the predictor and the stretch δ_lin adds, with the contact nodes and pantograph
DOFs at the predictor (:func:`predictor_state`), and the integrator's force scale and largest
residual there (:func:`residual_at_predictor`). The arrays are the named tuples of
:mod:`presag_opt.dynamics.batch.kernel_data`; the first two fill the run's
:class:`~presag_opt.dynamics.batch.kernel_data.PantographStep` and
:class:`~presag_opt.dynamics.batch.kernel_data.DropperStep` in its scratch arrays.
"""

from __future__ import annotations

from presag_opt.dynamics import assembly
from presag_opt.native.jit import kernel_part

newmark_predictor = kernel_part(assembly.newmark_predictor)


@kernel_part
def pantograph_predictor(b, scalars, shared, runs, state, scratch):
    """Run ``b``'s pantograph predictors, right-hand side (uplift on the heads), C ṽ + K ũ, g and
    δ_lin, into ``scratch.pantograph`` (a
    :class:`~presag_opt.dynamics.batch.kernel_data.PantographStep`).

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    scalars, shared, runs, state, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    c = scalars.scheme
    head_dof, damping, stiffness, inverse = (shared.head_dof, shared.pantograph_damping, shared.pantograph_stiffness,
                                             shared.pantograph_inverse)
    pantograph_u, pv, pa, pantograph_r = state.pantograph_u, state.pantograph_v, state.pantograph_a, state.pantograph_r
    n = shared.mass.shape[0]
    n_p = shared.pantograph_mass.shape[0]
    u_pred, v_pred, rhs, linear, g, delta_lin = scratch.pantograph
    for i in range(n_p):
        u_pred[i], v_pred[i] = newmark_predictor(pantograph_u[i, b], pv[i, b], pa[i, b], c)
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


@kernel_part
def predictor_state(b, step, shared, runs, state, work, scratch, pan):
    """Run ``b``'s droppers at the predictor (into ``scratch.droppers``, a
    :class:`~presag_opt.dynamics.batch.kernel_data.DropperStep`; ``scratch.stretch`` and ``.rate``
    set too) and its contact nodes and pantograph DOFs at the predictor in ``scratch``.

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    shared, runs, state, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    dropper_dofs, dropper_gradient, path_nodes = shared.dropper_dofs, shared.dropper_gradient, runs.path_nodes
    u_pred, v_pred, delta = state.u, state.v, work.delta
    u_of, v_of, stretch, rate = scratch.u_of, scratch.v_of, scratch.stretch, scratch.rate
    n = shared.mass.shape[0]
    n_d = dropper_dofs.shape[0]
    base_stretch, base_rate, linear_stretch = scratch.droppers
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


@kernel_part
def residual_at_predictor(b, s, shared, state, work, scratch, pan):
    """The integrator's force scale and largest residual at the predictor of run ``b`` [N], the
    sweep's values completed on the rows the nonlinear forces can reach.

    Parameters
    ----------
    b : int
        Run, the column of the batch arrays. [-]
    s : float
        1 + α of the HHT-α scheme. [-]
    pan : PantographStep
        Run ``b``'s pantograph predictors (``pantograph_predictor``).
    shared, state, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    set_force, position, candidate_rows = scratch.set_force, scratch.position, shared.candidate_rows
    linear, g, rhs = work.linear, work.g, state.r
    n = shared.mass.shape[0]
    largest_term = work.scale[b]
    largest = work.first_residual[b]
    for i in range(candidate_rows.shape[0]):
        j = candidate_rows[i]
        f0 = set_force[position[j]] if position[j] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (linear[j, b] + f0)), abs(rhs[j, b]))
        largest = max(largest, abs(s * f0 - g[i, b]))
    p_linear, p_rhs, p_g = pan.linear, pan.rhs, pan.g
    for i in range(p_linear.shape[0]):
        f0 = set_force[position[n + i]] if position[n + i] >= 0 else 0.0
        largest_term = max(largest_term, abs(s * (p_linear[i] + f0)), abs(p_rhs[i]))
        largest = max(largest, abs(s * f0 - p_g[i]))
    return largest_term, largest
