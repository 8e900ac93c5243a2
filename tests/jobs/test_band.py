"""The band jobs (presag_opt.jobs.band): the command line's defaults, the designer's units, the decision in a notebook."""

from __future__ import annotations

import argparse
import inspect

import pytest

from presag_opt import OperatingBand, jobs
from presag_opt.cli import recommend, robust
from presag_opt.design.band import CASE_STUDY_BAND
from presag_opt.errors import ModelError


def parser_of(register) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser()
    register(parser.add_subparsers(dest="command"))
    return parser


@pytest.mark.parametrize(("register", "argv", "job"), [
    (recommend.register, ["recommend"], jobs.recommend),
    (robust.register, ["robust"], jobs.robust_design),
])
def test_each_command_s_defaults_are_its_job_s(register, argv, job):
    from presag_opt.cli.decision_options import decision_keywords

    args = parser_of(register).parse_args(argv)
    defaults = {n: p.default for n, p in inspect.signature(job).parameters.items()}
    for name, value in decision_keywords(args).items():
        if name in defaults:
            assert value == defaults[name], name
    for option, keyword in (("element_length", "element_length"), ("step", "step"),
                            ("working_width", "working_width_mm"), ("rule", "rule"), ("shape", "shape"),
                            ("risk", "risk"), ("method", "method"), ("elasticity_method", "elasticity_method")):
        if hasattr(args, option) and keyword in defaults:
            assert getattr(args, option) == defaults[keyword], option
    band = OperatingBand.from_kmh(static_force=args.static_force, speed_kmh=(args.min_speed, args.max_speed),
                                  aero_coefficient_kmh=args.aero)
    assert band == CASE_STUDY_BAND  # the round trip through km/h is exact for the case study's numbers


def test_the_band_in_km_h_is_the_band_in_si():
    band = OperatingBand.from_kmh(static_force=(70, 140), speed_kmh=90, aero_coefficient_kmh=0.00097)
    assert band.speed_high == pytest.approx(25.0, rel=1e-12) and band.speed_low == 0.0
    assert band.aero_coefficient == pytest.approx(0.00097 * 3.6**2, rel=1e-12)
    assert band.speed_kmh == pytest.approx((0.0, 90.0), rel=1e-12)
    assert band.aero_coefficient_kmh == pytest.approx(0.00097, rel=1e-12)
    one = OperatingBand.from_kmh(static_force=120, speed_kmh=(50, 80), aero_coefficient_kmh=0.0)
    assert (one.static_force_low, one.static_force_high) == (120.0, 120.0)
    with pytest.raises(ModelError, match="speed_high = 600 km/h is outside the valid range"):
        OperatingBand.from_kmh(static_force=100, speed_kmh=600, aero_coefficient_kmh=0.00097)


def test_a_crew_tolerance_and_a_dropper_error_together_are_refused_before_any_work():
    with pytest.raises(ModelError, match="not both"):
        jobs.recommend(crew_tolerance_mm=3.0, dropper_error_mm=1.0)


def test_a_band_decision_shows_its_headline_reason_and_answers():
    answer = jobs.robust_design()
    page = answer._repr_html_()
    assert answer.decision.headline() in page.replace("&#x27;", "'") and "why: " in page and "<table>" in page
    frame = answer.to_frame()
    assert list(frame["method"]) == [a.method for a in answer.decision.answers]
    built = frame[frame["built"]]
    assert len(built) == 1 and built["S [mm]"].iloc[0] == pytest.approx(answer.decision.mm(answer.decision.presag_rel),
                                                                         abs=1e-9)
    assert answer.to_frame("layouts")["layout"].tolist() == ["ideal"]
    robust_rows = answer.robust.to_frame()
    assert robust_rows["design"].tolist() == ["robust", "Δe rule"]
    assert "<table>" in answer.robust._repr_html_()
    with pytest.raises(ModelError, match="table = 'spans' is not one of answers, layouts"):
        answer.table("spans")
