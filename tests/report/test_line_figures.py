"""The line's figures (presag_opt.report.line_figures): the height profile with a height change marked at its
mast, e(x) as built of every span, each embedded in the page with its id and caption."""

from __future__ import annotations

import dataclasses

import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.report import line_figures
from presag_opt.report.line_figures import embedded, plot_elasticity_along, plot_profile
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import Survey
from presag_opt.system.survey_writing import survey_of_catenary


@pytest.fixture(scope="module")
def design():
    """Four 45 m spans, the contact wire 0.1 m lower at the third mast."""
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(45.0,) * 4))
    survey = survey_of_catenary(base)
    masts = tuple(dataclasses.replace(m, contact_wire_height=5.4) if i == 2 else m for i, m in enumerate(survey.masts))
    return design_line(Survey(masts=masts), base, CASE_STUDY_BAND, LineOptions(element_length=1.0, workers=1))


def test_the_profile_marks_the_height_change_at_its_mast(design, tmp_path, monkeypatch):
    saved = {}

    def keep(fig, path):
        saved["axes"] = fig.axes
        return path

    monkeypatch.setattr(line_figures, "save_figure", keep)
    plot_profile(design, tmp_path / "profile.png")
    (ax,) = saved["axes"]
    marks = [t.get_text() for t in ax.texts]
    assert marks == ["M3: 5.40 m", "M4: 5.50 m"]  # into and out of the lowered mast
    lines = {line.get_label(): line for line in ax.get_lines()}
    assert len(lines["contact wire"].get_xdata()) == len(design.survey.masts) + len(design.droppers)


def test_the_elasticity_as_built_draws_every_span(design, tmp_path, monkeypatch):
    saved = {}
    monkeypatch.setattr(line_figures, "save_figure", lambda fig, path: saved.setdefault("fig", fig) and path)
    plot_elasticity_along(design, tmp_path / "e.png")
    top, bottom = saved["fig"].axes
    assert len(top.get_lines()) == len(design.spans)
    assert [p.get_height() for p in bottom.patches] == pytest.approx([s.uniformity for s in design.spans], abs=1e-12)


def test_a_figure_is_embedded_with_its_id_and_caption(design):
    html = embedded(plot_profile, design, "fig-profile", "Heights & droppers")
    assert html.startswith("<figure id='fig-profile'>") and "data:image/png;base64," in html
    assert "Heights &amp; droppers</figcaption>" in html
