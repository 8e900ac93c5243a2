"""``presag_opt.plotting``: each figure draws the numbers of its result in the units its axes name
(mm/N, mm, %, km/h), leaves failed runs out, and labels its lines. The figure is taken from the
saving step, so the drawn data are compared with the inputs (to 1e-12: a unit conversion only)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from presag_opt import plotting
from presag_opt.elasticity.curves import ElasticityCurve, ElasticityStudy
from presag_opt.units import KMH


@pytest.fixture
def drawn(monkeypatch, tmp_path):
    """The figures the plotting functions hand to save_figure, still open."""
    figures = []
    monkeypatch.setattr(plotting, "save_figure", lambda fig, path: figures.append(fig) or tmp_path / str(path))
    return figures


def test_elasticity_is_drawn_in_mm_per_n_with_the_linear_curve_dashed(drawn):
    x = np.linspace(0.0, 60.0, 7)
    study = ElasticityStudy(catenary_name="ST 9,8/9,8", span=4, curves=(
        ElasticityCurve(span=4, span_length=60.0, force=100.0, position=x, elasticity=0.4e-3 + 1e-5 * x),
        ElasticityCurve(span=4, span_length=60.0, force=None, position=x, elasticity=0.5e-3 + 1e-5 * x)))
    plotting.plot_elasticity(study, "e.png")
    (ax,) = drawn[0].axes
    nonlinear, linear = ax.get_lines()
    np.testing.assert_allclose(nonlinear.get_ydata(), 0.4 + 1e-2 * x, rtol=1e-12)
    np.testing.assert_allclose(linear.get_xdata(), x, rtol=0)
    assert (nonlinear.get_label(), linear.get_label()) == ("F = 100 N", "linear (tangent stiffness)")
    assert linear.get_linestyle() == "--"
    assert (ax.get_ylabel(), ax.get_title()) == ("elasticity e [mm/N]", "ST 9,8/9,8: span 5")


def _run(speed_kmh, force, sigma, ok=True):
    stats = SimpleNamespace(sigma_over_mean=sigma / force, std_force=sigma)
    return SimpleNamespace(point=SimpleNamespace(speed=speed_kmh * KMH, static_force=force), ok=ok,
                           statistics=(stats,) if ok else ())


def test_batch_statistics_draw_one_line_per_static_force_by_speed_without_the_failed_runs(drawn):
    batch = SimpleNamespace(catenary_name="c", pantograph_names=("p",), runs=(
        _run(160, 120.0, 30.0), _run(80, 120.0, 12.0), _run(80, 90.0, 9.0), _run(120, 90.0, 0.0, ok=False),
        _run(160, 90.0, 27.0)))
    plotting.plot_batch_statistics(batch, "b.png")
    top, bottom = drawn[0].axes
    low, high = top.get_lines()
    assert (low.get_label(), high.get_label()) == ("90 N", "120 N")
    np.testing.assert_allclose(low.get_xdata(), [80.0, 160.0], rtol=1e-12)  # 120 km/h failed: left out
    np.testing.assert_allclose(low.get_ydata(), [0.1, 0.3], rtol=1e-12)
    np.testing.assert_allclose(bottom.get_lines()[1].get_ydata(), [12.0, 30.0], rtol=1e-12)
    assert bottom.get_xlabel() == "speed [km/h]" and top.get_ylabel() == "σ/F_m [-]"


def test_the_single_curve_error_is_drawn_in_mm_and_percent(drawn):
    forces = np.array([70.0, 120.0, 179.0])
    study = SimpleNamespace(catenary_name="ST", geometry_presag=0.030, reference_force=100.0, mean_forces=forces,
                            presag_interpolated=np.array([0.050, 0.060, 0.070]),
                            presag_single_curve=np.array([0.050, 0.058, 0.060]),
                            relative_error=np.array([0.0, 0.02, 0.16]))
    plotting.plot_single_curve_error([study], "s.png")
    top, bottom = drawn[0].axes
    interpolated, single = top.get_lines()
    np.testing.assert_allclose(interpolated.get_ydata(), [50.0, 60.0, 70.0], rtol=1e-12)
    assert single.get_label() == "30 mm geometry, 100 N curve only"
    np.testing.assert_allclose(bottom.get_lines()[0].get_ydata(), [0.0, 2.0, 16.0], rtol=1e-12)


def test_moving_force_deflections_are_drawn_relative_to_the_static_one(drawn):
    t = np.linspace(0.0, 2.0, 81)
    check = SimpleNamespace(time=t, analytic=0.01 * np.sin(np.pi * t / 2), numerical=0.01 * np.sin(np.pi * t / 2),
                            static_mid=0.01, beta=0.4, element_length=0.5, time_step=2e-3)
    plotting.plot_moving_force([check], "m.png")
    series, points = drawn[0].axes[0].get_lines()
    np.testing.assert_allclose(series.get_xdata(), t / 2.0, rtol=1e-12)  # x/l = t/T for a constant speed
    np.testing.assert_allclose(series.get_ydata(), np.sin(np.pi * t / 2), rtol=1e-12, atol=1e-15)
    assert len(points.get_xdata()) == 41 and points.get_label() == "β = 0.4, Newmark (0.5 m, 2 ms)"
