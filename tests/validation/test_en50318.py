"""EN 50318 reference ranges and verdicts (presag_opt.validation.en50318)."""

from __future__ import annotations

import pytest

from presag_opt.errors import ModelError
from presag_opt.validation import EN50318_RANGES, en50318_ranges, en50318_verdicts


def test_every_published_statistic_gets_a_verdict_in_order():
    stats = {key: 0.5 * (low + high) for key, (low, high) in EN50318_RANGES[250].items()}
    verdicts = en50318_verdicts(250.0, stats)
    assert [v.statistic for v in verdicts] == list(EN50318_RANGES[250])
    assert all(v.inside for v in verdicts)


def test_the_range_is_closed_and_a_value_outside_is_marked():
    stats = {key: low for key, (low, _) in EN50318_RANGES[300].items()}
    stats["sigma_N"] = 31.9  # just below the 300 km/h range of 32–40 N
    verdicts = {v.statistic: v for v in en50318_verdicts(300.0, stats)}
    assert not verdicts["sigma_N"].inside
    assert all(v.inside for key, v in verdicts.items() if key != "sigma_N")  # the ends belong to the range


def test_the_speed_of_a_run_in_km_h_from_m_s_is_accepted():
    stats = {key: low for key, (low, _) in EN50318_RANGES[250].items()}
    assert len(en50318_verdicts(250 / 3.6 * 3.6, stats)) == len(EN50318_RANGES[250])


@pytest.mark.parametrize("speed", [200.0, 250.5])
def test_a_speed_without_published_ranges_is_an_error(speed):
    with pytest.raises(ModelError, match=r"no EN 50318 reference ranges; give one of 250, 300 km/h"):
        en50318_verdicts(speed, {})


def test_the_ranges_of_a_speed_are_the_published_ones():
    assert en50318_ranges(300.0) is EN50318_RANGES[300]
