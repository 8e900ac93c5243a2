"""Wave propagation on a lone tensioned string (the speed-ratio helpers are tested in tests/test_speed.py)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.integrator import IntegratorSettings, State, integrate
from presag_opt.speed import wave_speed
from presag_opt.validation.dynamic_model import lumped_string

TENSION = 20e3  # N, EN 50318-style contact wire
MASS_PER_LENGTH = 1.35  # kg/m


def _peak_position(x: np.ndarray, u: np.ndarray) -> float:
    """Position of the largest value, refined by a parabola through the three samples around it. [m]"""
    i = int(np.argmax(u))
    left, mid, right = u[i - 1], u[i], u[i + 1]
    shift = 0.5 * (left - right) / (left - 2.0 * mid + right)
    return float(x[i] + shift * (x[1] - x[0]))


def test_pulse_travels_at_sqrt_tension_over_mass():
    """A Gaussian pulse splits in two halves that travel at c = sqrt(T/ρ) = 121.7 m/s.

    Tolerance 2 %: the lumped string's phase speed is c·sin(kh/2)/(kh/2), 0.1 % below c for the
    pulse's wavenumbers (σ = 1.5 m, h = 0.25 m), and Newmark's period elongation at ω·Δt < 0.1 is
    below 0.1 %; the peak is located to a small fraction of an element.
    """
    string = lumped_string(tension=TENSION, mass_per_length=MASS_PER_LENGTH, length=200.0, element_length=0.25)
    start = 100.0
    pulse = 0.01 * np.exp(-0.5 * ((string.x - start) / 1.5) ** 2)
    times = (0.2, 0.6)
    result = integrate(
        string.mass,
        0 * string.mass,
        string.stiffness,
        duration=times[1],
        settings=IntegratorSettings(time_step=5e-4),
        initial_state=State(displacement=pulse, velocity=np.zeros_like(pulse)),
    )
    ahead = string.x > start + 5.0
    positions = [
        _peak_position(string.x[ahead], result.displacement[np.argmin(np.abs(result.time - t))][ahead]) for t in times
    ]
    measured = (positions[1] - positions[0]) / (times[1] - times[0])
    assert measured == pytest.approx(wave_speed(TENSION, MASS_PER_LENGTH), rel=0.02)
