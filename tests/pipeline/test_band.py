"""The decision for a band (presag_opt.pipeline.band): every method gathered once, one Δe number, the crew
tolerance from a Monte Carlo, a stored study's limit and uplift in the decision, and refusals before work."""

from __future__ import annotations

import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.decision import DELTA_E_RULE, QUASI_STATIC_ROBUST
from presag_opt.errors import ModelError
from presag_opt.pipeline.band import answer_band, reference_span
from presag_opt.robust.installation import InstallationErrors
from presag_opt.studies.store import write_store
from presag_opt.system.loader import load_catenary

ERRORS = InstallationErrors(dropper_length=1.5e-3)


@pytest.fixture(scope="module")
def answered():
    return answer_band(["st_9.8_ideal"], CASE_STUDY_BAND, installation_errors=ERRORS)


def test_one_rule_one_number_across_the_methods(answered):
    rec, robust, decision = answered.recommendation, answered.robust, answered.decision
    delta_e = decision.answer(DELTA_E_RULE)
    assert delta_e.presag_rel == rec.presag_rel == robust.nominal.presag_rel  # the same Δe number everywhere
    assert decision.answer(QUASI_STATIC_ROBUST).presag_rel == robust.robust_parabola.presag_rel
    quasi = next(i for i in decision.intervals if i.name == "quasi-static tolerance")
    assert (quasi.low, quasi.high) == (robust.tolerance.low, robust.tolerance.high)
    assert decision.reference_span == 60.0 == reference_span(load_catenary("st_9.8_ideal"))
    assert decision.validity.verdict == "holds" and decision.status in ("provisional", "tolerance-bound")


def test_the_crew_tolerance_comes_from_the_monte_carlo(answered):
    crew = answered.decision.evidence.installation
    assert crew.kind == "monte-carlo" and "dropper 1.5 mm" in crew.source
    assert answered.monte_carlo is not None and answered.monte_carlo.samples == 10_000
    # the mid-span pre-sag's P95 error over the spans is of the size of the dropper error (a few σ at most)
    assert 0.5 * 1.5e-3 < crew.half_width < 4 * 1.5e-3
    assert "installation_monte_carlo" not in answered.decision.missing


def test_a_stored_study_sets_the_limit_and_gives_the_dynamic_uplift(tmp_path):
    from tests.studies.conftest import synthetic_dataset
    from tests.studies.test_validity_analysis import relative_parabola, rule_mm

    ds = synthetic_dataset(sigma=relative_parabola(0.010), presags_mm=[20, 60, 100], betas=[0.2, 0.4, 0.45, 0.5],
                           static_forces=[50, 100, 150], rule_mm=rule_mm, uplift=0.06)
    path = tmp_path / "study.nc"
    write_store(ds, path)
    answered = answer_band(["st_9.8_ideal"], CASE_STUDY_BAND, study=path)
    validity = answered.decision.validity
    assert validity.limit.from_sweep and (validity.limit.low, validity.limit.high) == pytest.approx((0.40, 0.45))
    assert validity.verdict == "holds"
    assert answered.decision.uplift == 0.06 and answered.decision.uplift_kind == "dynamic"
    assert "validity_sweep" not in answered.decision.missing


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"sweep": "full"}, "sweep = 'full' is not one of reduced, quick"),
    ({"sweep": "quick", "study": "s.nc"}, "not both"),
    ({"crew": 0.002, "installation_errors": ERRORS}, "not both"),
    ({"crew": 0.2}, r"crew tolerance = 200 mm is outside the valid range \[0, 50\] mm"),
    ({"within": 3.0}, r"within = 300 % is outside the valid range"),
])
def test_bad_input_is_refused_before_any_form_finding(kwargs, message, monkeypatch):
    import presag_opt.pipeline.band as band

    def no_work(*args, **kwargs):
        raise AssertionError("work started before the input was checked")

    monkeypatch.setattr(band, "recommend", no_work)
    with pytest.raises(ModelError, match=message):
        answer_band(["st_9.8_ideal"], CASE_STUDY_BAND, **kwargs)
