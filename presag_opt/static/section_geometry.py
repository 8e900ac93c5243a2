"""Design geometry of a tension section: stations, plan, the wires' design heights, steady-arm pivots.

The pieces :func:`~presag_opt.static.discretisation.discretise` assembles its elements on:

- :func:`section_stations`: every span split at the masts and the droppers, and each piece into equal
  elements no longer than the element length;
- :func:`track_plan`: masts on the track centre line, straight or, per span, a circular arc;
- :func:`design_wire_positions`: the contact wire registered at each mast's signed stagger, straight
  chords in plan between the registrations, at the height of the straight line between its supports
  less the pre-sag; the messenger wire vertically above it at the masts (the system height there)
  with the first-guess sag of a cable carrying both wires less what the pre-sagged contact wire's
  tension carries itself;
- :func:`steady_arm_pivots`: a first-guess pivot per steady arm from the force it carries, on the
  side away from the wire's pull for a pull-off arm (tension), on the side it pulls towards for a
  push-off arm (compression).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.system.catenary import Catenary
from presag_opt.system.components import GRAVITY


@dataclass(frozen=True, kw_only=True)
class SectionStations:
    """Along-track stations of the contact (and messenger) wire nodes.

    Attributes
    ----------
    station : ndarray
        Distance of each node from the first mast. [m]
    local : ndarray
        Distance of each node from its span's first mast. [m]
    span : ndarray of int
        Span (from 0) of each node; a mast node belongs to the span it starts. [-]
    is_dropper : ndarray of bool
        Whether a dropper hangs at the node.
    mast_station : ndarray
        Distance of each mast from the first. [m]
    """

    station: np.ndarray
    local: np.ndarray
    span: np.ndarray
    is_dropper: np.ndarray
    mast_station: np.ndarray

    @property
    def mast_nodes(self) -> np.ndarray:
        """Node index at each mast."""
        return np.searchsorted(self.station, self.mast_station - 1e-9)


def section_stations(catenary: Catenary, element_length: float) -> SectionStations:
    """Stations of every span: masts, droppers, stitch-wire clamps and stitch droppers, and equal
    subdivisions no longer than ``element_length``.

    Parameters
    ----------
    catenary : Catenary
        Spans and dropper rule.
    element_length : float
        Longest element. [m]
    """
    spans = np.asarray(catenary.layout.span_lengths)
    mast_station = np.concatenate([[0.0], np.cumsum(spans)])
    stations, span_of, is_dropper, local = [], [], [], []
    for i, length in enumerate(spans):
        drop = catenary.droppers.positions_in_span(length)
        breaks = np.concatenate([[0.0], drop, [length]])
        if catenary.stitch_wire is not None:
            clamps, stitch_drops = catenary.stitch_wire.points_in_span(i, len(spans), length)
            breaks = np.unique(np.round(np.concatenate([breaks, clamps, stitch_drops]), 9))
        pts = [0.0]
        for a, b in itertools.pairwise(breaks):
            n = max(1, math.ceil((b - a) / element_length - 1e-9))
            pts.extend(a + (b - a) * np.arange(1, n + 1) / n)
        pts = np.asarray(pts)
        if i < len(spans) - 1:
            pts = pts[:-1]  # the next span starts at this mast
        stations.append(mast_station[i] + pts)
        local.append(pts)
        span_of.append(np.full(len(pts), i))
        is_dropper.append(np.isin(np.round(pts, 9), np.round(drop, 9)))
    return SectionStations(station=np.concatenate(stations), local=np.concatenate(local),
                           span=np.concatenate(span_of), is_dropper=np.concatenate(is_dropper),
                           mast_station=mast_station)


def track_plan(spans: np.ndarray, radii: np.ndarray, along_x_at: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Mast positions in plan and track heading at each mast for straight or circular spans.

    The first mast is at the origin; the plan is turned so that the track runs along +x at mast
    ``along_x_at``.

    Parameters
    ----------
    spans : ndarray
        Span lengths along the track. [m]
    radii : ndarray
        Curve radius per span, + curving to the left, 0 straight. [m]
    along_x_at : int
        Mast (from 0) at which the track runs along +x. [-]

    Returns
    -------
    xy : ndarray, shape (n_spans + 1, 2)
        Mast positions on the track centre line. [m]
    heading : ndarray, shape (n_spans + 1,)
        Track heading at each mast, from the x axis. [rad]
    """
    xy = np.zeros((len(spans) + 1, 2))
    heading = np.zeros(len(spans) + 1)
    for i, (length, radius) in enumerate(zip(spans, radii)):
        turn = 0.0 if radius == 0.0 else length / radius
        chord = length if radius == 0.0 else 2.0 * radius * math.sin(turn / 2.0)
        direction = heading[i] + turn / 2.0
        xy[i + 1] = xy[i] + abs(chord) * np.array([math.cos(direction), math.sin(direction)])
        heading[i + 1] = heading[i] + turn
    turn = heading[along_x_at]
    rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    return xy @ rotation, heading - turn


def mast_normals(heading: np.ndarray) -> np.ndarray:
    """Horizontal unit vector across the track, to the left, at each mast (rows). [-]

    Parameters
    ----------
    heading : ndarray
        Direction of the track at each mast, from the x axis. [rad]
    """
    return np.column_stack([-np.sin(heading), np.cos(heading), np.zeros_like(heading)])


def design_wire_positions(catenary: Catenary, stations: SectionStations, track_xy: np.ndarray,
                          normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Design-state coordinates of the contact-wire and messenger-wire nodes (rows x, y, z). [m]

    Plan: along the chord between the registrations (each mast's signed stagger off the centre
    line). Contact wire: the straight line between its support heights less the pre-sag depth.
    Messenger wire: the straight line between the mast heights (contact-wire height plus system
    height) less its first-guess sag (:func:`messenger_sag_guess`).

    Parameters
    ----------
    catenary : Catenary
        The catenary.
    stations : SectionStations
        Node stations along the section.
    track_xy : ndarray, shape (n_masts, 2)
        Plan position of the track centre line at each mast. [m]
    normal : ndarray, shape (n_masts, 3)
        Horizontal unit vector across the track at each mast, :func:`mast_normals`. [-]
    """
    spans = np.asarray(catenary.layout.span_lengths)
    n_spans = len(spans)
    reg_xy = track_xy + catenary.mast_stagger()[:, None] * normal[:, :2]
    span_idx = stations.span
    t = stations.local / spans[span_idx]
    start = reg_xy[span_idx]
    end = reg_xy[np.minimum(span_idx + 1, n_spans)]
    xy = start + t[:, None] * (end - start)
    z_cw = np.empty(len(t))
    for s in range(n_spans):
        here = span_idx == s
        local = stations.local[here]
        z_cw[here] = catenary.support_line(s, local) - catenary.presag_depth(s, local)
    mw_mast = catenary.mast_contact_wire_height() + catenary.mast_system_height()
    mw_line = mw_mast[span_idx] + (mw_mast[np.minimum(span_idx + 1, n_spans)] - mw_mast[span_idx]) * t
    z_mw = np.empty(len(t))
    for s in range(n_spans):
        here = span_idx == s
        z_mw[here] = mw_line[here] - messenger_sag_guess(catenary, s, stations.local[here])
    return np.column_stack([xy, z_cw]), np.column_stack([xy, z_mw])


def messenger_sag_guess(catenary: Catenary, span: int, positions: np.ndarray) -> np.ndarray:
    """First guess of the messenger wire's sag below the line between its supports in a span. [m]

    Both wires, the droppers and their clamps hang together: per unit length, vertical balance of the
    whole gives T_MW·D_MW'' + T_CW·D_CW'' = −w, with D the depth below each wire's support line (zero
    at the masts), w the weight of both wires and of the droppers spread along the span (each at the
    span's smaller system height), and D_CW the pre-sag. So D_MW(x) = (w·x(l − x)/2 − T_CW·D_CW(x))/T_MW:
    the sag of a cable carrying everything, less what the pre-sagged contact wire's tension carries
    itself. (The steady arms carry some of the contact wire next to the masts; leaving that out puts
    the guess up to about 20 mm below the form-found messenger wire on long spans.)

    Parameters
    ----------
    catenary : Catenary
        The catenary (masses, tensions, droppers, pre-sag).
    span : int
        Span, from 0. [-]
    positions : ndarray
        Distances from the span's first mast. [m]
    """
    length = catenary.layout.span_lengths[span]
    x = np.asarray(positions, dtype=float)
    droppers = catenary.droppers
    dropper_height = float(np.min(catenary.mast_system_height()[span : span + 2]))
    dropper_mass = len(droppers.positions_in_span(length)) * (
        droppers.mass_per_length * dropper_height + 2.0 * droppers.clamp_mass) / length
    weight = GRAVITY * (catenary.contact_wire.mass_per_length + catenary.messenger_wire.mass_per_length + dropper_mass)
    cw, mw = catenary.contact_wire.tension, catenary.messenger_wire.tension
    return (weight * x * (length - x) / 2.0 - cw * catenary.presag_depth(span, x)) / mw


DROPPER_GUESS_MARGIN = 0.03
"""How far the first-guess length of a dropper (:func:`messenger_sag_guess`) may lie below the shortest
dropper before the section is refused without a solve: more than the guess's largest underestimate over
the form-finding study's 600 sections (20 mm, on 64 m spans, the arms carrying the contact wire next to
the masts; ``benchmarks/bench_form_finding_fuzz.py``). [m]"""


def check_dropper_room(catenary: Catenary, stations: SectionStations, lengths: np.ndarray,
                       min_length: float) -> None:
    """Refuse a section whose droppers cannot be cut: the messenger wire's first guess
    (:func:`messenger_sag_guess`) comes closer to the contact wire than ``min_length`` less
    :data:`DROPPER_GUESS_MARGIN`. A dropper within the margin is left to the form-finding, which refuses
    it after the solve if it is short.

    Parameters
    ----------
    catenary : Catenary
        The catenary.
    stations : SectionStations
        Node stations along the section.
    lengths : ndarray
        First-guess length of the dropper at every dropper station, in order. [m]
    min_length : float
        Shortest buildable dropper. [m]

    Raises
    ------
    ModelError
        One line: the span, the dropper's place, its guessed length and what to change.
    """
    short = np.flatnonzero((lengths <= 0.0) | (lengths < min_length - DROPPER_GUESS_MARGIN))
    if not len(short):
        return
    i = short[np.argmin(lengths[short])]
    span = int(stations.span[stations.is_dropper][i])
    where = float(stations.local[stations.is_dropper][i])
    raise ModelError(
        f"span {span + 1} ({catenary.layout.span_lengths[span]:g} m): the messenger wire sags to about "
        f"{lengths[i] * 1e3:.0f} mm from the contact wire at the dropper {where:.2f} m from the mast, where the "
        f"shortest dropper is {min_length * 1e3:.0f} mm (settings.min_dropper_length); raise the system height "
        "or the messenger-wire tension, shorten the span or lessen the pre-sag"
    )


def steady_arm_pivots(
    catenary: Catenary,
    wire_pos: np.ndarray,
    cw_nodes: np.ndarray,
    mast_cw: np.ndarray,
    termination: np.ndarray,
    arm_masts: list[int],
) -> np.ndarray:
    """First-guess pivot of each steady arm, from an estimate of the force the arm carries.

    Sideways: the resultant of the contact-wire tension at the clamp, from the real wire directions
    there (stagger change and curve kinks). Vertically: the contact-wire weight out to the first
    droppers, the pull of the pre-sagged wire and the kink of the support line where the
    contact-wire height changes. A pull-off arm (tension) is stretched by that force and points
    away from the wire's pull; a push-off arm (compression) is shortened and points towards it, so
    that Newton's method starts with the arm's geometric stiffness of the right sign (negative
    vertically for a push-off arm: an inverted pendulum).

    Parameters
    ----------
    catenary : Catenary
        The catenary.
    wire_pos : ndarray, shape (n_wire_nodes, 3)
        Design coordinates of the contact-wire and messenger-wire nodes. [m]
    cw_nodes : ndarray of int
        Contact-wire nodes in order along the wire. [-]
    mast_cw : ndarray of int
        Contact-wire node at each mast. [-]
    termination : ndarray
        Termination forces of the wire ends on every DOF (zero elsewhere). [N]
    arm_masts : list of int
        Masts with a steady arm. [-]

    Raises
    ------
    ModelError
        If the contact wire exerts (almost) no lateral pull at a mast: the arm would have no
        axial force and so no vertical stiffness.
    """
    if not arm_masts:
        return np.zeros((0, 3))
    arm = catenary.contact_wire_support
    tension = catenary.contact_wire.tension
    spans = catenary.layout.span_lengths
    heights = catenary.mast_contact_wire_height()
    push_off = catenary.mast_push_off()
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
                f"steady arm at mast {m + 1} (of {len(mast_cw)}): the contact wire pulls only {size:.3g} N sideways "
                "there (its stagger change and the curve's kink cancel), so the arm would have no vertical "
                "stiffness; change the stagger there (on a curve, register the wire to the outside), or use a "
                "spring support"
            )
        adjacent = [(i, spans[i], i + 1 if i == m else i) for i in (m - 1, m) if 0 <= i < len(spans)]
        first_drop = [catenary.droppers.positions_in_span(length)[0] for _, length, _ in adjacent]
        vertical = GRAVITY * (catenary.contact_wire.mass_per_length * sum(first_drop) / 2.0 + arm.mass / 2.0)
        # the pull of the parabola of presag_rel (for a profile: of its label, as good as a first guess needs)
        vertical += sum(4.0 * tension * catenary.presag_rel * (1.0 - 2.0 * d / length)
                        for d, (_, length, _) in zip(first_drop, adjacent))
        # a support line rising away from the mast lifts the clamp
        vertical -= sum(tension * (heights[other] - heights[m]) / length for _, length, other in adjacent)
        direction = np.append(-pull[:2], vertical)
        force = np.linalg.norm(direction)
        if push_off[m]:
            pivots.append(wire_pos[node] - arm.length * (1.0 - force / arm.axial_stiffness) * direction / force)
        else:
            pivots.append(wire_pos[node] + arm.length * (1.0 + force / arm.axial_stiffness) * direction / force)
    return np.asarray(pivots)
