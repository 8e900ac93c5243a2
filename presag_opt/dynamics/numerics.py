"""Numerics that follow the speed: element length and time step from the speed ratio.

The contact force is analysed up to the cut-off frequency f_c (20 Hz, EN 50367). Ahead of a
pantograph at speed v the wire carries its shortest relevant waves: the pantograph meets them at
f_c, so their length is λ = (c − v)/f_c, and the wire carries them at the frequency
c/λ = f_c/(1 − β), β = v/c. Both shrink as β rises: 4.1 m and 23 Hz at 50 km/h on ST 9,8/9,8,
2.3 m and 42 Hz at 180 km/h, 1.9 m and 63 Hz at 300 km/h on the EN 50318-style wire.

The rule (:func:`numerics_for_speed`): at least :data:`ELEMENTS_PER_WAVELENGTH` elements per λ and
:data:`STEPS_PER_PERIOD` time steps per period of f_c/(1 − β), never coarser than the paper's 0.5 m
and 2 ms. The two numbers come from the convergence study ``research/convergence.py`` on the
EN 50318-style case, the least damped of the built-in systems, against 0.25 m / 0.5 ms:

- elements per λ at 300 km/h (0.5 ms): 3.8 → σ −15 %, 4.8 → −5.7 %, 5.8 → −1.8 %; at 250 km/h
  5.2 → −2.7 %, 6.5 → −0.65 %, 7.9 → −0.18 %;
- steps per period at 300 km/h (0.25 m): 7.9 → σ −6.5 %, 10.5 → −2.8 %, 15.8 → −0.5 %; at 250 km/h
  10.7 → −0.2 %, 14.3 → +0.05 %.

Eight elements and sixteen steps keep σ within about 0.5 % of the finest discretisation there
(0.24 m and 0.98 ms at 300 km/h, which puts all eight EN 50318 statistics inside their ranges).
On ST 9,8/9,8 the rule gives the paper's 0.5 m up to 56 km/h and its 2 ms up to 124 km/h.

:func:`resolution_warnings` names a setting of a run that falls below
:data:`WARN_ELEMENTS_PER_WAVELENGTH` or :data:`WARN_STEPS_PER_PERIOD`, where the same study puts the
error of σ at 2–3 % or more. The paper's 0.5 m and 2 ms pass up to about 120 km/h on ST 9,8/9,8
(β ≈ 0.35) and are flagged above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from presag_opt.errors import ModelError
from presag_opt.units import KMH

ELEMENTS_PER_WAVELENGTH = 8.0
"""Fewest elements per shortest relevant wavelength (c − v)/f_c. [-]"""

STEPS_PER_PERIOD = 16.0
"""Fewest time steps per period of the shortest relevant wave as the wire carries it, f_c/(1 − β). [-]"""

WARN_ELEMENTS_PER_WAVELENGTH = 6.0
"""Below this many elements per shortest wavelength a run is flagged as under-resolved. [-]"""

WARN_STEPS_PER_PERIOD = 11.0
"""Below this many steps per period of the wire frequency a run is flagged as under-resolved. [-]"""

MAX_ELEMENT_LENGTH = 0.5
"""Longest element the rule gives: the paper's "elements ≤ 0.5 m". [m]"""

MAX_TIME_STEP = 2e-3
"""Longest time step the rule gives: the paper's 2 ms. [s]"""

ELEMENT_GRID = 0.01
"""Element lengths are rounded down to this grid, so that nearby speeds share a discretisation. [m]"""

TIME_STEP_GRID = 1e-4
"""Time steps are rounded down to this grid, so that nearby speeds share a time step. [s]"""


@dataclass(frozen=True)
class Numerics:
    """Element length and time step for one speed, and the resolution they give.

    Attributes
    ----------
    element_length : float
        Longest element. [m]
    time_step : float
        Time step. [s]
    shortest_wavelength : float
        (c − v)/f_c. [m]
    wire_frequency : float
        f_c/(1 − β). [Hz]
    """

    element_length: float
    time_step: float
    shortest_wavelength: float
    wire_frequency: float

    @property
    def elements_per_wavelength(self) -> float:
        """Elements per shortest wavelength. [-]"""
        return self.shortest_wavelength / self.element_length

    @property
    def steps_per_period(self) -> float:
        """Time steps per period of the wire frequency. [-]"""
        return 1.0 / (self.wire_frequency * self.time_step)


def _wave(speed: float, wave_speed: float, cutoff: float) -> tuple[float, float]:
    return (wave_speed - speed) / cutoff, cutoff / (1.0 - speed / wave_speed)


def numerics_for_speed(speed: float, wave_speed: float, cutoff: float) -> Numerics:
    """Element length and time step the rule gives at one speed (see the module notes).

    Parameters
    ----------
    speed : float
        Train speed, below ``wave_speed``. [m/s]
    wave_speed : float
        Contact-wire wave speed. [m/s]
    cutoff : float
        Cut-off frequency of the analysed contact force. [Hz]

    Returns
    -------
    Numerics

    Raises
    ------
    ModelError
        A speed at or above the wave speed (no wave runs ahead of the pantograph).
    """
    if not 0.0 < speed < wave_speed:
        raise ModelError(
            f"speed = {speed / KMH:g} km/h is outside the valid range (0, {wave_speed / KMH:g}) km/h for automatic "
            "numerics (below the contact-wire wave speed)"
        )
    wavelength, frequency = _wave(speed, wave_speed, cutoff)
    element = min(MAX_ELEMENT_LENGTH, wavelength / ELEMENTS_PER_WAVELENGTH)
    step = min(MAX_TIME_STEP, 1.0 / (STEPS_PER_PERIOD * frequency))
    element = round(math.floor(element / ELEMENT_GRID + 1e-9) * ELEMENT_GRID, 10)
    step = round(math.floor(step / TIME_STEP_GRID + 1e-9) * TIME_STEP_GRID, 12)
    return Numerics(element, step, wavelength, frequency)


def resolution_warnings(
    speed: float, wave_speed: float, cutoff: float, *, element_length: float, time_step: float
) -> tuple[str, ...]:
    """One line per setting that under-resolves the run (see the module notes).

    Parameters
    ----------
    speed : float
        Train speed. [m/s]
    wave_speed : float
        Contact-wire wave speed. [m/s]
    cutoff : float
        Cut-off frequency. [Hz]
    element_length : float
        Longest element of the discretisation used. [m]
    time_step : float
        Time step used. [s]

    Returns
    -------
    tuple of str
        Empty when both settings resolve the run.
    """
    need = numerics_for_speed(speed, wave_speed, cutoff)
    given = Numerics(element_length, time_step, need.shortest_wavelength, need.wire_frequency)
    beta = speed / wave_speed
    out = []
    if given.elements_per_wavelength < WARN_ELEMENTS_PER_WAVELENGTH:
        out.append(
            f"element_length = {element_length:g} m under-resolves {speed / KMH:g} km/h (β = {beta:.2f}): "
            f"{given.elements_per_wavelength:.1f} elements per {need.shortest_wavelength:.2f} m wave, "
            f"use at most {need.element_length:g} m (or automatic numerics)"
        )
    if given.steps_per_period < WARN_STEPS_PER_PERIOD:
        out.append(
            f"time_step = {time_step * 1e3:g} ms under-resolves {speed / KMH:g} km/h (β = {beta:.2f}): "
            f"{given.steps_per_period:.1f} steps per period at {need.wire_frequency:.0f} Hz, "
            f"use at most {need.time_step * 1e3:g} ms (or automatic numerics)"
        )
    return tuple(out)
