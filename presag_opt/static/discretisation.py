"""Finite-element discretisation of a catenary tension section (geometry, elements, loads).

Nodes carry three translations (x along the track, y lateral, z up). Elements:

- *axial* two-node springs with energy ``k/2 (L - L0)^2`` (``L`` current length, ``L0`` unstretched
  length, ``k = EA/L0``): wire segments, droppers (tension only), steady arms;
- *bending* triples on the contact wire (and the messenger wire if it has EI): a rotation-free
  Euler–Bernoulli discretisation whose energy is ``EI/2 |r''|^2`` integrated along the wire, with the
  curvature vector ``r''`` taken from three consecutive nodes;
- *ground springs* on single degrees of freedom (EN 50318-style supports).

A stitched catenary also has a stitch wire at every inner mast (:mod:`presag_opt.static.stitch_elements`):
its own nodes, numbered after the wires, cable segments of group ``STITCH_WIRE`` and stitch droppers, which
are droppers like the others (in ``dropper_elements``).

Every span is split at the masts and the droppers, and each piece into equal elements no longer than
:attr:`StaticSettings.element_length`; the contact and messenger wire share the same stations, so
droppers are vertical in the design state.

A tension section is held at constant tension by balance weights at both ends: the end nodes are free
along the track and pulled outwards by the wire tension; a mid-point anchor (the along-track degree of
freedom of both wires at the central mast) removes the rigid sliding of the wires. The messenger wire
is pinned at the masts vertically and across the track but slides along it (swivelling cantilevers):
a sagging cable changes its length at first order under uplift, and holding it along the track too
would stiffen mid-span elasticity by about 12 % on ST 9,8/9,8. On curves, where the mast normal is
not the y axis, the across-track hold is a stiff spring along the normal
(:data:`PIN_STIFFNESS`). Spring supports (EN 50318 style) are for straight track only.

Plan geometry: masts lie on the track centre line, which is straight or, per span, a circular arc;
the contact wire is registered ``±stagger`` off the centre line, alternating, and the messenger wire
is vertically above it at the masts. Wire segments between masts are straight chords in plan. The
plan is turned so that the track runs along x at the mid-point anchor, where x is the held degree of
freedom: the anchor then holds the wires along the track on a curve too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.static.section_elements import (  # the element groups and types are re-exported here
    CONTACT_WIRE,
    DROPPER,
    GROUP_NAMES,
    MESSENGER_WIRE,
    STEADY_ARM,
    STITCH_WIRE,
    AxialElements,
    BendingTriples,
    SectionElements,
)
from presag_opt.static.section_geometry import (
    check_dropper_room,
    design_wire_positions,
    mast_normals,
    section_stations,
    steady_arm_pivots,
    track_plan,
)
from presag_opt.static.stitch_elements import add_stitch_wires
from presag_opt.system.catenary import Catenary
from presag_opt.system.components import GRAVITY, Damping, Wire
from presag_opt.system.quantity import quantity, validate_fields

__all__ = ["CONTACT_WIRE", "DROPPER", "GROUP_NAMES", "MESSENGER_WIRE", "PIN_STIFFNESS", "STEADY_ARM", "STITCH_WIRE",
           "AxialElements",
           "BendingTriples", "Discretisation", "StaticSettings", "discretise", "discretise_lone_wire"]

PIN_STIFFNESS = 1e9
"""Across-track stiffness of a messenger-wire pin on a curve: a kink force of ~1 kN moves it 1 μm. [N/m]"""


@dataclass(frozen=True, kw_only=True)
class StaticSettings:
    """Numerical settings of the static model (not physics).

    Attributes
    ----------
    element_length : float
        Longest element along the track. [m]
    force_tolerance : float
        Largest out-of-balance nodal force accepted at equilibrium. [N]
    geometry_tolerance : float
        Largest deviation from a form-finding target accepted. [m]
    max_newton_iterations : int
        Iteration limit of the equilibrium re-solve. [-]
    min_dropper_length : float
        Shortest buildable dropper; form-finding fails with a ModelError below it. [m]
    """

    element_length: float = quantity("length", 0.01, 5.0, default=0.5)
    force_tolerance: float = quantity("force", 1e-8, 1.0, default=1e-4)
    geometry_tolerance: float = quantity("length", 1e-9, 1e-3, default=5e-5)
    max_newton_iterations: int = 60
    min_dropper_length: float = quantity("length", 0.0, 2.0, default=0.1)

    def __post_init__(self) -> None:
        validate_fields(self, prefix="settings.")
        if not 1 <= self.max_newton_iterations <= 1000:
            raise ModelError(
                f"settings.max_newton_iterations = {self.max_newton_iterations} is outside the valid range [1, 1000]"
            )


@dataclass(frozen=True, kw_only=True)
class Discretisation:
    """Nodes, elements, supports and loads of a catenary section.

    Attributes
    ----------
    catenary : Catenary or None
        The system discretised (None for a lone wire, see :func:`discretise_lone_wire`).
    contact_wire : Wire
        The contact wire (of the catenary, or the lone wire): its tension, mass, EA and EI.
    damping : Damping or None
        Structural damping for dynamic analysis (the catenary's, or the lone wire's); None leaves
        the choice to the dynamic model.
    cw_tension : float
        Contact-wire tension. [N]
    settings : StaticSettings
        Numerical settings used.
    design_positions : ndarray, shape (n_nodes, 3)
        Node coordinates of the design state (target contact-wire geometry). [m]
    node_mass : ndarray, shape (n_nodes,)
        Lumped mass per node (wires, clamps, half steady arms, support masses). [kg]
    cw_nodes, mw_nodes : ndarray of int
        Contact / messenger wire nodes in along-track order. [-]
    cw_station : ndarray
        Along-track distance of each contact-wire node from the first mast. [m]
    mast_station : ndarray, shape (n_spans + 1,)
        Along-track distance of each mast from the first. [m]
    mast_cw_node, mast_mw_node : ndarray of int
        Contact / messenger wire node at each mast. [-]
    mast_normal : ndarray, shape (n_spans + 1, 3)
        Horizontal unit vector across the track at each mast (to the left). [-]
    axial : AxialElements
        Wire segments, droppers and steady arms.
    bending : BendingTriples
        Bending triples of the wires.
    dropper_elements : ndarray of int
        Indices into ``axial`` of the droppers, in along-track order. [-]
    dropper_span, dropper_position : ndarray
        Span (from 0) and distance from that span's first mast of each dropper. [-], [m]
    arm_elements, arm_pivot_nodes, arm_masts : ndarray of int
        Steady arms: element index, pivot node, mast index (empty with spring supports). [-]
    spring_dofs, spring_stiffness : ndarray
        Ground springs: degree of freedom and stiffness. [-], [N/m]
    spring_masts : ndarray of int
        Mast of each ground spring. [-]
    pin_nodes, pin_normals : ndarray
        Messenger-wire pins on curves: node and the horizontal direction they hold (stiffness
        :data:`PIN_STIFFNESS`). [-]
    fixed_dofs : ndarray of bool, shape (3 n_nodes,)
        Degrees of freedom held fixed in equilibrium (supports, anchor, pivots).
    termination_force : ndarray, shape (3 n_nodes,)
        Balance-weight pulls at the wire ends. [N]
    stitch_chains : tuple of ndarray of int
        Per stitched mast, the stitch wire's nodes along the track, its messenger-wire clamp nodes at
        the ends (empty for a simple catenary); the stitch-wire nodes are numbered after the wires. [-]
    stitch_dropper : ndarray of bool or None
        Per dropper (in ``dropper_elements`` order), whether it is a stitch dropper (None: none are).
    """

    catenary: Catenary | None
    contact_wire: Wire
    damping: Damping | None
    cw_tension: float
    settings: StaticSettings
    design_positions: np.ndarray
    node_mass: np.ndarray
    cw_nodes: np.ndarray
    mw_nodes: np.ndarray
    cw_station: np.ndarray
    mast_station: np.ndarray
    mast_cw_node: np.ndarray
    mast_mw_node: np.ndarray
    mast_normal: np.ndarray
    axial: AxialElements
    bending: BendingTriples
    dropper_elements: np.ndarray
    dropper_span: np.ndarray
    dropper_position: np.ndarray
    arm_elements: np.ndarray
    arm_pivot_nodes: np.ndarray
    arm_masts: np.ndarray
    spring_dofs: np.ndarray
    spring_stiffness: np.ndarray
    spring_masts: np.ndarray
    pin_nodes: np.ndarray
    pin_normals: np.ndarray
    fixed_dofs: np.ndarray
    termination_force: np.ndarray
    stitch_chains: tuple[np.ndarray, ...] = ()
    stitch_dropper: np.ndarray | None = None

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return len(self.design_positions)

    @property
    def n_dofs(self) -> int:
        """Number of degrees of freedom (3 per node)."""
        return 3 * self.n_nodes

    def gravity_force(self) -> np.ndarray:
        """Nodal weights as a force vector (z components negative). [N]"""
        f = np.zeros(self.n_dofs)
        f[2::3] = -GRAVITY * self.node_mass
        return f

    def cw_load_vector(self, station: float, force: float) -> np.ndarray:
        """Upward point force on the contact wire at an along-track station, as nodal forces.

        The force is shared between the two nodes of the element holding the station in
        proportion to the linear shape functions.

        Parameters
        ----------
        station : float
            Distance from the first mast along the track. [m]
        force : float
            Upward force. [N]
        """
        weights = self.cw_shape(np.atleast_1d(station))
        f = np.zeros(self.n_dofs)
        np.add.at(f, 3 * self.cw_nodes[weights.indices] + 2, force * weights.data)
        return f

    def cw_shape(self, stations: np.ndarray):
        """Sparse matrix (len(stations) x n_cw_nodes) of linear shape functions at the stations.

        Parameters
        ----------
        stations : ndarray
            Stations along the contact wire, inside the section. [m]
        """
        import scipy.sparse as sp

        s = np.asarray(stations, dtype=float)
        if np.any(s < self.cw_station[0] - 1e-9) or np.any(s > self.cw_station[-1] + 1e-9):
            raise ModelError(
                f"station {s.min():g}..{s.max():g} m lies outside the section [0, {self.cw_station[-1]:g}] m"
            )
        right = np.clip(np.searchsorted(self.cw_station, s, side="right"), 1, len(self.cw_station) - 1)
        left = right - 1
        h = self.cw_station[right] - self.cw_station[left]
        t = np.clip((s - self.cw_station[left]) / h, 0.0, 1.0)
        rows = np.repeat(np.arange(len(s)), 2)
        cols = np.column_stack([left, right]).ravel()
        vals = np.column_stack([1.0 - t, t]).ravel()
        return sp.csr_matrix((vals, (rows, cols)), shape=(len(s), len(self.cw_station)))

    def cw_element_compliance(self, stations: np.ndarray) -> np.ndarray:
        """Deflection per unit force of the contact wire inside its element, ends held. [m/N]

        A point force at local coordinate t of an element of length h deflects a tensioned string
        element with fixed ends by h·t(1 − t)/T (static condensation of the point inside the element).
        Linear shape functions miss this part, so it is added to the nodal (interpolated) uplift at
        the load point; without it the elasticity would dip between nodes.

        Parameters
        ----------
        stations : ndarray
            Stations along the contact wire. [m]
        """
        s = np.asarray(stations, dtype=float)
        right = np.clip(np.searchsorted(self.cw_station, s, side="right"), 1, len(self.cw_station) - 1)
        h = self.cw_station[right] - self.cw_station[right - 1]
        t = np.clip((s - self.cw_station[right - 1]) / h, 0.0, 1.0)
        return h * t * (1.0 - t) / self.cw_tension


def discretise(catenary: Catenary, settings: StaticSettings | None = None) -> Discretisation:
    """Build the finite-element discretisation of a catenary section in its design state.

    The design state has the contact wire on the pre-sag profile below the straight line between
    its supports (their designed heights at the masts) and a first guess of the messenger wire;
    form-finding then finds the dropper lengths and steady-arm settings that make it an equilibrium.
    Per-mast stagger, heights and steady-arm types come from the catenary's
    :class:`~presag_opt.system.masts.MastGeometry` where it has one.

    Parameters
    ----------
    catenary : Catenary
        System model.
    settings : StaticSettings, optional
        Numerical settings (element length).

    Returns
    -------
    Discretisation
    """
    settings = settings or StaticSettings()
    cat = catenary
    spans = np.asarray(cat.layout.span_lengths)
    n_spans = len(spans)
    stations = section_stations(cat, settings.element_length)
    anchor = n_spans // 2  # mast of the mid-point anchor
    # The plan is turned so that the track runs along x at the anchor: holding x there holds the
    # wires along the track, as the anchor does. Held along another direction on a curve, the
    # along-track force the anchor takes (the two halves' tension difference) would load the
    # steady arm there sideways and move the contact wire off its target height.
    track_xy, heading = track_plan(spans, np.asarray(cat.layout.radii), along_x_at=anchor)
    normal = mast_normals(heading)
    cw_pos, mw_pos = design_wire_positions(cat, stations, track_xy, normal)
    n_st = len(stations.station)
    cw_nodes = np.arange(n_st)
    mw_nodes = n_st + np.arange(n_st)
    mast_cw = stations.mast_nodes
    mast_mw = mw_nodes[mast_cw]

    parts = SectionElements(node_mass=np.zeros(2 * n_st), fixed=np.zeros((2 * n_st, 3), dtype=bool))
    for nodes, wire, grp, pos in ((cw_nodes, cat.contact_wire, CONTACT_WIRE, cw_pos),
                                  (mw_nodes, cat.messenger_wire, MESSENGER_WIRE, mw_pos)):
        parts.add_wire(nodes, wire, grp, pos)
    first_dropper = parts.n_axial
    dropper_lengths = mw_pos[stations.is_dropper, 2] - cw_pos[stations.is_dropper, 2]
    check_dropper_room(cat, stations, dropper_lengths, settings.min_dropper_length)
    n_droppers = parts.add_droppers(cat, cw_nodes[stations.is_dropper], mw_nodes[stations.is_dropper], dropper_lengths)
    stitch = add_stitch_wires(parts, cat, stations, cw_nodes, mw_nodes, cw_pos, mw_pos)
    # All droppers (the stitch droppers too) in along-track order of their contact-wire nodes.
    drop_elements = np.concatenate([first_dropper + np.arange(n_droppers), stitch.dropper_elements])
    drop_cw = np.concatenate([cw_nodes[stations.is_dropper], stitch.dropper_cw_nodes])
    order = np.argsort(drop_cw, kind="stable")
    drop_elements, drop_cw = drop_elements[order], drop_cw[order]
    parts.add_contact_wire_supports(cat.contact_wire_support, mast_cw)
    parts.add_messenger_wire_supports(cat.messenger_wire_support, mast_mw, normal)

    # Mid-point anchor: both wires fixed along the track (x, see above) at the central mast.
    parts.fixed[mast_cw[anchor], 0] = True
    parts.fixed[mast_mw[anchor], 0] = True

    wire_pos = np.vstack([cw_pos, mw_pos, stitch.positions])
    termination = _balance_weights(cat, cw_nodes, mw_nodes, heading, 3 * (len(wire_pos) + len(parts.arm_masts)))
    pivots = steady_arm_pivots(cat, wire_pos, cw_nodes, mast_cw, termination, parts.arm_masts)
    first_arm = parts.add_steady_arms()
    return Discretisation(
        catenary=cat,
        contact_wire=cat.contact_wire,
        damping=cat.damping,
        cw_tension=cat.contact_wire.tension,
        settings=settings,
        design_positions=np.vstack([wire_pos, pivots]) if len(pivots) else wire_pos,
        node_mass=parts.node_mass,
        cw_nodes=cw_nodes,
        mw_nodes=mw_nodes,
        cw_station=stations.station,
        mast_station=stations.mast_station,
        mast_cw_node=mast_cw,
        mast_mw_node=mast_mw,
        mast_normal=normal,
        axial=parts.axial(),
        bending=parts.bending(),
        dropper_elements=drop_elements,
        dropper_span=stations.span[drop_cw],
        dropper_position=stations.local[drop_cw],
        arm_elements=first_arm + np.arange(len(parts.arm_masts)),
        arm_pivot_nodes=np.asarray(parts.arm_b, dtype=int),
        arm_masts=np.asarray(parts.arm_masts, dtype=int),
        spring_dofs=np.asarray(parts.springs_dof, dtype=int),
        spring_stiffness=np.asarray(parts.springs_k, dtype=float),
        spring_masts=np.asarray(parts.springs_mast, dtype=int),
        pin_nodes=np.asarray(parts.pin_nodes, dtype=int),
        pin_normals=np.asarray(parts.pin_normals, dtype=float).reshape(-1, 3),
        fixed_dofs=parts.fixed.ravel(),
        termination_force=termination,
        stitch_chains=stitch.chains,
        stitch_dropper=np.isin(drop_elements, stitch.dropper_elements),
    )


def _balance_weights(cat: Catenary, cw_nodes: np.ndarray, mw_nodes: np.ndarray, heading: np.ndarray,
                     n_dofs: int) -> np.ndarray:
    """Balance-weight pulls: each wire end pulled outwards along the track by its tension. [N]"""
    n_spans = len(heading) - 1
    termination = np.zeros(n_dofs)
    for nodes, wire in ((cw_nodes, cat.contact_wire), (mw_nodes, cat.messenger_wire)):
        for end, mast, sign in ((nodes[0], 0, -1.0), (nodes[-1], n_spans, 1.0)):
            tangent = np.array([math.cos(heading[mast]), math.sin(heading[mast]), 0.0])
            termination[3 * end : 3 * end + 3] += sign * wire.tension * tangent
    return termination


def discretise_lone_wire(
    wire: Wire,
    length: float,
    settings: StaticSettings | None = None,
    *,
    support_stiffness: float | None = None,
    damping: Damping | None = None,
) -> Discretisation:
    """A single straight wire supported at both ends, held by a balance weight at its far end.

    For analytic checks (string and tensioned-beam solutions), wave-propagation tests and the
    simulator's moving-load check: the wire lies along x at z = 0, both ends are held laterally,
    the near end also along the track, and the far end is pulled along the track by the wire
    tension. It has two "masts" (its ends) and one span.

    Vertically the ends are pinned (held fixed), or, with ``support_stiffness``, held by vertical
    ground springs. The simulator needs the springs: the pantograph passes over the supports, and
    its contact model lifts the wire's nodes, so none may be fixed. A rigid support is then
    approximated by a stiff spring: the support yields F/k under a force F (1e-7 m at 100 N and
    1e9 N/m, against a mid-span string deflection F l/(4T) of order 0.1 m).

    Parameters
    ----------
    wire : Wire
        Tension, mass, EA and EI of the wire.
    length : float
        Distance between the supports. [m]
    settings : StaticSettings, optional
        Element length.
    support_stiffness : float, optional
        Vertical stiffness of each end support; None pins the ends. [N/m]
    damping : Damping, optional
        Structural damping for dynamic analysis (None: the dynamic model's default).
    """
    settings = settings or StaticSettings()
    if not 0.1 <= length <= 10000.0:
        raise ModelError(f"length = {length:g} m is outside the valid range [0.1, 10000] m")
    if support_stiffness is not None and not 1e3 <= support_stiffness <= 1e13:
        raise ModelError(
            f"support_stiffness = {support_stiffness:g} N/m is outside the valid range [1e3, 1e13] N/m"
        )
    n = max(2, math.ceil(length / settings.element_length - 1e-9))
    station = np.linspace(0.0, length, n + 1)
    positions = np.column_stack([station, np.zeros(n + 1), np.zeros(n + 1)])
    h = np.diff(station)
    node_mass = np.zeros(n + 1)
    np.add.at(node_mass, np.arange(n), 0.5 * wire.mass_per_length * h)
    np.add.at(node_mass, np.arange(1, n + 1), 0.5 * wire.mass_per_length * h)
    unstretched = h / (1.0 + wire.tension / wire.axial_stiffness)
    fixed = np.zeros((n + 1, 3), dtype=bool)
    fixed[[0, n], 1:] = True
    fixed[0, 0] = True
    springs = np.zeros(0, dtype=int)
    if support_stiffness is not None:
        fixed[[0, n], 2] = False
        springs = np.array([2, 3 * n + 2])
    termination = np.zeros(3 * (n + 1))
    termination[3 * n] = wire.tension
    nodes = np.arange(n + 1)
    empty = np.zeros(0, dtype=int)
    return Discretisation(
        catenary=None,
        contact_wire=wire,
        damping=damping,
        cw_tension=wire.tension,
        settings=settings,
        design_positions=positions,
        node_mass=node_mass,
        cw_nodes=nodes,
        mw_nodes=empty,
        cw_station=station,
        mast_station=np.array([0.0, length]),
        mast_cw_node=np.array([0, n]),
        mast_mw_node=empty,
        mast_normal=np.array([[0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]),
        axial=AxialElements(
            node_a=nodes[:-1], node_b=nodes[1:], stiffness=wire.axial_stiffness / unstretched,
            design_length=h, group=np.full(n, CONTACT_WIRE),
        ),
        bending=BendingTriples(
            node_a=nodes[:-2], node_b=nodes[1:-1], node_c=nodes[2:], spacing_ab=h[:-1], spacing_bc=h[1:],
            bending_stiffness=np.full(n - 1, wire.bending_stiffness),
        ) if wire.bending_stiffness > 0.0 else BendingTriples.empty(),
        dropper_elements=empty,
        dropper_span=empty,
        dropper_position=np.zeros(0),
        arm_elements=empty,
        arm_pivot_nodes=empty,
        arm_masts=empty,
        spring_dofs=springs,
        spring_stiffness=np.full(len(springs), support_stiffness or 0.0),
        spring_masts=np.arange(len(springs)),
        pin_nodes=empty,
        pin_normals=np.zeros((0, 3)),
        fixed_dofs=fixed.ravel(),
        termination_force=termination,
    )
