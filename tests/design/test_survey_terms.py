"""A section's failure in the survey's terms (presag_opt.design.survey_terms): the model's mast and span numbers
become the survey's ids and rows, the column to check is named, the error's kind and statistics are kept."""

from __future__ import annotations

from presag_opt.design.survey_terms import in_survey_terms
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.system.survey import SurveyMast, SurveySection


def section():
    return SurveySection(section="S2", masts=tuple(
        SurveyMast(mast=f"M{21 + i}", chainage=50.0 * i, stagger=0.3 if i % 2 else -0.3, contact_wire_height=5.5,
                   system_height=1.2, curve_radius=0.0, steady_arm="pull-off", section="S2", row=f"line.csv, row {22 + i}")
        for i in range(5)))


def test_masts_and_spans_are_named_as_the_survey_names_them():
    error = ModelError("steady arm at mast 3 (of 5): the contact wire pulls only 0 N sideways; span 2 (50 m) too")
    out = in_survey_terms(error, section())
    assert isinstance(out, ModelError) and out.__cause__ is error
    assert str(out) == ("steady arm at mast M23 (line.csv, row 24): the contact wire pulls only 0 N sideways; span "
                        "M22–M23 (50 m) too (survey column 'stagger_mm')")


def test_a_solver_failure_keeps_its_kind_and_statistics():
    error = ConvergenceError("span 4: no equilibrium under an uplift; push-off arm(s) at mast 5", {"iterations": 7})
    out = in_survey_terms(error, section())
    assert isinstance(out, ConvergenceError) and out.stats == {"iterations": 7}
    assert str(out).startswith("span M24–M25: no equilibrium") and "mast M25 (line.csv, row 26)" in str(out)
    assert str(out).endswith("(survey column 'steady_arm')")


def test_a_message_without_model_numbers_is_left_alone_and_numbers_beyond_the_section_too():
    error = ModelError("form-finding did not converge")
    assert in_survey_terms(error, section()) is error
    assert "mast 9" in str(in_survey_terms(ModelError("mast 9 and span 2"), section()))
