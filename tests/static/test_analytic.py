"""Analytic solutions: a tensioned string and a tensioned Euler–Bernoulli beam under a point load."""

from __future__ import annotations

import numpy as np

from presag_opt.elasticity import linear_elasticity, nonlinear_elasticity
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import lone_wire_state
from presag_opt.system.components import Wire


def string_elasticity(x, length, tension):
    """Point-load deflection of a string per unit force at the load, F·a·b/(T·l) / F. [m/N]"""
    return x * (length - x) / (tension * length)


def beam_elasticity(a, length, tension, ei):
    """Pinned–pinned beam under axial tension T, unit point load at a: deflection at a. [m/N]

    EI w'''' − T w'' = δ(x − a); with k = sqrt(T/EI),
    w(a) = [a b / l − sinh(k a) sinh(k b) / (k sinh(k l))] / T, b = l − a.
    """
    k = np.sqrt(tension / ei)
    b = length - a
    return (a * b / length - np.sinh(k * a) * np.sinh(k * b) / (k * np.sinh(k * length))) / tension


def test_string_matches_fab_over_tl_everywhere():
    # Linear elements are nodally exact for a string, and the in-element term makes every point
    # exact; 0.5 % is the bound, the model reaches round-off level.
    tension, length = 9800.0, 60.0
    state = lone_wire_state(Wire(tension=tension, mass_per_length=0.05, axial_stiffness=14.4e6), length)
    curve = linear_elasticity(state, span=0, step=0.1)
    inner = slice(1, -1)
    expected = string_elasticity(curve.position, length, tension)
    assert np.max(np.abs(curve.elasticity[inner] / expected[inner] - 1.0)) < 0.005
    assert curve.elasticity[0] == 0.0 and curve.elasticity[-1] == 0.0


def test_string_under_a_real_force_by_resolved_equilibrium():
    # 10 N on a 9.8 kN string: geometric nonlinearity is of order (F/2T)² ≈ 3e-7, far below 0.5 %.
    tension, length = 9800.0, 60.0
    state = lone_wire_state(Wire(tension=tension, mass_per_length=0.05, axial_stiffness=14.4e6), length)
    curve = nonlinear_elasticity(state, 10.0, span=0, step=3.7)
    expected = string_elasticity(curve.position, length, tension)
    assert np.max(np.abs(curve.elasticity[1:-1] / expected[1:-1] - 1.0)) < 0.005


BEAM = dict(tension=2000.0, length=4.0, ei=150.0)  # bending length sqrt(EI/T) = 0.27 m: bending matters


def beam_error(element_length: float) -> float:
    wire = Wire(tension=BEAM["tension"], mass_per_length=0.05, axial_stiffness=14.4e6, bending_stiffness=BEAM["ei"])
    state = lone_wire_state(wire, BEAM["length"], StaticSettings(element_length=element_length))
    curve = linear_elasticity(state, span=0, step=0.1)
    a = curve.position[1:-1]
    expected = beam_elasticity(a, BEAM["length"], BEAM["tension"], BEAM["ei"])
    return float(np.max(np.abs(curve.elasticity[1:-1] / expected - 1.0)))


def test_tensioned_beam_within_one_percent():
    # At h = 0.025 m (a tenth of the bending length) the rotation-free discretisation is within
    # 1 % everywhere; the string solution alone would be off by a factor of more than 2 near the ends.
    assert beam_error(0.025) < 0.01


def test_tensioned_beam_converges_at_second_order():
    # Central-difference curvature: error ∝ h². Fitted slope within 0.1 of 2 (scikit-fem practice).
    h = np.array([0.1, 0.05, 0.025])
    errors = np.array([beam_error(v) for v in h])
    slope = np.polyfit(np.log(h), np.log(errors), 1)[0]
    assert abs(slope - 2.0) < 0.1, (errors, slope)
