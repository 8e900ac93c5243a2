"""Robust pre-sag LPs (presag_opt.robust.lp): optimality against brute force, DPP re-solves, risk measures,
buildability, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.errors import ModelError
from presag_opt.robust import Buildability, ForceScenarios, Risk, evaluate_design, robust_presag


def test_minimax_parabola_matches_a_brute_force_scan(path, scenarios):
    design = robust_presag(path, scenarios)
    assert design.solver_status == "optimal"
    grid = np.linspace(0.0, 2.5e-3, 2501)  # S_rel step 0.001 ‰ = 0.06 mm on 60 m
    worst = np.array([path.waviness(path.parabola_depths(s), scenarios.forces).max() for s in grid])
    assert design.worst_case_waviness == pytest.approx(worst.min(), rel=0.005)  # issue: 0.5 %
    assert design.worst_case_waviness <= worst.min() + 1e-9  # the LP optimum is never beaten by the scan
    assert abs(design.presag_rel - grid[np.argmin(worst)]) < 2e-5


def test_lp_optimum_equals_its_exact_reevaluation(path, scenarios):
    """The per-dropper LP's own optimal value (its epigraph variable over the max/min constraints)
    equals the waviness re-evaluated exactly from its continuous depths; a wrong constraint in the
    LP would part them. Tolerance 1e-6 relative: Clarabel's default gap tolerances are 1e-8."""
    build = Buildability()
    design = robust_presag(path, scenarios, shape="per-dropper", buildability=build)
    problem = path.problems["robust"][("per-dropper", Risk().label, len(scenarios.forces), build)][0]
    assert problem.value == pytest.approx(design.continuous_objective, rel=1e-6)


def test_the_problem_is_dpp_and_reused(path, band):
    first = robust_presag(path, ForceScenarios.band(*band), shape="per-dropper")
    cached = dict(path.problems["robust"])
    narrow = robust_presag(path, ForceScenarios.band(band[0] + 20.0, band[1] - 20.0), shape="per-dropper")
    assert path.problems["robust"].keys() == cached.keys()  # same problem object re-solved
    problem = next(v[0] for k, v in path.problems["robust"].items() if k[0] == "per-dropper")
    assert problem.is_dpp()
    assert narrow.continuous_objective <= first.continuous_objective  # a narrower band is easier


def test_robust_beats_the_nominal_delta_e_design_over_the_band(path, scenarios, band):
    centre = 0.5 * (band[0] + band[1])
    nominal_rel = path.section.presag(centre, "delta-e").presag_rel_mean
    nominal = evaluate_design(path, path.parabola_depths(nominal_rel), scenarios, shape="parabola", risk=Risk())
    robust = robust_presag(path, scenarios)
    assert robust.worst_case_waviness <= nominal.worst_case_waviness  # by construction
    assert robust.worst_case_waviness < 0.9 * nominal.worst_case_waviness  # and clearly (measured 22 %)


def test_cvar_lies_between_mean_and_minimax(path):
    scen = ForceScenarios.from_operating_band(CASE_STUDY_BAND)
    objective = {r: robust_presag(path, scen, risk=Risk.parse(r)).objective for r in ("mean", "cvar:0.9", "minimax")}
    assert objective["mean"] <= objective["cvar:0.9"] + 1e-9 <= objective["minimax"] + 2e-9


def test_per_dropper_profile_is_buildable_and_at_least_as_good_as_the_parabola(path, scenarios):
    build = Buildability()
    parabola = robust_presag(path, scenarios)
    profile = robust_presag(path, scenarios, shape="per-dropper", buildability=build)
    assert profile.continuous_objective <= parabola.objective + 1e-9  # the parabola is a feasible profile
    steps = profile.depths / build.step
    assert np.allclose(steps, np.round(steps), atol=1e-9)  # on the 5 mm step
    assert np.allclose(profile.depths, profile.depths[::-1])  # symmetric
    assert profile.rounding == "exhaustive"
    assert profile.objective >= profile.continuous_objective - 1e-12


def test_infeasible_buildability_is_a_clear_error(path, scenarios):
    with pytest.raises(ModelError, match="no feasible profile|meets the limits"):
        robust_presag(path, scenarios, shape="per-dropper",
                      buildability=Buildability(min_dropper_length=1.5))


@pytest.mark.parametrize("call,words", [
    (lambda: ForceScenarios.band(148.0, 70.0), "empty, inverted"),
    (lambda: ForceScenarios.band(70.0, 70.0), "empty, inverted"),
    (lambda: ForceScenarios.band(70.0, 1500.0), "too high"),
    (lambda: Risk.parse("var:0.9"), "is not one of"),
    (lambda: Risk.parse("cvar:1.5"), "risk level"),
])
def test_bad_inputs(call, words):
    with pytest.raises(ModelError, match=words):
        call()


def test_forces_outside_the_computed_levels_are_refused(path):
    with pytest.raises(ModelError, match="outside the computed"):
        robust_presag(path, ForceScenarios.band(40.0, 140.0))
