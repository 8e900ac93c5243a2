"""Limits of a per-dropper pre-sag profile that a line crew can build, and how far a profile exceeds them.

Holds :class:`Buildability` (construction step, depth range, kink angle at a dropper, shortest
dropper) and the exact check of a profile against it. The same limits enter the linear program as
constraints in :mod:`presag_opt.robust.lp`; putting a profile on the construction step is
:mod:`presag_opt.robust.rounding`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.robust.path import PathModel
from presag_opt.system.quantity import quantity, validate_fields


@dataclass(frozen=True, kw_only=True)
class Buildability:
    """Limits of a per-dropper pre-sag profile that a line crew can build.

    Attributes
    ----------
    step : float
        Construction step of the dropper heights; 0 for none. [m]
    max_depth_rel : float
        Largest depth below the support level, relative to the span length. [-]
    max_kink : float
        Largest change of contact-wire slope at a dropper. [-] (shown in ‰)
    min_dropper_length : float
        Shortest dropper. [m]
    symmetric : bool
        Same depth at mirror-image droppers of a span.
    """

    step: float = quantity("length", 0.0, 50.0, display="mm", default=0.005)
    max_depth_rel: float = quantity("ratio", 0.0, 5.0, display="‰", default=0.004)
    max_kink: float = quantity("ratio", 0.0, 50.0, display="‰", default=0.003)
    min_dropper_length: float = quantity("length", 0.0, 2000.0, display="mm", default=0.15)
    symmetric: bool = True

    def __post_init__(self) -> None:
        validate_fields(self, prefix="buildability.")


def _span_kinks(path: PathModel) -> list[tuple[np.ndarray, np.ndarray]]:
    """For every analysed span: dropper indices and positions (with the masts, depth 0)."""
    out = []
    for s in path.spans:
        idx = np.flatnonzero(path.dropper_span == s)
        out.append((idx, path.dropper_fraction[idx] * path.state.catenary.layout.span_lengths[s]))
    return out


def _violation(path: PathModel, depths: np.ndarray, build: Buildability) -> float:
    """Largest excess of a profile over the buildability limits (0 if it meets them all). [m or -]"""
    lengths = np.asarray(path.state.catenary.layout.span_lengths)[path.dropper_span]
    excess = [
        np.max(-depths, initial=0.0),
        np.max(depths - build.max_depth_rel * lengths, initial=0.0),
        np.max(build.min_dropper_length
               - (path.dropper_length + path.length_sensitivity @ (depths - path.reference_depth)), initial=0.0),
    ]
    for idx, pos in _span_kinks(path):
        length = path.state.catenary.layout.span_lengths[int(path.dropper_span[idx[0]])]
        full = np.concatenate([[0.0], depths[idx], [0.0]])
        slope = np.diff(full) / np.diff(np.concatenate([[0.0], pos, [length]]))
        excess.append(np.max(np.abs(np.diff(slope)) - build.max_kink, initial=0.0))
    worst = max(excess)
    return worst if worst > 1e-9 else 0.0
