"""Elements, masses and holds of a catenary section as :func:`~presag_opt.static.discretisation.discretise`
collects them: wire segments and bending triples, droppers, steady arms or ground springs, messenger-wire
pins.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.system.catenary import Catenary
from presag_opt.system.components import SpringSupport, SteadyArm, Wire
from presag_opt.system.stitch import StitchWire

# Axial element groups.
CONTACT_WIRE, MESSENGER_WIRE, DROPPER, STEADY_ARM, STITCH_WIRE = 0, 1, 2, 3, 4
GROUP_NAMES = ("contact wire", "messenger wire", "dropper", "steady arm", "stitch wire")

@dataclass(frozen=True, kw_only=True)
class AxialElements:
    """Two-node spring elements (arrays of equal length).

    Attributes
    ----------
    node_a, node_b : ndarray of int
        End nodes of each element. [-]
    stiffness : ndarray
        Axial stiffness of each element. [N/m]
    design_length : ndarray
        Length of each element in the design (target) state. [m]
    group : ndarray of int
        ``CONTACT_WIRE``, ``MESSENGER_WIRE``, ``DROPPER`` or ``STEADY_ARM``. [-]
    """

    node_a: np.ndarray
    node_b: np.ndarray
    stiffness: np.ndarray  # [N/m]
    design_length: np.ndarray  # [m] length in the design (target) state
    group: np.ndarray  # CONTACT_WIRE, MESSENGER_WIRE, DROPPER, STEADY_ARM

    def __len__(self) -> int:
        return len(self.node_a)


@dataclass(frozen=True, kw_only=True)
class BendingTriples:
    """Three consecutive wire nodes a-b-c with the reference spacings and EI.

    Attributes
    ----------
    node_a, node_b, node_c : ndarray of int
        The three nodes of each triple, in order along the wire. [-]
    spacing_ab, spacing_bc : ndarray
        Reference spacings a-b and b-c. [m]
    bending_stiffness : ndarray
        Bending stiffness EI of the wire at each triple. [N·m²]
    """

    node_a: np.ndarray
    node_b: np.ndarray
    node_c: np.ndarray
    spacing_ab: np.ndarray  # [m]
    spacing_bc: np.ndarray  # [m]
    bending_stiffness: np.ndarray  # [N m^2]

    @classmethod
    def empty(cls) -> BendingTriples:
        """No bending (pure cables)."""
        none_i, none_f = np.zeros(0, dtype=int), np.zeros(0)
        return cls(node_a=none_i, node_b=none_i, node_c=none_i, spacing_ab=none_f, spacing_bc=none_f,
                   bending_stiffness=none_f)


@dataclass
class SectionElements:
    """Elements, masses and holds collected span by span (mutable; :func:`discretise` freezes them).

    Attributes
    ----------
    node_mass : ndarray
        Lumped mass of each node. [kg]
    fixed : ndarray of bool, shape (n_nodes, 3)
        Held coordinates of each node.
    ax_a, ax_b : list of ndarray of int
        End nodes of the axial elements, one array per call. [-]
    ax_k : list of ndarray
        Axial stiffness of the elements, one array per call. [N/m]
    ax_len : list of ndarray
        Design lengths of the elements, one array per call. [m]
    ax_grp : list of ndarray of int
        Element groups (``CONTACT_WIRE`` …), one array per call. [-]
    bend : dict of list of ndarray
        Bending triples by key: nodes ``"a"``, ``"b"``, ``"c"`` [-], spacings ``"h1"``, ``"h2"``
        [m], ``"ei"`` the bending stiffness [N·m²].
    springs_dof : list of int
        DOF (vertical) of each ground spring. [-]
    springs_k : list of float
        Stiffness of each ground spring. [N/m]
    springs_mast : list of int
        Mast of each ground spring. [-]
    arm_a, arm_b : list of int
        Clamp node and pivot node of each steady arm. [-]
    arm_k : list of float
        Axial stiffness of each steady arm. [N/m]
    arm_len : list of float
        Length of each steady arm. [m]
    arm_masts : list of int
        Mast of each steady arm. [-]
    pin_nodes : list of int
        Messenger-wire nodes pinned across a curved track. [-]
    pin_normals : list of ndarray
        Horizontal unit vector across the track at each pinned node. [-]
    """

    node_mass: np.ndarray
    fixed: np.ndarray
    ax_a: list = field(default_factory=list)
    ax_b: list = field(default_factory=list)
    ax_k: list = field(default_factory=list)
    ax_len: list = field(default_factory=list)
    ax_grp: list = field(default_factory=list)
    bend: dict = field(default_factory=lambda: {"a": [], "b": [], "c": [], "h1": [], "h2": [], "ei": []})
    springs_dof: list = field(default_factory=list)
    springs_k: list = field(default_factory=list)
    springs_mast: list = field(default_factory=list)
    arm_a: list = field(default_factory=list)
    arm_b: list = field(default_factory=list)
    arm_k: list = field(default_factory=list)
    arm_len: list = field(default_factory=list)
    arm_masts: list = field(default_factory=list)
    pin_nodes: list = field(default_factory=list)
    pin_normals: list = field(default_factory=list)

    @property
    def n_axial(self) -> int:
        """Axial elements added so far."""
        return sum(len(a) for a in self.ax_a)

    def _append(self, a, b, k, length, group) -> None:
        self.ax_a.append(np.asarray(a))
        self.ax_b.append(np.asarray(b))
        self.ax_k.append(np.asarray(k))
        self.ax_len.append(np.asarray(length))
        self.ax_grp.append(np.full(len(length), group))

    def add_wire(self, nodes: np.ndarray, wire: Wire | StitchWire, group: int, pos: np.ndarray) -> None:
        """Segments (stiffness EA over the unstretched length at the wire's tension), lumped mass and
        bending triples of one wire.

        Parameters
        ----------
        nodes : ndarray of int
            The wire's nodes in order along it. [-]
        wire : Wire
            The wire's properties.
        group : int
            ``CONTACT_WIRE`` or ``MESSENGER_WIRE``. [-]
        pos : ndarray, shape (len(nodes), 3)
            Design coordinates of the nodes. [m]
        """
        seg = np.linalg.norm(np.diff(pos, axis=0), axis=1)
        unstretched = seg / (1.0 + wire.tension / wire.axial_stiffness)
        self._append(nodes[:-1], nodes[1:], wire.axial_stiffness / unstretched, seg, group)
        np.add.at(self.node_mass, nodes[:-1], 0.5 * wire.mass_per_length * seg)
        np.add.at(self.node_mass, nodes[1:], 0.5 * wire.mass_per_length * seg)
        if wire.bending_stiffness > 0.0:
            b = self.bend
            b["a"].append(nodes[:-2])
            b["b"].append(nodes[1:-1])
            b["c"].append(nodes[2:])
            b["h1"].append(seg[:-1])
            b["h2"].append(seg[1:])
            b["ei"].append(np.full(len(seg) - 1, wire.bending_stiffness))

    def add_droppers(self, cat: Catenary, d_cw: np.ndarray, d_mw: np.ndarray, d_len: np.ndarray) -> int:
        """Droppers between the contact and messenger wire nodes, with their and their clamps' mass.

        Returns the number of droppers added.

        Parameters
        ----------
        cat : Catenary
            The catenary (its dropper properties).
        d_cw, d_mw : ndarray of int
            Contact-wire and messenger-wire node of each dropper. [-]
        d_len : ndarray
            Design length of each dropper. [m]
        """
        if np.any(d_len <= 0.0):
            raise ModelError("the messenger-wire first guess lies below the contact wire; check system_height")
        spec = cat.droppers
        d_k = np.full(len(d_len), spec.stiffness) if spec.stiffness is not None else spec.axial_stiffness / d_len
        d_mass = spec.mass_per_length * d_len
        np.add.at(self.node_mass, d_cw, 0.5 * d_mass + spec.clamp_mass)
        np.add.at(self.node_mass, d_mw, 0.5 * d_mass + spec.clamp_mass)
        self._append(d_cw, d_mw, d_k, d_len, DROPPER)
        return len(d_len)

    def add_contact_wire_supports(self, support: SteadyArm | SpringSupport, mast_cw: np.ndarray) -> None:
        """A steady arm (its pivot a new node, numbered after the wires) or a ground spring at each mast.

        Parameters
        ----------
        support : SteadyArm or SpringSupport
            The contact wire's support.
        mast_cw : ndarray of int
            Contact-wire node at each mast. [-]
        """
        n_wire_nodes = len(self.node_mass)
        for m, node in enumerate(mast_cw):
            if isinstance(support, SteadyArm):
                self.arm_a.append(node)
                self.arm_b.append(n_wire_nodes + len(self.arm_a) - 1)
                self.arm_k.append(support.axial_stiffness / support.length)
                self.arm_len.append(support.length)
                self.arm_masts.append(m)
                self.node_mass[node] += 0.5 * support.mass
            else:
                self.springs_dof.append(3 * node + 2)
                self.springs_k.append(support.stiffness)
                self.springs_mast.append(m)
                self.node_mass[node] += support.mass
                self.fixed[node, 1] = True  # a spring support has no lateral freedom of its own

    def add_messenger_wire_supports(self, support, mast_mw: np.ndarray, normal: np.ndarray) -> None:
        """A pin (across the track and vertically) or a ground spring at each mast.

        Parameters
        ----------
        support : SpringSupport or object
            The messenger wire's support (a pin when it is not a ground spring).
        mast_mw : ndarray of int
            Messenger-wire node at each mast. [-]
        normal : ndarray, shape (n_masts, 3)
            Horizontal unit vector across the track at each mast, :func:`mast_normals`. [-]
        """
        for m, node in enumerate(mast_mw):
            if isinstance(support, SpringSupport):
                self.fixed[node, 1] = True
                self.springs_dof.append(3 * node + 2)
                self.springs_k.append(support.stiffness)
                self.springs_mast.append(m)
                self.node_mass[node] += support.mass
            elif abs(normal[m, 0]) < 1e-12:
                self.fixed[node, 1:] = True
            else:
                # On a curve the pin holds the wire across the track (along the mast normal), not along y.
                self.fixed[node, 2] = True
                self.pin_nodes.append(node)
                self.pin_normals.append(normal[m])

    def add_steady_arms(self) -> int:
        """Append the steady-arm elements and their (fixed) pivot nodes; return the first arm's index."""
        first = self.n_axial
        if self.arm_a:
            self.fixed = np.vstack([self.fixed, np.ones((len(self.arm_a), 3), dtype=bool)])
            self.node_mass = np.concatenate([self.node_mass, np.zeros(len(self.arm_a))])
            self._append(self.arm_a, self.arm_b, self.arm_k, self.arm_len, STEADY_ARM)
        return first

    def axial(self) -> AxialElements:
        """All axial elements in the order added."""
        return AxialElements(
            node_a=np.concatenate(self.ax_a).astype(int),
            node_b=np.concatenate(self.ax_b).astype(int),
            stiffness=np.concatenate(self.ax_k).astype(float),
            design_length=np.concatenate(self.ax_len).astype(float),
            group=np.concatenate(self.ax_grp).astype(int),
        )

    def bending(self) -> BendingTriples:
        """The wires' bending triples (none for pure cables)."""
        b = self.bend
        if not b["a"]:
            return BendingTriples.empty()
        return BendingTriples(
            node_a=np.concatenate(b["a"]), node_b=np.concatenate(b["b"]), node_c=np.concatenate(b["c"]),
            spacing_ab=np.concatenate(b["h1"]), spacing_bc=np.concatenate(b["h2"]),
            bending_stiffness=np.concatenate(b["ei"]),
        )
