"""The quasi-static pantograph path of a section, affine in the dropper heights.

A constant upward force F moving slowly along a span lifts the contact wire at the contact point to

    h(x; d, F) = z_CW(x; d) + F · e(x; F),

with z_CW the form-found contact-wire height for the pre-sag design d and e the elasticity at the
force F (interpolated between computed force levels). Its peak-to-peak value over a span,
R(d, F) = max_x h − min_x h, is the waviness the pre-sag cancels. The form-found geometry is affine
in the dropper target heights — the sensitivity comes from the CasADi Jacobian of the form-finding
equations (:func:`presag_opt.static.form_finding.dropper_height_sensitivity`; the prediction of a
70 mm geometry from a 30 mm one is exact to 0.2 μm) — so R is convex in d. This module holds the
path model; the optimisation over d is :mod:`presag_opt.robust.lp`.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, sections 4.1 and 6.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from presag_opt.design.quasi_static import interpolate_elasticities
from presag_opt.design.section import SectionElasticity
from presag_opt.errors import ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import dropper_height_sensitivity

SENSITIVITY_CUTOFF = 1e-9
"""Geometry sensitivities smaller than this are round-off of the implicit-function solve. [m/m]"""

PROBLEM_KINDS = ("robust", "tolerance")
"""The optimisation problems a path model keeps (:meth:`PathModel.problem`): the robust pre-sag LPs
of :mod:`presag_opt.robust.lp` and the tolerance-band LP pairs of :mod:`presag_opt.robust.tolerance`."""


@dataclass(frozen=True)
class PathModel:
    """Quasi-static pantograph path of the analysed spans, affine in the dropper heights.

    Built from a form-found state and the elasticity curves of its analysed spans (computed at that
    geometry). Heights and depths are measured from each span's support line, the straight line
    between the contact-wire heights at its two masts (:meth:`~presag_opt.system.catenary.Catenary.support_line`;
    one level where the heights are all equal), so a pre-sag is the depth below that line.

    Attributes
    ----------
    state : EquilibriumState
        The reference geometry.
    section : SectionElasticity
        Elasticity curves at force levels, one study per analysed span.
    node_span : ndarray of int
        Analysed span of each path point (mast nodes appear once per adjacent analysed span). [-]
    node_position : ndarray
        Position of each path point from its span's first mast. [m]
    base_height : ndarray
        Contact-wire height at each path point in the reference geometry, above its span's support
        line. [m]
    sensitivity : ndarray
        ∂h/∂(dropper depth) of each path point for the analysed spans' droppers (depth positive
        downwards). [m/m]
    dropper_span, dropper_fraction : ndarray
        Span and relative position x/l of each design dropper. [-]
    reference_depth : ndarray
        Depth of each design dropper below its span's support line in the reference geometry. [m]
    dropper_length : ndarray
        Length of each design dropper in the reference geometry. [m]
    length_sensitivity : ndarray
        ∂(dropper length)/∂(depth) of each design dropper for each depth. [m/m]
    nodes : ndarray of int
        Node of the state at each path point. [-]
    """

    state: EquilibriumState
    section: SectionElasticity
    node_span: np.ndarray
    node_position: np.ndarray
    base_height: np.ndarray
    sensitivity: np.ndarray
    dropper_span: np.ndarray
    dropper_fraction: np.ndarray
    reference_depth: np.ndarray
    dropper_length: np.ndarray
    length_sensitivity: np.ndarray
    nodes: np.ndarray
    problems: dict[str, dict[Hashable, Any]] = field(
        default_factory=lambda: {kind: {} for kind in PROBLEM_KINDS}, init=False, repr=False, compare=False)
    """The optimisation problems built on this path, by kind (:data:`PROBLEM_KINDS`) and key."""

    def problem(self, kind: str, key: Hashable, build: Callable[[], Any]) -> Any:
        """The problem of ``kind`` for ``key``: built by ``build`` on first use, then kept with this
        path (a cvxpy problem is built once and re-solved with new parameter values).

        Parameters
        ----------
        kind : str
            One of :data:`PROBLEM_KINDS`.
        key : hashable
            What the problem's structure depends on (shape, risk, scenario count, ...).
        build : callable
            Builds the problem (and whatever the caller keeps with it).
        """
        kept = self.problems[kind]
        if key not in kept:
            kept[key] = build()
        return kept[key]

    @property
    def spans(self) -> tuple[int, ...]:
        """Analysed spans, from 0."""
        return self.section.spans

    @functools.cached_property
    def sparse_sensitivity(self) -> sp.csr_matrix:
        """:attr:`sensitivity` without its round-off entries (below 1e-9 m/m).

        A node feels only the droppers of its own span (the masts are held at their height), but the
        implicit-function solve leaves round-off everywhere; dropping it keeps the LP sparse.
        """
        return sp.csr_matrix(np.where(np.abs(self.sensitivity) < SENSITIVITY_CUTOFF, 0.0, self.sensitivity))

    @property
    def span_lengths(self) -> np.ndarray:
        """Length of each analysed span. [m]"""
        return self.section.span_lengths

    def of_span(self, span: int) -> PathModel:
        """The path model of one analysed span alone: its path points, its droppers, its elasticity.

        A path point feels only the droppers of its own span (the masts are held at their height;
        the sensitivities across a mast are round-off, below :data:`SENSITIVITY_CUTOFF`), so the
        spans' designs decouple and each span can be designed on its own.

        Parameters
        ----------
        span : int
            One of :attr:`spans`, from 0. [-]
        """
        if span not in self.spans:
            raise ModelError(f"path model: span {span} is not an analysed span ({', '.join(map(str, self.spans))})")
        points = self.node_span == span
        drops = self.dropper_span == span
        section = dataclasses.replace(self.section, studies=tuple(s for s in self.section.studies if s.span == span))
        return PathModel(
            state=self.state, section=section, node_span=self.node_span[points],
            node_position=self.node_position[points], base_height=self.base_height[points],
            sensitivity=self.sensitivity[np.ix_(points, drops)], dropper_span=self.dropper_span[drops],
            dropper_fraction=self.dropper_fraction[drops], reference_depth=self.reference_depth[drops],
            dropper_length=self.dropper_length[drops], length_sensitivity=self.length_sensitivity[np.ix_(drops, drops)],
            nodes=self.nodes[points],
        )

    def parabola_depths(self, presag_rel: float) -> np.ndarray:
        """Dropper depths of a parabolic pre-sag S_rel·l in every analysed span. [m]

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel (mid-span depth over span length). [-]
        """
        lengths = np.asarray(self.state.catenary.layout.span_lengths)[self.dropper_span]
        t = self.dropper_fraction
        return presag_rel * lengths * 4.0 * t * (1.0 - t)

    def uplift(self, forces: np.ndarray) -> np.ndarray:
        """F·e(x; F) at every path point for every force (K × points). [m]

        Parameters
        ----------
        forces : ndarray, shape (K,)
            Mean contact forces F_m. [N]
        """
        out = np.empty((len(forces), len(self.node_span)))
        for study in self.section.studies:
            sel = self.node_span == study.span
            for k, (force, curve) in enumerate(zip(forces, interpolate_elasticities(study.nonlinear, forces))):
                out[k, sel] = force * curve.at(self.node_position[sel])
        return out

    def heights(self, depths: np.ndarray, forces: np.ndarray, uplift: np.ndarray | None = None) -> np.ndarray:
        """Path height h at every point for every force (K × points). [m]

        ``uplift`` may pass :meth:`uplift` of the same forces, computed once for many designs.

        Parameters
        ----------
        depths : ndarray, shape (n_droppers,)
            Pre-sag depth at each dropper of the analysed spans. [m]
        forces : ndarray, shape (K,)
            Mean contact forces F_m. [N]
        uplift : ndarray, shape (K, n_points), optional
            Result of :meth:`uplift` for the same forces (computed here when None). [m]
        """
        z = self.base_height + self.sensitivity @ (np.asarray(depths) - self.reference_depth)
        return z[None, :] + (self.uplift(forces) if uplift is None else uplift)

    def waviness(self, depths: np.ndarray, forces: np.ndarray, uplift: np.ndarray | None = None) -> np.ndarray:
        """Peak-to-peak path height R of every analysed span for every force (K × spans). [m]

        Parameters
        ----------
        depths : ndarray, shape (n_droppers,)
            Pre-sag depth at each dropper of the analysed spans. [m]
        forces : ndarray, shape (K,)
            Mean contact forces F_m. [N]
        uplift : ndarray, shape (K, n_points), optional
            Result of :meth:`uplift` for the same forces (computed here when None). [m]
        """
        h = self.heights(depths, forces, uplift)
        return np.column_stack([np.ptp(h[:, self.node_span == s], axis=1) for s in self.spans])


def build_path_model(state: EquilibriumState, section: SectionElasticity) -> PathModel:
    """Assemble the path model of a form-found state and its elasticity curves.

    Parameters
    ----------
    state : EquilibriumState
        Form-found geometry; ``section`` must have been computed on it.
    section : SectionElasticity
        Elasticity curves at force levels covering the forces to be studied.
    """
    disc = state.discretisation
    if section.catenary != state.catenary:
        raise ModelError("path model: the elasticity curves were computed on another geometry than the state")
    spans = section.spans
    design = np.flatnonzero(np.isin(disc.dropper_span, spans))
    sens_all = dropper_height_sensitivity(state)[:, design]  # ∂z/∂(target height)
    node_span, node_pos, nodes = [], [], []
    for s in spans:
        lo, hi = disc.mast_station[s], disc.mast_station[s + 1]
        k = np.flatnonzero((disc.cw_station >= lo - 1e-9) & (disc.cw_station <= hi + 1e-9))
        nodes.append(disc.cw_nodes[k])
        node_span.append(np.full(len(k), s))
        node_pos.append(disc.cw_station[k] - lo)
    nodes = np.concatenate(nodes)
    lengths = np.asarray(state.catenary.layout.span_lengths)[disc.dropper_span[design]]
    drop_cw = disc.axial.node_a[disc.dropper_elements[design]]
    drop_mw = disc.axial.node_b[disc.dropper_elements[design]]
    node_span, node_pos = np.concatenate(node_span), np.concatenate(node_pos)
    cat = state.catenary
    support = np.concatenate([cat.support_line(int(s), node_pos[node_span == s]) for s in spans])
    drop_support = np.array([cat.support_line(int(s), np.array([x]))[0]
                             for s, x in zip(disc.dropper_span[design], disc.dropper_position[design])])
    # depth = support line − target height, so ∂/∂depth = −∂/∂target
    return PathModel(
        state=state,
        section=section,
        node_span=node_span,
        node_position=node_pos,
        base_height=state.positions[nodes, 2] - support,
        sensitivity=-sens_all[nodes],
        dropper_span=disc.dropper_span[design],
        dropper_fraction=disc.dropper_position[design] / lengths,
        reference_depth=drop_support - state.positions[drop_cw, 2],
        dropper_length=state.dropper_lengths()[design],
        length_sensitivity=-(sens_all[drop_mw] - sens_all[drop_cw]),
        nodes=nodes,
    )
