"""The laws of the dynamic model (:mod:`presag_opt.dynamics.laws`) against their closed forms, on
numbers and, where the single-run path uses them so, on arrays; and compiled by numba as the batch
kernel compiles them, equal to the plain-Python values to the last bit."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from presag_opt.dynamics import laws
from presag_opt.dynamics.batch import forces as batch_forces
from presag_opt.dynamics.integrator import IntegratorSettings


def test_contact_is_the_penalty_in_series_with_the_element_and_zero_in_a_gap():
    k_c, c = 50e3, 4e-6  # 50 kN/m penalty; 4 µm/N element compliance
    k = laws.contact_stiffness(k_c, c)
    assert k == pytest.approx(1.0 / (1.0 / 50e3 + 4e-6), rel=1e-15)  # 41 666.7 N/m
    assert k == pytest.approx(50e3 / 1.2, rel=1e-12)
    assert laws.contact_force(k, 2e-3) == pytest.approx(k * 2e-3, rel=1e-15)
    assert laws.contact_tangent(k, 2e-3) == k
    for gap in (-1e-3, 0.0):  # a gap, and touching without penetration
        assert laws.contact_force(k, gap) == 0.0 and laws.contact_tangent(k, gap) == 0.0
    assert laws.contact_stiffness(k_c, 0.0) == pytest.approx(k_c, rel=1e-15)  # rigid element: the penalty alone


def test_friction_is_regularised_coulomb_with_slope_f0_over_v_reg_at_rest():
    level, v_reg = 30.0, 1e-3
    force, slope = laws.friction(level, 0.0, v_reg, 1.0)
    assert force == 0.0 and slope == level / v_reg  # 30 000 N·s/m: the stick stiffness
    force, slope = laws.friction(level, 0.1, v_reg, 1.0)  # 100 v_reg: full Coulomb level
    assert force == pytest.approx(level, rel=1e-12) and 0.0 <= slope < 1e-80
    force, _ = laws.friction(level, -0.1, v_reg, 1.0)
    assert force == pytest.approx(-level, rel=1e-12)  # resists the motion
    step = 1e-7
    numeric = (laws.friction(level, 4e-4 + step, v_reg, 1.0)[0] - laws.friction(level, 4e-4 - step, v_reg, 1.0)[0]) / (
        2 * step)
    assert laws.friction(level, 4e-4, v_reg, 1.0)[1] == pytest.approx(numeric, rel=1e-6)
    # the factor scales the slope (the batch's Newton tangent a1 ∂F/∂v) and leaves the force alone
    a1 = 1000.0
    scaled = laws.friction(level, 4e-4, v_reg, a1)
    assert scaled[0] == laws.friction(level, 4e-4, v_reg, 1.0)[0]
    assert scaled[1] == pytest.approx(a1 * laws.friction(level, 4e-4, v_reg, 1.0)[1], rel=1e-15)
    forces, slopes = laws.friction(np.array([level, 0.0]), np.array([0.0, 1.0]), v_reg, 1.0)  # arrays too
    np.testing.assert_array_equal(forces, [0.0, 0.0])
    np.testing.assert_array_equal(slopes, [level / v_reg, 0.0])


def test_a_dropper_is_slack_below_zero_axial_force_and_carries_no_compression():
    n0, k, beta = 120.0, 1e5, 1e-4  # 120 N preload, 100 kN/m, β_R = 0.1 ms
    assert laws.dropper_axial_force(n0, k, -1e-3, 0.0, 0.0) == pytest.approx(20.0, rel=1e-12)
    assert laws.dropper_axial_force(n0, k, -1e-3, 0.5, beta) == pytest.approx(20.0 + beta * k * 0.5, rel=1e-12)
    threshold = -n0 / k  # 1.2 mm shortening unloads it
    assert laws.dropper_axial_force(n0, k, threshold, 0.0, 0.0) == pytest.approx(0.0, abs=1e-12)
    assert not laws.dropper_slack(laws.dropper_axial_force(n0, k, threshold + 1e-6, 0.0, 0.0))
    assert laws.dropper_slack(laws.dropper_axial_force(n0, k, threshold - 1e-6, 0.0, 0.0))
    assert not laws.dropper_slack(0.0)  # exactly unloaded: not slack, and its tension is zero
    assert laws.dropper_tension(-5.0) == 0.0 and laws.dropper_tension(5.0) == 5.0
    np.testing.assert_array_equal(laws.dropper_slack(np.array([-1.0, 0.0, 1.0])), [True, False, False])
    # statics (no rate, no damping): the law without its damping part
    assert laws.dropper_axial_force(n0, k, 2e-3, 123.0, 0.0) == n0 + k * 2e-3


@pytest.mark.parametrize("alpha", [0.0, -0.05])
def test_scheme_constants_are_the_textbook_hht_constants(alpha):
    dt = 2e-3
    settings = IntegratorSettings(time_step=dt, scheme="hht", hht_alpha=alpha)
    c = laws.scheme_constants(settings)
    beta, gamma = (1.0 - alpha) ** 2 / 4.0, 0.5 - alpha  # Hilber, Hughes, Taylor (1977)
    assert (c.alpha, c.beta, c.gamma, c.s, c.time_step) == (alpha, beta, gamma, 1.0 + alpha, dt)
    if alpha == 0.0:
        assert (c.beta, c.gamma) == (0.25, 0.5)  # Newmark's average acceleration
    else:
        assert c.beta == pytest.approx(0.275625, rel=1e-15) and c.gamma == pytest.approx(0.55, rel=1e-15)
    assert c.a0 == pytest.approx(1.0 / (beta * dt * dt), rel=1e-15)
    assert c.a1 == pytest.approx(gamma / (beta * dt), rel=1e-15)
    assert c.velocity_predictor == pytest.approx(dt * (1.0 - gamma), rel=1e-15)
    assert c.displacement_predictor == pytest.approx(dt * dt * (0.5 - beta), rel=1e-15)
    assert c.velocity_update == pytest.approx(gamma * dt, rel=1e-15)


def test_newmark_ignores_the_hht_alpha():
    newmark = laws.scheme_constants(IntegratorSettings(scheme="newmark", hht_alpha=-0.1))
    assert newmark.alpha == 0.0 and newmark.beta == 0.25 and newmark.gamma == 0.5


def test_the_suspension_ends_on_the_car_body():
    assert laws.suspension_elements(3) == ((0, 1), (1, 2), (2, -1))
    assert laws.suspension_elements(2) == ((0, 1), (1, -1))


def _plain_laws(penetration):
    """The laws at one penetration [m], as the single-run path calls them."""
    k = laws.contact_stiffness(50e3, 3.7e-6)
    return (k, laws.contact_force(k, penetration), laws.contact_tangent(k, penetration),
            laws.friction(25.0, penetration, 1e-3, 812.5), laws.dropper_axial_force(100.0, 1e5, penetration, 0.3, 1e-4))


@numba.njit
def _batch_laws(penetration):
    """The same through the batch's kernel parts (which only a compiled function can call)."""
    k = batch_forces.contact_stiffness(50e3, 3.7e-6)
    return (k, batch_forces.contact_force(k, penetration), batch_forces.contact_tangent(k, penetration),
            batch_forces.friction(25.0, penetration, 1e-3, 812.5),
            batch_forces.dropper_axial_force(100.0, 1e5, penetration, 0.3, 1e-4))


@pytest.mark.parametrize("penetration", [-2e-3, 0.0, 3e-3])
def test_the_compiled_laws_equal_the_plain_ones_to_the_last_bit(penetration):
    assert _batch_laws(penetration) == _plain_laws(penetration)
