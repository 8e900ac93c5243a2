"""The form-finding equations g(v; p) = 0 of a catenary section, and their sensitivity to the targets.

The form-finding problem: the unknowns v (node heights and sideways positions, steady-arm forces,
dropper lengths, spring references) that balance every free node with each wire element acting as
a string of constant horizontal tension, while the contact wire holds its target heights p. The
equations are CasADi SX expressions built from the same energy terms as the potential
(:mod:`presag_opt.static.potential`, with the wires as strings); :mod:`presag_opt.static.form_finding_solver`
solves them with IPOPT, and :func:`target_height_sensitivity` differentiates their solution with
respect to the targets.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse.linalg as spla

from presag_opt.static.discretisation import PIN_STIFFNESS, Discretisation
from presag_opt.static.potential import PhysicalParameters, axial_energy, spring_energy


def _axial_energy(disc: Discretisation, x, elements: np.ndarray, k, L0, slack):
    """Strain energy of the axial elements ``elements`` (:func:`~presag_opt.static.potential.axial_energy`)."""
    ax = disc.axial
    X = ca.reshape(x, 3, disc.n_nodes).T
    d = X[ax.node_b[elements].tolist(), :] - X[ax.node_a[elements].tolist(), :]
    return ca.sum1(axial_energy(ca.sqrt(ca.sum2(d**2)), k, L0, slack))


def _bending_energy(disc: Discretisation, x, ei):
    """Rotation-free Euler–Bernoulli bending energy of the wire triples."""
    b = disc.bending
    if not len(b.node_a):
        return 0
    X = ca.reshape(x, 3, disc.n_nodes).T
    d1 = (X[b.node_b.tolist(), :] - X[b.node_a.tolist(), :]) / ca.DM(b.spacing_ab)
    d2 = (X[b.node_c.tolist(), :] - X[b.node_b.tolist(), :]) / ca.DM(b.spacing_bc)
    return ca.sum1(ei / ca.DM(b.spacing_ab + b.spacing_bc) * ca.sum2((d2 - d1) ** 2))


def _spring_energy(disc: Discretisation, x, ks, ref):
    """Energy of the ground springs and of the messenger-wire pins on curves."""
    energy = 0
    if len(disc.spring_dofs):
        energy += ca.sum1(spring_energy(x[disc.spring_dofs.tolist()] - ref, ks))
    if len(disc.pin_nodes):
        X = ca.reshape(x, 3, disc.n_nodes).T
        offset = X[disc.pin_nodes.tolist(), :] - ca.DM(disc.design_positions[disc.pin_nodes])
        energy += ca.sum1(spring_energy(ca.sum2(offset * ca.DM(disc.pin_normals)), PIN_STIFFNESS))
    return energy


@dataclass(frozen=True)
class FormFindingSystem:
    """The symbolic form-finding equations g(v; p) = 0 and what is needed to evaluate them.

    Attributes
    ----------
    unknowns, targets, equations, coordinates : casadi.SX
        v; p, the target heights of ``target_dofs`` [m]; g [N]; and the coordinates x(v, p) [m].
    start : ndarray
        v at the design coordinates. [m]
    z_unknown : ndarray of int
        Nodes whose height is unknown, in the order of v. [-]
    n_side, n_arm, n_drop : int
        Sideways unknowns, steady arms and droppers. [-]
    """

    unknowns: ca.SX  # v
    targets: ca.SX  # p: target heights of target_dofs [m]
    equations: ca.SX  # g
    coordinates: ca.SX  # x(v, p)
    start: np.ndarray  # v at x_design
    z_unknown: np.ndarray  # nodes whose height is unknown (in the order of v)
    n_side: int
    n_arm: int
    n_drop: int


def form_finding_system(
    disc: Discretisation,
    params: PhysicalParameters,
    wire_tension: np.ndarray,
    target_dofs: np.ndarray,
    x_design: np.ndarray,
) -> FormFindingSystem:
    """The form-finding equations at the design coordinates ``x_design`` (arguments as for
    :func:`presag_opt.static.form_finding_solver.solve_form_finding`).

    Parameters
    ----------
    disc : Discretisation
        Topology.
    params : PhysicalParameters
        Parameter values; dropper lengths and spring references are starting values.
    wire_tension : ndarray
        Horizontal tension of each axial element that is a wire segment, 0 for the others. [N]
    target_dofs : ndarray of int
        Degrees of freedom (heights) that must keep their design value. [-]
    x_design : ndarray
        Design coordinates (the first-guess pivots give the arms' starting forces). [m]
    """
    base = x_design.reshape(-1, 3)
    fixed = disc.fixed_dofs.reshape(-1, 3)
    z_free = np.flatnonzero(~fixed[:, 2])
    z_unknown = z_free[~np.isin(3 * z_free + 2, target_dofs)]
    drops = disc.dropper_elements
    reg_nodes = disc.axial.node_a[disc.arm_elements]
    n_arm = len(reg_nodes)
    # Wire nodes that may move across their wire (in plan, perpendicular to it); their position
    # along the wire stays where the design puts it.
    side_nodes, across = [], []
    for wire in (disc.cw_nodes, disc.mw_nodes):
        if not len(wire):
            continue
        movable = ~fixed[wire, 1] & ~np.isin(wire, reg_nodes)
        k = np.flatnonzero(movable)
        tangent = base[wire[np.minimum(k + 1, len(wire) - 1)]] - base[wire[np.maximum(k - 1, 0)]]
        side_nodes.append(wire[k])
        across.append(np.column_stack([-tangent[:, 1], tangent[:, 0], np.zeros(len(k))])
                      / np.linalg.norm(tangent[:, :2], axis=1)[:, None])
    for chain in disc.stitch_chains:  # a stitch wire's own nodes (its clamps are messenger-wire nodes)
        k = np.arange(1, len(chain) - 1)
        tangent = base[chain[k + 1]] - base[chain[k - 1]]
        side_nodes.append(chain[k])
        across.append(np.column_stack([-tangent[:, 1], tangent[:, 0], np.zeros(len(k))])
                      / np.linalg.norm(tangent[:, :2], axis=1)[:, None])
    side_nodes = np.concatenate(side_nodes)
    across_dir = np.concatenate(across)

    v_z = ca.SX.sym("height", len(z_unknown))
    v_side = ca.SX.sym("sideways", len(side_nodes))
    v_arm = ca.SX.sym("arm_force", 2 * n_arm)
    v_drop = ca.SX.sym("dropper_length", len(drops))
    v_ref = ca.SX.sym("spring_reference", len(disc.spring_dofs))
    p = ca.SX.sym("target_height", len(target_dofs))

    # Coordinates as functions of the unknowns and the targets. A steady arm is a two-force member: its
    # unknowns are the force it puts on its clamp, f = f_n·normal + f_z·e_z, which enters the clamp's
    # balance linearly; its pivot follows, on the line of f at the arm's stretched length (see
    # _pivot). Solving for the pivot itself would make a stiff bar rotate under Newton steps, whose
    # second-order stretch swamps the clamp's balance where the arm carries little sideways pull.
    xs = ca.SX.sym("x", disc.n_dofs)
    x = ca.SX(x_design.astype(float))
    x[target_dofs.tolist()] = p
    x[(3 * z_unknown + 2).tolist()] = v_z
    for c in range(2):
        x[(3 * side_nodes + c).tolist()] = ca.DM(base[side_nodes, c]) + v_side * ca.DM(across_dir[:, c])
    arm_force = [v_arm[2 * j] * ca.DM(disc.mast_normal[mast]) + v_arm[2 * j + 1] * ca.DM([0.0, 0.0, 1.0])
                 for j, mast in enumerate(disc.arm_masts)]
    push_off = disc.catenary.mast_push_off()[disc.arm_masts] if n_arm else np.zeros(0, dtype=bool)
    for j, (arm, pivot) in enumerate(zip(disc.arm_elements, disc.arm_pivot_nodes)):
        clamp = x[3 * reg_nodes[j] : 3 * reg_nodes[j] + 3]
        x[3 * pivot : 3 * pivot + 3] = _pivot(clamp, arm_force[j], params.unstretched_length[arm],
                                              params.axial_stiffness[arm], push_off[j])

    is_wire = wire_tension > 0
    others = np.setdiff1d(np.flatnonzero(~is_wire), disc.arm_elements)
    k = ca.DM(params.axial_stiffness[others])
    L0 = _with(params.unstretched_length, drops, v_drop)[others.tolist()]
    energy = _axial_energy(disc, xs, others, k, L0, ca.DM.zeros(len(others)))
    wires = np.flatnonzero(is_wire)
    ax = disc.axial
    horizontal = np.linalg.norm(base[ax.node_b[wires], :2] - base[ax.node_a[wires], :2], axis=1)
    X = ca.reshape(xs, 3, disc.n_nodes).T
    d = X[ax.node_b[wires].tolist(), :] - X[ax.node_a[wires].tolist(), :]
    tension = ca.DM(wire_tension[wires])
    # H·l_h gives the constant horizontal pull (and so the lateral kink force at registrations);
    # H/(2 l_h)·Δz² the vertical string stiffness.
    energy += ca.sum1(tension * ca.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2) + tension / ca.DM(2.0 * horizontal) * d[:, 2] ** 2)
    energy += _bending_energy(disc, xs, ca.DM(params.bending_stiffness))
    energy += _spring_energy(disc, xs, ca.DM(params.spring_stiffness), v_ref)
    energy -= ca.dot(ca.DM(params.nodal_force), xs)
    X = ca.reshape(xs, 3, disc.n_nodes).T
    for j, force in enumerate(arm_force):
        energy -= ca.dot(force, X[int(reg_nodes[j]), :].T)
    gradient = ca.Function("gradient", [xs, v_drop, v_ref, v_arm], [ca.gradient(energy, xs)])(x, v_drop, v_ref, v_arm)

    vertical = gradient[(3 * z_free + 2).tolist()]
    sideways_balance = sum(gradient[(3 * side_nodes + c).tolist()] * ca.DM(across_dir[:, c]) for c in range(2))
    balance_across = [
        ca.dot(gradient[3 * node : 3 * node + 3], ca.DM(disc.mast_normal[mast]))
        for node, mast in zip(reg_nodes, disc.arm_masts)
    ]
    arm_start = []
    for j, (arm, mast) in enumerate(zip(disc.arm_elements, disc.arm_masts)):
        # the force of the arm at its first-guess pivot: N = k (|r| − L0) along r, the clamp-to-pivot vector
        rel = base[disc.arm_pivot_nodes[j]] - base[reg_nodes[j]]
        length = float(np.linalg.norm(rel))
        force = params.axial_stiffness[arm] * (length - params.unstretched_length[arm]) * rel / length
        arm_start += [float(force @ disc.mast_normal[mast]), float(force[2])]
    return FormFindingSystem(
        unknowns=ca.vertcat(v_z, v_side, v_arm, v_drop, v_ref),
        targets=p,
        equations=ca.vertcat(vertical, sideways_balance, *balance_across),
        coordinates=x,
        start=np.concatenate([
            x_design[3 * z_unknown + 2], np.zeros(len(side_nodes)), arm_start, params.unstretched_length[drops],
            params.spring_reference,
        ]),
        z_unknown=z_unknown,
        n_side=len(side_nodes),
        n_arm=n_arm,
        n_drop=len(drops),
    )

def _pivot(clamp, force, unstretched_length: float, stiffness: float, push_off: bool):
    """Pivot of a steady arm that puts ``force`` on its clamp (CasADi expressions). [m]

    A pull-off arm in tension N = |f| pulls the clamp towards its pivot; a push-off arm in compression
    N = −|f| pushes it away from its pivot. Either way the pivot lies on the line of f at the stretched
    length L0 + N/k from the clamp (k = EA/L0 the arm's spring stiffness).
    """
    size = ca.norm_2(force)
    sign = -1.0 if push_off else 1.0
    return clamp + sign * force / size * (unstretched_length + sign * size / stiffness)


def target_height_sensitivity(
    disc: Discretisation,
    params: PhysicalParameters,
    wire_tension: np.ndarray,
    target_dofs: np.ndarray,
    positions: np.ndarray,
) -> np.ndarray:
    """∂z/∂p: how every node height of a form-found state moves with the target heights.

    By the implicit-function theorem on the form-finding equations g(v; p) = 0 at the solution:
    dv/dp = −(∂g/∂v)⁻¹ ∂g/∂p (CasADi Jacobians, one sparse LU). Target heights move one for one.

    Parameters
    ----------
    disc : Discretisation
        Topology, as for :func:`solve_form_finding`.
    params : PhysicalParameters
        Parameter values holding the solved dropper lengths and spring references.
    wire_tension : ndarray
        Horizontal tension of each axial element that is a wire segment, 0 for the others. [N]
    target_dofs : ndarray of int
        Degrees of freedom (heights) that keep their design value. [-]
    positions : ndarray, shape (n_nodes, 3)
        The form-found coordinates. [m]

    Returns
    -------
    ndarray, shape (n_nodes, len(target_dofs))
        Height change of every node per unit change of each target height. [m/m]
    """
    x = positions.ravel()
    system = form_finding_system(disc, params, wire_tension, target_dofs, x)
    jacobians = ca.Function(
        "jacobians",
        [system.unknowns, system.targets],
        [ca.jacobian(system.equations, system.unknowns), ca.jacobian(system.equations, system.targets)],
    )
    j_v, j_p = jacobians(system.start, x[target_dofs])
    dv_dp = -spla.splu(j_v.sparse().tocsc()).solve(np.asarray(j_p.full()))
    sensitivity = np.zeros((disc.n_nodes, len(target_dofs)))
    sensitivity[target_dofs // 3, np.arange(len(target_dofs))] = 1.0
    sensitivity[system.z_unknown] = dv_dp[: len(system.z_unknown)]
    return sensitivity


def _with(values: np.ndarray, index: np.ndarray, replacement):
    out = ca.SX(values.astype(float))
    out[index.tolist()] = replacement
    return out
