"""Form-finding: target geometry, tensions, droppers in tension, symmetry, dropper schedule, errors."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.sensitivity.inputs import apply_inputs
from presag_opt.static.discretisation import CONTACT_WIRE, MESSENGER_WIRE
from presag_opt.static.equilibrium_newton import force_tolerance
from presag_opt.static.form_finding import check_form_finding_inputs, form_find
from presag_opt.static.solver_statistics import recording
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


def target_heights(state):
    """Designed contact-wire height at every dropper: the pre-sag parabola, zero at the masts. [m]"""
    cat = state.catenary
    disc = state.discretisation
    lengths = np.asarray(cat.layout.span_lengths)[disc.dropper_span]
    t = disc.dropper_position / lengths
    return cat.contact_wire_height - 4.0 * cat.presag_rel * lengths * t * (1.0 - t)


@pytest.mark.parametrize("fixture", ["st98", "st71", "st98_mixed"])
def test_contact_wire_on_target_at_every_dropper_and_support(fixture, request):
    state = request.getfixturevalue(fixture)
    disc = state.discretisation
    z_drop = state.positions[disc.axial.node_a[disc.dropper_elements], 2]
    assert np.max(np.abs(z_drop - target_heights(state))) < 1e-4  # 0.1 mm (issue)
    z_mast = state.positions[disc.mast_cw_node, 2]
    assert np.max(np.abs(z_mast - state.catenary.contact_wire_height)) < 1e-4
    # and at its stagger, alternating
    y_mast = state.positions[disc.mast_cw_node, 1]
    stagger = state.catenary.stagger * np.where(np.arange(len(y_mast)) % 2 == 0, 1.0, -1.0)
    assert np.max(np.abs(y_mast - stagger)) < 1e-4


@pytest.mark.parametrize("fixture", ["st98", "st71", "st98_mixed"])
def test_wires_carry_their_balance_weight_tension(fixture, request):
    state = request.getfixturevalue(fixture)
    cat = state.catenary
    for group, wire in ((CONTACT_WIRE, cat.contact_wire), (MESSENGER_WIRE, cat.messenger_wire)):
        horizontal = state.horizontal_tension(group)
        assert np.max(np.abs(horizontal / wire.tension - 1.0)) < 1e-3  # 0.1 % (issue)


@pytest.mark.parametrize("fixture", ["st98", "st71", "st98_mixed"])
def test_every_dropper_is_in_tension_and_the_state_is_balanced(fixture, request):
    state = request.getfixturevalue(fixture)
    assert np.all(state.dropper_forces() > 0.0)
    assert np.abs(state.out_of_balance()).max() <= force_tolerance(state.params, state.positions.ravel(),
                                                                   state.discretisation.settings)


def test_ideal_span_dropper_lengths_are_symmetric(st98):
    disc = st98.discretisation
    central = disc.dropper_span == st98.catenary.layout.central_span
    lengths = st98.dropper_lengths()[central]
    assert np.max(np.abs(lengths - lengths[::-1])) < 1e-4  # 0.1 mm (issue)


def test_dropper_forces_carry_the_weight_of_the_span(st98):
    """Vertical balance of the central span: the droppers hold the contact wire's weight less the
    lift of its pre-sag curvature (8·S·T/l² per metre, i.e. 8·S·T/l over the span), less the share
    the steady arms carry (taken as half of each end bay), plus the clamps and the lower half of
    each dropper's own weight. Measured 0.49 % apart: the end-bay split between arm and first
    dropper is only approximately half; tolerance 1 %, while leaving out the clamps and dropper
    weight (2.9 %) or the arm share (8.9 %) fails."""
    cat = st98.catenary
    disc = st98.discretisation
    span = cat.layout.central_span
    l = cat.layout.span_lengths[span]
    in_span = disc.dropper_span == span
    carried = st98.dropper_forces()[in_span].sum()
    g = 9.81
    weight = g * cat.contact_wire.mass_per_length * l
    lift = 8.0 * cat.presag_of_span(span) * cat.contact_wire.tension / l
    arm_share = g * cat.contact_wire.mass_per_length * 2 * cat.droppers.end_distance / 2
    clamps = g * cat.droppers.clamp_mass * np.count_nonzero(in_span)
    dropper_halves = g * cat.droppers.mass_per_length * st98.dropper_lengths()[in_span].sum() / 2
    assert carried == pytest.approx(weight - lift - arm_share + clamps + dropper_halves, rel=0.01)


def test_messenger_wire_sag_follows_cable_statics(st98):
    # A cable of horizontal tension H sags M(x)/H below its chord, M being the bending moment of a
    # simply supported beam with the same vertical loads: its own weight and, at each dropper, the
    # dropper force plus the dropper's messenger-side weight. Independent of the FE solution;
    # 0.5 % covers the lumping of the wire's weight at 0.5 m nodes.
    cat = st98.catenary
    disc = st98.discretisation
    drops = cat.droppers
    span = cat.layout.central_span
    l = cat.layout.span_lengths[span]
    in_span = disc.dropper_span == span
    a = disc.dropper_position[in_span]
    loads = st98.dropper_forces()[in_span] + 9.81 * (
        0.5 * drops.mass_per_length * st98.dropper_lengths()[in_span] + drops.clamp_mass
    )
    w = 9.81 * cat.messenger_wire.mass_per_length
    left = np.sum(loads * (l - a)) / l + w * l / 2
    moment = left * l / 2 - np.sum(loads[a < l / 2] * (l / 2 - a[a < l / 2])) - w * l**2 / 8
    mid = disc.mast_station[span] + l / 2
    k = int(np.argmin(np.abs(disc.cw_station - mid)))
    sag = cat.contact_wire_height + cat.system_height - st98.positions[disc.mw_nodes[k], 2]
    assert sag == pytest.approx(moment / cat.messenger_wire.tension, rel=0.005)


def test_steady_arms_pull_against_the_stagger_kink(st98):
    # Lateral pull at an inner registration: T·(2·2·stagger/l) for alternating ±stagger.
    cat = st98.catenary
    angles = st98.steady_arm_angles()
    forces = st98.steady_arm_forces()
    lateral = forces * np.cos(angles)
    expected = cat.contact_wire.tension * 4 * cat.stagger / 60.0
    assert np.allclose(lateral[1:-1], expected, rtol=0.01)


def test_dropper_schedule_rows(st98):
    rows = st98.dropper_schedule()
    assert len(rows) == 70  # 7 droppers in each of 10 spans
    assert rows[0].span == 1 and rows[-1].span == 10
    assert [r.position_m for r in rows[:7]] == pytest.approx([4.5, 13.0, 21.5, 30.0, 38.5, 47.0, 55.5])
    for r in rows:
        assert r.length_mm == round(r.length_mm)
        assert r.force_N > 0
        assert abs(r.installed_length_mm - r.length_mm) < 1.0  # stretch under ~80 N is < 0.1 mm


def test_spring_supported_reference_model_form_finds():
    state = form_find(load_catenary("en50318_reference"))
    disc = state.discretisation
    z = state.positions[disc.axial.node_a[disc.dropper_elements], 2]
    assert np.max(np.abs(z - state.catenary.contact_wire_height)) < 1e-4  # no pre-sag: level wire
    assert np.all(state.dropper_forces() > 0.0)


def test_a_spring_support_holds_the_contact_wire_at_its_stagger():
    """A spring support is vertical only: across the track the wire is held at its stagger there
    (left free, the zig-zag pull of the staggered wire draws it to ±27 mm instead of ±200 mm)."""
    catenary = dataclasses.replace(load_catenary("en50318_reference"), stagger=0.2)
    state = form_find(catenary)
    nodes = state.discretisation.mast_cw_node
    np.testing.assert_allclose(state.positions[nodes, 1], state.discretisation.design_positions[nodes, 1], atol=1e-6)
    assert np.all(np.abs(state.positions[nodes, 1]) == pytest.approx(0.2))


def curved(spans: int, radius: float):
    """The ST 9,8/9,8 ideal section cut to ``spans`` spans of 60 m on one curve (alternating stagger)."""
    cat = load_catenary("st_9.8_ideal")
    return cat.with_layout(SpanLayout(span_lengths=(60.0,) * spans, curve_radii=(radius,) * spans))


@pytest.mark.parametrize(("spans", "radius"), [(5, 300.0), (5, 1000.0), (7, -300.0), (4, 300.0)])
def test_curved_sections_meet_the_standard_geometry_tolerance(spans, radius):
    """5 × 60 m at R = +300 m and +1000 m once missed 0.05 mm by 55–93 µm (odd span counts): the
    mid-point anchor held the global x, not the track, so on a curve it pushed the steady arm there
    sideways by the two halves' tension difference. Checked here against the targets themselves."""
    state = form_find(curved(spans, radius))
    disc = state.discretisation
    anchor = spans // 2
    np.testing.assert_allclose(disc.mast_normal[anchor], [0.0, 1.0, 0.0], rtol=0, atol=1e-15)  # track along x
    assert np.max(np.abs(state.positions[disc.axial.node_a[disc.dropper_elements], 2] - target_heights(state))) < 5e-5
    assert np.max(np.abs(state.positions[disc.mast_cw_node, 2] - state.catenary.contact_wire_height)) < 5e-5
    assert state.form_finding.passes <= 2


def test_the_screening_sample_that_ran_out_of_iterations_form_finds_at_once():
    """Evaluation 137 of ``presag sensitivity --output recommendation --method morris --seed 3`` (ideal
    layout): a soft registration — 0.2 m stagger, 1.5 m arms, the first droppers 6 m out — ran IPOPT
    to its 100 iterations while the arms' pivots were the unknowns (a stiff bar turning under Newton
    steps). With the arm forces as unknowns it takes a few."""
    values = {"contact_wire.mass_per_length": 1.035, "contact_wire.axial_stiffness": 12.0e6,
              "contact_wire.bending_stiffness": 133.3333, "messenger_wire.mass_per_length": 0.42,
              "messenger_wire.axial_stiffness": 5.3333e6, "droppers.end_distance": 6.0, "droppers.max_spacing": 6.0,
              "droppers.axial_stiffness": 0.5e6, "droppers.mass_per_length": 0.1267, "droppers.clamp_mass": 0.3,
              "contact_wire_support.length": 1.5, "contact_wire_support.mass": 0.5,
              "contact_wire_support.axial_stiffness": 21.3333e6, "system_height": 1.0, "stagger": 0.2}
    catenary = apply_inputs({"catenary": load_catenary("st_9.8_ideal")},
                            {f"catenary.{k}": v for k, v in values.items()})["catenary"]
    with recording() as found:
        state = form_find(catenary)
    assert found == [state.form_finding]
    stats = state.form_finding
    assert stats.passes == 1 and stats.restarts == 0 and stats.ipopt_iterations <= 10, stats
    assert stats.seconds > 0.0 and not stats.cached
    assert state.iterations == stats.ipopt_iterations + stats.newton_iterations
    assert np.max(np.abs(state.positions[state.discretisation.axial.node_a[state.discretisation.dropper_elements], 2]
                         - target_heights(state))) < 5e-5


def test_droppers_that_cannot_be_cut_are_refused_before_any_solve(monkeypatch):
    """ST 7,1/7,1 with a 0.9 m system height: the messenger wire's first guess (both wires, the droppers,
    less what the pre-sag carries) reaches the contact wire; refused in one line, no solver run."""
    import presag_opt.static.form_finding as module

    def no_solve(*args):
        raise AssertionError("the solver ran")

    monkeypatch.setattr(module, "solve_form_finding", no_solve)
    cat = dataclasses.replace(load_catenary("st_7.1_ideal"), system_height=0.9)
    with pytest.raises(ModelError, match=r"^span 1 \(60 m\): the messenger wire sags to about -?\d+ mm from the "
                                         r"contact wire at the dropper 30.00 m from the mast, where the shortest "
                                         r"dropper is 100 mm"):
        check_form_finding_inputs(cat)
    with pytest.raises(ModelError, match="raise the system height or the messenger-wire tension"):
        form_find(cat)
