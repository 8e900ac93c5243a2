"""Finite-element discretisation of a catenary tension section (geometry, elements, loads).

Nodes carry three translations (x along the track, y lateral, z up). Elements:

- *axial* two-node springs with energy ``k/2 (L - L0)^2`` (``L`` current length, ``L0`` unstretched
  length, ``k = EA/L0``): wire segments, droppers (tension only), steady arms;
- *bending* triples on the contact wire (and the messenger wire if it has EI): a rotation-free
  Euler–Bernoulli discretisation whose energy is ``EI/2 |r''|^2`` integrated along the wire, with the
  curvature vector ``r''`` taken from three consecutive nodes;
- *ground springs* on single degrees of freedom (EN 50318-style supports).

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
is vertically above it at the masts. Wire segments between masts are straight chords in plan.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.system.catenary import GRAVITY, Catenary, Damping, SpringSupport, SteadyArm, Wire
from presag_opt.system.quantity import quantity, validate_fields

# Axial element groups.
CONTACT_WIRE, MESSENGER_WIRE, DROPPER, STEADY_ARM = 0, 1, 2, 3
GROUP_NAMES = ("contact wire", "messenger wire", "dropper", "steady arm")

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
class AxialElements:
    """Two-node spring elements (arrays of equal length)."""

    node_a: np.ndarray
    node_b: np.ndarray
    stiffness: np.ndarray  # [N/m]
    design_length: np.ndarray  # [m] length in the design (target) state
    group: np.ndarray  # CONTACT_WIRE, MESSENGER_WIRE, DROPPER, STEADY_ARM

    def __len__(self) -> int:
        return len(self.node_a)


@dataclass(frozen=True, kw_only=True)
class BendingTriples:
    """Three consecutive wire nodes a-b-c with the reference spacings and EI."""

    node_a: np.ndarray
    node_b: np.ndarray
    node_c: np.ndarray
    spacing_ab: np.ndarray  # [m]
    spacing_bc: np.ndarray  # [m]
    bending_stiffness: np.ndarray  # [N m^2]

    @classmethod
    def empty(cls) -> "BendingTriples":
        """No bending (pure cables)."""
        none_i, none_f = np.zeros(0, dtype=int), np.zeros(0)
        return cls(node_a=none_i, node_b=none_i, node_c=none_i, spacing_ab=none_f, spacing_bc=none_f,
                   bending_stiffness=none_f)


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
        """Sparse matrix (len(stations) x n_cw_nodes) of linear shape functions at the stations."""
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
        """
        s = np.asarray(stations, dtype=float)
        right = np.clip(np.searchsorted(self.cw_station, s, side="right"), 1, len(self.cw_station) - 1)
        h = self.cw_station[right] - self.cw_station[right - 1]
        t = np.clip((s - self.cw_station[right - 1]) / h, 0.0, 1.0)
        return h * t * (1.0 - t) / self.cw_tension


def discretise(catenary: Catenary, settings: StaticSettings | None = None) -> Discretisation:
    """Build the finite-element discretisation of a catenary section in its design state.

    The design state has the contact wire on the pre-sag parabola (zero at the masts, designed
    height there) and a first guess of the messenger wire; form-finding then finds the dropper
    lengths and steady-arm settings that make it an equilibrium.

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
    mast_station = np.concatenate([[0.0], np.cumsum(spans)])
    track_xy, heading = _track_plan(spans, np.asarray(cat.layout.radii))
    normal = np.column_stack([-np.sin(heading), np.cos(heading), np.zeros_like(heading)])
    stagger = cat.stagger * np.where(np.arange(n_spans + 1) % 2 == 0, 1.0, -1.0)
    reg_xy = track_xy + stagger[:, None] * normal[:, :2]

    # Stations of one span: masts, droppers, and equal subdivisions no longer than element_length.
    stations, span_of, is_dropper, local = [], [], [], []
    for i, length in enumerate(spans):
        drop = cat.droppers.positions_in_span(length)
        breaks = np.concatenate([[0.0], drop, [length]])
        pts = [0.0]
        for a, b in zip(breaks[:-1], breaks[1:]):
            n = max(1, math.ceil((b - a) / settings.element_length - 1e-9))
            pts.extend(a + (b - a) * np.arange(1, n + 1) / n)
        pts = np.asarray(pts)
        if i < n_spans - 1:
            pts = pts[:-1]  # the next span starts at this mast
        stations.append(mast_station[i] + pts)
        local.append(pts)
        span_of.append(np.full(len(pts), i))
        is_dropper.append(np.isin(np.round(pts, 9), np.round(drop, 9)))
    cw_station = np.concatenate(stations)
    local_s = np.concatenate(local)
    span_idx = np.concatenate(span_of)
    dropper_mask = np.concatenate(is_dropper)
    n_st = len(cw_station)

    # Plan position: along the chord between the registrations of the span.
    lengths = spans[span_idx]
    t = local_s / lengths
    start = reg_xy[span_idx]
    end = reg_xy[np.minimum(span_idx + 1, n_spans)]
    xy = start + t[:, None] * (end - start)

    z_cw = cat.contact_wire_height - np.concatenate([cat.presag_depth(i, pts) for i, pts in enumerate(local)])
    z_mw = cat.contact_wire_height + cat.system_height - 4.0 * _messenger_sag_guess(cat, lengths) * t * (1.0 - t)

    cw_nodes = np.arange(n_st)
    mw_nodes = n_st + np.arange(n_st)
    positions = [np.column_stack([xy, z_cw]), np.column_stack([xy, z_mw])]
    node_mass = np.zeros(2 * n_st)

    mast_cw = np.searchsorted(cw_station, mast_station - 1e-9)
    mast_mw = mw_nodes[mast_cw]

    # Wires.
    ax_a, ax_b, ax_k, ax_len, ax_grp = [], [], [], [], []
    bend = {"a": [], "b": [], "c": [], "h1": [], "h2": [], "ei": []}
    for nodes, wire, grp, pos in (
        (cw_nodes, cat.contact_wire, CONTACT_WIRE, positions[0]),
        (mw_nodes, cat.messenger_wire, MESSENGER_WIRE, positions[1]),
    ):
        seg = np.linalg.norm(np.diff(pos, axis=0), axis=1)
        ax_a.append(nodes[:-1])
        ax_b.append(nodes[1:])
        unstretched = seg / (1.0 + wire.tension / wire.axial_stiffness)
        ax_k.append(wire.axial_stiffness / unstretched)
        ax_len.append(seg)
        ax_grp.append(np.full(len(seg), grp))
        np.add.at(node_mass, nodes[:-1], 0.5 * wire.mass_per_length * seg)
        np.add.at(node_mass, nodes[1:], 0.5 * wire.mass_per_length * seg)
        if wire.bending_stiffness > 0.0:
            bend["a"].append(nodes[:-2])
            bend["b"].append(nodes[1:-1])
            bend["c"].append(nodes[2:])
            bend["h1"].append(seg[:-1])
            bend["h2"].append(seg[1:])
            bend["ei"].append(np.full(len(seg) - 1, wire.bending_stiffness))

    # Droppers.
    d_cw = cw_nodes[dropper_mask]
    d_mw = mw_nodes[dropper_mask]
    d_len = positions[1][dropper_mask, 2] - positions[0][dropper_mask, 2]
    if np.any(d_len <= 0.0):
        raise ModelError("the messenger-wire first guess lies below the contact wire; check system_height")
    drop_spec = cat.droppers
    if drop_spec.stiffness is not None:
        d_k = np.full(len(d_len), drop_spec.stiffness)
    else:
        d_k = drop_spec.axial_stiffness / d_len
    d_mass = drop_spec.mass_per_length * d_len
    np.add.at(node_mass, d_cw, 0.5 * d_mass + drop_spec.clamp_mass)
    np.add.at(node_mass, d_mw, 0.5 * d_mass + drop_spec.clamp_mass)
    first_dropper = sum(len(a) for a in ax_a)
    ax_a.append(d_cw)
    ax_b.append(d_mw)
    ax_k.append(d_k)
    ax_len.append(d_len)
    ax_grp.append(np.full(len(d_len), DROPPER))

    n_nodes = 2 * n_st
    fixed = np.zeros((n_nodes, 3), dtype=bool)
    springs_dof, springs_k, springs_mast = [], [], []
    arm_a, arm_b, arm_k, arm_len, arm_masts = [], [], [], [], []

    support = cat.contact_wire_support
    for m, node in enumerate(mast_cw):
        if isinstance(support, SteadyArm):
            arm_a.append(node)
            arm_b.append(n_nodes + len(arm_a) - 1)
            arm_k.append(support.axial_stiffness / support.length)
            arm_len.append(support.length)
            arm_masts.append(m)
            node_mass[node] += 0.5 * support.mass
        else:
            springs_dof.append(3 * node + 2)
            springs_k.append(support.stiffness)
            springs_mast.append(m)
            node_mass[node] += support.mass
            fixed[node, 1] = True  # a spring support has no lateral freedom of its own
    mw_support = cat.messenger_wire_support
    pin_nodes, pin_normals = [], []
    for m, node in enumerate(mast_mw):
        if isinstance(mw_support, SpringSupport):
            fixed[node, 1] = True
            springs_dof.append(3 * node + 2)
            springs_k.append(mw_support.stiffness)
            springs_mast.append(m)
            node_mass[node] += mw_support.mass
        elif abs(normal[m, 0]) < 1e-12:
            fixed[node, 1:] = True
        else:
            # On a curve the pin holds the wire across the track (along the mast normal), not along y.
            fixed[node, 2] = True
            pin_nodes.append(node)
            pin_normals.append(normal[m])

    if arm_a:
        fixed = np.vstack([fixed, np.ones((len(arm_a), 3), dtype=bool)])
        node_mass = np.concatenate([node_mass, np.zeros(len(arm_a))])
        first_arm = sum(len(a) for a in ax_a)
        ax_a.append(np.asarray(arm_a))
        ax_b.append(np.asarray(arm_b))
        ax_k.append(np.asarray(arm_k))
        ax_len.append(np.asarray(arm_len))
        ax_grp.append(np.full(len(arm_a), STEADY_ARM))
        arm_elements = first_arm + np.arange(len(arm_a))
        arm_pivots = np.asarray(arm_b)
    else:
        arm_elements = np.zeros(0, dtype=int)
        arm_pivots = np.zeros(0, dtype=int)

    # Mid-point anchor: both wires fixed along the track at the central mast.
    anchor = n_spans // 2
    fixed[mast_cw[anchor], 0] = True
    fixed[mast_mw[anchor], 0] = True

    wire_pos = np.vstack(positions)
    # Balance weights pull each wire end outwards along the track.
    termination = np.zeros(3 * (n_nodes + len(arm_a)))
    for nodes, wire in ((cw_nodes, cat.contact_wire), (mw_nodes, cat.messenger_wire)):
        for end, mast, sign in ((nodes[0], 0, -1.0), (nodes[-1], n_spans, 1.0)):
            tangent = np.array([math.cos(heading[mast]), math.sin(heading[mast]), 0.0])
            termination[3 * end : 3 * end + 3] += sign * wire.tension * tangent
    pivots = _steady_arm_pivots(cat, wire_pos, cw_nodes, mast_cw, termination, arm_masts)
    all_pos = np.vstack([wire_pos, pivots]) if len(pivots) else wire_pos

    axial = AxialElements(
        node_a=np.concatenate(ax_a).astype(int),
        node_b=np.concatenate(ax_b).astype(int),
        stiffness=np.concatenate(ax_k).astype(float),
        design_length=np.concatenate(ax_len).astype(float),
        group=np.concatenate(ax_grp).astype(int),
    )
    if bend["a"]:
        bending = BendingTriples(
            node_a=np.concatenate(bend["a"]),
            node_b=np.concatenate(bend["b"]),
            node_c=np.concatenate(bend["c"]),
            spacing_ab=np.concatenate(bend["h1"]),
            spacing_bc=np.concatenate(bend["h2"]),
            bending_stiffness=np.concatenate(bend["ei"]),
        )
    else:
        bending = BendingTriples.empty()
    return Discretisation(
        catenary=cat,
        contact_wire=cat.contact_wire,
        damping=cat.damping,
        cw_tension=cat.contact_wire.tension,
        settings=settings,
        design_positions=all_pos,
        node_mass=node_mass,
        cw_nodes=cw_nodes,
        mw_nodes=mw_nodes,
        cw_station=cw_station,
        mast_station=mast_station,
        mast_cw_node=mast_cw,
        mast_mw_node=mast_mw,
        mast_normal=normal,
        axial=axial,
        bending=bending,
        dropper_elements=first_dropper + np.arange(len(d_len)),
        dropper_span=span_idx[dropper_mask],
        dropper_position=local_s[dropper_mask],
        arm_elements=arm_elements,
        arm_pivot_nodes=arm_pivots,
        arm_masts=np.asarray(arm_masts, dtype=int),
        spring_dofs=np.asarray(springs_dof, dtype=int),
        spring_stiffness=np.asarray(springs_k, dtype=float),
        spring_masts=np.asarray(springs_mast, dtype=int),
        pin_nodes=np.asarray(pin_nodes, dtype=int),
        pin_normals=np.asarray(pin_normals, dtype=float).reshape(-1, 3),
        fixed_dofs=fixed.ravel(),
        termination_force=termination,
    )


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


def _steady_arm_pivots(
    cat: Catenary,
    wire_pos: np.ndarray,
    cw_nodes: np.ndarray,
    mast_cw: np.ndarray,
    termination: np.ndarray,
    arm_masts: list[int],
) -> np.ndarray:
    """First-guess pivot of each steady arm, from an estimate of the force the arm carries.

    Sideways: the resultant of the contact-wire tension at the clamp (stagger and curve kinks).
    Vertically: the contact-wire weight out to the first droppers plus the pull of the pre-sagged
    wire. The arm is stretched by its estimated tension so that Newton's method starts with an arm
    that has geometric stiffness.

    Raises
    ------
    ModelError
        If the contact wire exerts (almost) no lateral pull at a mast: the arm would have no
        tension and so no vertical stiffness.
    """
    if not arm_masts:
        return np.zeros((0, 3))
    arm = cat.contact_wire_support
    tension = cat.contact_wire.tension
    spans = cat.layout.span_lengths
    pivots = []
    for m in arm_masts:
        node = mast_cw[m]
        pull = termination[3 * node : 3 * node + 3].copy()
        k = int(np.searchsorted(cw_nodes, node))
        for nb in (k - 1, k + 1):
            if 0 <= nb < len(cw_nodes):
                d = wire_pos[cw_nodes[nb]] - wire_pos[node]
                pull += tension * d / np.linalg.norm(d)
        pull[2] = 0.0
        size = np.linalg.norm(pull)
        if size < 1e-3 * tension:
            raise ModelError(
                f"steady arm at mast {m}: the contact wire pulls only {size:.3g} N sideways there, so the arm "
                "would have no vertical stiffness; give a stagger or a curve, or use a spring support"
            )
        adjacent = [spans[i] for i in (m - 1, m) if 0 <= i < len(spans)]
        first_drop = [cat.droppers.positions_in_span(length)[0] for length in adjacent]
        vertical = GRAVITY * (cat.contact_wire.mass_per_length * sum(first_drop) / 2.0 + arm.mass / 2.0)
        # the pull of the parabola of presag_rel (for a profile: of its label, as good as a first guess needs)
        vertical += sum(4.0 * tension * cat.presag_rel * (1.0 - 2.0 * d / length) for d, length in zip(first_drop, adjacent))
        direction = np.append(-pull[:2] / size * size, vertical)
        force = np.linalg.norm(direction)
        stretched = arm.length * (1.0 + force / arm.axial_stiffness)
        pivots.append(wire_pos[node] + stretched * direction / force)
    return np.asarray(pivots)


def _track_plan(spans: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mast positions in plan and track heading at each mast for straight or circular spans."""
    xy = np.zeros((len(spans) + 1, 2))
    heading = np.zeros(len(spans) + 1)
    for i, (length, radius) in enumerate(zip(spans, radii)):
        turn = 0.0 if radius == 0.0 else length / radius
        chord = length if radius == 0.0 else 2.0 * radius * math.sin(turn / 2.0)
        direction = heading[i] + turn / 2.0
        xy[i + 1] = xy[i] + abs(chord) * np.array([math.cos(direction), math.sin(direction)])
        heading[i + 1] = heading[i] + turn
    return xy, heading


def _messenger_sag_guess(cat: Catenary, span_lengths: np.ndarray) -> np.ndarray:
    """Parabolic mid-span sag of the messenger wire carrying both wires' weight (first guess). [m]"""
    weight = GRAVITY * (cat.contact_wire.mass_per_length + cat.messenger_wire.mass_per_length)
    return weight * span_lengths**2 / (8.0 * cat.messenger_wire.tension)
