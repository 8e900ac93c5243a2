"""The stitch wires of a stitched catenary as elements: nodes, cable segments and stitch droppers.

:func:`add_stitch_wires` adds, at every stitched inner mast, a chain of new nodes between the two
messenger-wire nodes at the stitch wire's clamps, one node at every contact-wire station between them
(the contact and messenger wire share their stations, so the stitch droppers hang vertically in the
design state). The design height of the stitch wire is the straight line between its clamps (a first
guess; form-finding sets its sag). Its segments are axial elements of group ``STITCH_WIRE`` whose
stiffness is EA over the unstretched length at the stitch wire's tension; the stitch droppers are
droppers (group ``DROPPER``, tension-only after form-finding) from the contact wire to the stitch wire.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.static.section_elements import STITCH_WIRE, SectionElements
from presag_opt.static.section_geometry import SectionStations
from presag_opt.system.catenary import Catenary


@dataclass(frozen=True, kw_only=True)
class StitchParts:
    """What :func:`add_stitch_wires` added.

    Attributes
    ----------
    positions : ndarray, shape (n_stitch_nodes, 3)
        Design coordinates of the new stitch-wire nodes (numbered after the wires). [m]
    chains : tuple of ndarray of int
        Per inner mast, the stitch wire's nodes in along-track order, its two messenger-wire clamp
        nodes at the ends. [-]
    masts : ndarray of int
        The mast of each chain. [-]
    dropper_elements : ndarray of int
        Axial-element indices of the stitch droppers, in along-track order. [-]
    dropper_cw_nodes : ndarray of int
        Contact-wire node of each stitch dropper. [-]
    """

    positions: np.ndarray
    chains: tuple[np.ndarray, ...]
    masts: np.ndarray
    dropper_elements: np.ndarray
    dropper_cw_nodes: np.ndarray


def add_stitch_wires(parts: SectionElements, cat: Catenary, stations: SectionStations, cw_nodes: np.ndarray,
                     mw_nodes: np.ndarray, cw_pos: np.ndarray, mw_pos: np.ndarray) -> StitchParts:
    """Add the stitch wires and their droppers to ``parts`` (nodes after the wires, before any pivot).

    Parameters
    ----------
    parts : SectionElements
        Elements collected so far (the wires and their droppers); extended in place.
    cat : Catenary
        System model; without a stitch wire nothing is added.
    stations : SectionStations
        Along-track stations of the wire nodes.
    cw_nodes : ndarray of int, shape (n_stations,)
        Contact-wire node of each station. [-]
    mw_nodes : ndarray of int, shape (n_stations,)
        Messenger-wire node of each station. [-]
    cw_pos : ndarray, shape (n_stations, 3)
        Design coordinates of the contact-wire nodes. [m]
    mw_pos : ndarray, shape (n_stations, 3)
        Design coordinates of the messenger-wire nodes. [m]

    Returns
    -------
    StitchParts
        What was added (empty when the catenary has no stitch wire).

    Raises
    ------
    ModelError
        If the straight first guess of a stitch wire does not lie above the contact wire.
    """
    stitch = cat.stitch_wire
    empty = np.zeros(0, dtype=int)
    n_spans = len(stations.mast_station) - 1
    if stitch is None or not any(stitch.at_mast(m, n_spans) for m in range(n_spans + 1)):
        return StitchParts(positions=np.zeros((0, 3)), chains=(), masts=empty, dropper_elements=empty,
                           dropper_cw_nodes=empty)
    half = 0.5 * stitch.length
    first = len(parts.node_mass)
    positions, chains, masts, d_cw, d_st = [], [], [], [], []
    for m in range(1, n_spans):
        if not stitch.at_mast(m, n_spans):
            continue
        mast = stations.mast_station[m]
        left = int(np.argmin(np.abs(stations.station - (mast - half))))
        right = int(np.argmin(np.abs(stations.station - (mast + half))))
        inner = np.arange(left + 1, right)
        t = (stations.station[inner] - stations.station[left]) / (stations.station[right] - stations.station[left])
        z = mw_pos[left, 2] + t * (mw_pos[right, 2] - mw_pos[left, 2])
        if np.any(z - cw_pos[inner, 2] <= 0.05):
            raise ModelError(
                f"stitch_wire at mast {m}: the stitch wire between its clamps comes within 50 mm of the contact "
                "wire; shorten it or raise the system height"
            )
        new = first + sum(len(p) for p in positions) + np.arange(len(inner))
        positions.append(np.column_stack([mw_pos[inner, :2], z]))
        chains.append(np.concatenate([[mw_nodes[left]], new, [mw_nodes[right]]]))
        masts.append(m)
        wanted = mast + np.asarray(stitch.dropper_positions)
        at = np.searchsorted(stations.station[inner], wanted - 1e-9)
        if np.any(np.abs(stations.station[inner][np.minimum(at, len(inner) - 1)] - wanted) > 1e-6):
            raise ModelError(f"stitch_wire at mast {m}: a stitch dropper has no station (internal error)")
        d_cw.append(cw_nodes[inner[at]])
        d_st.append(new[at])
    pos = np.vstack(positions)
    parts.node_mass = np.concatenate([parts.node_mass, np.zeros(len(pos))])
    parts.fixed = np.vstack([parts.fixed, np.zeros((len(pos), 3), dtype=bool)])
    all_pos = np.vstack([cw_pos, mw_pos, pos])
    for chain in chains:
        parts.add_wire(chain, stitch, STITCH_WIRE, all_pos[chain])
    d_cw, d_st = np.concatenate(d_cw), np.concatenate(d_st)
    start = parts.n_axial
    count = parts.add_droppers(cat, d_cw, d_st, all_pos[d_st, 2] - all_pos[d_cw, 2])
    return StitchParts(positions=pos, chains=tuple(chains), masts=np.asarray(masts, dtype=int),
                       dropper_elements=start + np.arange(count), dropper_cw_nodes=d_cw)
