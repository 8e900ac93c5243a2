"""``presag_opt.validation.dynamic_model``: the references the dynamic model is checked against, checked
themselves — the modal series of a string under a moving force (Frýba 1999, the string chapter) against
its static limit, the lumped string against the exact eigenfrequencies of a discrete string, and the
named check results' error measures."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from presag_opt.errors import ModelError
from presag_opt.validation.dynamic_model import (
    ConvergenceRung,
    ConvergenceStudy,
    CrawlingCheck,
    MovingForceCheck,
    lumped_string,
    moving_force_on_string,
    string_under_moving_force,
)

TENSION = 10e3
"""[N]"""
MASS_PER_LENGTH = 1.0
"""[kg/m]; with TENSION a wave speed c of exactly 100 m/s."""
LENGTH = 60.0
"""Distance between the fixed ends. [m]"""
FORCE = 100.0
"""Moving force (downward positive in w). [N]"""
STATIC_MID = FORCE * LENGTH / (4.0 * TENSION)
"""Static deflection of the mid-point with the force there, P l / (4 T): the error scale. [m]"""


def test_series_reduces_to_the_static_deflection_at_crawling_speed():
    """At β → 0 the series is the static line F·a·(l − x)/(T·l): a check of the reference itself."""
    speed = 2e-3  # β = 2e-5
    t = np.linspace(0.0, LENGTH / speed, 7)
    w = string_under_moving_force(LENGTH / 2, t, speed=speed, tension=TENSION, mass_per_length=MASS_PER_LENGTH,
                                  length=LENGTH, force=FORCE)
    a = speed * t
    static = np.where(LENGTH / 2 <= a, FORCE * 30.0 * (LENGTH - a), FORCE * a * 30.0) / (TENSION * LENGTH)
    # β = 2e-5: the dynamic correction is of order β (free part) and β² (1/(1 − β²)); round-off ~1e-16.
    assert np.max(np.abs(w - static)) < 1e-4 * STATIC_MID



def _series(x, t, speed, terms=4000):
    return string_under_moving_force(x, t, speed=speed, tension=TENSION, mass_per_length=MASS_PER_LENGTH,
                                      length=LENGTH, force=FORCE, terms=terms)


def test_the_series_starts_at_rest_holds_its_ends_and_has_converged_in_its_terms():
    speed = 50.0  # β = 0.5
    t = np.linspace(0.0, LENGTH / speed, 41)
    assert _series(LENGTH / 2, t[:1], speed)[0] == pytest.approx(0.0, abs=1e-15)  # zero initial conditions
    np.testing.assert_allclose(_series(0.0, t, speed), 0.0, atol=1e-15)  # fixed end
    # the free part falls as 1/j²: doubling the terms changes the deflection by < 1e-4 of P l/(4T)
    change = np.max(np.abs(_series(LENGTH / 3, t, speed, 8000) - _series(LENGTH / 3, t, speed)))
    assert change < 1e-4 * STATIC_MID


def test_at_half_the_wave_speed_the_force_reaches_mid_span_with_no_free_vibration():
    """v = c/2 reaches x = l/2 at t = l/c, when every mode's free part sin(ω_j t) = sin(jπ) vanishes: the
    deflection is the static one amplified by 1/(1 − β²) = 4/3, exactly (round-off of 4000 terms, 1e-12)."""
    speed = 50.0
    w = _series(LENGTH / 2, np.array([LENGTH / 100.0]), speed)[0]
    assert w == pytest.approx(STATIC_MID / (1 - 0.5**2), rel=1e-12)
    # a quarter of the way there the free part does not vanish: the reference is dynamic, not static
    quarter = _series(LENGTH / 4, np.array([LENGTH / 4 / speed]), speed)[0]
    static = FORCE * (LENGTH / 4) * (3 * LENGTH / 4) / (TENSION * LENGTH)
    assert abs(quarter - static / 0.75) > 1e-3 * STATIC_MID


def test_the_lumped_string_has_the_exact_eigenfrequencies_of_a_discrete_string():
    """A chain of n − 1 masses ρh on springs T/h: ω_j = (2c/h) sin(jπh/(2l)) exactly (round-off, 1e-10);
    the lowest modes approach the continuous string's jπc/l (to (πh/l)²/24 relative)."""
    string = lumped_string(tension=TENSION, mass_per_length=MASS_PER_LENGTH, length=LENGTH, element_length=1.0)
    assert string.element_length == 1.0 and len(string.x) == 59 and string.x[0] == 1.0
    omega = np.sqrt(scipy.linalg.eigh(string.stiffness.toarray(), string.mass.toarray(), eigvals_only=True))
    j = np.arange(1, 60)
    c = 100.0
    np.testing.assert_allclose(omega, 2 * c / 1.0 * np.sin(j * np.pi * 1.0 / (2 * LENGTH)), rtol=1e-10)
    assert omega[0] == pytest.approx(np.pi * c / LENGTH, rel=(np.pi / 60) ** 2 / 24 * 1.01)
    assert lumped_string(tension=TENSION, mass_per_length=1.0, length=LENGTH, element_length=0.7).element_length == \
        pytest.approx(60.0 / 86, rel=1e-15)  # rounded to whole elements


def test_error_measures_of_the_check_results():
    crawl = CrawlingCheck(speed=0.28, beta=0.003, static_force=60.0, position=np.array([0.0, 30.0]),
                          contact_force=np.array([60.0, 63.0]), uplift=np.array([0.020, 0.051]),
                          expected=np.array([0.021, 0.050]), any_slack=False)
    assert crawl.max_relative_error == pytest.approx(1 / 21, rel=1e-12)  # |0.020/0.021 − 1| > |0.051/0.050 − 1|
    assert crawl.force_deviation == pytest.approx(0.05, rel=1e-12)
    moving = MovingForceCheck(beta=0.2, element_length=0.25, time_step=1e-3, time=np.arange(4.0),
                              numerical=np.array([0.0, 0.1, 0.2, 0.1]), analytic=np.array([0.0, 0.1, 0.1, 0.1]),
                              static_mid=0.5)
    assert moving.max_error == pytest.approx(0.2, rel=1e-12) and moving.rms_error == pytest.approx(0.1, rel=1e-12)
    rung = dict(speeds=(50.0, 60.0), betas=(0.5, 0.6), mean_force=(100.0, 100.0), max_force=(150.0, 160.0), seconds=1.0)
    study = ConvergenceStudy(case_name="c", rungs=(
        ConvergenceRung(element_length=1.0, time_step=4e-3, std_force=(22.0, 33.0), **rung),
        ConvergenceRung(element_length=0.5, time_step=2e-3, std_force=(20.0, 30.0), **rung)))
    np.testing.assert_allclose(study.sigma_change(), [[0.1, 0.1], [0.0, 0.0]], rtol=1e-12, atol=1e-15)


def test_a_moving_force_check_needs_a_speed_ratio_below_one():
    with pytest.raises(ModelError, match="beta"):
        moving_force_on_string(1.0, element_length=1.0, time_step=1e-3)
