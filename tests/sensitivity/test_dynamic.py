"""Dynamic outputs through the studies machinery: resumable, independent of the worker count."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from presag_opt.sensitivity.analysis import sensitivity_analysis
from presag_opt.sensitivity.dynamic import _moves, _rise
from presag_opt.studies.validity_results import ForceOptimum, Minimum

TINY = Path(__file__).parents[1] / "cli" / "models" / "tiny_case.toml"


def test_dynamic_output_resumes_from_its_store_and_does_not_depend_on_workers(tmp_path):
    # r = 2 trajectories over 2 inputs: 6 samples of one 60 km/h run each on four 30 m spans
    kwargs = {"output": "dynamic:60", "inputs": ["pantograph.head.mass", "pantograph.frame.friction"], "samples": 2,
                  "seed": 1}
    first = sensitivity_analysis(TINY, workers=1, out=tmp_path / "store", **kwargs)
    assert first.values.shape == (6, 2)
    assert np.all(first.values[:, 0] > 0.0) and np.all(first.values[:, 1] < 1.0)  # σ > 0 N, σ/F_m < 1
    assert len(list((tmp_path / "store").glob("sample_*.nc.units"))) == 6
    resumed = sensitivity_analysis(TINY, workers=2, out=tmp_path / "store", **kwargs)
    assert np.array_equal(resumed.values, first.values)
    fresh = sensitivity_analysis(TINY, workers=2, **kwargs)  # computed again, by two workers
    assert np.array_equal(fresh.values, first.values)
    assert fresh.indices == first.indices


def test_rise_of_a_curve_to_its_lower_end():
    assert _rise(np.array([2.0, 1.0, 1.5])) == pytest.approx(0.5, rel=1e-15)
    assert _rise(np.array([1.0, 2.0, 3.0])) == 0.0  # minimum at an end
    assert _rise(np.array([2.0, 1.0, np.nan])) == 0.0  # a failed run: no reading


def optimum(presag, location):
    m = Minimum(location=location, value=1.0, distinct=location is not None)
    return ForceOptimum(presag=presag, speed=14.0, beta=0.15, ratio=m, sigma=m)


class Result:
    def __init__(self, optima):
        self.force_optima = optima


def test_minima_move_only_if_distinct_at_two_presags_and_rising_by_more_than_the_threshold():
    assert _moves(Result([optimum(0.03, 90.0), optimum(0.05, 100.0)]), "ratio") == 1.0
    assert _moves(Result([optimum(0.03, 90.0), optimum(0.05, 93.0)]), "ratio") == 0.0  # 3 N < 5 N
    assert _moves(Result([optimum(0.03, 90.0), optimum(0.05, None)]), "ratio") == 0.0  # one distinct only
    assert _moves(Result([optimum(0.03, 110.0), optimum(0.07, 90.0)]), "sigma") == 0.0  # falls with S
