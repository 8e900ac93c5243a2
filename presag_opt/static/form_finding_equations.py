"""The form-finding equations g(v; p) = 0 of a catenary section, and their sensitivity to the targets.

The form-finding problem: the unknowns v (node heights and sideways positions, steady-arm forces,
dropper lengths, spring references) that balance every free node with each wire element acting as
a string of constant horizontal tension, while the contact wire holds its target heights. The
equations are CasADi SX expressions built from the same energy terms as the potential
(:mod:`presag_opt.static.potential`, with the wires as strings); :mod:`presag_opt.static.form_finding_solver`
solves them with IPOPT, and :func:`target_height_sensitivity` differentiates their solution with
respect to the targets.

Every number of the problem (target heights, design coordinates, stiffnesses, tensions, loads, the
directions across the wires and the steady-arm data) is a parameter p of the symbolic equations, and
only its structure (:class:`FormFindingTopology`) shapes them: :func:`form_finding_problem` pairs the
equations of a topology, built once (:func:`topology_system`), with the numbers of one problem. A
Morris screening, the passes of one form-finding and every re-solve of a section therefore share one
set of equations, and one IPOPT solver built from them.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import scipy.sparse.linalg as spla

from presag_opt.static.discretisation import PIN_STIFFNESS, Discretisation
from presag_opt.static.potential import PhysicalParameters, axial_energy, spring_energy

SYSTEMS_KEPT = 4
"""Topologies whose symbolic equations a process keeps (least recently used dropped first): the two
layouts of a recommendation and the last span lists a screening drew for the mixed one, a section's
passes and re-solves. The equations and solver of the 1.34 km mixed layout add about 170 MB to a
process (75 MB for the 600 m ideal one), which bounds the memo's size. [-]"""


@dataclass(frozen=True, eq=False)
class FormFindingTopology:
    """The structure of a form-finding problem: every index that shapes its equations, no number.

    Two problems with equal topologies have the same symbolic equations (with their numbers as
    parameters), so the topology is the key under which a process keeps them
    (:func:`topology_system`) and their IPOPT solver
    (:func:`presag_opt.static.form_finding_solver.solve_form_finding`). It is built from the
    discretisation, the set of wire segments and the target degrees of freedom
    (:meth:`of`); equal when every index array is.

    Attributes
    ----------
    n_nodes : int
        Nodes, steady-arm pivots included. [-]
    target_dofs : ndarray of int
        Degrees of freedom (heights) held at their targets. [-]
    z_free, z_unknown : ndarray of int
        Nodes whose height is free; of those, the ones whose height is unknown (not a target). [-]
    side_nodes, side_before, side_after : ndarray of int
        Nodes that move across their wire, and their neighbours along it (the chord between them gives
        the direction across). [-]
    node_a, node_b : ndarray of int
        End nodes of every axial element. [-]
    wires, others, droppers : ndarray of int
        Axial elements that are wire segments (strings), that carry strain energy (neither wire nor
        steady arm) and that are droppers (their lengths unknown; a subset of ``others``). [-]
    arm_clamps, arm_pivots : ndarray of int
        Clamp (contact-wire) node and pivot node of every steady arm. [-]
    bending : ndarray of int, shape (3, n_triples)
        Nodes a, b, c of every bending triple. [-]
    spring_dofs, pin_nodes : ndarray of int
        Degrees of freedom held by ground springs, and messenger-wire nodes pinned across a curve. [-]
    """

    n_nodes: int
    target_dofs: np.ndarray
    z_free: np.ndarray
    z_unknown: np.ndarray
    side_nodes: np.ndarray
    side_before: np.ndarray
    side_after: np.ndarray
    node_a: np.ndarray
    node_b: np.ndarray
    wires: np.ndarray
    others: np.ndarray
    droppers: np.ndarray
    arm_clamps: np.ndarray
    arm_pivots: np.ndarray
    bending: np.ndarray
    spring_dofs: np.ndarray
    pin_nodes: np.ndarray
    _key: tuple = field(init=False, repr=False)

    def __post_init__(self) -> None:
        arrays = tuple(np.ascontiguousarray(getattr(self, name), dtype=np.int64)
                       for name in self.__dataclass_fields__ if name not in ("n_nodes", "_key"))
        object.__setattr__(self, "_key", (self.n_nodes, *((a.shape, a.tobytes()) for a in arrays)))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, FormFindingTopology) and self._key == other._key

    def __hash__(self) -> int:
        return hash(self._key)

    @classmethod
    def of(cls, disc: Discretisation, wire_tension: np.ndarray, target_dofs: np.ndarray) -> FormFindingTopology:
        """The topology of the form-finding of ``disc``.

        Parameters
        ----------
        disc : Discretisation
            The discretised section.
        wire_tension : ndarray
            Horizontal tension of each axial element, 0 for those that are not wire segments (only
            which are wires enters the topology). [N]
        target_dofs : ndarray of int
            Degrees of freedom (heights) held at their targets. [-]
        """
        fixed = disc.fixed_dofs.reshape(-1, 3)
        z_free = np.flatnonzero(~fixed[:, 2])
        clamps = disc.axial.node_a[disc.arm_elements]
        # Wire nodes that may move across their wire (in plan, perpendicular to it); their position
        # along the wire stays where the design puts it.
        side, before, after = [], [], []
        for wire in (disc.cw_nodes, disc.mw_nodes):
            if not len(wire):
                continue
            k = np.flatnonzero(~fixed[wire, 1] & ~np.isin(wire, clamps))
            side.append(wire[k])
            before.append(wire[np.maximum(k - 1, 0)])
            after.append(wire[np.minimum(k + 1, len(wire) - 1)])
        for chain in disc.stitch_chains:  # a stitch wire's own nodes (its clamps are messenger-wire nodes)
            k = np.arange(1, len(chain) - 1)
            side.append(chain[k])
            before.append(chain[k - 1])
            after.append(chain[k + 1])
        is_wire = wire_tension > 0
        b = disc.bending
        return cls(
            n_nodes=disc.n_nodes,
            target_dofs=np.asarray(target_dofs, dtype=int),
            z_free=z_free,
            z_unknown=z_free[~np.isin(3 * z_free + 2, target_dofs)],
            side_nodes=np.concatenate(side),
            side_before=np.concatenate(before),
            side_after=np.concatenate(after),
            node_a=disc.axial.node_a,
            node_b=disc.axial.node_b,
            wires=np.flatnonzero(is_wire),
            others=np.setdiff1d(np.flatnonzero(~is_wire), disc.arm_elements),
            droppers=disc.dropper_elements,
            arm_clamps=clamps,
            arm_pivots=disc.arm_pivot_nodes,
            bending=np.array([b.node_a, b.node_b, b.node_c], dtype=int).reshape(3, -1),
            spring_dofs=disc.spring_dofs,
            pin_nodes=disc.pin_nodes,
        )


def _numbers(topology: FormFindingTopology, disc: Discretisation, params: PhysicalParameters,
             wire_tension: np.ndarray, x_design: np.ndarray) -> dict[str, np.ndarray]:
    """Every number of one form-finding problem, by the name of its block of the parameter vector p.

    The first block is the target heights (the ``targets`` of :class:`FormFindingSystem`); the others
    are in the order :func:`topology_system` takes them. [m], [N/m], [N], [N·m²], [-]
    """
    t = topology
    base = x_design.reshape(-1, 3)
    tangent = base[t.side_after] - base[t.side_before]
    across = np.column_stack([-tangent[:, 1], tangent[:, 0]]) / np.linalg.norm(tangent[:, :2], axis=1)[:, None]
    arms = disc.arm_elements
    push_off = disc.catenary.mast_push_off()[disc.arm_masts] if len(arms) else np.zeros(0, dtype=bool)
    horizontal = np.linalg.norm(base[t.node_b[t.wires], :2] - base[t.node_a[t.wires], :2], axis=1)
    return {
        "target_height": x_design[t.target_dofs],
        "design": x_design,
        "across_x": across[:, 0],
        "across_y": across[:, 1],
        "arm_normal": disc.mast_normal[disc.arm_masts].ravel(),
        "arm_sign": np.where(push_off, -1.0, 1.0),
        "arm_unstretched_length": params.unstretched_length[arms],
        "arm_stiffness": params.axial_stiffness[arms],
        "stiffness": params.axial_stiffness[t.others],
        "unstretched_length": params.unstretched_length[t.others],
        "wire_tension": wire_tension[t.wires],
        "string_stiffness": wire_tension[t.wires] / (2.0 * horizontal),
        "bending_factor": params.bending_stiffness / (disc.bending.spacing_ab + disc.bending.spacing_bc),
        "spacing_ab": disc.bending.spacing_ab,
        "spacing_bc": disc.bending.spacing_bc,
        "spring_stiffness": params.spring_stiffness,
        "pin_position": disc.design_positions[t.pin_nodes].ravel(),
        "pin_normal": disc.pin_normals.ravel(),
        "nodal_force": params.nodal_force,
    }


def _axial_energy(t: FormFindingTopology, x, elements: np.ndarray, k, L0):
    """Strain energy of the axial elements ``elements`` (:func:`~presag_opt.static.potential.axial_energy`)."""
    X = ca.reshape(x, 3, t.n_nodes).T
    d = X[t.node_b[elements].tolist(), :] - X[t.node_a[elements].tolist(), :]
    return ca.sum1(axial_energy(ca.sqrt(ca.sum2(d**2)), k, L0, 0))


def _bending_energy(t: FormFindingTopology, x, factor, spacing_ab, spacing_bc):
    """Rotation-free Euler–Bernoulli bending energy of the wire triples."""
    if not t.bending.shape[1]:
        return 0
    X = ca.reshape(x, 3, t.n_nodes).T
    a, b, c = (row.tolist() for row in t.bending)
    d1 = (X[b, :] - X[a, :]) / spacing_ab
    d2 = (X[c, :] - X[b, :]) / spacing_bc
    return ca.sum1(factor * ca.sum2((d2 - d1) ** 2))


def _spring_energy(t: FormFindingTopology, x, ks, ref, pin_position, pin_normal):
    """Energy of the ground springs and of the messenger-wire pins on curves."""
    energy = 0
    if len(t.spring_dofs):
        energy += ca.sum1(spring_energy(x[t.spring_dofs.tolist()] - ref, ks))
    if len(t.pin_nodes):
        X = ca.reshape(x, 3, t.n_nodes).T
        offset = X[t.pin_nodes.tolist(), :] - ca.reshape(pin_position, 3, len(t.pin_nodes)).T
        normal = ca.reshape(pin_normal, 3, len(t.pin_nodes)).T
        energy += ca.sum1(spring_energy(ca.sum2(offset * normal), PIN_STIFFNESS))
    return energy


@dataclass(frozen=True, eq=False)
class FormFindingSystem:
    """The symbolic form-finding equations g(v; p) = 0 of one topology, numbers as parameters.

    Attributes
    ----------
    unknowns, parameters, targets, equations : casadi.SX
        v; p, every number of the problem; its first block, the target heights of ``target_dofs``
        [m]; g [N].
    coordinates : casadi.Function
        x(v, p), every coordinate. [m]
    layout : tuple of (str, int)
        The blocks of p, by name and size, in order. [-]
    z_unknown : ndarray of int
        Nodes whose height is unknown, in the order of v. [-]
    n_side, n_arm, n_drop : int
        Sideways unknowns, steady arms and droppers. [-]
    """

    unknowns: ca.SX
    parameters: ca.SX
    targets: ca.SX
    equations: ca.SX
    coordinates: ca.Function
    layout: tuple[tuple[str, int], ...]
    z_unknown: np.ndarray
    n_side: int
    n_arm: int
    n_drop: int


@dataclass(frozen=True)
class FormFindingProblem:
    """One form-finding problem: the equations of its topology and its numbers.

    Attributes
    ----------
    topology : FormFindingTopology
        Its structure.
    system : FormFindingSystem
        The equations of the topology (shared by every problem of that topology).
    parameters : ndarray
        p, in the order of ``system.layout``. [m], [N/m], [N], [N·m²], [-]
    start : ndarray
        v at the design coordinates. [m], [N]
    """

    topology: FormFindingTopology
    system: FormFindingSystem
    parameters: np.ndarray
    start: np.ndarray


def form_finding_problem(
    disc: Discretisation,
    params: PhysicalParameters,
    wire_tension: np.ndarray,
    target_dofs: np.ndarray,
    x_design: np.ndarray,
) -> FormFindingProblem:
    """The form-finding equations at the design coordinates ``x_design`` (arguments as for
    :func:`presag_opt.static.form_finding_solver.solve_form_finding`): the topology's equations
    (built once per topology, :func:`topology_system`) and this problem's numbers.

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
    topology = FormFindingTopology.of(disc, wire_tension, target_dofs)
    numbers = _numbers(topology, disc, params, wire_tension, x_design)
    system = topology_system(topology, tuple((name, value.size) for name, value in numbers.items()))
    arm_start = []
    for j, (arm, mast) in enumerate(zip(disc.arm_elements, disc.arm_masts)):
        # the force of the arm at its first-guess pivot: N = k (|r| − L0) along r, the clamp-to-pivot vector
        rel = x_design[3 * topology.arm_pivots[j] : 3 * topology.arm_pivots[j] + 3] \
            - x_design[3 * topology.arm_clamps[j] : 3 * topology.arm_clamps[j] + 3]
        length = float(np.linalg.norm(rel))
        force = params.axial_stiffness[arm] * (length - params.unstretched_length[arm]) * rel / length
        arm_start += [float(force @ disc.mast_normal[mast]), float(force[2])]
    start = np.concatenate([
        x_design[3 * topology.z_unknown + 2], np.zeros(system.n_side), arm_start,
        params.unstretched_length[topology.droppers], params.spring_reference,
    ])
    return FormFindingProblem(topology=topology, system=system,
                              parameters=np.concatenate(list(numbers.values())).astype(float), start=start)


@functools.lru_cache(maxsize=SYSTEMS_KEPT)
def topology_system(topology: FormFindingTopology, layout: tuple[tuple[str, int], ...]) -> FormFindingSystem:
    """The form-finding equations of ``topology`` with the blocks of ``layout`` as parameters.

    Built once per topology and process and kept (:data:`SYSTEMS_KEPT` of them, least recently used
    dropped first: a process-owned memo keyed by the structure alone, so it cannot hand one problem
    another's numbers, and bounded, so a long line design or screening does not grow it).

    Parameters
    ----------
    topology : FormFindingTopology
        The structure.
    layout : tuple of (str, int)
        Names and sizes of the blocks of p (:func:`_numbers`; the sizes follow from the topology). [-]
    """
    t = topology
    p = {name: ca.SX.sym(name, size) for name, size in layout}
    n_arm = len(t.arm_clamps)
    v_z = ca.SX.sym("height", len(t.z_unknown))
    v_side = ca.SX.sym("sideways", len(t.side_nodes))
    v_arm = ca.SX.sym("arm_force", 2 * n_arm)
    v_drop = ca.SX.sym("dropper_length", len(t.droppers))
    v_ref = ca.SX.sym("spring_reference", len(t.spring_dofs))

    # Coordinates as functions of the unknowns and the numbers. A steady arm is a two-force member: its
    # unknowns are the force it puts on its clamp, f = f_n·normal + f_z·e_z, which enters the clamp's
    # balance linearly; its pivot follows, on the line of f at the arm's stretched length (see
    # _pivot). Solving for the pivot itself would make a stiff bar rotate under Newton steps, whose
    # second-order stretch swamps the clamp's balance where the arm carries little sideways pull.
    xs = ca.SX.sym("x", 3 * t.n_nodes)
    x = ca.SX(p["design"])
    x[t.target_dofs.tolist()] = p["target_height"]
    x[(3 * t.z_unknown + 2).tolist()] = v_z
    base = ca.reshape(p["design"], 3, t.n_nodes).T
    for c, across in enumerate((p["across_x"], p["across_y"])):
        x[(3 * t.side_nodes + c).tolist()] = base[t.side_nodes.tolist(), c] + v_side * across
    normal = ca.reshape(p["arm_normal"], 3, n_arm)
    arm_force = [v_arm[2 * j] * normal[:, j] + v_arm[2 * j + 1] * ca.DM([0.0, 0.0, 1.0]) for j in range(n_arm)]
    for j, (clamp, pivot) in enumerate(zip(t.arm_clamps, t.arm_pivots)):
        x[3 * pivot : 3 * pivot + 3] = _pivot(x[3 * clamp : 3 * clamp + 3], arm_force[j], p["arm_unstretched_length"][j],
                                              p["arm_stiffness"][j], p["arm_sign"][j])

    L0 = ca.SX(p["unstretched_length"])
    L0[np.searchsorted(t.others, t.droppers).tolist()] = v_drop
    energy = _axial_energy(t, xs, t.others, p["stiffness"], L0)
    X = ca.reshape(xs, 3, t.n_nodes).T
    d = X[t.node_b[t.wires].tolist(), :] - X[t.node_a[t.wires].tolist(), :]
    tension = p["wire_tension"]
    # H·l_h gives the constant horizontal pull (and so the lateral kink force at registrations);
    # H/(2 l_h)·Δz² the vertical string stiffness.
    energy += ca.sum1(tension * ca.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2) + p["string_stiffness"] * d[:, 2] ** 2)
    energy += _bending_energy(t, xs, p["bending_factor"], p["spacing_ab"], p["spacing_bc"])
    energy += _spring_energy(t, xs, p["spring_stiffness"], v_ref, p["pin_position"], p["pin_normal"])
    energy -= ca.dot(p["nodal_force"], xs)
    for j, force in enumerate(arm_force):
        energy -= ca.dot(force, X[int(t.arm_clamps[j]), :].T)
    parameters = ca.vertcat(*p.values())
    gradient = ca.Function("gradient", [xs, v_drop, v_ref, v_arm, parameters],
                           [ca.gradient(energy, xs)])(x, v_drop, v_ref, v_arm, parameters)

    vertical = gradient[(3 * t.z_free + 2).tolist()]
    sideways_balance = sum(gradient[(3 * t.side_nodes + c).tolist()] * across
                           for c, across in enumerate((p["across_x"], p["across_y"])))
    balance_across = [ca.dot(gradient[3 * node : 3 * node + 3], normal[:, j]) for j, node in enumerate(t.arm_clamps)]
    unknowns = ca.vertcat(v_z, v_side, v_arm, v_drop, v_ref)
    return FormFindingSystem(
        unknowns=unknowns,
        parameters=parameters,
        targets=p["target_height"],
        equations=ca.vertcat(vertical, sideways_balance, *balance_across),
        coordinates=ca.Function("coordinates", [unknowns, parameters], [x]),
        layout=layout,
        z_unknown=t.z_unknown,
        n_side=len(t.side_nodes),
        n_arm=n_arm,
        n_drop=len(t.droppers),
    )


def _pivot(clamp, force, unstretched_length, stiffness, sign):
    """Pivot of a steady arm that puts ``force`` on its clamp (CasADi expressions). [m]

    A pull-off arm (``sign`` 1) in tension N = |f| pulls the clamp towards its pivot; a push-off arm
    (``sign`` −1) in compression N = −|f| pushes it away from its pivot. Either way the pivot lies on
    the line of f at the stretched length L0 + N/k from the clamp (k = EA/L0 the arm's spring stiffness).
    """
    size = ca.norm_2(force)
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
    problem = form_finding_problem(disc, params, wire_tension, target_dofs, positions.ravel())
    system = problem.system
    j_v, j_p = _target_jacobians(problem.topology, system.layout)(problem.start, problem.parameters)
    dv_dp = -spla.splu(j_v.sparse().tocsc()).solve(np.asarray(j_p.full()))
    sensitivity = np.zeros((disc.n_nodes, len(target_dofs)))
    sensitivity[target_dofs // 3, np.arange(len(target_dofs))] = 1.0
    sensitivity[system.z_unknown] = dv_dp[: len(system.z_unknown)]
    return sensitivity


@functools.lru_cache(maxsize=SYSTEMS_KEPT)
def _target_jacobians(topology: FormFindingTopology, layout: tuple[tuple[str, int], ...]) -> ca.Function:
    """∂g/∂v and ∂g/∂p_target of a topology's equations as a function of (v, p), built once per
    topology (kept as :func:`topology_system` keeps the equations)."""
    system = topology_system(topology, layout)
    return ca.Function("jacobians", [system.unknowns, system.parameters],
                       [ca.jacobian(system.equations, system.unknowns), ca.jacobian(system.equations, system.targets)])
