"""Stitch wires: a short cable at each inner support of a stitched catenary, and its stitch droppers.

A stitch wire (Y-wire) hangs from two clamps on the messenger wire, half its length either side of a
support, and passes below the support; one or more stitch droppers hang the contact wire from it near
the mast. Being a taut string between its clamps, it gives the contact wire near the support a
flexibility of its own (about F·a·b/(T·l) under a point force F at distances a, b from its ends) in
series with the messenger wire's, which is what flattens the elasticity there.

The same stitch wire is fitted at every inner mast of the section, or at the inner masts listed in
``masts`` (a surveyed line, :mod:`presag_opt.system.survey`, marks its stitched masts); the two end
masts (the terminations) are never stitched in the model. Values are SI; model files may use kN and MN.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

from presag_opt.errors import ModelError
from presag_opt.system.quantity import quantity, validate_fields


@dataclass(frozen=True, kw_only=True)
class StitchWire:
    """A stitch wire at every inner support (or at the listed ones), with its stitch droppers.

    Attributes
    ----------
    length : float
        Distance between the two messenger-wire clamps, centred on the support. [m]
    tension : float
        Horizontal tension of the stitch wire in the design state; form-finding finds the stitch
        wire's unstretched length that carries it. [N]
    mass_per_length : float
        Mass per metre. [kg/m]
    axial_stiffness : float
        EA. [N]
    dropper_positions : tuple of float
        Signed distance of each stitch dropper from the support, negative before it along the track
        (strictly increasing, inside the stitch wire, not at the support). The stitch droppers have
        the properties of the section's droppers. [m]
    masts : tuple of int or None
        The inner masts that carry the stitch wire, counted from the section's first mast (0), strictly
        increasing, each at least 1 (the end masts are never stitched; the catenary checks the upper
        end); None: every inner mast. [-]
    """

    length: float = quantity("length", 2.0, 40.0)
    tension: float = quantity("force", 0.1, 20.0, display="kN")
    mass_per_length: float = quantity("mass_per_length", 0.01, 2.0)
    axial_stiffness: float = quantity("force", 0.1, 100.0, display="MN")
    dropper_positions: tuple[float, ...] = quantity("length", -20.0, 20.0)
    masts: tuple[int, ...] | None = None

    def __post_init__(self) -> None:
        validate_fields(self)
        if self.masts is not None:
            if isinstance(self.masts, (str, bytes)) or not all(isinstance(m, int) and not isinstance(m, bool)
                                                                 for m in self.masts):
                raise ModelError(f"stitch_wire.masts = {self.masts!r} must be whole mast numbers (the first mast is 0)")
            masts = tuple(int(m) for m in self.masts)
            if not masts or masts[0] < 1 or any(b <= a for a, b in itertools.pairwise(masts)):
                raise ModelError(f"stitch_wire.masts = {list(masts)} must be strictly increasing inner masts, each "
                                 ">= 1 (mast 0 and the last mast are the section's ends, never stitched)")
            object.__setattr__(self, "masts", masts)
        pos = tuple(float(p) for p in self.dropper_positions)
        object.__setattr__(self, "dropper_positions", pos)
        half = 0.5 * self.length
        for i, p in enumerate(pos):
            if not (-half < p < half) or abs(p) < 0.1:
                raise ModelError(
                    f"dropper_positions[{i}] = {p:g} m is outside the valid range (-{half:g}, -0.1] or "
                    f"[0.1, {half:g}) m (inside the {self.length:g} m stitch wire, not at the support)"
                )
        if any(b <= a for a, b in itertools.pairwise(pos)):
            raise ModelError(f"dropper_positions = {list(pos)} m must be strictly increasing")

    @property
    def bending_stiffness(self) -> float:
        """EI of the stitch wire: none, it is a pure cable. [N·m²]"""
        return 0.0

    def at_mast(self, mast: int, n_spans: int) -> bool:
        """Whether mast ``mast`` (0 = the section's first) carries the stitch wire.

        Parameters
        ----------
        mast : int
            Mast, from 0. [-]
        n_spans : int
            Spans of the section (its end masts 0 and ``n_spans`` are never stitched). [-]
        """
        if not 1 <= mast <= n_spans - 1:
            return False
        return self.masts is None or mast in self.masts

    def points_in_span(self, span: int, n_spans: int, span_length: float) -> tuple[list[float], list[float]]:
        """Clamp and stitch-dropper positions of the stitch wires that reach into a span.

        Parameters
        ----------
        span : int
            Span, from 0. [-]
        n_spans : int
            Spans of the section (its end masts are not stitched). [-]
        span_length : float
            Length of the span. [m]

        Returns
        -------
        clamps, droppers : list of float
            Distances from the span's first mast of the stitch wires' messenger-wire clamps and of the
            stitch droppers in the span. [m]
        """
        half = 0.5 * self.length
        clamps, droppers = [], []
        if self.at_mast(span, n_spans):  # the stitch wire of the span's first mast
            clamps.append(half)
            droppers += [p for p in self.dropper_positions if p > 0.0]
        if self.at_mast(span + 1, n_spans):  # the stitch wire of the span's last mast
            clamps.append(span_length - half)
            droppers += [span_length + p for p in self.dropper_positions if p < 0.0]
        return clamps, sorted(droppers)


def stitch_summary(catenary) -> str:
    """One line saying whether a catenary is stitched and with what, for reports and command output.

    Parameters
    ----------
    catenary : Catenary
        The system.

    Returns
    -------
    str
        ``"simple (no stitch wires)"``, or e.g. ``"stitched: a 14 m stitch wire at 2 kN at every inner
        mast, stitch droppers at -4, 4 m from the support"``.
    """
    stitch = catenary.stitch_wire
    n_spans = catenary.layout.n_spans
    masts = [m for m in range(n_spans + 1) if stitch is not None and stitch.at_mast(m, n_spans)]
    if not masts:
        return "simple (no stitch wires)"
    where = "every inner mast" if stitch.masts is None else "masts " + ", ".join(str(m + 1) for m in masts)
    drops = ", ".join(f"{p:g}" for p in stitch.dropper_positions)
    return (f"stitched: a {stitch.length:g} m stitch wire at {stitch.tension * 1e-3:g} kN at {where} "
            f"(counted from 1), stitch droppers at {drops} m from the support")
