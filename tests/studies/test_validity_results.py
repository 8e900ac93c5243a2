"""``presag_opt.studies.validity_results``: the named results of the validity analysis — whether the Δe
rule lies in a near-optimal band (an open end extends it), the uplift verdict, and the JSON summary in
mm and km/h."""

from __future__ import annotations

import dataclasses
import math

import pytest

from presag_opt.studies.validity_results import (
    BetaVerdict,
    ForceOptimum,
    Minimum,
    PowerFit,
    PresagBand,
    UpliftCheck,
    ValidityResult,
)
from presag_opt.units import KMH

BAND = PresagBand(static_force=120.0, mean_force=120.0, optimal=0.060, band_low=0.050, band_high=0.070, open_low=False,
                  open_high=False, benefit=True, presag_delta_e=0.065, presag_mid_mast=0.052)


@pytest.mark.parametrize(("changes", "inside"), [
    ({}, True), ({"presag_delta_e": 0.050}, True), ({"presag_delta_e": 0.070}, True),  # the ends belong to the band
    ({"presag_delta_e": 0.0701}, False), ({"presag_delta_e": 0.049}, False),
    ({"presag_delta_e": 0.090, "open_high": True}, True),  # the band reaches the top of the grid: it may go on
    ({"presag_delta_e": 0.010, "open_low": True}, True),
    ({"presag_delta_e": math.nan}, False), ({"presag_delta_e": math.nan, "open_low": True, "open_high": True}, False),
])
def test_the_rule_is_inside_a_closed_band_between_its_ends_and_beyond_an_open_end(changes, inside):
    assert dataclasses.replace(BAND, **changes).rule_inside is inside


def test_an_uplift_equal_to_the_limit_is_within_it():
    check = UpliftCheck(maximum=0.0835, limit=0.0835, presag=0.06, speed=50.0, static_force=120.0)
    assert check.within_limit and not dataclasses.replace(check, maximum=0.0836).within_limit


def test_the_summary_gives_presag_in_mm_and_speeds_in_km_h():
    verdict = BetaVerdict(speed=90 * KMH, beta=0.26, bands=(BAND,), holds=True)
    optimum = ForceOptimum(presag=0.060, speed=90 * KMH, beta=0.26, ratio=Minimum(location=110.0, value=0.2, distinct=True),
                           sigma=Minimum(location=None, value=20.0, distinct=False))
    result = ValidityResult(beta_limit=0.425, beta_limit_uncertainty=0.025, criterion="c",
                            fit=PowerFit(k=0.05, a=2.0, points=9, r2=0.99), per_beta=(verdict,),
                            force_optima=(optimum,),
                            uplift=UpliftCheck(maximum=0.05, limit=0.0835, presag=0.06, speed=90 * KMH,
                                               static_force=120.0), settings={"margin": 0.05})
    out = result.to_dict()
    band = out["per_beta"][0]["bands"][0]
    assert band["presag_delta_e_mm"] == pytest.approx(65.0, rel=1e-12)
    assert band["band_mm"] == pytest.approx([50.0, 70.0], rel=1e-12) and band["rule_inside"] is True
    assert out["per_beta"][0]["speed_kmh"] == pytest.approx(90.0, rel=1e-12)
    assert out["fit"]["k_mm"] == pytest.approx(50.0, rel=1e-12) and out["fit"]["a"] == 2.0
    assert out["force_optima"][0]["sigma"] == {"F_m_N": None, "value": 20.0, "distinct": False}
    assert out["uplift"]["max_mm"] == pytest.approx(50.0, rel=1e-12) and out["uplift"]["within_limit"] is True
    assert (out["beta_limit"], out["settings"]) == (0.425, {"margin": 0.05})
    bare = dataclasses.replace(result, fit=None, uplift=None, no_fit_reason="too few optima").to_dict()
    assert (bare["fit"], bare["uplift"], bare["no_fit_reason"]) == (None, None, "too few optima")
