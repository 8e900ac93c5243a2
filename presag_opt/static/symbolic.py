"""The CasADi boundary of the static model.

Everything symbolic lives here. The total potential energy of a discretised catenary is the sum of
element energies defined once as small named :class:`casadi.Function` objects (an axial element and
a bending triple, with their exact gradients and Hessians from CasADi's automatic differentiation);
:func:`build_potential` maps them over all elements and scatters the results into global vectors
and the fixed sparsity pattern of the tangent stiffness. The form-finding problem handed to IPOPT is
built here as well. Callers pass numpy arrays in and get numpy arrays (and SciPy sparse matrices) out.

Total potential energy (x: all node coordinates)::

    Π(x) = Σ_axial k/2 · (L − L0)²            (max(L − L0, 0)² where the element may go slack)
         + Σ_bending EI/(h1 + h2) · |(x_c − x_b)/h2 − (x_b − x_a)/h1|²
         + Σ_springs k_s/2 · (x_dof − ref)²
         − f · x

Equilibrium is ∂Π/∂x = 0 on the free degrees of freedom; the tangent stiffness is the Hessian.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from presag_opt.errors import ConvergenceError
from presag_opt.static.compiled import compile_elements, element_map
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


def _element_functions() -> tuple[ca.Function, ca.Function, ca.Function]:
    """Energy, gradient and Hessian of one axial element and of one bending triple (CasADi SX), and
    the axial energy alone (the line search needs only the energy).

    Axial: the energy depends on the nodes only through d = x_b − x_a, so the function takes d (3),
    stiffness k, unstretched length L0 and the slack flag, and returns the energy, ∂/∂d (3) and
    ∂²/∂d² (3×3); :class:`PotentialFunctions` expands them to the two nodes with signs ∓.
    Bending: inputs (x_a, x_b, x_c) stacked (9), EI, spacings h_ab and h_bc.
    """
    d = ca.SX.sym("d", 3)
    k, L0, slack = ca.SX.sym("k"), ca.SX.sym("L0"), ca.SX.sym("slack")
    stretch = ca.norm_2(d) - L0
    taut = (1 - slack) * stretch + slack * ca.fmax(stretch, 0)
    energy = 0.5 * k * taut**2
    hess, grad = ca.hessian(energy, d)
    axial = ca.Function("axial_element", [d, k, L0, slack], [energy, grad, ca.vec(hess)],
                        ["chord", "stiffness", "unstretched_length", "slack_allowed"], ["energy", "gradient", "hessian"])
    axial_energy = ca.Function("axial_energy", [d, k, L0, slack], [energy],
                               ["chord", "stiffness", "unstretched_length", "slack_allowed"], ["energy"])
    r = ca.SX.sym("r", 9)
    ei, h1, h2 = ca.SX.sym("ei"), ca.SX.sym("h1"), ca.SX.sym("h2")
    curvature = (r[6:9] - r[3:6]) / h2 - (r[3:6] - r[0:3]) / h1
    energy = ei / (h1 + h2) * ca.sumsqr(curvature)
    hess, grad = ca.hessian(energy, r)
    bending = ca.Function("bending_triple", [r, ei, h1, h2], [energy, grad, ca.vec(hess)],
                          ["x", "bending_stiffness", "spacing_ab", "spacing_bc"], ["energy", "gradient", "hessian"])
    return axial, bending, axial_energy


_AXIAL, _BENDING, _AXIAL_ENERGY = _element_functions()
compile_elements(_AXIAL, _AXIAL_ENERGY)  # the bending Hessian is constant: evaluated once per EI set


class _MappedCall:
    """A mapped CasADi function evaluated through its buffer interface.

    ``Function.__call__`` converts every numpy input to a DM and every DM output back through Python
    lists, which cost more than the evaluation itself in the Newton loops of the elasticity (about
    two thirds of ``presag elasticity``). The buffer interface reads and writes numpy arrays in
    place. One instance per thread (see :func:`_mapped_call`), since the buffers are shared state.

    Parameters
    ----------
    function : casadi.Function
        A mapped function whose inputs and outputs are dense (rows × elements); it may take more
        elements than are evaluated (padding up to whole compiled chunks, see
        :func:`~presag_opt.static.compiled.element_map`).
    count : int
        Elements evaluated: the first ``count`` columns. [-]
    """

    def __init__(self, function: ca.Function, count: int):
        self.count = count
        self.buffer, self.trigger = function.buffer()
        # CasADi stores an (rows × n) matrix column-major, i.e. as a C-ordered (n × rows) array.
        # Padding elements get inputs of 1 (finite results, discarded).
        self.inputs = [np.ones((function.size2_in(i), function.size1_in(i))) for i in range(function.n_in())]
        self.outputs = [np.zeros((function.size2_out(i), function.size1_out(i))) for i in range(function.n_out())]
        for i, a in enumerate(self.inputs):
            self.buffer.set_arg(i, memoryview(a))
        for i, a in enumerate(self.outputs):
            self.buffer.set_res(i, memoryview(a))

    def __call__(self, *inputs: np.ndarray) -> list[np.ndarray]:
        """Evaluate; inputs and returned outputs are (rows × count) arrays (the outputs are copies)."""
        for buffer, value in zip(self.inputs, inputs):
            np.copyto(buffer[: self.count], np.asarray(value).T)
        self.trigger()
        return [out[: self.count].T.copy() for out in self.outputs]


_CALLS = threading.local()


def _mapped_call(function: ca.Function, count: int) -> _MappedCall:
    """This thread's buffered evaluator of a mapped element function over ``count`` elements (kept by
    the function's name, which holds its mapped size, and the count)."""
    calls = _CALLS.__dict__.setdefault("calls", {})
    key = (function.name(), count)
    if key not in calls:
        if len(calls) >= 16:  # a few discretisations at a time; drop the oldest
            calls.pop(next(iter(calls)))
        calls[key] = _MappedCall(function, count)
    return calls[key]

# Entry (i, j) of the 6×6 element Hessian, column-major (j·6 + i), from the 3×3 one in d = x_b − x_a:
# H6[i, j] = σ_i σ_j H3[i mod 3, j mod 3] with σ = −1 on node a, +1 on node b.
_I6, _J6 = np.tile(np.arange(6), 6), np.repeat(np.arange(6), 6)
_AXIAL_ENTRY = (_J6 % 3) * 3 + _I6 % 3
_AXIAL_SIGNS = np.where(_I6 < 3, -1.0, 1.0) * np.where(_J6 < 3, -1.0, 1.0)


@dataclass(frozen=True)
class PotentialFunctions:
    """The total potential energy of one discretisation, assembled from CasADi element functions.

    The element energies, gradients and Hessians come from two small named CasADi functions
    (:func:`_element_functions`), evaluated for all elements at once (``Function.map``) and
    scattered into the global vectors and the fixed sparsity pattern of the free degrees of freedom.
    Ground springs and curve pins are quadratic and added directly.

    Attributes
    ----------
    discretisation : Discretisation
        Topology.
    free_dofs : ndarray of int
        Degrees of freedom that move in equilibrium (not supports, anchors or pivots). [-]
    solver : BandedSolver
        Ordering and factorisation of the tangent-stiffness pattern (free DOFs, CSC).
    """

    discretisation: Discretisation
    free_dofs: np.ndarray
    solver: BandedSolver
    _axial: ca.Function
    _axial_energy: ca.Function
    _bending: ca.Function | None
    _axial_dofs: np.ndarray  # (6, n_axial)
    _bending_dofs: np.ndarray  # (9, n_bending)
    _hessian_slots: np.ndarray  # data index of every axial-Hessian entry, -1 if it touches a fixed DOF
    _bending_slots: np.ndarray  # the same for the bending-Hessian entries
    _bending_rows: np.ndarray
    _bending_cols: np.ndarray
    _hessian_size: int

    def _element_terms(self, x: np.ndarray, params: PhysicalParameters):
        """Energies, gradients (6 per element) and Hessian entries (36 per element, in the order of
        ``_hessian_slots``) of the axial elements (one mapped CasADi call)."""
        energy, grad, hess = _mapped_call(self._axial, self._axial_dofs.shape[1])(*self._axial_inputs(x, params))
        grad6 = np.vstack([-grad, grad])
        hess6 = _AXIAL_SIGNS[:, None] * hess[_AXIAL_ENTRY]
        return energy.ravel(), grad6.ravel(), hess6.ravel()

    def _axial_inputs(self, x: np.ndarray, params: PhysicalParameters) -> tuple[np.ndarray, ...]:
        """Inputs of the mapped axial functions: chords x_b − x_a (3 × elements) and the parameters."""
        chord = x[self._axial_dofs[3:]] - x[self._axial_dofs[:3]]
        return chord, params.axial_stiffness[None, :], params.unstretched_length[None, :], params.slack_allowed[None, :]

    def _bending_terms(self, params: PhysicalParameters) -> tuple[sp.csr_matrix, np.ndarray]:
        """The bending energy is quadratic: its (constant) Hessian on all DOFs and its entries in
        the free-DOF pattern, computed once per set of EI values."""
        cache = self.__dict__.setdefault("_bending_cache", {})
        key = params.bending_stiffness.tobytes()
        if key not in cache:
            b = self.discretisation.bending
            hess = np.asarray(self._bending(
                np.zeros(self._bending_dofs.shape), params.bending_stiffness[None, :], b.spacing_ab[None, :],
                b.spacing_bc[None, :])[2]).ravel()
            n = self.discretisation.n_dofs
            matrix = sp.csr_matrix((hess, (self._bending_rows, self._bending_cols)), shape=(n, n))
            keep = self._bending_slots >= 0
            data = np.bincount(self._bending_slots[keep], weights=hess[keep], minlength=self._hessian_size)
            cache.clear()
            cache[key] = (matrix, data)
        return cache[key]

    def _extra_gradient(self, x: np.ndarray, params: PhysicalParameters) -> np.ndarray:
        disc = self.discretisation
        g = -params.nodal_force.copy()
        if len(disc.spring_dofs):
            np.add.at(g, disc.spring_dofs, params.spring_stiffness * (x[disc.spring_dofs] - params.spring_reference))
        if len(disc.pin_nodes):
            offset = x.reshape(-1, 3)[disc.pin_nodes] - disc.design_positions[disc.pin_nodes]
            across = PIN_STIFFNESS * np.sum(offset * disc.pin_normals, axis=1)
            for c in range(3):
                np.add.at(g, 3 * disc.pin_nodes + c, across * disc.pin_normals[:, c])
        return g

    def gradient(self, x: np.ndarray, params: PhysicalParameters) -> np.ndarray:
        """∂Π/∂x at coordinates ``x`` (out-of-balance force, internal minus external). [N]"""
        g = self._extra_gradient(x, params)
        _, grad, _ = self._element_terms(x, params)
        g += np.bincount(self._axial_dofs.ravel(), weights=grad, minlength=len(g))
        if self._bending is not None:
            g += self._bending_terms(params)[0] @ x
        return g

    def hessian_values(self, x: np.ndarray, params: PhysicalParameters) -> tuple[np.ndarray, np.ndarray]:
        """Nonzeros of the free-DOF tangent stiffness (CSC order of ``solver.pattern``) and the
        free-DOF gradient at ``x``. [N/m], [N]"""
        disc = self.discretisation
        g = self._extra_gradient(x, params)
        _, grad, hess = self._element_terms(x, params)
        g += np.bincount(self._axial_dofs.ravel(), weights=grad, minlength=len(g))
        keep = self._hessian_slots >= 0
        values = np.bincount(self._hessian_slots[keep], weights=hess[keep], minlength=self._hessian_size)
        if self._bending is not None:
            matrix, data = self._bending_terms(params)
            g += matrix @ x
            values += data
        diagonal = np.zeros(disc.n_dofs)
        if len(disc.spring_dofs):
            np.add.at(diagonal, disc.spring_dofs, params.spring_stiffness)
        values += self._extra_diagonal(diagonal)
        return values, g[self.free_dofs]

    def _extra_diagonal(self, diagonal: np.ndarray) -> np.ndarray:
        """Ground springs (diagonal) and curve pins (3×3 blocks) in the pattern's data order."""
        slots = self.__dict__["_extra_slots"]
        disc = self.discretisation
        weights = [diagonal[slots["spring_dofs"]]] if len(slots["spring_dofs"]) else []
        if len(disc.pin_nodes):
            weights.append(slots["pin_values"])
        if not weights:
            return 0.0
        return np.bincount(np.concatenate(slots["indices"]), weights=np.concatenate(weights), minlength=self._hessian_size)

    def hessian(self, x: np.ndarray, params: PhysicalParameters) -> tuple[sp.csc_matrix, np.ndarray]:
        """Tangent stiffness (sparse) and gradient on the free degrees of freedom at ``x``. [N/m], [N]"""
        values, grad = self.hessian_values(x, params)
        return self.solver.matrix(values), grad

    def energy(self, x: np.ndarray, params: PhysicalParameters) -> float:
        """Total potential energy. [J]"""
        disc = self.discretisation
        count = self._axial_dofs.shape[1]
        total = -float(params.nodal_force @ x) + float(_mapped_call(self._axial_energy, count)(*self._axial_inputs(x, params))[0].sum())
        if self._bending is not None:
            total += 0.5 * float(x @ (self._bending_terms(params)[0] @ x))
        if len(disc.spring_dofs):
            total += float(0.5 * np.sum(params.spring_stiffness * (x[disc.spring_dofs] - params.spring_reference) ** 2))
        if len(disc.pin_nodes):
            offset = x.reshape(-1, 3)[disc.pin_nodes] - disc.design_positions[disc.pin_nodes]
            total += float(0.5 * PIN_STIFFNESS * np.sum(np.sum(offset * disc.pin_normals, axis=1) ** 2))
        return total


def build_potential(disc: Discretisation) -> PotentialFunctions:
    """Map the element functions over a discretisation and fix its tangent-stiffness pattern."""
    ax, b = disc.axial, disc.bending
    axial_dofs = np.vstack([3 * ax.node_a + c for c in range(3)] + [3 * ax.node_b + c for c in range(3)])
    bending_dofs = np.vstack([3 * n + c for n in (b.node_a, b.node_b, b.node_c) for c in range(3)])
    free = np.flatnonzero(~disc.fixed_dofs)
    position = np.full(disc.n_dofs, -1)
    position[free] = np.arange(len(free))

    rows, cols = [], []
    for dofs in (axial_dofs, bending_dofs) if len(b.node_a) else (axial_dofs,):
        m = dofs.shape[0]
        # ca.vec of an m×m Hessian is column-major: entry (i, j) at j·m + i; mapped outputs are
        # (entries × elements), flattened entry after entry
        i_idx = np.tile(np.arange(m), m)
        j_idx = np.repeat(np.arange(m), m)
        rows.append(dofs[i_idx, :].ravel())
        cols.append(dofs[j_idx, :].ravel())
    extra_rows, extra_cols = [disc.spring_dofs], [disc.spring_dofs]
    pin_values = []
    for node, normal in zip(disc.pin_nodes, disc.pin_normals):
        block = PIN_STIFFNESS * np.outer(normal, normal)
        for i in range(3):
            for j in range(3):
                extra_rows.append(np.array([3 * node + i]))
                extra_cols.append(np.array([3 * node + j]))
                pin_values.append(block[i, j])
    all_rows = np.concatenate(rows + extra_rows).astype(int)
    all_cols = np.concatenate(cols + extra_cols).astype(int)
    r, c = position[all_rows], position[all_cols]
    inside = (r >= 0) & (c >= 0)
    n_free = len(free)
    keys = np.where(inside, c.astype(np.int64) * n_free + r, -1)
    unique, inverse = np.unique(keys[inside], return_inverse=True)
    slots = np.full(len(keys), -1)
    slots[inside] = inverse
    pattern_cols = unique // n_free
    pattern = sp.csc_matrix(
        (np.ones(len(unique)), (unique % n_free, pattern_cols)), shape=(n_free, n_free)
    )
    pattern.sort_indices()
    n_axial_entries = len(rows[0])
    n_element_entries = sum(len(v) for v in rows)
    extra_slots = slots[n_element_entries:]
    n_spring = len(disc.spring_dofs)
    spring_slots = extra_slots[:n_spring]
    pin_slots = extra_slots[n_spring:]
    spring_keep = spring_slots >= 0
    pin_keep = pin_slots >= 0
    functions = PotentialFunctions(
        disc,
        free,
        BandedSolver.for_pattern(pattern),
        element_map(_AXIAL, len(ax))[0],
        element_map(_AXIAL_ENERGY, len(ax))[0],
        _BENDING.map(len(b.node_a)) if len(b.node_a) else None,
        axial_dofs,
        bending_dofs,
        slots[:n_axial_entries],
        slots[n_axial_entries:n_element_entries],
        rows[1] if len(rows) > 1 else np.zeros(0, dtype=int),
        cols[1] if len(cols) > 1 else np.zeros(0, dtype=int),
        len(unique),
    )
    functions.__dict__["_extra_slots"] = {
        "spring_dofs": disc.spring_dofs[spring_keep],
        "pin_values": np.asarray(pin_values)[pin_keep] if len(pin_values) else np.zeros(0),
        "indices": [spring_slots[spring_keep], pin_slots[pin_keep]],
    }
    return functions


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
        Degrees of freedom (heights) that must keep their design value. [-]
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
    disc : Discretisation
        As for :func:`solve_form_finding`.
    params : PhysicalParameters
        As for :func:`solve_form_finding`, holding the solved dropper lengths and spring references.
    wire_tension : ndarray
        As for :func:`solve_form_finding`. [N]
    target_dofs : ndarray of int
        As for :func:`solve_form_finding`. [-]
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
