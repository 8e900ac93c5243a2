"""``presag_opt.studies.plots``: the validity-study figures draw the study's numbers in the units their
axes name (mm, N, β), on a synthetic study whose uplift and rules are known by construction
(``make_dataset`` of ``conftest.py``: no simulation). The figures are taken from the saving step."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.studies import plots
from presag_opt.studies.validity_analysis import validity_analysis

BETAS = [0.1, 0.2, 0.3]
PRESAGS_MM = [20, 60, 100]
FORCES = [80, 120, 160]


def _uplift(s, beta, static_force):
    """Uplift that grows with β and F_stat, and falls with S: 10 mm + 100 mm·β + 0.1 mm/N·F_stat − 0.1·S. [m]"""
    return 0.010 + 0.100 * beta + 1e-4 * static_force - 0.1 * s


@pytest.fixture(scope="module")
def study(make_dataset):
    dataset = make_dataset(sigma=lambda s, beta, f, fm: 5.0 + 0.002 * (fm - 110.0) ** 2 + 300.0 * (s - 0.060) ** 2,
                           presags_mm=PRESAGS_MM, betas=BETAS, static_forces=FORCES, rule_mm=lambda fm: 0.45 * fm,
                           uplift=_uplift)
    return dataset, validity_analysis(dataset)


@pytest.fixture
def drawn(monkeypatch):
    figures = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path: figures.append(fig) or path)
    return figures


def test_the_four_figures_are_written_by_name(study, tmp_path):
    dataset, result = study
    paths = plots.save_validity_plots(dataset, result, tmp_path / "new" / "plots")
    assert [p.name for p in paths] == ["fig6_ratio.png", "fig7_presag.png", "fig8_optimal_force.png", "uplift.png"]
    assert all(p.read_bytes()[:4] == b"\x89PNG" for p in paths)


def test_a_chosen_few_are_drawn_in_the_order_given_and_an_unknown_name_is_refused(study, tmp_path, drawn):
    paths = plots.save_validity_plots(*study, tmp_path, figures=("uplift", "fig7_presag"))
    assert [p.name for p in paths] == ["uplift.png", "fig7_presag.png"]
    assert len(drawn) == 2 and drawn[0].axes[0].get_ylabel() == "max steady-arm uplift over F_stat [mm]"
    with pytest.raises(ModelError, match=r"^figures = \['fig9'\] are not validity figures"):
        plots.save_validity_plots(*study, tmp_path, figures=("fig9",))


def test_a_folder_that_cannot_be_made_is_one_line(study, tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(ModelError, match=r"^--plot .*file/plots: cannot create the folder \(Not a directory\)$"):
        plots.save_validity_plots(*study, tmp_path / "file" / "plots")


def test_the_uplift_figure_draws_the_worst_static_force_per_presag_in_mm_against_beta(study, drawn):
    plots.save_validity_plots(*study, "unused")
    ax = drawn[3].axes[0]
    lines = ax.get_lines()
    for line, s_mm in zip(lines, PRESAGS_MM):
        np.testing.assert_allclose(line.get_xdata(), BETAS, rtol=1e-12)
        worst = [_uplift(s_mm * 1e-3, b, max(FORCES)) * 1e3 for b in BETAS]  # the largest F_stat lifts most
        np.testing.assert_allclose(line.get_ydata(), worst, rtol=1e-9)
        assert line.get_label() == f"S = {s_mm:g} mm"
    assert lines[-1].get_ydata()[0] == pytest.approx(83.5, rel=1e-12)  # the limit line, 0.0835 m
    assert ax.get_ylabel() == "max steady-arm uplift over F_stat [mm]"


def test_fig7_draws_the_rules_in_mm_against_the_mean_force(study, drawn):
    dataset, result = study
    plots.save_validity_plots(dataset, result, "unused")
    first = drawn[1].axes[0]
    delta_e = next(line for line in first.get_lines() if line.get_label() == "Δe rule")
    np.testing.assert_allclose(delta_e.get_xdata(), FORCES, rtol=1e-12)  # α_ae = 0: F_m = F_stat
    np.testing.assert_allclose(delta_e.get_ydata(), [0.45 * f for f in FORCES], rtol=1e-9)
    mid_mast = next(line for line in first.get_lines() if line.get_label() == "mid/mast rule")
    np.testing.assert_allclose(mid_mast.get_ydata(), [0.8 * 0.45 * f for f in FORCES], rtol=1e-9)
    assert len([ax for ax in drawn[1].axes if ax.get_visible() and ax.get_title()]) == len(BETAS)
