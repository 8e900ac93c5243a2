"""A constant force moving along a tensioned string: the time integrator against the modal series.

The reference is independent of the catenary code: the closed-form modal solution of an undamped
string with fixed ends under a constant force P moving at speed v (Frýba, *Vibration of Solids and
Structures under Moving Loads*, chapter on the string), in
:func:`presag_opt.validation.dynamic_model.string_under_moving_force`; the numerical model is a
lumped-mass string (:func:`~presag_opt.validation.dynamic_model.lumped_string`) stepped by
:func:`presag_opt.dynamics.integrator.integrate` (Newmark average acceleration, no damping).
"""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.pantograph import Pantograph, PantographStage
from presag_opt.dynamics.simulate import SimulationSettings, simulate
from presag_opt.static.equilibrium import lone_wire_state
from presag_opt.system.catenary import Wire
from presag_opt.validation.dynamic_model import moving_force_on_string
from presag_opt.validation.dynamic_model import string_under_moving_force as series

TENSION = 10e3
"""[N]"""
MASS_PER_LENGTH = 1.0
"""[kg/m]; with TENSION a wave speed c of exactly 100 m/s."""
LENGTH = 60.0
"""Distance between the fixed ends. [m]"""
FORCE = 100.0
"""Moving force (downward positive in w). [N]"""
WAVE_SPEED = np.sqrt(TENSION / MASS_PER_LENGTH)
STATIC_MID = FORCE * LENGTH / (4.0 * TENSION)
"""Static deflection of the mid-point with the force there, P l / (4 T): the error scale. [m]"""


def string_under_moving_force(x, t, speed):
    """The package's modal series for this module's string and force."""
    return series(x, t, speed=speed, tension=TENSION, mass_per_length=MASS_PER_LENGTH, length=LENGTH, force=FORCE)


def _errors(beta: float, element_length: float, time_step: float) -> tuple[float, float]:
    """Largest and RMS mid-point error over the passage, relative to STATIC_MID."""
    check = moving_force_on_string(beta, element_length=element_length, time_step=time_step, tension=TENSION,
                                   mass_per_length=MASS_PER_LENGTH, length=LENGTH, force=FORCE)
    assert check.static_mid == pytest.approx(STATIC_MID, rel=1e-15)
    return check.max_error, check.rms_error


def test_series_reduces_to_the_static_deflection_at_crawling_speed():
    """At β → 0 the series is the static line F·a·(l − x)/(T·l): a check of the reference itself."""
    speed = 2e-3  # β = 2e-5
    t = np.linspace(0.0, LENGTH / speed, 7)
    w = string_under_moving_force(LENGTH / 2, t, speed)
    a = speed * t
    static = np.where(LENGTH / 2 <= a, FORCE * 30.0 * (LENGTH - a), FORCE * a * 30.0) / (TENSION * LENGTH)
    # β = 2e-5: the dynamic correction is of order β (free part) and β² (1/(1 − β²)); round-off ~1e-16.
    assert np.max(np.abs(w - static)) < 1e-4 * STATIC_MID


@pytest.mark.parametrize(
    ("beta", "max_tol", "rms_tol"),
    # Measured at 0.25 m / 1 ms: max 0.66, 0.99, 1.81 %; RMS 0.14, 0.20, 0.33 % of P l/(4T).
    # Tolerances ≈ 1.4 × measured: a wrong Newmark coefficient or a load put on the wrong node
    # changes the error by far more (the β = 0.6 deflection is 1/(1 − β²) = 1.56 × static).
    [(0.2, 0.010, 0.002), (0.4, 0.014, 0.003), (0.6, 0.025, 0.005)],
)
def test_newmark_follows_the_modal_series(beta, max_tol, rms_tol):
    """Mid-point deflection while the force crosses the string, at β = 0.2, 0.4 and 0.6.

    The error falls at first order in the element length (halving element and step: RMS error
    ÷ 2.0, 1.5, 2.0 at the three speeds, measured), not at the second order of the scheme: the exact
    solution has slope jumps at the wave fronts the force sends out and that the ends reflect,
    which the dispersive lumped-mass string smears over a few elements. The time step is not the
    limit (a 4 × smaller step moves the error by less than a fifth, measured).
    """
    coarse_max, coarse_rms = _errors(beta, 0.5, 2e-3)
    fine_max, fine_rms = _errors(beta, 0.25, 1e-3)
    assert fine_max < max_tol and fine_rms < rms_tol
    # First-order convergence (ratio 2); 1.3 leaves room for the β = 0.4 case's measured 1.5.
    assert coarse_rms / fine_rms > 1.3


@pytest.mark.xfail(strict=True, raises=AttributeError, reason="needs simulate() to accept a lone-wire state (lone_wire_state): today it "
                   "reads state.catenary.contact_wire and fails with AttributeError")
def test_simulator_on_a_lone_wire_follows_the_modal_series():
    """The whole simulator (structure, contact, pantograph, statistics path) on a lone tensioned wire
    at β = 0.2, against the series evaluated under the force, w(vt, t).

    Expected API: ``simulate(lone_wire_state(wire, length), pantograph, speed=…, static_force=…,
    settings=SimulationSettings(analysed_spans=1, lead_in_spans=0))`` runs the pantograph from one end
    of the wire to the other (the wire is one span between two fixed ends) and returns the uplift of
    the contact point in ``result.pantographs[0].wire_uplift`` at ``result.time``, measured from the
    static equilibrium under gravity. The pantograph below has heavy, stiffly coupled stages, so its
    contact force stays close to the static force at β = 0.2; tolerance 5 % of P l/(4T): the 1 %
    of the integrator check above plus the contact-force variation (a first estimate, to be
    confirmed when the API exists).
    """
    wire = Wire(tension=TENSION, mass_per_length=MASS_PER_LENGTH, axial_stiffness=14.4e6)
    pantograph = Pantograph(name="near-constant force", stages=(
        PantographStage(name="head", mass=5.0, stiffness=1e5, damping=0.0),
        PantographStage(name="frame", mass=5.0),
    ))
    speed = 0.2 * WAVE_SPEED
    result = simulate(lone_wire_state(wire, LENGTH), pantograph, speed=speed, static_force=FORCE,
                      settings=SimulationSettings(analysed_spans=1, lead_in_spans=0))
    t = result.time
    inside = (speed * t > 1.0) & (speed * t < LENGTH - 1.0)
    expected = string_under_moving_force(speed * t[inside], t[inside], speed)
    error = np.abs(result.pantographs[0].wire_uplift[inside] - expected).max()
    assert error < 0.05 * STATIC_MID
