"""The catenary as a dynamic structure, linearised about its static equilibrium.

:func:`structural_model` turns a form-found :class:`~presag_opt.static.equilibrium.EquilibriumState`
into the matrices of ``M a + C v + K u = f`` for displacements ``u`` measured from that equilibrium,
plus the one nonlinearity of the catenary that matters for pantograph–catenary interaction: droppers
carry tension only.

Degrees of freedom: 3-D
    The model keeps every free translation of the static model (x along the track, y lateral, z up;
    about 7 200 DOFs for 10 spans of 60 m at 0.5 m elements). A vertical-plane model was tried and
    rejected, because neither way of getting one reproduces the static elasticity:

    - *Dropping* the x and y DOFs (holding them fixed) leaves the sagging wires' axial stiffness EA in
      the vertical stiffness: ``k·e_z²`` per element, with k = EA/h ≈ 29 MN/m and slopes e_z of
      0.004–0.04, is as large as the string stiffness T/h ≈ 20 kN/m it should sit beside. In the
      real system (and the 3-D model) the wires slide along the track towards the balance weights
      and relieve that stretch. Measured against :func:`~presag_opt.elasticity.linear_elasticity`:
      elasticity 75 % (EN 50318-style model) to 100 % (ST 9,8/9,8) wrong.
    - *Condensing* them statically (K_zz − K_zh K_hh⁻¹ K_hz, exact for statics) gives a dense
      matrix: the sliding wire chains and the lateral string of the contact wire between steady arms
      couple every vertical DOF with every other. The couplings beyond 1 m are small (below 1e-5 of
      the diagonal) but coherent; dropping them changes the elasticity by 0.1–0.5 %, and keeping
      them makes every time step a dense solve.

    The 3-D model costs about 0.3 ms per linear solve at 7 200 DOFs (0.06 ms for the 2 400 vertical
    DOFs) and needs no approximation: its static response is exactly the linear elasticity of the
    static model, stagger, steady arms and curves included.

Mass: lumped
    The node masses of the discretisation (wire mass shared between an element's two nodes,
    dropper clamps, half a steady arm, support masses) on each of the node's three translations.
    Lumped masses keep M diagonal (no extra fill in the effective matrix). With the linear
    string-like wire elements the phase speed falls below sqrt(T/ρ) by 1 − sin(kh/2)/(kh/2) ≈
    (kh)²/24: 1.8 % for 20 Hz waves on ST 9,8/9,8 (wavelength c/f = 4.8 m) at 0.5 m elements,
    0.5 % at 0.25 m. Ahead of a fast pantograph the waves it meets at 20 Hz are shorter,
    (c − v)/f: 1.9 m at 300 km/h on the EN 50318-style wire, where 0.5 m elements are 11 % slow;
    there (β ≈ 0.7) σ needs 0.25 m elements (see the convergence figures of issue 4). The half-arm
    mass at the clamp overstates the rotary inertia of a uniform arm (m/3 at the tip) by 1/6 of
    the arm mass (0.17 kg, against about 0.6 kg of wire and clamps at a registration node).

Stiffness: the tangent stiffness at the equilibrium
    The Hessian of the static model's potential energy on the free DOFs
    (:meth:`EquilibriumState.tangent_stiffness`): material and geometric stiffness of wires, droppers and steady arms,
    bending of the wires, support springs. Small displacements about the equilibrium: geometric
    nonlinearity is left out. Against re-solved equilibria (tension-only droppers in both) the
    uplift under a point load agrees within 0.03 % on the EN 50318-style model (spring supports) at
    120 N; with steady arms (ST 9,8/9,8, arms inclined 24°) the arm's rotation makes the wire near
    a mast up to 1.7 % softer at 120 N (6 % at 200 N) than the linear model, mid-span within 0.2 %.

Damping: Rayleigh, C = α M + β K
    From the catenary's ``damping``: Rayleigh coefficients as given (the EN 50318 reference model
    has α = 0.0125 1/s, β = 1e-4 s), or a modal damping ratio ζ (the paper's 0.02) turned into the
    Rayleigh pair that gives exactly ζ at both ends of a frequency band [f1, f2]
    (:func:`rayleigh_coefficients`): ζ(f) = α/(4πf) + βπf lies below ζ inside the band (lowest,
    2ζ·sqrt(f1 f2)/(f1 + f2), at sqrt(f1 f2)) and above it outside. Default band 1–20 Hz: 20 Hz is
    the upper end of the evaluated contact force (EN 50367 low-pass), and 1 Hz the lowest vertical
    modes of a 60 m span (half a wavelength per span at the combined wave speed of the two wires,
    sqrt((T_CW + T_MW)/(ρ_CW + ρ_MW)) ≈ 110 m/s for ST 9,8/9,8, gives 0.9 Hz). With ζ = 0.02 the
    ratio dips to 0.0085 at 4.5 Hz.

Tension-only droppers
    The linear model carries every dropper at its static preload N0 with its full tangent stiffness.
    A dropper is a tension-only Kelvin–Voigt element along its axis e: where its axial force
    N = N0 + k e·(Δu_MW − Δu_CW) + β k e·(Δv_MW − Δv_CW) would drop below zero it is slack, and a
    nonlinear force on its six DOFs removes that axial force, −N·[−e, e]
    (:meth:`StructuralModel.dropper_slack_force`). This is the physical nonlinearity of the catenary
    (droppers unload near the pantograph and near the masts).

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, section 2 (structural
damping ratio 0.02, tension-only droppers, 3-D model with steady arms).
R. W. Clough, J. Penzien, *Dynamics of Structures*, 2nd ed., McGraw-Hill 1993, section 12-5
(Rayleigh damping from two modal damping ratios).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from presag_opt.dynamics import laws
from presag_opt.dynamics.assembly import force_contribution
from presag_opt.dynamics.step_solvers import NO_FORCE, NonlinearForce
from presag_opt.errors import ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.linearised import TensionOnlyStructure, dropper_directions
from presag_opt.system.components import Damping
from presag_opt.system.quantity import quantity, validate_fields

DEFAULT_DAMPING = Damping(ratio=0.02)
"""Structural damping used when the catenary file gives none: the paper's ratio 0.02 (section 2)."""


@dataclass(frozen=True, kw_only=True)
class StructureSettings:
    """Modelling choices of the dynamic structure that are not physical data.

    Attributes
    ----------
    damping_band : tuple of float
        Frequencies (f1, f2) at which a modal damping ratio is met exactly by the Rayleigh
        coefficients (see :func:`rayleigh_coefficients`). [Hz]
    """

    damping_band: tuple[float, float] = quantity("frequency", 0.01, 1000.0, display="Hz", default=(1.0, 20.0))

    def __post_init__(self) -> None:
        object.__setattr__(self, "damping_band", tuple(float(f) for f in self.damping_band))
        validate_fields(self)
        if len(self.damping_band) != 2 or not self.damping_band[0] < self.damping_band[1]:
            raise ModelError(
                f"damping_band = {list(self.damping_band)} Hz must be two frequencies (f1, f2) with f1 < f2"
            )


def rayleigh_coefficients(ratio: float, band: tuple[float, float]) -> tuple[float, float]:
    """Rayleigh coefficients that give a damping ratio exactly at two frequencies.

    ζ(ω) = α/(2ω) + β·ω/2 equals ``ratio`` at ω1 = 2π f1 and ω2 = 2π f2 for
    α = 2ζ ω1 ω2/(ω1 + ω2) and β = 2ζ/(ω1 + ω2).

    Parameters
    ----------
    ratio : float
        Modal damping ratio ζ. [-]
    band : tuple of float
        The two frequencies (f1, f2). [Hz]

    Returns
    -------
    alpha : float
        Mass-proportional coefficient. [1/s]
    beta : float
        Stiffness-proportional coefficient. [s]

    References
    ----------
    Clough & Penzien, *Dynamics of Structures*, 2nd ed. (1993), eq. (12-38).
    """
    w1, w2 = (2.0 * math.pi * f for f in band)
    return 2.0 * ratio * w1 * w2 / (w1 + w2), 2.0 * ratio / (w1 + w2)


@dataclass(frozen=True, kw_only=True)
class DropperLinearisation:
    """The droppers of the structural model about their static state (arrays in along-track order).

    Attributes
    ----------
    dofs : ndarray of int, shape (n, 6)
        Model DOFs (x, y, z of the contact-wire clamp, then of the messenger-wire clamp). [-]
    direction : ndarray, shape (n, 3)
        Unit vector from the contact-wire clamp to the messenger-wire clamp. [-]
    axial_stiffness : ndarray, shape (n,)
        Material stiffness k of the dropper (force per unit stretch). [N/m]
    preload : ndarray, shape (n,)
        Static tensile force N0. [N]
    station : ndarray, shape (n,)
        Along-track distance from the first mast. [m]
    span : ndarray of int, shape (n,)
        Span of each dropper, from 0. [-]
    gradient : ndarray, shape (n, 6)
        Derivative of each dropper's stretch e·(Δu_MW − Δu_CW) with respect to its six DOFs, [−e, e]. [-]
    """

    dofs: np.ndarray
    direction: np.ndarray
    axial_stiffness: np.ndarray
    preload: np.ndarray
    station: np.ndarray
    span: np.ndarray
    gradient: np.ndarray

    def __len__(self) -> int:
        return len(self.preload)


@dataclass(frozen=True)
class StructuralModel:
    """Mass, damping and stiffness of a catenary about a static equilibrium, with its droppers.

    Model DOF i is the static model's free DOF ``state.model.functions.free_dofs[i]``; all
    displacements are measured from the equilibrium ``state``.

    Attributes
    ----------
    state : EquilibriumState
        The equilibrium linearised about.
    mass : scipy.sparse.csr_matrix
        Lumped (diagonal) mass matrix. [kg]
    stiffness : scipy.sparse.csr_matrix
        Tangent stiffness at the equilibrium, all droppers taut. [N/m]
    damping : scipy.sparse.csr_matrix
        Rayleigh damping α M + β K. [N·s/m]
    rayleigh_alpha : float
        Mass-proportional damping coefficient α. [1/s]
    rayleigh_beta : float
        Stiffness-proportional damping coefficient β. [s]
    damping_source : Damping
        The damping specification the coefficients come from.
    cw_z : ndarray of int
        Model DOF of the vertical displacement of each contact-wire node (along-track order). [-]
    cw_height : ndarray
        Static height of each contact-wire node. [m]
    support_z : ndarray of int
        Model DOF of the vertical displacement of the contact wire at each mast (steady-arm or
        support point). [-]
    droppers : DropperLinearisation
        Dropper data for the tension-only law.
    """

    state: EquilibriumState
    mass: sp.csr_matrix
    stiffness: sp.csr_matrix
    damping: sp.csr_matrix
    rayleigh_alpha: float
    rayleigh_beta: float
    damping_source: Damping
    cw_z: np.ndarray
    cw_height: np.ndarray
    support_z: np.ndarray
    droppers: DropperLinearisation

    @property
    def n_dofs(self) -> int:
        """Number of model DOFs."""
        return self.mass.shape[0]

    @property
    def global_dofs(self) -> np.ndarray:
        """Degree of freedom of the static model (3·node + component) of each model DOF."""
        return self.state.model.functions.free_dofs

    def damping_ratio(self, frequency: float | np.ndarray) -> float | np.ndarray:
        """Modal damping ratio of the Rayleigh damping at a frequency, α/(2ω) + βω/2. [-]

        Parameters
        ----------
        frequency : float or ndarray
            Frequency. [Hz]
        """
        omega = 2.0 * np.pi * np.asarray(frequency, dtype=float)
        return self.rayleigh_alpha / (2.0 * omega) + self.rayleigh_beta * omega / 2.0

    def dropper_force(self, u: np.ndarray, v: np.ndarray | None = None) -> np.ndarray:
        """Tensile force of every dropper, zero when slack. [N]

        The axial force of the linearised dropper, N0 + k e·(Δu_MW − Δu_CW) + β k e·(Δv_MW − Δv_CW)
        (its share of the stiffness-proportional damping included), cut off at zero.

        Parameters
        ----------
        u : ndarray
            Displacements from the equilibrium; the model DOFs first (entries after them, such as
            pantograph DOFs, are ignored). [m]
        v : ndarray, optional
            Velocities, laid out like ``u``. [m/s]
        """
        return laws.dropper_tension(self._axial_force(u, v))

    def _axial_force(self, u: np.ndarray, v: np.ndarray | None) -> np.ndarray:
        """Axial force of every dropper, N = N0 + k e + β_R k ė (:func:`~presag_opt.dynamics.laws.dropper_axial_force`). [N]"""
        d = self.droppers
        stretch = np.einsum("ij,ij->i", u[d.dofs], d.gradient)
        if v is None:
            return laws.dropper_axial_force(d.preload, d.axial_stiffness, stretch, 0.0, 0.0)
        rate = np.einsum("ij,ij->i", v[d.dofs], d.gradient)
        return laws.dropper_axial_force(d.preload, d.axial_stiffness, stretch, rate, self.rayleigh_beta)

    def dropper_slack_force(self, u: np.ndarray, v: np.ndarray | None = None) -> NonlinearForce:
        """Force that removes the axial force of the slack droppers.

        A dropper is slack where its axial force N = N0 + k e·(Δu_MW − Δu_CW) + β k e·(Δv_MW − Δv_CW)
        is below zero; the force −N·[−e, e] on its six DOFs then cancels the axial part of its linear
        contribution (static preload, stiffness k e eᵀ and its Rayleigh damping β k e eᵀ). Its
        transverse geometric stiffness N0/L (I − e eᵀ) stays: about 100 N/m against the 2T/h ≈ 40 kN/m
        of the contact wire at a clamp, and it keeps the force law continuous, which Newton's method
        needs (removing it too makes the force jump where N changes sign, and the iterations cycle).

        Parameters
        ----------
        u : ndarray
            Model displacements. [m]
        v : ndarray, optional
            Model velocities; without them the damping part is left out (statics). [m/s]

        Returns
        -------
        NonlinearForce
            On the DOFs of the slack droppers, with stiffness −k B Bᵀ and damping −β k B Bᵀ,
            B = [−e, e].
        """
        axial = self._axial_force(u, v)
        slack = np.flatnonzero(laws.dropper_slack(axial))
        if not len(slack):
            return NO_FORCE
        d = self.droppers
        force, blocks = np.empty((len(slack), 6)), np.empty((len(slack), 6, 6))
        for i, dropper in enumerate(slack):
            force_contribution(-axial[dropper], -d.axial_stiffness[dropper], d.gradient[dropper], force[i], blocks[i])
        block = _block_diagonal(blocks)
        return NonlinearForce(
            dofs=d.dofs[slack].ravel(),
            force=force.ravel(),
            stiffness=block,
            damping=self.rayleigh_beta * block,
        )

    def static_response(self, load: np.ndarray, *, max_iterations: int = 30) -> np.ndarray:
        """Static displacement under extra loads, droppers tension-only.

        Solves K u + f_slack(u) = load, where f_slack removes the slack droppers (their preload and
        axial stiffness, as :meth:`dropper_slack_force` does): the problem of
        :class:`~presag_opt.static.linearised.TensionOnlyStructure`, which the elasticity's
        active-set method solves too, with one factorisation of K for every load.

        Parameters
        ----------
        load : ndarray, shape (n_dofs,)
            Nodal forces on the model DOFs. [N]
        max_iterations : int
            Active-set iterations allowed. [-]

        Returns
        -------
        ndarray
            Displacements from the equilibrium. [m]

        Raises
        ------
        ConvergenceError
            If the set of slack droppers does not settle.
        """
        displacement, _ = TensionOnlyStructure.of(self.state).displacement(load, max_iterations=max_iterations)
        return displacement


def structural_model(
    state: EquilibriumState,
    *,
    damping: Damping | None = None,
    settings: StructureSettings | None = None,
) -> StructuralModel:
    """Linearise a catenary about its static equilibrium for dynamic analysis.

    Parameters
    ----------
    state : EquilibriumState
        A form-found equilibrium (all droppers in tension).
    damping : Damping, optional
        Structural damping; default the system's own (the catenary's, or a lone wire's), or the
        paper's ratio 0.02 if it has none.
    settings : StructureSettings, optional
        Frequency band for a damping ratio.

    Returns
    -------
    StructuralModel

    Raises
    ------
    ModelError
        If a dropper is not in tension at the equilibrium, or a contact-wire node is held fixed
        vertically (the pantograph could not lift it).
    """
    settings = settings or StructureSettings()
    damping = damping or state.discretisation.damping or DEFAULT_DAMPING
    disc = state.discretisation
    free = state.model.functions.free_dofs
    position_of = np.full(disc.n_dofs, -1)
    position_of[free] = np.arange(len(free))

    cw_z = position_of[3 * disc.cw_nodes + 2]
    if np.any(cw_z < 0):
        node = disc.cw_nodes[np.flatnonzero(cw_z < 0)[0]]
        raise ModelError(
            f"contact-wire node {node} is held fixed vertically; the pantograph could not lift it (a lone wire "
            "needs spring supports: lone_wire_state(..., support_stiffness=...))"
        )

    stiffness = sp.csr_matrix(state.tangent_stiffness())
    mass = sp.diags(np.repeat(disc.node_mass, 3)[free], format="csr")
    if damping.ratio is not None:
        alpha, beta = rayleigh_coefficients(damping.ratio, settings.damping_band)
    else:
        alpha, beta = damping.rayleigh_alpha or 0.0, damping.rayleigh_beta or 0.0
    return StructuralModel(
        state=state,
        mass=mass,
        stiffness=stiffness,
        damping=(alpha * mass + beta * stiffness).tocsr(),
        rayleigh_alpha=alpha,
        rayleigh_beta=beta,
        damping_source=damping,
        cw_z=cw_z,
        cw_height=state.positions[disc.cw_nodes, 2].copy(),
        support_z=cw_z[np.searchsorted(disc.cw_nodes, disc.mast_cw_node)],
        droppers=_linearise_droppers(state, position_of),
    )


def _linearise_droppers(state: EquilibriumState, position_of: np.ndarray) -> DropperLinearisation:
    disc = state.discretisation
    elements = disc.dropper_elements
    a, b = disc.axial.node_a[elements], disc.axial.node_b[elements]
    nodes = np.column_stack([a, b])
    global_dofs = (3 * nodes[:, :, None] + np.arange(3)).reshape(len(elements), 6)
    dofs = position_of[global_dofs]
    if np.any(dofs < 0):
        i = int(np.flatnonzero(np.any(dofs < 0, axis=1))[0])
        raise ModelError(f"dropper {i + 1} is attached to a fixed node; droppers must hang between free wire nodes")
    e = dropper_directions(state)
    preload = state.dropper_forces()
    if np.any(preload <= 0.0):
        i = int(np.flatnonzero(preload <= 0.0)[0])
        raise ModelError(
            f"the dropper in span {disc.dropper_span[i] + 1} at {disc.dropper_position[i]:.2f} m is slack at the "
            "equilibrium; the dynamic model linearises about taut droppers"
        )
    return DropperLinearisation(
        dofs=dofs,
        direction=e,
        gradient=np.concatenate([-e, e], axis=1),
        axial_stiffness=state.params.axial_stiffness[elements],
        preload=preload,
        station=disc.mast_station[disc.dropper_span] + disc.dropper_position,
        span=disc.dropper_span.copy(),
    )


def _block_diagonal(blocks: np.ndarray) -> np.ndarray:
    """Dense block-diagonal matrix from a stack of equal square blocks, shape (n, b, b)."""
    n, b, _ = blocks.shape
    out = np.zeros((n * b, n * b))
    for i in range(n):
        out[i * b : (i + 1) * b, i * b : (i + 1) * b] = blocks[i]
    return out
