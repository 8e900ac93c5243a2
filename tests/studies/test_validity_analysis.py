"""``presag_opt.studies.validity_analysis`` on synthetic datasets whose answer is known by construction.

σ is built as a parabola in S around a known optimum S_opt = S_rule + k·β^a, so that the near-optimal
band (σ within 5 % of its minimum) has a known half-width w and the Δe rule leaves it where
k·β^a = w. Splines are cubic, so they reproduce the parabolas exactly; the remaining error is the
dense evaluation grid (100 mm / 2000 = 0.05 mm), far below every tolerance used here.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.studies.store import write_store
from presag_opt.studies.validity_analysis import NEAR_OPTIMAL_MARGIN, validity_analysis

BETAS = [0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6]
PRESAGS_MM = [20, 40, 60, 80, 100, 120]
FORCES = [50, 65, 80, 95, 110, 125, 140, 155]
K, A = 0.05, 2.0  # optimum shift k·β^a [m]


def rule_mm(mean_force):
    """A Δe rule of 0.45 mm/N."""
    return 0.45 * mean_force


def optimum(beta, mean_force):
    return rule_mm(mean_force) * 1e-3 + K * beta**A


def relative_parabola(half_width):
    """σ with a minimum over F_m near 100 N and a relative parabola in S of the given band half-width."""
    curvature = NEAR_OPTIMAL_MARGIN / half_width**2

    def sigma(s, beta, static_force, mean_force):
        return (5.0 + 0.002 * (mean_force - 100.0) ** 2) * (1.0 + curvature * (s - optimum(beta, mean_force)) ** 2)

    return sigma


@pytest.fixture(scope="module")
def parabola(make_dataset):
    return make_dataset(sigma=relative_parabola(0.010), presags_mm=PRESAGS_MM, betas=BETAS,
                             static_forces=FORCES, rule_mm=rule_mm)


def test_limit_and_fit_are_recovered_from_a_known_optimum_line(parabola):
    result = validity_analysis(parabola)
    # The rule leaves the 10 mm band where 0.05 β² > 0.010, β > 0.447: between grid β 0.40 and 0.45.
    assert result.beta_limit == pytest.approx(0.425, abs=1e-9)
    assert result.beta_limit_uncertainty == pytest.approx(0.025, abs=1e-9)
    assert [v.holds for v in result.per_beta] == [b < 0.447 for b in BETAS]
    assert "left the near-optimal band" in result.criterion
    # The optima are read to the dense grid (0.05 mm) out of shifts of 0.5-18 mm: k and a within 1 %.
    assert result.fit.k == pytest.approx(K, rel=0.01)
    assert result.fit.a == pytest.approx(A, rel=0.01)
    assert result.fit.r2 > 0.999
    band = result.per_beta[0].bands[3]
    assert band.optimal == pytest.approx(optimum(0.1, 95.0), abs=0.05e-3)
    assert band.band_high - band.band_low == pytest.approx(0.020, abs=0.1e-3)
    assert band.presag_delta_e == pytest.approx(rule_mm(95.0) * 1e-3, rel=1e-12)
    assert band.presag_mid_mast == pytest.approx(0.8 * rule_mm(95.0) * 1e-3, rel=1e-12)


def test_force_optima_are_distinct_minima_of_sigma_over_fm(parabola):
    result = validity_analysis(parabola)
    assert "distinct minimum in 66 of 66" in result.criterion
    # At S = S_opt(F_m), σ/F_m = (5 + 0.002 (F_m - 100)^2)/F_m, minimal at F_m = sqrt(100^2 + 5/0.002) = 111.8 N;
    # off the optimum line the parabola in S moves it, so only the F_m band [50, 155] N is certain.
    for o in result.force_optima:
        assert o.ratio.distinct and 50.0 < o.ratio.location < 155.0
        assert o.sigma.distinct


def test_a_floor_in_sigma_leaves_no_ratio_minimum_and_the_limit_comes_from_sigma(make_dataset):
    # σ = 4.5 N + 2000 N/m² (S - S_opt)², the same at every F_m: σ/F_m only falls with F_m. Within 5 %
    # for |S - S_opt| < sqrt(0.05 · 4.5 / 2000) = 10.6 mm.
    half_width = math.sqrt(NEAR_OPTIMAL_MARGIN * 4.5 / 2000.0)

    def sigma(s, beta, static_force, mean_force):
        return 4.5 + 2000.0 * (s - 0.060 - K * beta**A) ** 2

    ds = make_dataset(sigma=sigma, presags_mm=PRESAGS_MM, betas=BETAS, static_forces=FORCES,
                      rule_mm=lambda mean_force: 60.0)
    result = validity_analysis(ds)
    assert not any(o.ratio.distinct for o in result.force_optima)
    assert all(o.ratio.location is None for o in result.force_optima)
    assert "no distinct minimum" in result.criterion and "from sigma and the optimal-S band" in result.criterion
    # 0.05 β² = 10.6 mm at β = 0.460: between 0.45 and 0.50.
    assert 0.05 * 0.45**2 < half_width < 0.05 * 0.5**2
    assert result.beta_limit == pytest.approx(0.475, abs=1e-9)
    assert result.beta_limit_uncertainty == pytest.approx(0.025, abs=1e-9)


def test_vanishing_benefit_sets_the_limit(make_dataset):
    def sigma(s, beta, static_force, mean_force):
        flat = beta >= 0.4  # S stops mattering: σ varies by 1 % over the whole S grid
        curvature = 1.0 if flat else NEAR_OPTIMAL_MARGIN / 0.02**2
        return 5.0 * (1.0 + curvature * (s - optimum(0.0, mean_force)) ** 2)

    ds = make_dataset(sigma=sigma, presags_mm=PRESAGS_MM, betas=BETAS, static_forces=FORCES, rule_mm=rule_mm)
    result = validity_analysis(ds)
    assert result.beta_limit == pytest.approx(0.375, abs=1e-9)
    assert "benefit on sigma vanished" in result.criterion
    # The optimum does not move with β: nothing to fit, and said so (not k = 0 with a meaningless a).
    assert result.fit is None and "does not move" in result.no_fit_reason


def test_rule_never_in_band_gives_no_limit_and_no_crash(make_dataset):
    ds = make_dataset(sigma=relative_parabola(0.005), presags_mm=PRESAGS_MM, betas=BETAS,
                           static_forces=FORCES, rule_mm=lambda f: 0.45 * f + 30.0)
    result = validity_analysis(ds)
    assert result.beta_limit is None and result.beta_limit_uncertainty is None
    assert "holds at no beta" in result.criterion


def test_failed_runs_are_skipped_and_uplift_is_checked(parabola):
    ds = parabola.copy(deep=True)
    ds["sigma"][2, 0, 3] = np.nan
    ds["uplift_max"][1, 5, 7] = 0.09
    result = validity_analysis(ds)
    assert math.isfinite(result.beta_limit)
    assert result.uplift.maximum == 0.09 and not result.uplift.within_limit
    assert result.uplift.presag == pytest.approx(0.040) and result.uplift.static_force == 155.0


def test_extra_parameter_needs_a_selection(parabola):
    name = "pantograph.frame.friction"
    ds = parabola.expand_dims({name: [0.0, 10.0]})
    with pytest.raises(ModelError, match="give a value of the swept parameter pantograph.frame.friction"):
        validity_analysis(ds)
    with pytest.raises(ModelError, match="= 3 is not a grid value"):
        validity_analysis(ds, {name: 3.0})
    assert validity_analysis(ds, {name: 10.0}).beta_limit == pytest.approx(0.425, abs=1e-9)


def test_cli_json_and_plots(presag, parabola, tmp_path):
    store = tmp_path / "synthetic.nc"
    write_store(parabola, store)
    proc = presag("validity", str(store), "--json", "--plot", str(tmp_path / "plots"))
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["beta_limit"] == pytest.approx(0.425, abs=1e-9)
    assert set(summary["fit"]) >= {"k", "a", "r2"}
    entry = summary["per_beta"][0]
    assert set(entry) >= {"beta", "holds", "bands"}
    assert set(entry["bands"][0]) >= {"presag_delta_e_mm", "presag_optimal_mm", "band_mm", "F_m_N"}
    assert sorted(p.name for p in (tmp_path / "plots").iterdir()) == [
        "fig6_ratio.png", "fig7_presag.png", "fig8_optimal_force.png", "uplift.png"]


def _shifted(shift):
    """σ as :func:`relative_parabola` (10 mm band) around S_rule + shift(β) [m]."""
    curvature = NEAR_OPTIMAL_MARGIN / 0.010**2

    def sigma(s, beta, static_force, mean_force):
        best = rule_mm(mean_force) * 1e-3 + shift(beta)
        return (5.0 + 0.002 * (mean_force - 100.0) ** 2) * (1.0 + curvature * (s - best) ** 2)

    return sigma


def test_an_exponent_on_its_bound_is_no_fit(make_dataset):
    # The optimum stays on the rule up to β = 0.55 and jumps by 15 mm at 0.6: the steepest power the
    # bounds allow (a = 20) is the least-squares answer, which describes a step, not eq. 7.
    ds = make_dataset(sigma=_shifted(lambda b: 0.015 if b > 0.58 else 0.0), presags_mm=PRESAGS_MM, betas=BETAS,
                      static_forces=FORCES, rule_mm=rule_mm)
    result = validity_analysis(ds)
    assert result.fit is None
    assert "ran to its bound a = 20" in result.no_fit_reason
    summary = result.to_dict()
    assert summary["fit"] is None and summary["no_fit_reason"] == result.no_fit_reason


def test_scattered_optima_below_the_r2_threshold_are_no_fit(make_dataset):
    # Optima alternating 4 mm above and below a 6 mm mean: no power of β explains the spread.
    betas = BETAS
    ds = make_dataset(sigma=_shifted(lambda b: 0.006 + (0.004 if round(b * 20) % 2 else -0.004)),
                      presags_mm=PRESAGS_MM, betas=betas, static_forces=FORCES, rule_mm=rule_mm)
    result = validity_analysis(ds)
    assert result.fit is None
    assert "below 0.8" in result.no_fit_reason or "ran to its bound" in result.no_fit_reason


def test_cli_prints_no_fit_with_its_reason(presag, make_dataset, tmp_path):
    ds = make_dataset(sigma=_shifted(lambda b: 0.015 if b > 0.58 else 0.0), presags_mm=PRESAGS_MM, betas=BETAS,
                      static_forces=FORCES, rule_mm=rule_mm)
    store = tmp_path / "step.nc"
    write_store(ds, store)
    out = presag("validity", str(store))
    assert out.returncode == 0, out.stderr
    line = next(x for x in out.stdout.splitlines() if x.startswith("fit "))
    assert line.startswith("fit S_dyn = S_stat + k*beta^a: no fit (the exponent ran to its bound a = 20")
    assert "k =" not in line
