"""robust/scenarios.py: the mean-force scenarios of a band and the risk measures over them,
against values computed by hand."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.errors import ModelError
from presag_opt.robust.scenarios import ForceScenarios, Risk


def test_a_band_is_evenly_spaced_and_equally_likely():
    s = ForceScenarios.band(70.0, 150.0, count=5)
    assert s.forces.tolist() == [70.0, 90.0, 110.0, 130.0, 150.0]
    assert np.all(s.weights == 0.2)
    with pytest.raises(ModelError, match=r"F_m band = \[150, 70\] N is empty, inverted or too high"):
        ForceScenarios.band(150.0, 70.0)
    with pytest.raises(ModelError, match=r"count = 1 is outside the valid range \[2, 200\]"):
        ForceScenarios.band(70.0, 150.0, count=1)


def test_scenarios_are_validated():
    with pytest.raises(ModelError, match="give one weight per force"):
        ForceScenarios(forces=np.array([80.0, 90.0]), weights=np.array([1.0]))
    with pytest.raises(ModelError, match="must be positive"):
        ForceScenarios(forces=np.array([-1.0, 90.0]), weights=np.array([0.5, 0.5]))
    with pytest.raises(ModelError, match="sum to 1"):
        ForceScenarios(forces=np.array([80.0, 90.0]), weights=np.array([0.5, 0.6]))


def test_an_operating_band_without_aerodynamics_merges_the_speeds():
    band = OperatingBand(static_force_low=60.0, static_force_high=100.0, speed_low=50 * KMH, speed_high=90 * KMH,
                         aero_coefficient=0.0)
    s = ForceScenarios.from_operating_band(band, static_points=4, speed_points=3)
    # midpoints of four equal cells of 60-100 N, each the weight of its three speeds
    assert s.forces == pytest.approx([65.0, 75.0, 85.0, 95.0], abs=1e-12)
    assert s.weights == pytest.approx([0.25] * 4, abs=1e-15)


def test_an_operating_band_with_aerodynamics_has_the_mean_of_f_stat_plus_alpha_v_squared():
    alpha = 0.00097 / KMH**2
    band = OperatingBand(static_force_low=70.0, static_force_high=140.0, speed_low=50 * KMH, speed_high=90 * KMH,
                         aero_coefficient=alpha)
    s = ForceScenarios.from_operating_band(band, static_points=8, speed_points=8)
    f_mid = 70.0 + (np.arange(8) + 0.5) / 8 * 70.0
    v_mid = 50 * KMH + (np.arange(8) + 0.5) / 8 * 40 * KMH
    expected = f_mid.mean() + alpha * np.mean(v_mid**2)
    # forces rounded to 0.01 N when merged: the mean moves by at most 0.005 N
    assert s.weights @ s.forces == pytest.approx(expected, abs=0.005)
    assert s.weights.sum() == pytest.approx(1.0, abs=1e-12) and len(s.forces) == 64


def test_risk_measures_of_four_equally_likely_losses():
    losses, weights = np.array([1.0, 4.0, 2.0, 3.0]), np.full(4, 0.25)
    assert Risk().value(losses, weights) == 4.0
    assert Risk(measure="mean").value(losses, weights) == 2.5
    # CVaR_α = mean of the worst (1 − α) share: α = 0.5 -> (3 + 4)/2, α = 0.75 -> 4, α = 0 -> the mean
    assert Risk(measure="cvar", level=0.5).value(losses, weights) == pytest.approx(3.5, abs=1e-12)
    assert Risk(measure="cvar", level=0.75).value(losses, weights) == pytest.approx(4.0, abs=1e-12)
    assert Risk(measure="cvar", level=0.0).value(losses, weights) == pytest.approx(2.5, abs=1e-12)
    # α = 0.6: the worst 40 % = all of 4 (25 %) and 15/25 of 3 -> (0.25·4 + 0.15·3)/0.4
    assert Risk(measure="cvar", level=0.6).value(losses, weights) == pytest.approx(3.625, abs=1e-12)


def test_risk_parsing_and_labels():
    assert Risk.parse("cvar:0.8") == Risk(measure="cvar", level=0.8)
    assert Risk.parse("cvar").level == 0.9 and Risk.parse("mean").label == "mean"
    assert Risk.parse("cvar:0.8").label == "cvar:0.80"
    with pytest.raises(ModelError, match="write cvar:LEVEL with LEVEL in"):
        Risk.parse("cvar:high")
    with pytest.raises(ModelError, match=r"risk level = 1 is outside the valid range \[0, 1\)"):
        Risk(measure="cvar", level=1.0)
    with pytest.raises(ModelError, match="risk = 'max' is not one of minimax, mean, cvar:LEVEL"):
        Risk.parse("max")
