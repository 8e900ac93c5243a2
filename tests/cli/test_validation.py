"""``presag en50318``: the reference case judged against the published ranges from the command line."""

from __future__ import annotations

import json

import pytest

from presag_opt.validation import EN50318_RANGES


@pytest.mark.slow  # the reference case simulated at 250 km/h on its ten spans
def test_en50318_json_gives_a_verdict_per_published_statistic(presag):
    """At 250 km/h on the default discretisation F_m, the extremes, the uplift and the loss of contact
    are inside their ranges (σ, 26.2 N against 26–31 N, is the tight one; see the dynamics tests)."""
    result = presag("en50318", "--speed", "250", "--json")
    assert result.returncode == 0, result.stderr
    (run,) = json.loads(result.stdout)["runs"]
    verdicts = {v["statistic"]: v for v in run["verdicts"]}
    assert list(verdicts) == list(EN50318_RANGES[250])
    for key in ("Fm_N", "uplift_max_mm", "stat_max_N", "stat_min_N", "max_N", "min_N", "loss_of_contact_pct"):
        assert verdicts[key]["inside"], verdicts[key]


def test_en50318_refuses_a_speed_without_published_ranges_before_simulating(presag):
    result = presag("en50318", "--speed", "250,200")
    assert result.returncode == 2
    assert "speed = 200 km/h has no EN 50318 reference ranges; give one of 250, 300 km/h" in result.stderr
    assert "simulating" not in result.stderr
