"""The one validity statement (presag_opt.design.validity_limit): the limit in force, its source, its speed
on the contact wire, and a verdict that does not turn on round-off."""

from __future__ import annotations

import pytest

from presag_opt.design.validity_limit import (
    PAPER,
    SweepLimit,
    limit_in_force,
    validity_statement,
)
from presag_opt.errors import ModelError
from presag_opt.system.loader import load_catenary
from presag_opt.units import KMH

C = 100.0  # a contact wire of 100 m/s (360 km/h): β = v/100


def study(beta_star, resolution=0.03, kind="study", grid=(0.2, 0.3, 0.4, 0.5, 0.6), holds=None):
    holds = holds if holds is not None else tuple(beta_star is None or b < beta_star for b in grid)
    return SweepLimit(kind=kind, name="the test sweep", beta_star=beta_star, resolution=resolution,
                      grid_betas=grid, holds_at=holds)


def test_the_case_study_against_the_paper_s_limit():
    wire = load_catenary("st_9.8_ideal").contact_wire
    s = validity_statement(wire.wave_speed, 90 * KMH)
    assert s.verdict == "holds" and s.trusted
    assert s.beta_max == pytest.approx(0.2612, abs=5e-4)  # the paper's β = 0.26 at 90 km/h
    lo, hi = (v / KMH for v in s.limit_speeds)
    assert (lo, hi) == pytest.approx((0.35 * wire.wave_speed / KMH, 0.40 * wire.wave_speed / KMH), rel=1e-12)
    assert "121–138 km/h" in s.sentence() and "holds over the band" in s.sentence()


@pytest.mark.parametrize(("beta", "verdict"), [(0.30, "holds"), (0.35, "holds"), (0.351, "at the limit"),
                                                (0.40, "at the limit"), (0.401, "beyond")])
def test_paper_verdicts(beta, verdict):
    s = validity_statement(C, beta * C)
    assert s.verdict == verdict
    assert s.limit is PAPER and not s.limit.from_sweep
    if verdict == "at the limit":
        assert "where the paper's σ/F_m minimum already weakens" in s.sentence()


@pytest.mark.parametrize(("beta", "verdict"), [(0.45, "holds"), (0.46, "holds"), (0.47, "at the limit"),
                                                (0.51, "at the limit"), (0.53, "beyond")])
def test_a_stored_study_is_in_force_with_its_resolution(beta, verdict):
    """β* = 0.49 ± 0.03 (the paper's grid on our model): a band within the resolution is at the limit,
    whichever side of β* it lies."""
    s = validity_statement(C, beta * C, study(0.49))
    assert s.verdict == verdict
    assert s.limit.from_sweep and (s.limit.low, s.limit.high) == pytest.approx((0.46, 0.52), abs=1e-12)
    if verdict == "at the limit":
        assert "within the sweep's resolution" in s.sentence()


def test_a_reduced_sweep_lowers_the_limit_but_never_raises_it():
    up = validity_statement(C, 0.3 * C, study(0.55, 0.06, kind="reduced"))
    assert up.limit is PAPER and "does not raise the paper's limit" in up.note
    assert up.sentence() == validity_statement(C, 0.3 * C).sentence()  # the same statement as without the sweep
    down = validity_statement(C, 0.3 * C, study(0.25, 0.05, kind="reduced"))
    assert down.limit.from_sweep and down.verdict == "at the limit"


def test_a_sweep_without_a_speed_below_the_band_is_indicative():
    """The 1e-6 of the report's quick sweep: its lowest β equals the band's top up to round-off."""
    sweep = study(None, 0.0, kind="reduced", grid=(0.261226479, 0.6), holds=(False, False))
    for beta in (0.261225479, 0.261226479, 0.261227479):
        limit, note = limit_in_force(sweep, beta)
        assert limit is PAPER and "indicative" in note


def test_a_study_that_never_fails_trusts_up_to_its_top_and_the_paper_beyond():
    s = validity_statement(C, 0.35 * C, study(None, 0.0, grid=(0.1, 0.2, 0.3), holds=(True, True, True)))
    assert (s.limit.low, s.limit.high) == (0.3, 0.4) and s.verdict == "at the limit"


def test_a_study_that_fails_everywhere_puts_the_limit_below_its_grid():
    s = validity_statement(C, 0.25 * C, study(None, 0.0, grid=(0.2, 0.3), holds=(False, False)))
    assert (s.limit.low, s.limit.high) == (0.0, 0.2) and s.verdict == "beyond"
    assert "below its lowest speed" in s.limit.source


def test_bad_input_is_one_line_with_its_unit_and_range():
    with pytest.raises(ModelError, match=r"wave_speed = -1 m/s is outside the valid range \(0, ∞\) m/s"):
        validity_statement(-1.0, 10.0)
    with pytest.raises(ModelError, match=r"speed_high = 360 km/h is outside the valid range \[0, 360\) km/h"):
        validity_statement(C, C)
    with pytest.raises(ModelError, match="one verdict per grid β"):
        SweepLimit(kind="study", name="x", beta_star=None, resolution=0.0, grid_betas=(0.2,), holds_at=())
    with pytest.raises(ModelError, match="sweep kind 'full'"):
        SweepLimit(kind="full", name="x", beta_star=None, resolution=0.0, grid_betas=(0.2,), holds_at=(True,))
