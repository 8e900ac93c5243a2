"""The installed line: a form-found section built with installation errors, re-solved or linearised.

A crew cuts the droppers to the schedule of the form-found state, each with its error, and sets the
supports at their heights, each with its error; the line then hangs where equilibrium puts it — it is
not form-found back to the target. :func:`installed_state` re-solves that equilibrium (Newton's
method on the potential energy, :meth:`EquilibriumState.solve`, from the nominal geometry) with

- each dropper's unstretched length L0 + δL (its axial stiffness EA/L0 scaled to the new length),
- each steady-arm pivot (or, on spring supports, the spring's unloaded end) raised by the
  registration error,
- each messenger-wire support (pinned, or the spring's unloaded end) raised by its error.

:class:`InstallationResponse` is the fast path for many samples: the same equilibrium linearised on
the nominal structure. For error vector ε, the out-of-balance force of the nominal geometry changes by
(∂g/∂ε)·ε and the free degrees of freedom move by δx = −K⁻¹(∂g/∂ε)·ε (K the tangent stiffness of the
nominal state), the held ones by the support shift itself: the installed geometry is affine in the
errors, as the form-found geometry is affine in the dropper target heights
(:func:`~presag_opt.static.form_finding.dropper_height_sensitivity`, the implicit-function theorem on
the same equations with the lengths as unknowns instead of parameters). ∂g/∂ε is taken by central
differences of the gradient with a step a tenth of the smallest dropper stretch: droppers are nearly
inextensible (their static stretch is a few hundredths of a millimetre), so a step as large as an
installation error would make a dropper slack at the nominal geometry and the difference would
straddle the kink of its tension-only law. Within the step the gradient is linear in the dropper
lengths (their energy is quadratic in L0) and smooth in the support shifts.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.robust.installation import InstallationSample
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.potential import PhysicalParameters

STEP_SHARE = 0.1
"""Step of the central differences of the out-of-balance force per error, as a share of the smallest
static dropper stretch. [-]"""


@dataclass(frozen=True)
class _Supports:
    """Where each mast's two support errors act: the held coordinate (fixed DOF) or the spring entry."""

    cw_position: np.ndarray  # per mast: flat position index of the held coordinate, or −1
    cw_spring: np.ndarray  # per mast: index into spring_reference, or −1
    mw_position: np.ndarray
    mw_spring: np.ndarray


def _supports(state: EquilibriumState) -> _Supports:
    disc = state.discretisation
    masts = len(disc.mast_station)
    spring_node = np.asarray(disc.spring_dofs) // 3
    fixed = np.asarray(disc.fixed_dofs, dtype=bool)

    def where(mast_nodes, arm_pivots):
        position, spring = np.full(masts, -1), np.full(masts, -1)
        for m, node in enumerate(mast_nodes):
            hit = np.flatnonzero((spring_node == node) & (np.asarray(disc.spring_dofs) % 3 == 2))
            if len(hit):
                spring[m] = hit[0]
            elif arm_pivots is not None and m in arm_pivots:
                position[m] = 3 * arm_pivots[m] + 2
            elif fixed[3 * node + 2]:
                position[m] = 3 * node + 2
            else:
                raise ModelError(f"installed line: mast {m + 1} holds its wire neither by a spring, a steady arm nor a "
                                 "pin; its height error cannot be placed")
        return position, spring

    pivots = {int(m): int(n) for m, n in zip(disc.arm_masts, disc.arm_pivot_nodes)}
    cw_position, cw_spring = where(disc.mast_cw_node, pivots)
    mw_position, mw_spring = where(disc.mast_mw_node, None)
    return _Supports(cw_position, cw_spring, mw_position, mw_spring)


def _check_shapes(state: EquilibriumState, dropper: np.ndarray, contact_wire: np.ndarray, messenger: np.ndarray) -> None:
    disc = state.discretisation
    n_drop, n_mast = len(disc.dropper_elements), len(disc.mast_station)
    if dropper.shape != (n_drop,) or contact_wire.shape != (n_mast,) or messenger.shape != (n_mast,):
        raise ModelError(f"installed line: give {n_drop} dropper errors and {n_mast} errors per support row, got "
                         f"{dropper.shape}, {contact_wire.shape}, {messenger.shape}")


def _built(state: EquilibriumState, dropper: np.ndarray, contact_wire: np.ndarray,
           messenger: np.ndarray) -> tuple[np.ndarray, PhysicalParameters]:
    """Start positions (held coordinates moved) and element parameters of the line built with these
    errors, at the nominal geometry of the free coordinates. [m], -"""
    disc = state.discretisation
    _check_shapes(state, dropper, contact_wire, messenger)
    supports = _supports(state)
    params = state.params
    unstretched = params.unstretched_length.copy()
    stiffness = params.axial_stiffness.copy()
    drops = disc.dropper_elements
    cut = unstretched[drops] + dropper
    if np.any(cut <= 0.0):
        raise ModelError("installed line: a dropper error makes a dropper's cut length zero or negative")
    stiffness[drops] *= unstretched[drops] / cut  # EA/L0 of the longer or shorter dropper
    unstretched[drops] = cut
    reference = params.spring_reference.copy()
    x = state.positions.ravel().copy()
    for position, spring, error in ((supports.cw_position, supports.cw_spring, contact_wire),
                                    (supports.mw_position, supports.mw_spring, messenger)):
        held = position >= 0
        x[position[held]] += error[held]
        reference[spring[~held]] += error[~held]
    built = PhysicalParameters(**{**params.__dict__, "unstretched_length": unstretched,
                                  "axial_stiffness": stiffness, "spring_reference": reference})
    return x, built


def installed_state(state: EquilibriumState, sample: InstallationSample, index: int = 0) -> EquilibriumState:
    """The equilibrium of the line built from ``state`` with the errors of one realisation.

    Parameters
    ----------
    state : EquilibriumState
        The form-found (nominal) state; its dropper lengths are the schedule the crew cuts to, and it
        must carry no applied load.
    sample : InstallationSample
        Installation errors. [m]
    index : int
        Realisation of ``sample`` to build. [-]

    Returns
    -------
    EquilibriumState
        The installed line under gravity and the balance weights (droppers free to go slack).

    Raises
    ------
    ConvergenceError
        If Newton's method does not converge.
    """
    if np.any(state.applied_load != 0.0):
        raise ModelError("installed line: build from the form-found state, not from a loaded one")
    x, params = _built(state, sample.dropper[index], sample.contact_wire[index], sample.messenger[index])
    built = EquilibriumState(state.model, x.reshape(-1, 3), params, np.zeros_like(state.applied_load))
    return built.solve(np.zeros_like(state.applied_load))


@dataclass(frozen=True)
class InstallationResponse:
    """Node heights of the installed line, linearised in the installation errors on the nominal structure.

    Attributes
    ----------
    state : EquilibriumState
        The nominal (form-found) state.
    nodes : ndarray of int
        Nodes whose heights the response gives. [-]
    matrix : ndarray, shape (nodes, droppers + 2 masts)
        ∂z/∂ε of each node for each error, columns in the order of
        :meth:`InstallationSample.stacked`. [m/m]
    """

    state: EquilibriumState
    nodes: np.ndarray
    matrix: np.ndarray

    def heights(self, sample: InstallationSample) -> np.ndarray:
        """Height change of every node for every realisation (samples × nodes). [m]"""
        return sample.stacked() @ self.matrix.T


def installation_response(state: EquilibriumState, nodes: np.ndarray) -> InstallationResponse:
    """Linearised installation response of the given nodes' heights on the nominal structure.

    One central difference of the out-of-balance force per error (2·(droppers + 2·masts) gradient
    evaluations) and one multi-column back-substitution with the factorised tangent stiffness.

    Parameters
    ----------
    state : EquilibriumState
        The form-found (nominal) state.
    nodes : ndarray of int
        Nodes whose heights are wanted (e.g. :attr:`PathModel.nodes`). [-]
    """
    disc = state.discretisation
    funcs = state.model.functions
    free = funcs.free_dofs
    n_drop, n_mast = len(disc.dropper_elements), len(disc.mast_station)
    n_err = n_drop + 2 * n_mast
    drops = disc.dropper_elements
    stretch = state.element_lengths()[drops] - state.params.unstretched_length[drops]
    step = STEP_SHARE * float(stretch.min())
    if step <= 0.0:
        raise ModelError("installation response: a dropper of the nominal state is slack; linearise a taut state")
    slope = np.empty((len(free), n_err))
    shift = np.zeros((state.positions.size, n_err))
    for j in range(n_err):
        unit = np.zeros(n_err)
        unit[j] = step
        parts = (unit[:n_drop], unit[n_drop : n_drop + n_mast], unit[n_drop + n_mast :])
        x_up, p_up = _built(state, *parts)
        x_down, p_down = _built(state, *(-u for u in parts))
        slope[:, j] = (funcs.gradient(x_up, p_up)[free] - funcs.gradient(x_down, p_down)[free]) / (2 * step)
        shift[:, j] = (x_up - x_down) / (2 * step)
    moved = shift.copy()
    moved[free] = -state.factorised_stiffness().solve(slope)
    nodes = np.asarray(nodes, dtype=int)
    return InstallationResponse(state=state, nodes=nodes, matrix=moved[3 * nodes + 2])


@dataclass(frozen=True, kw_only=True)
class RealisationCheck:
    """One realisation built both ways: linearised on the nominal structure and fully re-solved.

    Attributes
    ----------
    height_difference : float
        Largest |z_linearised − z_re-solved| over the path points. [m]
    height_change : float
        Largest |z_re-solved − z_nominal| over the path points (the size of the effect). [m]
    linearised_worst_case : float
        Worst-case waviness over the forces, nominal elasticity plus linearised geometry. [m]
    resolved_geometry_worst_case : float
        The same with the re-solved geometry and the nominal elasticity (separates the geometry's
        linearisation from the change of the elasticity). [m]
    resolved_worst_case : float
        The same from the re-solved state with its own elasticity curves. [m]
    """

    height_difference: float
    height_change: float
    linearised_worst_case: float
    resolved_geometry_worst_case: float
    resolved_worst_case: float


def check_realisation(path, forces: np.ndarray, sample: InstallationSample, index: int = 0,
                      response: InstallationResponse | None = None) -> RealisationCheck:
    """Build realisation ``index`` of ``sample`` linearised and re-solved, and compare them.

    The re-solved realisation gets its own elasticity curves (active-set, at the path model's force
    levels) and its own path model; its worst case is that of its own geometry. The linearised one
    keeps the nominal elasticity.

    Parameters
    ----------
    path : PathModel
        Path model of the nominal state (the design is its reference geometry).
    forces : ndarray
        Mean contact forces of the band. [N]
    sample : InstallationSample
        Installation errors. [m]
    index : int
        Realisation. [-]
    response : InstallationResponse, optional
        Linearised response of ``path.nodes`` (computed here by default).
    """
    from presag_opt.design.section import section_elasticity
    from presag_opt.robust.path import build_path_model

    response = response or installation_response(path.state, path.nodes)
    moved = response.heights(sample.row(index))[0]
    installed = installed_state(path.state, sample, index)
    resolved = installed.positions[path.nodes, 2] - path.state.positions[path.nodes, 2]
    base = path.heights(path.reference_depth, forces)

    def worst(z: np.ndarray) -> float:
        h = base + z[None, :]
        return max(float(np.ptp(h[:, path.node_span == s], axis=1).max()) for s in path.spans)

    section = section_elasticity(installed, force_levels=path.section.force_levels, elasticity_method="active-set")
    own = build_path_model(installed, section)
    return RealisationCheck(
        height_difference=float(np.abs(moved - resolved).max()),
        height_change=float(np.abs(resolved).max()),
        linearised_worst_case=worst(moved),
        resolved_geometry_worst_case=worst(resolved),
        resolved_worst_case=float(own.waviness(own.reference_depth, forces).max()),
    )
