"""``presag_opt.report.html``: the pieces the page is built from, each on inputs whose HTML is known.
The whole page of the case-study report is checked in ``test_content.py`` (written once there)."""

from __future__ import annotations

import math

import pytest

from presag_opt.report import html
from presag_opt.units import KMH


class _Decision:
    """A stand-in with the two members :func:`html.decision_html` reads."""

    def __init__(self, status: str, lines: list[str]):
        self.status = status
        self._lines = lines

    def lines(self, span_length: float) -> list[str]:
        assert span_length == 60.0
        return self._lines


def test_a_table_escapes_every_cell_and_right_aligns_only_the_numeric_columns():
    text = html._table(["input", "S [mm]"], [["<wire> & arm", 67], ["x", "1.2"]], numeric={1})
    assert text == ("<table><thead><tr><th>input</th><th>S [mm]</th></tr></thead><tbody>"
                    "<tr><td>&lt;wire&gt; &amp; arm</td><td class=\"num\">67</td></tr>"
                    "<tr><td>x</td><td class=\"num\">1.2</td></tr></tbody></table>")


@pytest.mark.parametrize(("status", "css"), [("decided", "summary"), ("not decided", "warn")])
def test_the_decision_heads_the_page_in_the_style_of_its_status(status, css):
    text = html.decision_html(_Decision(status, ["Build S = 67 mm <1.12 ‰>", "  why: inside the band", "  not checked"]),
                              60.0)
    assert text == (f"<div class='{css}' id='decision'><p><b>Build S = 67 mm &lt;1.12 ‰&gt;</b></p>"
                    "<ul><li>why: inside the band</li><li>not checked</li></ul></div>")


@pytest.mark.parametrize(("speed", "text"), [(200 * KMH, "200 km/h"), (None, "–"), (math.inf, "–"),
                                             (math.nan, "–"), (99.6 * KMH, "100 km/h")])
def test_speeds_are_shown_in_km_h_and_a_missing_one_as_a_dash(speed, text):
    assert html._kmh(speed) == text


def test_values_of_the_input_table_print_as_written():
    assert html._value((0.5, 1.0, 1.5)) == "0.5, 1, 1.5"
    assert html._value(9800.0) == "9800" and html._value(3) == "3" and html._value("assumed") == "assumed"


def test_the_mean_of_values_in_m_is_given_in_mm():
    assert html._mean([0.050, 0.070]) == pytest.approx(60.0, rel=1e-12)


def test_a_figure_carries_its_id_its_embedded_image_and_an_escaped_caption():
    text = html._figure({"fig-presag": "data:image/png;base64,AAAA"}, "fig-presag", "S against F_m < 148 N")
    assert text == ('<figure id="fig-presag"><img class="report-figure" src="data:image/png;base64,AAAA" '
                    'alt="S against F_m &lt; 148 N"><figcaption>S against F_m &lt; 148 N</figcaption></figure>')
