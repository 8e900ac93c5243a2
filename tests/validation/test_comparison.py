"""Our numbers beside the paper's (presag_opt.validation.comparison): Table 1, Table 2, recommendation.

Published numbers: Schick, Liu & Stichel (2025), doi:10.1108/RS-05-2025-0016, Table 1 (exact to the
printed digits), Table 2 (our values as regression values beside the paper's).
"""

from __future__ import annotations

import pytest

from presag_opt.validation import comparison_rows, single_curve_error, table2_row

# Regression values (Table 2, F_m = 140 N, active-set elasticity, 0.5 m point spacing, default static
# settings), computed once with this code on the built-in models and stored here. The paper prints
# 96/118 mm (7.1/7.1) and 58/79 mm (9.8/9.8); ours differ by −10, −11, +7 and −5 % (assumed
# parameters, see models/README.md). Tolerance 0.1 %: the form-finding and re-solve tolerances move
# these by ~1e-6 relative, so anything above 0.1 % is a change of the model, not noise.
TABLE2_REGRESSION_MM = {
    "7.1/7.1": (86.2955, 104.4561),
    "9.8/9.8": (62.0075, 75.0647),
}


@pytest.mark.parametrize("system", ["7.1/7.1", "9.8/9.8"])
def test_table2_regression(system, ideal71, ideal98):
    row = table2_row(ideal71 if system == "7.1/7.1" else ideal98, 140.0)
    mid_mast, delta_e = TABLE2_REGRESSION_MM[system]
    assert row.tension_label == system
    assert row.presag_mid_mast * 1e3 == pytest.approx(mid_mast, rel=1e-3)
    assert row.presag_delta_e * 1e3 == pytest.approx(delta_e, rel=1e-3)


def test_table2_keeps_the_papers_ordering(ideal71, ideal98):
    soft, stiff = table2_row(ideal71), table2_row(ideal98)
    # The paper's two findings: Δe exceeds e_mid − e_mast, and the softer system needs more pre-sag.
    assert soft.presag_delta_e > soft.presag_mid_mast and stiff.presag_delta_e > stiff.presag_mid_mast
    assert soft.presag_mid_mast > stiff.presag_mid_mast and soft.presag_delta_e > stiff.presag_delta_e


def test_table1_rows_of_the_comparison_match_exactly():
    rows = comparison_rows()
    assert len(rows) == 10
    assert all(r.difference == 0.0 for r in rows)


def test_comparison_rows_set_ours_beside_the_papers(short_recommendation, ideal71, ideal98, ideal98_70mm):
    table2 = [table2_row(ideal71), table2_row(ideal98)]
    errors = [single_curve_error(ideal98), single_curve_error(ideal98_70mm)]
    rows = {r.item: r for r in comparison_rows(recommendation=short_recommendation, table2_rows=table2, single_curve_errors=errors)}
    assert rows["Table 2 7.1/7.1 S delta-e"].ours == table2[0].presag_delta_e * 1e3
    assert rows["Table 2 9.8/9.8 S mid-mast"].paper == 58.0
    assert rows["S_rel ideal low (delta-e)"].paper == 0.68 and rows["S_rel mixed high (delta-e)"].paper == 1.62
    assert rows["S_rel recommended (delta-e)"].ours == short_recommendation.presag_rel * 1e3
    fig5b = rows["Fig. 5b error at 179 N, 70 mm geometry"]
    assert (fig5b.ours, fig5b.paper) == (errors[1].error_at(179.0) * 100, 2.0)
    for row in rows.values():  # both differences from the same two numbers
        assert row.difference == row.ours - row.paper
        assert row.relative_difference == pytest.approx(row.difference / row.paper, rel=1e-12)


def test_compare_with_paper_recomputes_table2_and_fig5b():
    """The whole comparison recomputed by :func:`compare_with_paper` (coarse 1 m elements and point
    spacing to keep it short). Table 2 stays within 1 % of the 0.5 m regression values (the halving
    bound of ``test_elasticity``; measured 0.13–0.23 %); the rows are made from the returned studies."""
    from presag_opt.static.discretisation import StaticSettings
    from presag_opt.validation import compare_with_paper

    comparison = compare_with_paper(step=1.0, settings=StaticSettings(element_length=1.0))
    rows = {r.item: r for r in comparison.rows}
    assert all(r.difference == 0.0 for item, r in rows.items() if item.startswith("Table 1"))
    for row in comparison.table2:
        mid_mast, delta_e = TABLE2_REGRESSION_MM[row.tension_label]
        assert row.presag_mid_mast * 1e3 == pytest.approx(mid_mast, rel=0.01)
        assert row.presag_delta_e * 1e3 == pytest.approx(delta_e, rel=0.01)
        assert rows[f"Table 2 {row.tension_label} S delta-e"].ours == row.presag_delta_e * 1e3
    nominal, large = comparison.single_curve_errors
    assert rows["Fig. 5b error at 179 N, 70 mm geometry"].ours == large.error_at(179.0) * 100
    assert large.error_at(179.0) < 0.5 * nominal.error_at(179.0)  # the paper's finding, as in test_single_curve
    assert not any(item.startswith("S_rel") for item in rows)  # no recommendation given, no such rows
