"""Dynamic simulation: crawling speed against static elasticity, slack droppers, several pantographs,
the EN 50318-style reference case, and bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.dynamics.simulate import simulate
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.validation import EN50318_RANGES, en50318_verdicts
from presag_opt.validation.dynamic_model import crawling_check

ONE_SPAN = SimulationSettings(analysed_spans=1, lead_in_spans=0, droppers="all")
"""Analyse the middle span of a three-span section, starting at its first mast, every dropper recorded."""


@pytest.fixture(scope="module")
def three_spans():
    """ST 9,8/9,8 on three 60 m spans (the middle one is analysed): a small, fast model."""
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    return form_find(catenary)


@pytest.fixture(scope="module")
def en50318_runs():
    """The EN 50318-style case at its two speeds, default discretisation (0.5 m, 2 ms)."""
    case = load_case("en50318_2002")
    state = form_find(case.catenary, case.settings.static)
    paper = case.settings.with_fixed_numerics()  # the case ships automatic numerics
    return {round(v * 3.6): case.run(v, state=state, settings=paper) for v in case.speeds}


@pytest.mark.slow  # 31 000 steps of the single-run path; the default run has notebook 02's check (10 km/h, 10 %)
def test_crawling_uplift_equals_force_times_static_elasticity(three_spans):
    """At 1 km/h a constant 60 N lifts the contact point by F·e(x), e from the tangent stiffness.

    β = 0.003 makes inertia negligible (the moving-load correction is of order β²); the
    pantograph has no frame spring or friction, so the contact force stays within 1 % of 60 N (the
    frame damper, 90 N·s/m, times the frame's speed, 0.28 m/s times path slopes up to 0.01, is
    0.25 N), and the relation is checked with the actual contact force. No dropper slackens at 60 N, so the
    linear elasticity applies. Required: within 2 % (issue 4); measured: 0.5 %. Time step 7 ms,
    just below the contact limit of 7.54 ms (the run is 216 s long).
    """
    check = crawling_check(three_spans, speed=1.0 / 3.6, static_force=60.0, time_step=7e-3)
    assert check.position.min() < 0.5 and check.position.max() > 59.5  # the whole middle span
    assert not check.any_slack
    assert check.force_deviation < 1e-2
    assert check.max_relative_error < 0.02


def test_droppers_near_the_pantograph_go_slack_under_high_uplift(three_spans):
    """250 N at 90 km/h lifts the wire by about 0.2 m: every dropper of the span goes slack as the
    pantograph passes, its recorded force is exactly zero then, and every slack moment falls within
    15 m (under two dropper spacings) of the contact point. At 120 N only droppers next to the masts
    slacken (within 5 m of a mast), while the pantograph is within 5 m of them."""
    pantograph = load_pantograph("case_study_2mass_friction")
    high = simulate(three_spans, pantograph, speed=25.0, static_force=250.0, settings=ONE_SPAN)
    in_span = (high.dropper_station > 60.0) & (high.dropper_station < 120.0)
    assert high.slack[:, in_span].any(axis=0).all()
    assert np.all(high.dropper_force[high.slack] == 0.0)
    times, droppers = np.nonzero(high.slack)
    distance = np.abs(high.dropper_station[droppers] - high.pantographs[0].position[times])
    assert distance.max() < 15.0

    low = simulate(three_spans, pantograph, speed=25.0, static_force=120.0, settings=ONE_SPAN)
    times, droppers = np.nonzero(low.slack)
    assert 0 < len(np.unique(droppers)) < np.count_nonzero(in_span)
    assert np.abs(low.dropper_station[droppers] - low.pantographs[0].position[times]).max() < 5.0
    assert np.all(np.min(np.abs(low.dropper_station[droppers][:, None] - np.array([60.0, 120.0])), axis=1) < 5.0)


def test_two_pantographs_start_in_static_contact_and_keep_their_spacing(three_spans):
    """Two case-study pantographs 30 m apart at 90 km/h.

    Both start pressed with the uplift force (static contact, to 1e-6); their contact points stay
    30 m apart and their analysis windows are 30 m / 25 m/s = 1.2 s apart. Each mean contact force is
    its uplift force within 2 %: averaged over the window the pantograph's inertia, damper and friction
    forces nearly cancel (the frame has no spring to the car body).
    """
    pantograph = load_pantograph("case_study_2mass_friction")
    uplift = 120.0 + 0.00097 * 90.0**2
    result = simulate(
        three_spans, pantograph, speed=25.0, static_force=120.0, aero_coefficient=0.00097 * 3.6**2,
        spacings=[30.0], settings=ONE_SPAN,
    )
    lead, trail = result.pantographs
    assert (lead.offset, trail.offset) == (0.0, 30.0)
    np.testing.assert_allclose(lead.position - trail.position, 30.0, rtol=1e-12)
    assert trail.window[0] - lead.window[0] == pytest.approx(1.2, rel=1e-9)
    for run in (lead, trail):
        assert run.contact_force[0] == pytest.approx(uplift, rel=1e-6)
        assert run.statistics.mean_force == pytest.approx(uplift, rel=0.02)


def test_speed_ratio_above_0_7_warns_and_the_run_completes(three_spans):
    """250 km/h on ST 9,8/9,8 is β = 69.4 / 95.7 = 0.726: a warning (EN 50119), not an error."""
    pantograph = load_pantograph("case_study_2mass_friction")
    with pytest.warns(UserWarning, match=r"β = 0.73 exceeds 0.7"):
        result = simulate(three_spans, pantograph, speed=250 / 3.6, static_force=120.0, settings=ONE_SPAN)
    assert result.speed_ratio == pytest.approx(250 / 3.6 / np.sqrt(9800 / 1.07), rel=1e-12)
    assert result.doppler_factor == pytest.approx((1 - result.speed_ratio) / (1 + result.speed_ratio), rel=1e-12)


@pytest.mark.slow  # keeps the default run under 5 minutes; the shipped EN 50318 case is judged by tests/cli/test_validation.py
def test_en50318_case_at_default_discretisation(en50318_runs):
    """The EN 50318-style reference case at 250 and 300 km/h, 0.5 m elements and 2 ms steps.

    Checked against the published reference ranges (EN50318_RANGES): F_m, the steady-arm uplift and
    no loss of contact at both speeds, and at 250 km/h also the actual and statistical extremes.
    σ at 250 km/h is 26.2 N against a range from 26 N; this discretisation underestimates it by
    2.8 % (26.9 N with 0.25 m and 1 ms, converged to 0.1 %), so σ is required within the range less 3 %.
    At 300 km/h (β = 0.68) the 0.5 m elements cannot carry the short waves ahead of the pantograph
    (wavelength (c − v)/20 Hz ≈ 1.9 m): σ is 13 % low (29.2 N against 33.3-33.5 N with 0.25 and
    0.17 m). That speed is checked in full by the slow test at the finer discretisation; here σ must
    grow with speed.
    """
    for speed in (250, 300):
        stats = en50318_runs[speed].to_dict()
        ranges = EN50318_RANGES[speed]
        for key in ("Fm_N", "uplift_max_mm"):
            assert ranges[key][0] <= stats[key] <= ranges[key][1], (speed, key, stats[key])
        assert stats["loss_of_contact_pct"] == 0.0
    stats = en50318_runs[250].to_dict()
    for key in ("stat_max_N", "stat_min_N", "max_N", "min_N"):
        assert EN50318_RANGES[250][key][0] <= stats[key] <= EN50318_RANGES[250][key][1], (key, stats[key])
    assert 0.97 * 26.0 <= stats["sigma_N"] <= 31.0
    assert en50318_runs[300].statistics.std_force > en50318_runs[250].statistics.std_force


@pytest.mark.slow
def test_en50318_case_converged_is_inside_every_reference_range():
    """With 0.25 m elements and 1 ms steps (σ converged to 0.6 % against 0.17 m and 0.5 ms), all
    seven published statistics fall inside the reference ranges at both speeds, with no loss of
    contact."""
    case = load_case("en50318_2002")
    settings = dataclasses.replace(
        case.settings,
        static=StaticSettings(element_length=0.25),
        integrator=dataclasses.replace(case.settings.integrator, time_step=1e-3),
    )
    state = form_find(case.catenary, settings.static)
    for speed in EN50318_RANGES:
        stats = case.run(speed / 3.6, state=state, settings=settings).to_dict()
        for verdict in en50318_verdicts(speed, stats):
            assert verdict.inside, (speed, verdict)
        assert stats["loss_of_contact_pct"] == 0.0


@pytest.mark.slow
@pytest.mark.parametrize("speed_kmh", [90, 180])
def test_sigma_converges_in_time_step_and_element_length(speed_kmh):
    """Case study (ST 9,8/9,8, 2-mass pantograph with friction, 120 N): σ changes by less than 3 %
    from 2 to 1 ms and from 0.5 to 0.25 m elements (issue 4). Measured: 0.1 % and 0.3 % at 90 km/h,
    0.1 % and 0.9 % at 180 km/h."""
    case = load_case("case_study_st98")
    base = case.settings
    fine_step = dataclasses.replace(base, integrator=dataclasses.replace(base.integrator, time_step=1e-3))
    fine_mesh = dataclasses.replace(base, static=StaticSettings(element_length=0.25))
    sigma = {
        name: case.run(speed_kmh / 3.6, settings=settings).statistics.std_force
        for name, settings in (("base", base), ("dt", fine_step), ("h", fine_mesh))
    }
    assert sigma["dt"] == pytest.approx(sigma["base"], rel=0.03)
    assert sigma["h"] == pytest.approx(sigma["base"], rel=0.03)
