"""A result in a notebook (presag_opt.display): the headline, its lines and its table as HTML, the same rows as a
data frame."""

from __future__ import annotations

import math

from presag_opt.display import data_frame, html_summary, html_table

ROWS = [{"method": "Δe rule", "S [mm]": 60.8, "uplift [mm]": None, "built": False},
        {"method": "robust <minimax>", "S [mm]": 55.78, "uplift [mm]": 0.05381, "built": True}]


def test_the_table_escapes_text_and_shows_missing_values_and_flags():
    page = html_table(ROWS)
    assert page.startswith("<table><thead><tr><th>method</th><th>S [mm]</th>")
    assert "robust &lt;minimax&gt;" in page and "<td>–</td>" in page and "<td>yes</td>" in page
    assert "<td>55.8</td>" in page and "<td>0.05381</td>" in page  # 0.1 above 1, four digits below
    assert html_table([]) == "" and "<td>–</td>" in html_table([{"x": math.nan}])


def test_the_summary_puts_the_headline_first_and_each_line_in_a_list():
    page = html_summary("Pre-sag to build: 56 mm", ["  why: the band", "  margins: 2.5 mm"], ROWS)
    assert page.index("<strong>Pre-sag to build: 56 mm</strong>") < page.index("<li>why: the band</li>")
    assert page.count("<li>") == 2 and page.count("<tr>") == 3
    assert "<ul>" not in html_summary("Headline")


def test_the_data_frame_has_the_rows_columns_in_order():
    frame = data_frame(ROWS)
    assert list(frame.columns) == list(ROWS[0]) and frame["S [mm]"].tolist() == [60.8, 55.78]
    assert data_frame([]).empty
