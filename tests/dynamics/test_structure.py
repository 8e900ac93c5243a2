"""Structural model for dynamics: mass, Rayleigh damping, linearised stiffness, tension-only droppers."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.integrator import IntegratorSettings, State, integrate
from presag_opt.dynamics.structure import StructureSettings, rayleigh_coefficients, structural_model
from presag_opt.elasticity import linear_elasticity, nonlinear_elasticity
from presag_opt.errors import ModelError
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import load_catenary


@pytest.fixture(scope="module")
def en50318():
    """Form-found EN 50318-style reference catenary (10 × 60 m, spring supports)."""
    return form_find(load_catenary("en50318_reference"))


def _load_point_elasticity(model, station: float, force: float) -> tuple[float, int]:
    """Uplift per unit force at the load point [m/N] and the number of slack droppers, statically."""
    disc = model.state.discretisation
    u = model.static_response(disc.cw_load_vector(station, force)[model.global_dofs])
    uplift = disc.cw_shape([station]) @ u[model.cw_z]
    return float(uplift[0]) / force + float(disc.cw_element_compliance([station])[0]), int(
        np.sum(model.dropper_force(u) <= 0.0)
    )


def test_rayleigh_coefficients_meet_the_ratio_at_both_ends_of_the_band():
    """ζ(f) = α/(4πf) + βπf equals 0.02 at 1 and 20 Hz (round-off: 1e-12) and is lowest at
    sqrt(1·20) Hz with 2ζ·sqrt(20)/21 = 0.00852 (Clough & Penzien eq. 12-38)."""
    alpha, beta = rayleigh_coefficients(0.02, (1.0, 20.0))

    def ratio(f):
        return alpha / (4 * np.pi * f) + beta * np.pi * f

    assert ratio(1.0) == pytest.approx(0.02, rel=1e-12)
    assert ratio(20.0) == pytest.approx(0.02, rel=1e-12)
    assert ratio(np.sqrt(20.0)) == pytest.approx(2 * 0.02 * np.sqrt(20.0) / 21.0, rel=1e-12)
    assert ratio(np.sqrt(20.0)) < ratio(np.array([2.0, 10.0])).min()


def test_damping_ratio_of_the_case_study_catenary_comes_from_its_file(st98):
    """st_9.8_ideal gives ζ = 0.02 (paper): the model uses the default 1-20 Hz band, and C = αM + βK."""
    model = structural_model(st98)
    assert (model.rayleigh_alpha, model.rayleigh_beta) == rayleigh_coefficients(0.02, (1.0, 20.0))
    assert model.damping_ratio(1.0) == pytest.approx(0.02, rel=1e-12)
    difference = model.damping - (model.rayleigh_alpha * model.mass + model.rayleigh_beta * model.stiffness)
    assert abs(difference).max() <= 1e-12 * abs(model.damping).max()


def test_en50318_rayleigh_coefficients_are_used_as_given(en50318):
    """The reference model's α = 0.0125 1/s and β = 1e-4 s pass through unchanged."""
    model = structural_model(en50318)
    assert (model.rayleigh_alpha, model.rayleigh_beta) == (0.0125, 1e-4)


def test_vertical_mass_is_the_whole_catenary(en50318):
    """Lumped masses on the vertical DOFs add up to the section's mass: 600 m of contact wire at
    1.35 kg/m (no pre-sag: straight), eleven 1 kg support masses (massless droppers and clamps), and
    the messenger wire at 1.07 kg/m along its sagging length. The wires' lengths are those of the
    design state, in which the messenger wire hangs as a parabola carrying both wires' weight:
    sag d = w l²/(8 T_MW) = 0.668 m per 60 m span, length l (1 + 8/3 (d/l)²) with a 4th-order term
    below 2e-8 relative. Every node is free vertically (spring supports). Tolerance 1e-6: the
    polygon of 0.5 m chords is shorter than the parabola by 1e-9."""
    model = structural_model(en50318)
    free = en50318.model.functions.free_dofs
    vertical = model.mass.diagonal()[free % 3 == 2]
    sag = 9.81 * (1.35 + 1.07) * 60.0**2 / (8.0 * 16e3)
    messenger = 600.0 * (1.0 + 8.0 / 3.0 * (sag / 60.0) ** 2)
    assert vertical.sum() == pytest.approx(600.0 * 1.35 + messenger * 1.07 + 11 * 1.0, rel=1e-6)


def test_static_response_at_small_force_is_the_linear_elasticity(st98):
    """At 20 N no dropper slackens, so the structural model's static uplift at the load point (nodal
    interpolation plus the element term) is the linear elasticity of the static model: the same
    stiffness matrix, solved by another factorisation, to 1e-9."""
    model = structural_model(st98)
    span = 5
    curve = linear_elasticity(st98, span, step=2.5)
    for position, expected in zip(curve.position, curve.elasticity):
        elasticity, slack = _load_point_elasticity(model, st98.discretisation.mast_station[span] + position, 20.0)
        assert slack == 0
        assert elasticity == pytest.approx(expected, rel=1e-9)


def test_tension_only_droppers_match_the_active_set_and_the_nonlinear_equilibrium(st98):
    """200 N along a span: droppers go slack near the load (up to two at the masts).

    Against the elasticity module's active-set method (same linearised equations, Woodbury updates
    of one factorisation): equal to 1e-9, with the same number of slack droppers. Against the full
    nonlinear equilibrium (Newton's method on the potential): the same slack droppers, and the uplift
    within 0.2 % away from the masts; within 7.5 m of a mast the linearised model is up to 6 % stiffer
    (geometric nonlinearity at the registration, 1.7 % at 120 N), which is the approximation of a
    dynamic model about the static equilibrium.
    """
    model = structural_model(st98)
    span, force = 5, 200.0
    active = nonlinear_elasticity(st98, force, span, step=7.5, method="active-set")
    newton = nonlinear_elasticity(st98, force, span, step=7.5, method="newton")
    stations = st98.discretisation.mast_station[span] + active.position
    results = [_load_point_elasticity(model, x, force) for x in stations]
    elasticity = np.array([e for e, _ in results])
    slack = np.array([n for _, n in results])
    np.testing.assert_allclose(elasticity, active.elasticity, rtol=1e-9)
    np.testing.assert_array_equal(slack, active.slack_droppers)
    np.testing.assert_array_equal(slack, newton.slack_droppers)
    assert slack.max() >= 2
    inner = (active.position > 7.5) & (active.position < 52.5)
    np.testing.assert_allclose(elasticity[inner], newton.elasticity[inner], rtol=2e-3)
    assert np.max(np.abs(elasticity / newton.elasticity - 1.0)) < 0.06


def test_slack_dropper_force_cancels_the_axial_force_and_has_an_exact_tangent(st98):
    """Pull one dropper's contact-wire clamp up until the dropper would push: the slack force is
    −N·[−e, e] with N the linearised axial force (so the dropper carries nothing), its stiffness is
    the derivative of that force (exact for this piecewise-linear law: central differences agree to
    1e-6), and it vanishes while the dropper is taut."""
    model = structural_model(st98)
    d = model.droppers
    i = len(d) // 2
    n = model.n_dofs
    cw_z = d.dofs[i, 2]
    u = np.zeros(n)
    assert len(model.dropper_slack_force(u).dofs) == 0
    u[cw_z] = 2.0 * d.preload[i] / d.axial_stiffness[i] / d.direction[i, 2]
    slack = model.dropper_slack_force(u)
    axial = d.preload[i] + d.axial_stiffness[i] * (d.gradient[i] @ u[d.dofs[i]])
    assert axial < 0.0
    np.testing.assert_array_equal(slack.dofs, d.dofs[i])
    np.testing.assert_allclose(slack.force, -axial * np.concatenate([-d.direction[i], d.direction[i]]), rtol=1e-12)
    step = 1e-7
    numeric = np.column_stack([
        (model.dropper_slack_force(u + step * e).force - model.dropper_slack_force(u - step * e).force) / (2 * step)
        for e in np.eye(n)[d.dofs[i]]
    ])
    np.testing.assert_allclose(slack.stiffness, numeric, atol=1e-6 * np.abs(slack.stiffness).max())


def test_damping_band_must_be_two_increasing_frequencies():
    with pytest.raises(ModelError, match=r"damping_band = \[20.0, 1.0\] Hz must be two frequencies"):
        StructureSettings(damping_band=(20.0, 1.0))
    with pytest.raises(ModelError, match=r"damping_band\[0\] = 0 Hz is outside the valid range"):
        StructureSettings(damping_band=(0.0, 20.0))


def test_undamped_catenary_keeps_its_energy_under_average_acceleration_newmark(st98):
    """Issue 4: undamped and contact-free, the catenary released from its static deflection under
    100 N at mid-span keeps ½vᵀMv + ½uᵀKu within 0.1 % over 10 s (2 ms steps). Average-acceleration
    Newmark conserves it exactly for a linear system with symmetric M and K; the 1e-8 asserted is
    round-off over 5 000 steps, so an unsymmetric or indefinite assembly would fail it."""
    model = structural_model(st98)
    disc = st98.discretisation
    u0 = model.state.factorised_stiffness().solve(disc.cw_load_vector(270.0, 100.0)[model.global_dofs])
    mass = model.mass.diagonal()

    def energy(t, u, v):
        return 0.5 * v @ (mass * v) + 0.5 * u @ (model.stiffness @ u)

    result = integrate(
        model.mass, 0 * model.mass, model.stiffness, duration=10.0, settings=IntegratorSettings(),
        initial_state=State(displacement=u0, velocity=np.zeros_like(u0)), record_dofs=[0], observe=energy,
    )
    history = result.observed[:, 0]
    assert np.max(np.abs(history / history[0] - 1.0)) < 1e-8
