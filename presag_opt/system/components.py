"""Parts of a catenary system model: wires, droppers, steady arms, supports, damping, provenance.

All values are SI inside these classes (N, m, kg, N/m, N·m²); model files and the command line may
use kN, mm, ‰ and are converted on loading. Every class is frozen and keyword-only, and checks its
fields on construction (see :mod:`presag_opt.system.quantity`). The span layout and the whole
tension section that assemble them are in :mod:`presag_opt.system.catenary`.

Sign convention: x along the track, y lateral (positive to the left looking in +x), z up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.system.quantity import quantity, validate_fields

GRAVITY = 9.81
"""Acceleration due to gravity. [m/s²]"""


@dataclass(frozen=True, kw_only=True)
class Provenance:
    """Where a number in a model file comes from.

    Attributes
    ----------
    source : str
        One of ``paper``, ``standard``, ``secondary-source``, ``assumed``.
    note : str
        Free text: table, page or reasoning.
    range : tuple of float or None
        Plausible range of the number declared beside it (``range = [low, high]``), SI; None if the
        file declares none. [SI unit of the number]
    range_note : str
        Why the range is plausible (its source or reasoning).
    """

    source: str
    note: str = ""
    range: tuple[float, float] | None = None
    range_note: str = ""


@dataclass(frozen=True, kw_only=True)
class Wire:
    """A contact or messenger wire held at constant tension by balance weights.

    Attributes
    ----------
    tension : float
        Tension set by the balance weights (horizontal component). [N]
    mass_per_length : float
        Mass per metre. [kg/m]
    axial_stiffness : float
        EA. [N]
    bending_stiffness : float
        EI; zero makes a pure cable. [N·m²]
    """

    tension: float = quantity("force", 0.5, 60.0, display="kN")
    mass_per_length: float = quantity("mass_per_length", 0.05, 5.0)
    axial_stiffness: float = quantity("force", 0.1, 100.0, display="MN")
    bending_stiffness: float = quantity("bending_stiffness", 0.0, 5000.0, default=0.0)

    def __post_init__(self) -> None:
        validate_fields(self)

    @property
    def wave_speed(self) -> float:
        """Transverse wave speed sqrt(T/ρ). [m/s]"""
        from presag_opt.speed import wave_speed

        return wave_speed(self.tension, self.mass_per_length)


@dataclass(frozen=True, kw_only=True)
class Droppers:
    """Dropper placement and properties (the same rule in every span).

    Placement is either explicit ``positions`` (distances from the span's first mast, used in every
    span) or the rule: first and last dropper ``end_distance`` from the masts, the rest evenly spaced
    no more than ``max_spacing`` apart.

    Attributes
    ----------
    end_distance : float
        Distance of the first and last dropper from the masts. [m]
    max_spacing : float
        Largest spacing between inner droppers. [m]
    positions : tuple of float or None
        Explicit positions from the first mast of each span. [m]
    axial_stiffness : float or None
        EA of the dropper; the spring stiffness is EA divided by the designed dropper length. [N]
    stiffness : float or None
        Spring stiffness in tension, independent of length (EN 50318 style). [N/m]
    mass_per_length : float
        Dropper wire mass per metre. [kg/m]
    clamp_mass : float
        Mass of each of the two clamps (on the contact and on the messenger wire). [kg]
    """

    end_distance: float = quantity("length", 0.5, 20.0, default=4.5)
    max_spacing: float = quantity("length", 1.0, 30.0, default=8.5)
    positions: tuple[float, ...] | None = quantity("length", 0.0, 100.0, low_open=True, default=None, allow_none=True)
    axial_stiffness: float | None = quantity("force", 0.001, 100.0, display="MN", default=None, allow_none=True)
    stiffness: float | None = quantity("stiffness", 1.0, 1e5, display="kN/m", default=None, allow_none=True)
    mass_per_length: float = quantity("mass_per_length", 0.0, 1.0, default=0.0)
    clamp_mass: float = quantity("mass", 0.0, 2.0, default=0.0)

    def __post_init__(self) -> None:
        validate_fields(self)
        if (self.axial_stiffness is None) == (self.stiffness is None):
            raise ModelError(
                "droppers: give exactly one of axial_stiffness (EA, in MN) or stiffness (spring, in kN/m)"
            )
        if self.positions is not None:
            object.__setattr__(self, "positions", tuple(float(p) for p in self.positions))
            if any(b <= a for a, b in zip(self.positions, self.positions[1:])):
                raise ModelError(f"droppers.positions = {list(self.positions)} m must be strictly increasing")

    def positions_in_span(self, span_length: float) -> np.ndarray:
        """Dropper positions from the first mast of a span of the given length. [m]

        Parameters
        ----------
        span_length : float
            Length of the span. [m]
        """
        if self.positions is not None:
            pos = np.asarray(self.positions)
            if pos[-1] >= span_length:
                raise ModelError(
                    f"droppers.positions: last dropper at {pos[-1]:g} m lies outside a span of {span_length:g} m"
                )
            return pos
        inner = span_length - 2.0 * self.end_distance
        if inner <= 1e-9:  # at exactly twice the end distance both end droppers would hang at one point
            raise ModelError(
                f"droppers.end_distance = {self.end_distance:g} m does not fit a span of {span_length:g} m "
                f"(needs span length > {2 * self.end_distance:g} m)"
            )
        intervals = max(1, math.ceil(inner / self.max_spacing - 1e-9))
        return self.end_distance + np.linspace(0.0, inner, intervals + 1)


@dataclass(frozen=True, kw_only=True)
class SteadyArm:
    """Steady arm: a link pivoting at the mast that registers the contact wire laterally.

    Its vertical stiffness is not an input: it follows from the arm's tension, which the lateral
    pull of the staggered (or curved) contact wire sets.

    Attributes
    ----------
    type : {"steady_arm"}
        The support's kind in a model file.
    length : float
        Pivot-to-clamp length. [m]
    mass : float
        Arm mass; half of it acts at the contact-wire clamp. [kg]
    axial_stiffness : float
        EA of the arm tube. [N]
    """

    type: Literal["steady_arm"] = "steady_arm"
    length: float = quantity("length", 0.3, 3.0)
    mass: float = quantity("mass", 0.0, 10.0)
    axial_stiffness: float = quantity("force", 0.1, 1000.0, display="MN", default=20e6)

    def __post_init__(self) -> None:
        validate_fields(self)


@dataclass(frozen=True, kw_only=True)
class SpringSupport:
    """A plain vertical spring with a lumped mass at the support (EN 50318 reference model style).

    Attributes
    ----------
    type : {"spring"}
        The support's kind in a model file.
    stiffness : float
        Vertical spring stiffness. [N/m]
    mass : float
        Lumped mass at the support point. [kg]
    """

    type: Literal["spring"] = "spring"
    stiffness: float = quantity("stiffness", 1.0, 1e8, low_open=False)
    mass: float = quantity("mass", 0.0, 50.0, default=0.0)

    def __post_init__(self) -> None:
        validate_fields(self)


@dataclass(frozen=True, kw_only=True)
class PinSupport:
    """The messenger wire fixed laterally and vertically at the mast (free along the track)."""

    type: Literal["pin"] = "pin"


@dataclass(frozen=True, kw_only=True)
class Damping:
    """Structural damping for dynamic analysis: a modal ratio, or Rayleigh coefficients.

    Attributes
    ----------
    ratio : float or None
        Damping ratio used to build Rayleigh damping over the band of interest. [-]
    rayleigh_alpha : float or None
        Mass-proportional coefficient. [1/s]
    rayleigh_beta : float or None
        Stiffness-proportional coefficient. [s]
    """

    ratio: float | None = quantity("ratio", 0.0, 0.5, default=None, allow_none=True)
    rayleigh_alpha: float | None = quantity("frequency", 0.0, 50.0, display="1/s", default=None, allow_none=True)
    rayleigh_beta: float | None = quantity("time", 0.0, 0.05, default=None, allow_none=True)

    def __post_init__(self) -> None:
        validate_fields(self)
        has_ratio = self.ratio is not None
        has_rayleigh = self.rayleigh_alpha is not None or self.rayleigh_beta is not None
        if has_ratio == has_rayleigh:
            raise ModelError("damping: give either ratio, or rayleigh_alpha and rayleigh_beta")
