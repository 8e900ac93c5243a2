"""The batch kernel's nonlinear forces of one run: contact, pantograph friction and slack droppers (numba).

:func:`nonlinear_forces` gathers the forces and the Newton tangent ∂f/∂u + a1 ∂f/∂v of one run at
one iterate into a small dense set: the DOFs that carry a nonlinear force, in order of entry
(:func:`enter_set`), each with its force [N] and the set's tangent [N/m]. The three force sets, in
the order they enter: the penalty contact of every pantograph head with the two contact-wire nodes
under it (:func:`contact_set`), the regularised friction of every pantograph suspension element
(:func:`friction_set`), and every slack dropper, whose axial part is removed (:func:`dropper_set`).
The laws are those of :mod:`presag_opt.dynamics.laws`, and the penetration and each contribution's
force and tangent those of :mod:`presag_opt.dynamics.assembly`, compiled as kernel parts (the same functions
the single-run path calls plainly). The arrays are the named tuples of
:mod:`presag_opt.dynamics.batch.kernel_data`; the iteration that uses the set is
:mod:`presag_opt.dynamics.batch.newton_step`'s.
"""

from __future__ import annotations

from presag_opt.dynamics import assembly, laws
from presag_opt.native.jit import kernel_part

contact_stiffness = kernel_part(laws.contact_stiffness)
contact_force = kernel_part(laws.contact_force)
contact_tangent = kernel_part(laws.contact_tangent)
friction = kernel_part(laws.friction)
dropper_axial_force = kernel_part(laws.dropper_axial_force)
dropper_slack = kernel_part(laws.dropper_slack)
dropper_tension = kernel_part(laws.dropper_tension)
head_penetration = kernel_part(assembly.head_penetration)
force_contribution = kernel_part(assembly.force_contribution)


@kernel_part
def enter_set(dof, set_dofs, set_force, tangent, position, count):
    """Position of ``dof`` in the current nonlinear set, adding it (zero force and tangent) if new;
    returns (its position, the new set size).

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


@kernel_part
def add_piece(size, piece_dofs, piece_force, piece_tangent, set_force, tangent):
    """Add one contribution (:func:`~presag_opt.dynamics.assembly.force_contribution`) to the set:
    its forces [N] and tangent [N/m] at the set positions ``piece_dofs``, row by row.

    Parameters
    ----------
    size : int
        DOFs of the contribution. [-]
    piece_dofs : ndarray of int
        Their positions in the set. [-]
    piece_force : ndarray
        The contribution's forces. [N]
    piece_tangent : ndarray
        Its tangent. [N/m]
    set_force : ndarray
        The set's forces. [N]
    tangent : ndarray
        The set's dense tangent. [N/m]
    """
    for i in range(size):
        set_force[piece_dofs[i]] += piece_force[i]
        for j in range(size):
            tangent[piece_dofs[i], piece_dofs[j]] += piece_tangent[i, j]


@kernel_part
def contact_set(b, step, count, shared, runs, scratch):
    """Each head's penalty contact with the contact wire: the two wire nodes under the head and the
    head enter the set (in contact or not), the force and tangent where the head penetrates the
    wire's chord; each contact force [N] in ``scratch.contact_now``. Reads the displacements
    ``scratch.u_of`` [m]. Returns the set size.

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    count : int
        Size of the set before. [-]
    shared, runs, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    head_dof, penalty, cw_height = shared.head_dof, shared.contact_stiffness, runs.cw_height
    path_nodes, path_weights, path_compliance, head_height = (runs.path_nodes, runs.path_weights, runs.path_compliance,
                                                              runs.head_height)
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    contact_now, u_of = scratch.contact_now, scratch.u_of
    q, piece_force, piece_tangent = scratch.piece_dofs, scratch.piece_force, scratch.piece_tangent
    for p in range(head_dof.shape[0]):
        n1, n2 = path_nodes[b, p, step, 0], path_nodes[b, p, step, 1]
        w1, w2 = path_weights[b, p, step, 0], path_weights[b, p, step, 1]
        stiffness = contact_stiffness(penalty[p], path_compliance[b, p, step])
        head = head_dof[p]
        penetration = head_penetration(head_height[b, p], u_of[head], w1, cw_height[b, n1], u_of[n1], w2,
                                       cw_height[b, n2], u_of[n2])
        q[0], count = enter_set(n1, set_dofs, set_force, tangent, position, count)
        q[1], count = enter_set(n2, set_dofs, set_force, tangent, position, count)
        q[2], count = enter_set(head, set_dofs, set_force, tangent, position, count)
        force = contact_force(stiffness, penetration)
        k = contact_tangent(stiffness, penetration)
        contact_now[p] = force
        if k != 0.0:
            force_contribution(force, k, (-w1, -w2, 1.0), piece_force, piece_tangent)
            add_piece(3, q, piece_force, piece_tangent, set_force, tangent)
    return count


@kernel_part
def friction_set(a1, count, scalars, shared, scratch):
    """Each suspension element's regularised friction, on its upper stage and, but for the lowest
    (on the car body), the stage below. Reads the velocities ``scratch.v_of`` [m/s]. Returns the set
    size.

    Parameters
    ----------
    a1 : float
        Velocity coefficient of the scheme (∂v/∂u within the step; 0 at rest). [1/s]
    count : int
        Size of the set before. [-]
    scalars, shared, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    friction_dofs, friction_levels, friction_velocity = (shared.friction_dofs, shared.friction_levels,
                                                         scalars.friction_velocity)
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    v_of = scratch.v_of
    q, piece_force, piece_tangent = scratch.piece_dofs, scratch.piece_force, scratch.piece_tangent
    for e in range(friction_levels.shape[0]):
        upper, lower = friction_dofs[e, 0], friction_dofs[e, 1]
        relative = v_of[upper] - (v_of[lower] if lower >= 0 else 0.0)
        force, slope = friction(friction_levels[e], relative, friction_velocity, a1)
        q[0], count = enter_set(upper, set_dofs, set_force, tangent, position, count)
        if lower >= 0:
            q[1], count = enter_set(lower, set_dofs, set_force, tangent, position, count)
            force_contribution(force, slope, (1.0, -1.0), piece_force, piece_tangent)
            size = 2
        else:
            force_contribution(force, slope, (1.0,), piece_force, piece_tangent)
            size = 1
        add_piece(size, q, piece_force, piece_tangent, set_force, tangent)
    return count


@kernel_part
def dropper_set(b, a1, count, scalars, shared, runs, scratch):
    """Each slack dropper's six DOFs, with the force and tangent that remove its axial part, from
    its preload ``runs.dropper_preload`` [N], stretch ``scratch.stretch`` [m] and rate
    ``scratch.rate`` [m/s]. Returns (set size, recorded droppers slack).

    Parameters
    ----------
    b : int
        Run, the row of its dropper preloads. [-]
    a1 : float
        Velocity coefficient of the scheme (∂v/∂u within the step; 0 at rest). [1/s]
    count : int
        Size of the set before. [-]
    scalars, shared, runs, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    dropper_dofs, dropper_gradient, dropper_stiffness = shared.dropper_dofs, shared.dropper_gradient, shared.dropper_stiffness
    dropper_preload, dropper_recorded, rayleigh_beta = runs.dropper_preload, shared.dropper_recorded, scalars.rayleigh_beta
    set_dofs, set_force, tangent, position = scratch.set_dofs, scratch.set_force, scratch.tangent, scratch.position
    stretch, rate = scratch.stretch, scratch.rate
    q, piece_force, piece_tangent = scratch.piece_dofs, scratch.piece_force, scratch.piece_tangent
    slack_recorded = 0
    for d in range(dropper_preload.shape[1]):
        axial = dropper_axial_force(dropper_preload[b, d], dropper_stiffness[d], stretch[d], rate[d], rayleigh_beta)
        if dropper_tension(axial) <= 0.0 and dropper_recorded[d]:
            slack_recorded += 1
        if dropper_slack(axial):
            for c in range(6):
                q[c], count = enter_set(dropper_dofs[d, c], set_dofs, set_force, tangent, position, count)
            force_contribution(-axial, -dropper_stiffness[d] * (1.0 + a1 * rayleigh_beta), dropper_gradient[d],
                               piece_force, piece_tangent)
            add_piece(6, q, piece_force, piece_tangent, set_force, tangent)
    return count, slack_recorded


@kernel_part
def nonlinear_forces(b, step, a1, scalars, shared, runs, scratch):
    """Nonlinear forces and Newton tangent ∂f/∂u + a1 ∂f/∂v of run ``b`` at record ``step``.

    Reads the full displacement ``scratch.u_of`` [m] and velocity ``scratch.v_of`` [m/s] at the
    contact nodes and the pantograph DOFs, and every dropper's stretch ``scratch.stretch`` [m] and
    rate ``scratch.rate`` [m/s]. Writes the set's DOFs, forces [N], dense tangent [N/m] and each
    contact force [N] into ``scratch``; returns (set size, recorded droppers slack).

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    a1 : float
        Velocity coefficient of the scheme (∂v/∂u within the step; 0 at rest). [1/s]
    scalars, shared, runs, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    count = contact_set(b, step, 0, shared, runs, scratch)
    count = friction_set(a1, count, scalars, shared, scratch)
    return dropper_set(b, a1, count, scalars, shared, runs, scratch)
