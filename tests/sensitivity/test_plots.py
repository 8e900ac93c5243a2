"""The Morris and Sobol figures: what they draw and where they are written."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from presag_opt.sensitivity import plots  # noqa: E402
from presag_opt.sensitivity.methods import MorrisEffect, OutputIndices, SobolIndex  # noqa: E402


def morris_table(count: int) -> OutputIndices:
    effects = tuple(MorrisEffect(name=f"catenary.input_{i}", mu_star=float(count - i), mu_star_conf=0.1,
                                 sigma=0.5 * (count - i), relative=(count - i) / count) for i in range(count))
    return OutputIndices(output="presag_rel", unit="‰", method="morris", morris=effects, mean=1.0, std=0.1)


def sobol_table() -> OutputIndices:
    rows = (SobolIndex(name="pantograph.frame.friction", first=0.7, first_conf=0.1, total=0.9, total_conf=0.1),
            SobolIndex(name="catenary.damping.ratio", first=0.05, first_conf=0.02, total=0.1, total_conf=0.03))
    return OutputIndices(output="sigma_over_F_m@50kmh", unit="-", method="sobol", sobol=rows)


@pytest.fixture
def captured(monkeypatch):
    """The figure each plot function saves (kept open for inspection instead of being written)."""
    figures = []

    def keep(fig, path):
        figures.append(fig)
        return path

    monkeypatch.setattr(plots, "save_figure", keep)
    yield figures
    for fig in figures:
        plt.close(fig)


def test_morris_plane_labels_the_largest_effects_only(captured, tmp_path):
    plots.plot_morris(morris_table(12), tmp_path / "m.png")
    ax = captured[0].axes[0]
    labels = [t.get_text() for t in ax.texts]
    assert len(labels) == plots.LABELLED and labels[0] == "input_0"  # the root name is dropped
    assert "input_11" not in labels  # the smallest μ* is not labelled
    assert ax.get_xlabel() == "μ* [‰]" and ax.get_ylabel() == "σ [‰]"
    assert ax.get_xlim()[1] == pytest.approx(12 * 1.1)  # the largest of μ* and σ, with a margin


def test_sobol_bars_in_ranked_order(captured, tmp_path):
    plots.plot_sobol(sobol_table(), tmp_path / "s.png")
    ax = captured[0].axes[0]
    ticks = {round(float(y)): t.get_text() for y, t in zip(ax.get_yticks(), ax.get_yticklabels())}
    assert ticks == {1: "frame.friction", 0: "damping.ratio"}  # the largest ST on top
    widths = sorted(round(p.get_width(), 6) for p in ax.patches)
    assert widths == [0.05, 0.1, 0.7, 0.9]


def test_one_file_per_value_named_after_output_value_and_method(tmp_path):
    result = SimpleNamespace(method="morris", output="dynamic:50,90", indices=(morris_table(3),))
    (path,) = plots.save_sensitivity_plots(result, tmp_path)
    assert path.name == "sensitivity_dynamic_50_90_presag_rel_morris.png" and path.exists()
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
