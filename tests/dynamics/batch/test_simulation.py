"""The batch engine against the single-run reference path, its independence of batch composition,
failed runs inside a batch, bad input, and installed lines sharing the design's structure.

The runs use a 5-span ST 9,8/9,8 section (one lead-in span, the central span analysed) to keep the
reference path cheap. Tolerances: where the reference path is well conditioned (no friction, no
slack droppers, below β ≈ 0.3) the two paths differ only by round-off and the Newton tolerance
(1e-10 of the step's force scale), and agree to 1e-9 relative. With friction at higher speed the
reference itself moves by up to 1e-4 in σ when its input moves by 1e-14 (the stick–slip instants
and the Newton stopping decisions shift), so there the test asks the batch to stay within the
reference's own spread under such a perturbation (measured here, times 10).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.dynamics.batch import simulate_installed, simulate_many
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.dynamics.simulate import simulate
from presag_opt.errors import ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout

STATISTICS = ("mean_force", "std_force", "statistical_max", "statistical_min", "max_force", "min_force")
EXACT = 1e-9
"""Agreement of the two paths where the reference is well conditioned (see the module notes). [-]"""

AERO = 0.00097 * 3.6**2  # the case study's α_ae [N/(m/s)²]


@pytest.fixture(scope="module")
def settings(case):
    return dataclasses.replace(case.settings, lead_in_spans=1, analysed_spans=1)


@pytest.fixture(scope="module")
def frictionless(case):
    return dataclasses.replace(
        case.pantograph, stages=tuple(dataclasses.replace(s, friction=0.0) for s in case.pantograph.stages)
    )


def _reference(state, pantograph, point, settings, spacings=None):
    return simulate(state, pantograph, speed=point.speed, static_force=point.static_force,
                    aero_coefficient=point.aero_coefficient, spacings=spacings, settings=settings)


def _assert_same(outcome, reference, rel):
    assert outcome.ok, outcome.error
    for batch_stats, ref in zip(outcome.statistics, (p.statistics for p in reference.pantographs)):
        for name in STATISTICS:
            assert getattr(batch_stats, name) == pytest.approx(getattr(ref, name), rel=rel), name
        assert batch_stats.loss_of_contact == pytest.approx(ref.loss_of_contact, abs=1e-12)
    assert outcome.uplift_max == pytest.approx(reference.uplift_max, rel=rel)
    assert outcome.slack_droppers_max == int(reference.slack.sum(axis=1).max())


def test_batch_equals_single_runs_across_speeds_and_forces(short_state, frictionless, settings):
    """Two operating points of different speed and force in one batch (they stop at different steps),
    each equal to its own single run (1e-9)."""
    points = [OperatingPoint(speed=v / 3.6, static_force=f, aero_coefficient=AERO) for v, f in ((60, 70), (90, 140))]
    batch = simulate_many(short_state, frictionless, points, settings=settings, keep_histories=True)
    for point, outcome in zip(points, batch.runs):
        assert outcome.point == point
        reference = _reference(short_state, frictionless, point, settings)
        _assert_same(outcome, reference, EXACT)
        assert np.max(np.abs(outcome.contact_force[:, 0] - reference.pantographs[0].contact_force)) < 1e-7
        assert outcome.newton_iterations == int(reference.newton_iterations.sum())


def test_two_pantographs_on_one_train(short_state, frictionless, settings):
    """The trailing pantograph (20 m behind) meets the wave field of the leading one; both equal
    the single run's statistics (1e-9)."""
    point = OperatingPoint(speed=70 / 3.6, static_force=100.0, aero_coefficient=AERO)
    batch = simulate_many(short_state, frictionless, [point], spacings=(20.0,), settings=settings)
    reference = _reference(short_state, frictionless, point, settings, spacings=(20.0,))
    assert len(batch.runs[0].statistics) == 2
    _assert_same(batch.runs[0], reference, EXACT)


def test_friction_within_the_references_own_spread(short_state, case, settings):
    """With dry friction at β = 0.46 the batch stays within 10 × the spread of the reference under a
    1e-14 relative change of the static force (measured in the test)."""
    point = OperatingPoint(speed=160 / 3.6, static_force=120.0, aero_coefficient=AERO)
    reference = _reference(short_state, case.pantograph, point, settings)
    nudged = _reference(short_state, case.pantograph, dataclasses.replace(point, static_force=120.0 * (1 + 1e-14)),
                        settings)
    outcome = simulate_many(short_state, case.pantograph, [point], settings=settings).runs[0]
    assert outcome.ok
    for name in ("mean_force", "std_force", "max_force", "min_force"):
        spread = abs(getattr(nudged.statistics, name) / getattr(reference.statistics, name) - 1.0)
        got = abs(getattr(outcome.statistics[0], name) / getattr(reference.statistics, name) - 1.0)
        assert got <= 10.0 * max(spread, 1e-9), (name, got, spread)


def test_a_run_does_not_depend_on_its_batch(short_state, case, settings):
    """The same operating point alone and among others gives bit-identical records."""
    point = OperatingPoint(speed=120 / 3.6, static_force=85.0, aero_coefficient=AERO)
    others = [OperatingPoint(speed=v / 3.6, static_force=f, aero_coefficient=AERO) for v, f in ((60, 140), (150, 55))]
    alone = simulate_many(short_state, case.pantograph, [point], settings=settings, keep_histories=True).runs[0]
    mixed = simulate_many(short_state, case.pantograph, [others[0], point, others[1]], settings=settings,
                          keep_histories=True).runs[1]
    assert np.array_equal(alone.contact_force, mixed.contact_force)
    assert alone.statistics == mixed.statistics
    assert alone.uplift_max == mixed.uplift_max


def test_a_failed_run_is_reported_and_the_others_finish(short_state, frictionless, settings):
    """One Newton correction per step is too few at 200 km/h, where droppers go slack, but enough at
    60 km/h and 50 N, where no dropper goes slack and the frictionless system stays linear: the fast run fails with its
    reason; the slow run equals the same run alone, bit for bit."""
    tight = dataclasses.replace(settings, integrator=dataclasses.replace(settings.integrator, max_iterations=1))
    slow = OperatingPoint(speed=60 / 3.6, static_force=50.0, aero_coefficient=AERO)
    fast = OperatingPoint(speed=200 / 3.6, static_force=100.0, aero_coefficient=AERO)
    batch = simulate_many(short_state, frictionless, [fast, slow], settings=tight, keep_histories=True)
    failed, finished = batch.runs
    assert not failed.ok and "did not converge in step" in failed.error
    assert failed.statistics == () and np.isnan(failed.uplift_max)
    assert batch.failed == (failed,)
    alone = simulate_many(short_state, frictionless, [slow], settings=tight, keep_histories=True).runs[0]
    assert finished.ok and np.array_equal(finished.contact_force, alone.contact_force)
    assert "error" in batch.to_dict()["runs"][0]


@pytest.mark.parametrize(
    ("points", "message"),
    [
        ([], "the list is empty"),
        ([OperatingPoint(speed=350 / 3.6, static_force=100.0)], "below the contact-wire wave speed"),
    ],
    ids=["empty", "speed above the wave speed"],
)
def test_bad_batches_are_refused_before_any_run(short_state, case, settings, points, message):
    with pytest.raises(ModelError, match=message):
        simulate_many(short_state, case.pantograph, points, settings=settings)


def test_a_time_step_too_large_for_the_contact_is_refused(short_state, settings):
    stiff = load_pantograph("case_study_2mass_friction")
    coarse = settings.with_fixed_numerics(time_step=0.02)
    with pytest.raises(ModelError, match=r"90 km/h, 100 N: time_step = 20 ms is too large"):
        simulate_many(short_state, stiff, [OperatingPoint(speed=25.0, static_force=100.0)], settings=coarse)


# ----- installed lines on a shared structure (simulate_installed) ---------------------------------

def _raised(state, height):
    """The same line translated upwards by ``height`` [m]: the same forces, every wire ``height`` higher."""
    return EquilibriumState(state.model, state.positions + np.array([0.0, 0.0, height]), state.params,
                            state.applied_load)


@pytest.fixture(scope="module")
def installed_points():
    return [OperatingPoint(speed=v / 3.6, static_force=f, aero_coefficient=AERO) for v, f in ((80, 100), (140, 70))]


def test_the_structures_own_line_is_simulate_many_bit_for_bit(short_state, case, settings, installed_points):
    """The design as its own installed line, alone and beside a raised copy in the same batches."""
    reference = simulate_many(short_state, case.pantograph, installed_points, settings=settings, keep_histories=True)
    alone, = simulate_installed(short_state, [short_state], case.pantograph, installed_points, settings=settings,
                                keep_histories=True)
    beside = simulate_installed(short_state, [_raised(short_state, 0.05), short_state], case.pantograph,
                                installed_points, settings=settings, keep_histories=True)[1]
    for result in (alone, beside):
        for run, ref in zip(result.runs, reference.runs, strict=True):
            assert np.array_equal(run.contact_force, ref.contact_force)
            assert run.statistics == ref.statistics and run.uplift_max == ref.uplift_max


def test_a_raised_line_feels_the_same_contact_force(short_state, case, settings, installed_points):
    """Translating the whole line 50 mm up leaves every force unchanged: the runs read their own line's
    wire heights in the contact law and in the head's start height (an error would cost k·0.05 m ≈ 2.5 kN)."""
    own, raised = simulate_installed(short_state, [short_state, _raised(short_state, 0.05)], case.pantograph,
                                     installed_points, settings=settings, keep_histories=True)
    for a, b in zip(own.runs, raised.runs, strict=True):
        assert b.ok, b.error
        np.testing.assert_allclose(b.contact_force, a.contact_force, rtol=0.0, atol=1e-6)  # N, round-off of 5.3 m heights
        assert b.statistics[0].std_force == pytest.approx(a.statistics[0].std_force, rel=1e-9)


def test_installed_lines_are_checked(short_state, case, settings, installed_points):
    with pytest.raises(ModelError, match="the list is empty"):
        simulate_installed(short_state, [], case.pantograph, installed_points, settings=settings)
    other = form_find(case.catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 4, label="4 spans")),
                      case.settings.static)
    with pytest.raises(ModelError, match="another discretisation"):
        simulate_installed(short_state, [other], case.pantograph, installed_points, settings=settings)
