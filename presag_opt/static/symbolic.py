"""The CasADi boundary of the static model.

Everything symbolic lives here: the total potential energy of a discretised catenary built once into
named :class:`casadi.Function` objects, and the form-finding problem handed to IPOPT. Callers pass
numpy arrays in and get numpy arrays (and SciPy sparse matrices) out.

Total potential energy (x: all node coordinates)::

    Π(x) = Σ_axial k/2 · (L − L0)²            (max(L − L0, 0)² where the element may go slack)
         + Σ_bending EI/(h1 + h2) · |(x_c − x_b)/h2 − (x_b − x_a)/h1|²
         + Σ_springs k_s/2 · (x_dof − ref)²
         − f · x

Equilibrium is ∂Π/∂x = 0 on the free degrees of freedom; the tangent stiffness is the Hessian.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from presag_opt.errors import ConvergenceError
from presag_opt.static.discretisation import PIN_STIFFNESS, Discretisation
from presag_opt.static.linalg import BandedSolver

POTENTIAL_INPUTS = (
    "x",
    "axial_stiffness",
    "unstretched_length",
    "slack_allowed",
    "bending_stiffness",
    "spring_stiffness",
    "spring_reference",
    "nodal_force",
)


@dataclass(frozen=True, kw_only=True)
class PhysicalParameters:
    """Numeric values of the potential's parameter inputs (everything but ``x``).

    Attributes
    ----------
    axial_stiffness : ndarray
        Spring stiffness of each axial element. [N/m]
    unstretched_length : ndarray
        Unstretched length of each axial element. [m]
    slack_allowed : ndarray
        1 where an element carries tension only (droppers in equilibrium), else 0. [-]
    bending_stiffness : ndarray
        EI of each bending triple. [N·m²]
    spring_stiffness, spring_reference : ndarray
        Ground springs: stiffness and unloaded position of the spring end. [N/m], [m]
    nodal_force : ndarray
        External nodal forces: weights, balance-weight pulls, point loads. [N]
    """

    axial_stiffness: np.ndarray
    unstretched_length: np.ndarray
    slack_allowed: np.ndarray
    bending_stiffness: np.ndarray
    spring_stiffness: np.ndarray
    spring_reference: np.ndarray
    nodal_force: np.ndarray

    def as_args(self) -> list[np.ndarray]:
        """Values in the order of :data:`POTENTIAL_INPUTS` after ``x``."""
        return [getattr(self, name) for name in POTENTIAL_INPUTS[1:]]


def _axial_energy(disc: Discretisation, x, elements: np.ndarray, k, L0, slack):
    """Strain energy of the axial elements ``elements`` (slack=1: tension only)."""
    ax = disc.axial
    X = ca.reshape(x, 3, disc.n_nodes).T
    d = X[ax.node_b[elements].tolist(), :] - X[ax.node_a[elements].tolist(), :]
    stretch = ca.sqrt(ca.sum2(d**2)) - L0
    taut = (1 - slack) * stretch + slack * ca.fmax(stretch, 0)
    return ca.sum1(0.5 * k * taut**2)


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
        energy += ca.sum1(0.5 * ks * (x[disc.spring_dofs.tolist()] - ref) ** 2)
    if len(disc.pin_nodes):
        X = ca.reshape(x, 3, disc.n_nodes).T
        offset = X[disc.pin_nodes.tolist(), :] - ca.DM(disc.design_positions[disc.pin_nodes])
        energy += ca.sum1(0.5 * PIN_STIFFNESS * ca.sum2(offset * ca.DM(disc.pin_normals)) ** 2)
    return energy


def _potential_expression(disc: Discretisation, x, k, L0, slack, ei, ks, ref, f):
    """Symbolic total potential energy (works on SX symbols or expressions)."""
    every = np.arange(len(disc.axial))
    return (
        _axial_energy(disc, x, every, k, L0, slack)
        + _bending_energy(disc, x, ei)
        + _spring_energy(disc, x, ks, ref)
        - ca.dot(f, x)
    )


@dataclass(frozen=True)
class PotentialFunctions:
    """Named CasADi functions of one discretisation, with numpy wrappers.

    Attributes
    ----------
    potential : casadi.Function
        Inputs :data:`POTENTIAL_INPUTS`, output ``energy`` [J].
    residual : casadi.Function
        Same inputs, output ``gradient`` ∂Π/∂x (out-of-balance force, sign: internal minus external). [N]
    stiffness : casadi.Function
        Same inputs, outputs ``hessian_nonzeros`` (the nonzeros, in CSC order of ``solver.pattern``,
        of the tangent stiffness on the free degrees of freedom) [N/m] and ``gradient`` (on the free
        degrees of freedom) [N].
    free_dofs : ndarray of int
        Degrees of freedom that move in equilibrium (not supports, anchors or pivots).
    solver : BandedSolver
        Ordering and factorisation of the tangent stiffness pattern.
    """

    discretisation: Discretisation
    potential: ca.Function
    residual: ca.Function
    stiffness: ca.Function
    free_dofs: np.ndarray
    solver: BandedSolver

    def gradient(self, x: np.ndarray, params: PhysicalParameters) -> np.ndarray:
        """∂Π/∂x at coordinates ``x``. [N]"""
        return np.asarray(self.residual(x, *params.as_args())).ravel()

    def hessian_values(self, x: np.ndarray, params: PhysicalParameters) -> tuple[np.ndarray, np.ndarray]:
        """Nonzeros of the free-DOF tangent stiffness and the free-DOF gradient at ``x``. [N/m], [N]"""
        values, grad = self.stiffness(x, *params.as_args())
        return np.asarray(values).ravel(), np.asarray(grad).ravel()

    def hessian(self, x: np.ndarray, params: PhysicalParameters) -> tuple[sp.csc_matrix, np.ndarray]:
        """Tangent stiffness (sparse) and gradient on the free degrees of freedom at ``x``. [N/m], [N]"""
        values, grad = self.hessian_values(x, params)
        return self.solver.matrix(values), grad

    def energy(self, x: np.ndarray, params: PhysicalParameters) -> float:
        """Total potential energy. [J]"""
        return float(self.potential(x, *params.as_args()))


def build_potential(disc: Discretisation) -> PotentialFunctions:
    """Build the potential-energy functions of a discretisation (once per topology)."""
    n_ax = len(disc.axial)
    syms = [
        ca.SX.sym("x", disc.n_dofs),
        ca.SX.sym("axial_stiffness", n_ax),
        ca.SX.sym("unstretched_length", n_ax),
        ca.SX.sym("slack_allowed", n_ax),
        ca.SX.sym("bending_stiffness", len(disc.bending.node_a)),
        ca.SX.sym("spring_stiffness", len(disc.spring_dofs)),
        ca.SX.sym("spring_reference", len(disc.spring_dofs)),
        ca.SX.sym("nodal_force", disc.n_dofs),
    ]
    energy = _potential_expression(disc, *syms)
    hess, grad = ca.hessian(energy, syms[0])
    free = np.flatnonzero(~disc.fixed_dofs)
    hess = hess[free.tolist(), free.tolist()]
    sparsity = hess.sparsity()
    pattern = sp.csc_matrix(
        (np.ones(sparsity.nnz()), np.asarray(sparsity.row()), np.asarray(sparsity.colind())), shape=hess.shape
    )
    names = list(POTENTIAL_INPUTS)
    return PotentialFunctions(
        disc,
        ca.Function("potential", syms, [energy], names, ["energy"]),
        ca.Function("residual", syms, [grad], names, ["gradient"]),
        ca.Function("stiffness", syms, [hess.nz[:], grad[free.tolist()]], names, ["hessian_nonzeros", "gradient"]),
        free,
        BandedSolver.for_pattern(pattern),
    )


@dataclass(frozen=True, kw_only=True)
class FormFindingSolution:
    """What the form-finding NLP returns (numeric).

    Attributes
    ----------
    positions : ndarray, shape (n_nodes, 3)
        Equilibrium coordinates including the steady-arm pivots. [m]
    dropper_unstretched_length : ndarray
        Unstretched length of each dropper. [m]
    spring_reference : ndarray
        Unloaded position of each ground spring. [m]
    iterations : int
        IPOPT iterations. [-]
    """

    positions: np.ndarray
    dropper_unstretched_length: np.ndarray
    spring_reference: np.ndarray
    iterations: int


@dataclass(frozen=True)
class _FormFindingSystem:
    """The symbolic form-finding equations g(v; p) = 0 and what is needed to evaluate them."""

    unknowns: ca.SX  # v
    targets: ca.SX  # p: target heights of target_dofs [m]
    equations: ca.SX  # g
    coordinates: ca.SX  # x(v, p)
    start: np.ndarray  # v at x_design
    z_unknown: np.ndarray  # nodes whose height is unknown (in the order of v)
    n_side: int
    n_arm: int
    n_drop: int


def _form_finding_system(
    disc: Discretisation,
    params: PhysicalParameters,
    wire_tension: np.ndarray,
    target_dofs: np.ndarray,
    x_design: np.ndarray,
) -> _FormFindingSystem:
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
    side_nodes = np.concatenate(side_nodes)
    across_dir = np.concatenate(across)

    v_z = ca.SX.sym("height", len(z_unknown))
    v_side = ca.SX.sym("sideways", len(side_nodes))
    v_arm = ca.SX.sym("arm_setting", 2 * n_arm)
    v_drop = ca.SX.sym("dropper_length", len(drops))
    v_ref = ca.SX.sym("spring_reference", len(disc.spring_dofs))
    p = ca.SX.sym("target_height", len(target_dofs))

    # Coordinates as functions of the unknowns and the targets; a pivot sits at its clamp's design
    # point plus a·normal + b·e_z.
    xs = ca.SX.sym("x", disc.n_dofs)
    x = ca.SX(x_design.astype(float))
    x[target_dofs.tolist()] = p
    x[(3 * z_unknown + 2).tolist()] = v_z
    for c in range(2):
        x[(3 * side_nodes + c).tolist()] = ca.DM(base[side_nodes, c]) + v_side * ca.DM(across_dir[:, c])
    for j, (pivot, mast) in enumerate(zip(disc.arm_pivot_nodes, disc.arm_masts)):
        normal = disc.mast_normal[mast]
        for c in range(3):
            x[3 * pivot + c] = base[reg_nodes[j], c] + v_arm[2 * j] * normal[c] + (v_arm[2 * j + 1] if c == 2 else 0)

    is_wire = wire_tension > 0
    others = np.flatnonzero(~is_wire)
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
    gradient = ca.Function("gradient", [xs, v_drop, v_ref], [ca.gradient(energy, xs)])(x, v_drop, v_ref)

    vertical = gradient[(3 * z_free + 2).tolist()]
    sideways_balance = sum(gradient[(3 * side_nodes + c).tolist()] * ca.DM(across_dir[:, c]) for c in range(2))
    balance_across = [
        ca.dot(gradient[3 * node : 3 * node + 3], ca.DM(disc.mast_normal[mast]))
        for node, mast in zip(reg_nodes, disc.arm_masts)
    ]
    arm_start = []
    for j, mast in enumerate(disc.arm_masts):
        rel = base[disc.arm_pivot_nodes[j]] - base[reg_nodes[j]]
        arm_start += [float(rel @ disc.mast_normal[mast]), float(rel[2])]
    return _FormFindingSystem(
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


def solve_form_finding(
    disc: Discretisation,
    params: PhysicalParameters,
    wire_tension: np.ndarray,
    target_dofs: np.ndarray,
    x_design: np.ndarray,
) -> FormFindingSolution:
    """Solve the form-finding equations with IPOPT.

    The wire nodes keep their designed position along the wire (droppers vertical, clamps where the
    design puts them), so every wire element acts as a string of constant horizontal tension H:
    energy ``H l_h + H/(2 l_h₀) (Δz)²`` with ``l_h`` its horizontal length. Unknowns: the heights
    of the wire nodes, their sideways (in-plan, across the wire) positions, the dropper unstretched
    lengths, the steady-arm pivot positions (across the track and vertically, in the mast plane) and
    the ground-spring references. Equations: vertical and sideways equilibrium at every free node,
    equilibrium across the track at every steady-arm clamp (whose lateral position is the stagger),
    and the designed height at ``target_dofs``. The system is
    square; IPOPT solves it as a feasibility problem (zero objective).

    Parameters
    ----------
    disc : Discretisation
        Topology.
    params : PhysicalParameters
        Parameter values; dropper lengths and spring references are starting values.
    wire_tension : ndarray
        Horizontal tension of each axial element that is a wire segment, 0 for the others. [N]
    target_dofs : ndarray of int
        Degrees of freedom (heights) that must keep their design value.
    x_design : ndarray
        Design coordinates (first-guess pivots). [m]

    Raises
    ------
    ConvergenceError
        If IPOPT does not report success.
    """
    system = _form_finding_system(disc, params, wire_tension, target_dofs, x_design)
    solver = ca.nlpsol(
        "form_finding",
        "ipopt",
        {"x": system.unknowns, "p": system.targets, "f": ca.SX(0), "g": system.equations},
        {
            "print_time": False,
            "ipopt": {
                "print_level": 0,
                "sb": "yes",
                "tol": 1e-8,
                "constr_viol_tol": 1e-6,
                "max_iter": 100,
                "hessian_approximation": "limited-memory",
                "linear_solver": "mumps",
            },
        },
    )
    targets = x_design[target_dofs]
    result = solver(x0=system.start, p=targets, lbg=0, ubg=0)
    stats = solver.stats()
    if not stats.get("success", False):
        raise ConvergenceError(
            f"form-finding did not converge: IPOPT status {stats.get('return_status')!r} "
            f"after {stats.get('iter_count')} iterations",
            stats,
        )
    sol = np.asarray(result["x"]).ravel()
    positions = np.asarray(ca.Function("x_of_v", [system.unknowns, system.targets], [system.coordinates])(sol, targets)).ravel()
    start = len(system.z_unknown) + system.n_side + 2 * system.n_arm
    return FormFindingSolution(
        positions=positions.reshape(-1, 3),
        dropper_unstretched_length=sol[start : start + system.n_drop],
        spring_reference=sol[start + system.n_drop :],
        iterations=int(stats.get("iter_count", -1)),
    )


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
    disc, params, wire_tension, target_dofs
        As for :func:`solve_form_finding`; ``params`` holds the solved dropper lengths and spring
        references.
    positions : ndarray, shape (n_nodes, 3)
        The form-found coordinates. [m]

    Returns
    -------
    ndarray, shape (n_nodes, len(target_dofs))
        Height change of every node per unit change of each target height. [m/m]
    """
    x = positions.ravel()
    system = _form_finding_system(disc, params, wire_tension, target_dofs, x)
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
