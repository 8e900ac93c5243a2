"""A sample of the form-finding study (``benchmarks/bench_form_finding_fuzz.py`` runs 600 sets): each set
converges within the form-finding tolerances or is refused before any solve with a one-line reason."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.sensitivity.form_finding_fuzz import (
    EQUAL_SPAN_RANGE,
    FUZZ_SYSTEMS,
    HEIGHT_STEP,
    MIXED_SPAN_RANGE,
    PRESAG_RANGE,
    RADIUS_RANGE,
    SPAN_COUNTS,
    STATUSES,
    draw_cases,
    fuzz_table,
    solve_case,
)
from presag_opt.sensitivity.inputs import model_inputs
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import load_catenary

SAMPLE = {4: "converged", 7: "refused", 14: "converged", 16: "converged", 19: "converged", 38: "converged"}
"""Sets of seed 0: a 2 km curve with two push-off arms; a 2.9 km curve whose alternating stagger cancels the
curve's kink at the first mast (no sideways pull: refused); straight track with push-off arms; a 310 m curve
with height changes (the set that needs a second pass); an 800 m curve registered outside with push-off
arms and height changes; a 410 m curve, outside, a push-off arm at the first mast, height changes."""


def test_the_draw_is_reproducible_and_covers_the_ranges():
    cases = draw_cases(600, seed=0)
    assert [c.to_dict() for c in draw_cases(40, seed=0)] == [c.to_dict() for c in cases[:40]]
    assert {c.system for c in cases} == set(FUZZ_SYSTEMS)
    ranges = {name: model_inputs({"catenary": load_catenary(name)}, {"catenary": load_catenary(name).provenance})
              for name in FUZZ_SYSTEMS}
    for c in cases:
        assert set(c.inputs) == set(ranges[c.system])  # every assumed input of the system, drawn in its range
        assert all(ranges[c.system][n].low <= v <= ranges[c.system][n].high for n, v in c.inputs.items())
        assert SPAN_COUNTS[0] <= len(c.span_lengths) <= SPAN_COUNTS[1]
        assert min(EQUAL_SPAN_RANGE[0], MIXED_SPAN_RANGE[0]) - 0.05 <= min(c.span_lengths)
        assert max(c.span_lengths) <= max(EQUAL_SPAN_RANGE[1], MIXED_SPAN_RANGE[1]) + 0.05
        assert c.radius == 0.0 or RADIUS_RANGE[0] - 0.5 <= abs(c.radius) <= RADIUS_RANGE[1] + 0.5
        assert np.max(np.abs(np.diff(c.heights))) <= HEIGHT_STEP + 1e-9
        assert PRESAG_RANGE[0] <= c.presag_rel <= PRESAG_RANGE[1]
    # every kind of section is there: odd and even counts, both hands, both staggers, push-off arms
    assert {len(c.span_lengths) % 2 for c in cases} == {0, 1}
    assert {np.sign(c.radius) for c in cases} == {-1.0, 0.0, 1.0}
    assert {c.outside for c in cases if c.radius} == {False, True}
    assert sum(any(c.push_off) for c in cases) > 200 and sum(c.heights[1] != c.heights[0] for c in cases) > 200


@pytest.mark.parametrize("index", sorted(SAMPLE))
def test_a_set_converges_or_is_refused_before_any_solve(index):
    case = draw_cases(max(SAMPLE) + 1, seed=0)[index]
    outcome = solve_case(case)
    assert outcome.status == SAMPLE[index], outcome.reason
    if outcome.status == "refused":
        assert len(outcome.reason.splitlines()) == 1 and "steady arm at mast 1 (of 9)" in outcome.reason
        return
    stats = outcome.statistics
    assert stats.restarts == 0 and stats.passes <= 2 and stats.ipopt_iterations <= 10, stats
    # independent of the form-finding's own check: the contact wire at its targets within 0.05 mm
    state = form_find(case.catenary())
    disc = state.discretisation
    cat = state.catenary
    drop_cw = disc.axial.node_a[disc.dropper_elements]
    target = np.array([cat.support_line(int(s), np.array([x]))[0] - cat.presag_depth(int(s), np.array([x]))[0]
                       for s, x in zip(disc.dropper_span, disc.dropper_position)])
    assert np.max(np.abs(state.positions[drop_cw, 2] - target)) < 5e-5
    assert np.max(np.abs(state.positions[disc.mast_cw_node, 2] - cat.mast_contact_wire_height())) < 5e-5
    # the first guess of the droppers (which the refusal of short droppers reads) within its margin
    assert abs(outcome.dropper_guess_error) < 0.03


def test_the_table_counts_every_status_and_quantiles_the_solves():
    cases = draw_cases(max(SAMPLE) + 1, seed=0)
    outcomes = [solve_case(cases[i]) for i in (7, 14)]
    table = fuzz_table(outcomes)
    assert table["count"] == {"converged": 1, "refused": 1, "refused after solving": 0, "failed": 0}
    assert sum(table["share"].values()) == pytest.approx(1.0, abs=1e-12) and set(table["share"]) == set(STATUSES)
    solved = outcomes[1].statistics
    assert table["quantiles"]["ipopt_iterations"] == {q: float(solved.ipopt_iterations)
                                                      for q in ("q50", "q90", "q99", "q100")}
