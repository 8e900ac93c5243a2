"""The total potential energy of a discretised catenary: the static problem, stated once.

The energy is the sum of element energies defined once as small named :class:`casadi.Function`
objects (an axial element and a bending triple, with their exact gradients and Hessians from
CasADi's automatic differentiation); :func:`build_potential` maps them over all elements and
scatters the results into global vectors and the fixed sparsity pattern of the tangent stiffness.
Callers pass numpy arrays in and get numpy arrays (and SciPy sparse matrices) out. How the problem
is solved lives elsewhere: Newton's method on this potential in :mod:`presag_opt.static.equilibrium_newton`, the
form-finding equations in :mod:`presag_opt.static.form_finding_equations` and their IPOPT solve in
:mod:`presag_opt.static.form_finding_solver`.

Total potential energy (x: all node coordinates)::

    Π(x) = Σ_axial k/2 · (L − L0)²            (max(L − L0, 0)² where the element may go slack)
         + Σ_bending EI/(h1 + h2) · |(x_c − x_b)/h2 − (x_b − x_a)/h1|²
         + Σ_springs k_s/2 · (x_dof − ref)²
         − f · x

Equilibrium is ∂Π/∂x = 0 on the free degrees of freedom; the tangent stiffness is the Hessian.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import scipy.sparse as sp

from presag_opt.native.casadi_elements import compile_elements, element_map
from presag_opt.static.banded_solver import BandedSolver
from presag_opt.static.discretisation import PIN_STIFFNESS, Discretisation

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


def spring_energy(stretch, stiffness):
    """Energy ½ k e² of linear springs (an axial element's strain, a ground spring, a pin across a
    curve), element by element, on CasADi expressions or NumPy arrays alike. [J]

    Parameters
    ----------
    stretch : casadi.SX or ndarray
        The spring's extension e. [m]
    stiffness : float, casadi.SX, DM or ndarray
        Its stiffness k. [N/m]
    """
    return 0.5 * stiffness * stretch**2


def axial_energy(length, stiffness, unstretched_length, slack_allowed):
    """Strain energy ½ k e² of axial elements, e = l − L0; where ``slack_allowed`` is 1 the element
    carries tension only (e cut at 0). CasADi expressions, element by element: the one statement of
    the law, for the potential's element function and the form-finding equations
    (:mod:`presag_opt.static.form_finding_equations`). [J]

    Parameters
    ----------
    length : casadi.SX
        Chord length l of each element. [m]
    stiffness : casadi.SX or DM
        Axial stiffness k = EA/L0. [N/m]
    unstretched_length : casadi.SX or DM
        L0. [m]
    slack_allowed : casadi.SX or DM
        1 for a tension-only element (a dropper), 0 for one that takes compression too. [-]
    """
    stretch = length - unstretched_length
    taut = (1 - slack_allowed) * stretch + slack_allowed * ca.fmax(stretch, 0)
    return spring_energy(taut, stiffness)


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
    energy = axial_energy(ca.norm_2(d), k, L0, slack)
    hess, grad = ca.hessian(energy, d)
    axial = ca.Function("axial_element", [d, k, L0, slack], [energy, grad, ca.vec(hess)],
                        ["chord", "stiffness", "unstretched_length", "slack_allowed"], ["energy", "gradient", "hessian"])
    energy_only = ca.Function("axial_energy", [d, k, L0, slack], [energy],
                              ["chord", "stiffness", "unstretched_length", "slack_allowed"], ["energy"])
    r = ca.SX.sym("r", 9)
    ei, h1, h2 = ca.SX.sym("ei"), ca.SX.sym("h1"), ca.SX.sym("h2")
    curvature = (r[6:9] - r[3:6]) / h2 - (r[3:6] - r[0:3]) / h1
    energy = ei / (h1 + h2) * ca.sumsqr(curvature)
    hess, grad = ca.hessian(energy, r)
    bending = ca.Function("bending_triple", [r, ei, h1, h2], [energy, grad, ca.vec(hess)],
                          ["x", "bending_stiffness", "spacing_ab", "spacing_bc"], ["energy", "gradient", "hessian"])
    return axial, bending, energy_only


_AXIAL, _BENDING, _AXIAL_ENERGY = _element_functions()
compile_elements(_AXIAL, _AXIAL_ENERGY)  # the bending Hessian is constant: evaluated once per EI set


class _MappedCall:
    """A mapped CasADi function evaluated through its buffer interface.

    ``Function.__call__`` converts every numpy input to a DM and every DM output back through Python
    lists, which cost more than the evaluation itself in the Newton loops of the elasticity (about
    two thirds of ``presag elasticity``). The buffer interface reads and writes numpy arrays in
    place. One instance per function and thread (:meth:`PotentialFunctions._call`), since the buffers
    are shared state.

    Parameters
    ----------
    function : casadi.Function
        A mapped function whose inputs and outputs are dense (rows × elements); it may take more
        elements than are evaluated (padding up to whole compiled chunks, see
        :func:`~presag_opt.native.casadi_elements.element_map`).
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
    _extra_slots: dict  # data indices and values of the ground springs and curve pins (build_potential)
    _bending_memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    """The bending Hessian of the last set of EI values (:meth:`_bending_terms`)."""
    _threads: threading.local = field(default_factory=threading.local, init=False, repr=False, compare=False)
    """Each thread's buffered evaluators of the mapped axial functions (:meth:`_call`)."""

    def _call(self, function: ca.Function) -> _MappedCall:
        """This thread's buffered evaluator of one of the mapped axial functions (built on first use)."""
        calls = getattr(self._threads, "calls", None)
        if calls is None:
            calls = self._threads.calls = {}
        if function.name() not in calls:
            calls[function.name()] = _MappedCall(function, self._axial_dofs.shape[1])
        return calls[function.name()]

    def _element_terms(self, x: np.ndarray, params: PhysicalParameters):
        """Energies, gradients (6 per element) and Hessian entries (36 per element, in the order of
        ``_hessian_slots``) of the axial elements (one mapped CasADi call)."""
        energy, grad, hess = self._call(self._axial)(*self._axial_inputs(x, params))
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
        cache = self._bending_memo
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
        """∂Π/∂x at coordinates ``x`` (out-of-balance force, internal minus external). [N]

        Parameters
        ----------
        x : ndarray, shape (n_dofs,)
            Nodal coordinates. [m]
        params : PhysicalParameters
            Physical parameters the functions are evaluated with.
        """
        g = self._extra_gradient(x, params)
        _, grad, _ = self._element_terms(x, params)
        g += np.bincount(self._axial_dofs.ravel(), weights=grad, minlength=len(g))
        if self._bending is not None:
            g += self._bending_terms(params)[0] @ x
        return g

    def hessian_values(self, x: np.ndarray, params: PhysicalParameters) -> tuple[np.ndarray, np.ndarray]:
        """Nonzeros of the free-DOF tangent stiffness (CSC order of ``solver.pattern``) and the
        free-DOF gradient at ``x``. [N/m], [N]

        Parameters
        ----------
        x : ndarray, shape (n_dofs,)
            Nodal coordinates. [m]
        params : PhysicalParameters
            Physical parameters the functions are evaluated with.
        """
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
        slots = self._extra_slots
        disc = self.discretisation
        weights = [diagonal[slots["spring_dofs"]]] if len(slots["spring_dofs"]) else []
        if len(disc.pin_nodes):
            weights.append(slots["pin_values"])
        if not weights:
            return 0.0
        return np.bincount(np.concatenate(slots["indices"]), weights=np.concatenate(weights), minlength=self._hessian_size)

    def hessian(self, x: np.ndarray, params: PhysicalParameters) -> tuple[sp.csc_matrix, np.ndarray]:
        """Tangent stiffness (sparse) and gradient on the free degrees of freedom at ``x``. [N/m], [N]

        Parameters
        ----------
        x : ndarray, shape (n_dofs,)
            Nodal coordinates. [m]
        params : PhysicalParameters
            Physical parameters the functions are evaluated with.
        """
        values, grad = self.hessian_values(x, params)
        return self.solver.matrix(values), grad

    def energy(self, x: np.ndarray, params: PhysicalParameters) -> float:
        """Total potential energy. [J]

        Parameters
        ----------
        x : ndarray, shape (n_dofs,)
            Nodal coordinates. [m]
        params : PhysicalParameters
            Physical parameters the functions are evaluated with.
        """
        disc = self.discretisation
        axial = self._call(self._axial_energy)(*self._axial_inputs(x, params))[0]
        total = -float(params.nodal_force @ x) + float(axial.sum())
        if self._bending is not None:
            total += 0.5 * float(x @ (self._bending_terms(params)[0] @ x))
        if len(disc.spring_dofs):
            total += float(np.sum(spring_energy(x[disc.spring_dofs] - params.spring_reference, params.spring_stiffness)))
        if len(disc.pin_nodes):
            offset = x.reshape(-1, 3)[disc.pin_nodes] - disc.design_positions[disc.pin_nodes]
            total += float(np.sum(spring_energy(np.sum(offset * disc.pin_normals, axis=1), PIN_STIFFNESS)))
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
        {
            "spring_dofs": disc.spring_dofs[spring_keep],
            "pin_values": np.asarray(pin_values)[pin_keep] if len(pin_values) else np.zeros(0),
            "indices": [spring_slots[spring_keep], pin_slots[pin_keep]],
        },
    )
    return functions
