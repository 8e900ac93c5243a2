"""The operating band of a line: static forces and speeds, the mean contact force, force levels.

Holds eq. (4), F_m = F_stat + α_ae v², the :class:`OperatingBand` with the case study's band, and the
grids of forces derived from a band (elasticity force levels that bracket it, the 1 N grid the
rules are evaluated on). The rules themselves are in :mod:`presag_opt.design.quasi_static`.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: eq. (4), section 5.2.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt import contact_force
from presag_opt.errors import ModelError
from presag_opt.system.quantity import quantity, validate_fields
from presag_opt.units import KMH

FORCE_LEVEL_SPACING = 50.0
"""Spacing of the elasticity force levels (the paper: "three force steps of 50 N"). [N]"""



def mean_contact_force(
    static_force: float | np.ndarray, speed: float | np.ndarray, aero_coefficient: float
) -> float | np.ndarray:
    """Mean contact force F_m = F_stat + α_ae v².

    Parameters
    ----------
    static_force : float or ndarray
        Static contact force F_stat. [N]
    speed : float or ndarray
        Train speed v. [m/s]
    aero_coefficient : float
        Aerodynamic uplift coefficient α_ae. [N/(m/s)²] (0.00097 N/(km/h)² = 0.01257 N/(m/s)²)

    Returns
    -------
    float or ndarray
        F_m. [N]

    Raises
    ------
    ModelError
        If a force, speed or coefficient is not finite or is negative.

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, eq. (4).
    """
    for name, value, unit in (("static_force", static_force, "N"), ("speed", speed, "m/s"),
                              ("aero_coefficient", aero_coefficient, "N/(m/s)²")):
        values = np.asarray(value, dtype=float)
        if not np.all(np.isfinite(values)) or np.any(values < 0.0):
            bad = values.ravel()[~(np.isfinite(values.ravel()) & (values.ravel() >= 0.0))][0]
            raise ModelError(f"{name} = {bad:g} {unit} is outside the valid range [0, ∞) {unit} (finite)")
    return contact_force.mean_force(static_force, speed, aero_coefficient)


@dataclass(frozen=True, kw_only=True)
class OperatingBand:
    """The band of static contact forces and speeds a line must serve.

    Attributes
    ----------
    static_force_low, static_force_high : float
        Range of the fleet's static contact force F_stat. [N]
    speed_low, speed_high : float
        Range of train speeds. [m/s] (given in km/h in files and on the command line)
    aero_coefficient : float
        Aerodynamic uplift coefficient α_ae. [N/(m/s)²] (shown in N/(km/h)²)
    """

    static_force_low: float = quantity("force", 0.0, 1000.0, low_open=True)
    static_force_high: float = quantity("force", 0.0, 1000.0, low_open=True)
    speed_low: float = quantity("speed", 0.0, 500.0, display="km/h", default=0.0)
    speed_high: float = quantity("speed", 0.0, 500.0, display="km/h")
    aero_coefficient: float = quantity("aero_coefficient", 0.0, 0.01, display="N/(km/h)^2")

    def __post_init__(self) -> None:
        validate_fields(self)
        if self.static_force_low > self.static_force_high:
            raise ModelError(
                f"static_force_low = {self.static_force_low:g} N is above static_force_high = "
                f"{self.static_force_high:g} N; give the band as low <= high"
            )
        if self.speed_low > self.speed_high:
            raise ModelError(
                f"speed_low = {self.speed_low / KMH:g} km/h is above speed_high = {self.speed_high / KMH:g} km/h; "
                "give the band as low <= high"
            )

    @classmethod
    def from_kmh(cls, *, static_force: float | tuple[float, float], speed_kmh: float | tuple[float, float],
                 aero_coefficient_kmh: float) -> OperatingBand:
        """The band in the designer's units: N, km/h and N/(km/h)².

        Parameters
        ----------
        static_force : float or (float, float)
            Static contact force F_stat, one value or the band (low, high). [N]
        speed_kmh : float or (float, float)
            The top speed, or the speed band (low, high). [km/h]
        aero_coefficient_kmh : float
            Aerodynamic uplift coefficient α_ae. [N/(km/h)²]

        Examples
        --------
        The case study's band, F_stat 70–140 N up to 90 km/h:

        >>> from presag_opt import OperatingBand
        >>> band = OperatingBand.from_kmh(static_force=(70, 140), speed_kmh=90, aero_coefficient_kmh=0.00097)
        >>> band.speed_kmh, band.mean_force_band()
        ((0.0, 90.0), (70.0, 147.857))
        """
        low, high = (static_force, static_force) if isinstance(static_force, int | float) else static_force
        slow, shigh = (0.0, speed_kmh) if isinstance(speed_kmh, int | float) else speed_kmh
        return cls(static_force_low=float(low), static_force_high=float(high), speed_low=slow * KMH,
                   speed_high=shigh * KMH, aero_coefficient=aero_coefficient_kmh / KMH**2)

    @property
    def speed_kmh(self) -> tuple[float, float]:
        """The speed band (low, high). [km/h]"""
        return (self.speed_low / KMH, self.speed_high / KMH)

    @property
    def aero_coefficient_kmh(self) -> float:
        """α_ae. [N/(km/h)²]"""
        return self.aero_coefficient * KMH**2

    def mean_force_band(self) -> tuple[float, float]:
        """F_m at the low end (lowest F_stat, lowest speed) and the high end of the band. [N]"""
        return (
            float(mean_contact_force(self.static_force_low, self.speed_low, self.aero_coefficient)),
            float(mean_contact_force(self.static_force_high, self.speed_high, self.aero_coefficient)),
        )

    def to_dict(self) -> dict:
        """JSON-ready content in edge units (N, km/h, N/(km/h)²)."""
        return {
            "static_force_N": [self.static_force_low, self.static_force_high],
            "speed_kmh": list(self.speed_kmh),
            "aero_coefficient_N_per_kmh2": self.aero_coefficient_kmh,
        }


CASE_STUDY_BAND = OperatingBand(
    static_force_low=70.0,
    static_force_high=140.0,
    speed_low=0.0,
    speed_high=90.0 * KMH,
    aero_coefficient=0.00097 / KMH**2,
)
"""The case study's band: F_stat 70–140 N, 0–90 km/h, α_ae = 0.00097 N/(km/h)² (section 5.2)."""


def force_levels_for_band(low: float, high: float, spacing: float = FORCE_LEVEL_SPACING) -> tuple[float, ...]:
    """Elasticity force levels on a regular grid that brackets a force band.

    Multiples of ``spacing`` from the one at or below ``low`` to the one at or above ``high``; if
    the lowest multiple would be zero, ``low`` itself is the lowest level (a level must be positive).

    Parameters
    ----------
    low, high : float
        The mean-force band. [N]
    spacing : float
        Grid spacing. [N]

    Returns
    -------
    tuple of float
        Increasing force levels. [N]
    """
    if not 0.0 < low <= high:
        raise ModelError(f"force band [{low:g}, {high:g}] N: need 0 < low <= high")
    first = math.floor(low / spacing + 1e-9)
    last = math.ceil(high / spacing - 1e-9)
    levels = [spacing * i for i in range(max(first, 1), last + 1)]
    if first < 1:
        levels.insert(0, float(low))
    return tuple(sorted(set(levels)))


def check_levels_cover(levels: Sequence[float], low: float, high: float) -> None:
    """Raise ModelError unless the force levels [N] are positive and span the mean-force band [low, high] [N].

    Parameters
    ----------
    levels : sequence of float
        Mean-force levels of the elasticity study. [N]
    low : float
        Lower end of the mean-force band. [N]
    high : float
        Upper end of the mean-force band. [N]
    """
    bad = [f for f in levels if not 0.0 < f <= 2000.0]
    if bad:
        raise ModelError(f"force level = {bad[0]:g} N is outside the valid range (0, 2000] N")
    if not levels or not (min(levels) <= low and high <= max(levels)):
        suggested = force_levels_for_band(low, high)
        raise ModelError(
            f"force levels {[float(f) for f in levels]} N do not cover the mean-force band [{low:.1f}, {high:.1f}] N; "
            f"use levels from {suggested[0]:g} N to {suggested[-1]:g} N, e.g. {','.join(f'{f:g}' for f in suggested)}"
        )


def mean_force_grid(low: float, high: float, extra: Sequence[float] = ()) -> np.ndarray:
    """Forces from ``low`` to ``high`` at most 1 N apart, with the ends and ``extra`` points inside.

    Parameters
    ----------
    low, high : float
        Ends of the grid. [N]
    extra : sequence of float
        Forces to include where they lie strictly inside. [N]

    Returns
    -------
    ndarray
        Increasing forces. [N]
    """
    n = max(2, math.ceil(high - low) + 1)
    inside = [f for f in extra if low < f < high]
    return np.unique(np.concatenate([np.linspace(low, high, n), inside]))
