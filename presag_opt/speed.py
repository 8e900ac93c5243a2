"""Train speed against the contact wire's wave speed.

The speed ratio β = v / c_CW with c_CW = sqrt(T_CW / ρ_CW) separates the quasi-static from the
dynamic regime (Schick, Liu & Stichel 2025, eq. (6): the quasi-static pre-sag rule holds for
β ≲ 0.4); EN 50119 limits design speeds to 0.7 c_CW. The Doppler factor (c − v)/(c + v) measures
how strongly waves reflected ahead of the pantograph are amplified.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, eq. (6).
"""

from __future__ import annotations

import math
import warnings

from presag_opt.errors import ModelError
from presag_opt.units import KMH

SPEED_RATIO_LIMIT = 0.7
"""Largest speed ratio β = v / c_CW EN 50119 allows for a design speed; :func:`speed_ratio` warns
above it and :func:`check_speed_limit` refuses speeds at or above it unless they are accepted. [-]"""


def wave_speed(tension: float, mass_per_length: float) -> float:
    """Transverse wave propagation speed of a tensioned wire, c = sqrt(T / ρ).

    Parameters
    ----------
    tension : float
        Wire tension T. [N]
    mass_per_length : float
        Mass per metre ρ. [kg/m]

    Returns
    -------
    float
        Wave speed c. [m/s]
    """
    for name, value, unit in (("tension", tension, "N"), ("mass_per_length", mass_per_length, "kg/m")):
        if not (value > 0.0 and math.isfinite(value)):
            raise ModelError(f"{name} = {value!r} {unit} is outside the valid range (0, ∞) {unit}")
    return math.sqrt(tension / mass_per_length)


def speed_ratio(speed: float, wave_speed: float) -> float:
    """Speed ratio β = v / c; warns above :data:`SPEED_RATIO_LIMIT` (0.7).

    Parameters
    ----------
    speed : float
        Train speed v. [m/s]
    wave_speed : float
        Contact-wire wave speed c. [m/s]

    Returns
    -------
    float
        β. [-]

    Raises
    ------
    ModelError
        A negative speed, a non-positive wave speed, or a speed at or above the wave speed (the
        contact wire cannot carry the pantograph's wave ahead of it: no steady solution).
    """
    _check_below_wave_speed(speed, wave_speed)
    beta = speed / wave_speed
    if beta > SPEED_RATIO_LIMIT:
        warnings.warn(
            f"speed ratio β = {beta:.2f} exceeds {SPEED_RATIO_LIMIT} (EN 50119): wave reflections and the "
            "Doppler effect dominate the interaction",
            stacklevel=2,
        )
    return beta


def check_speed_limit(speed: float, wave_speed: float, *, accept: str = "allow_supercritical=True") -> None:
    """Refuse a speed at or above :data:`SPEED_RATIO_LIMIT` of the wave speed (EN 50119).

    Such runs are legitimate studies of the near-critical regime but expensive (their automatic
    numerics shrink with 1 − β) and almost always a typing slip on a design command, so they must be
    accepted explicitly.

    Parameters
    ----------
    speed : float
        Train speed v. [m/s]
    wave_speed : float
        Contact-wire wave speed c. [m/s]
    accept : str
        The setting that accepts such a speed, named in the message (the command line passes its
        option). [-]

    Raises
    ------
    ModelError
        One line naming the speed, its β, the limit and the largest speed within it, and ``accept``;
        a speed at or above the wave speed as :func:`speed_ratio` does (no option accepts it).
    """
    _check_below_wave_speed(speed, wave_speed)
    beta = speed / wave_speed
    if beta >= SPEED_RATIO_LIMIT:
        raise ModelError(
            f"speed = {speed / KMH:g} km/h is β = {beta:.2f} of the contact-wire wave speed {wave_speed / KMH:.0f} km/h, "
            f"at or above the EN 50119 limit β < {SPEED_RATIO_LIMIT} (speeds below {SPEED_RATIO_LIMIT * wave_speed / KMH:.0f} "
            f"km/h); give {accept} to run it anyway"
        )


def _check_below_wave_speed(speed: float, wave_speed: float) -> None:
    """Refuse a non-positive wave speed, a negative speed or one at or above the wave speed."""
    if not wave_speed > 0.0:
        raise ModelError(f"wave_speed = {wave_speed!r} m/s must be positive")
    if not 0.0 <= speed < wave_speed:
        raise ModelError(
            f"speed = {speed / KMH:g} km/h is outside the valid range [0, {wave_speed / KMH:g}) km/h "
            f"(below the contact-wire wave speed {wave_speed:g} m/s)"
        )


def doppler_factor(speed: float, wave_speed: float) -> float:
    """Doppler factor (c - v)/(c + v) of waves reflected ahead of the pantograph.

    Parameters
    ----------
    speed : float
        Train speed v. [m/s]
    wave_speed : float
        Contact-wire wave speed c. [m/s]

    Returns
    -------
    float
        (1 - β)/(1 + β), in (0, 1]. [-]
    """
    beta = speed_ratio(speed, wave_speed)
    return (1.0 - beta) / (1.0 + beta)
