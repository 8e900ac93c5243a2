"""``presag_opt.units``: the conversion factors at the package's edges."""

from __future__ import annotations

import pytest

from presag_opt.units import KMH


def test_km_per_hour_in_metres_per_second():
    assert 3.6 * KMH == pytest.approx(1.0, rel=1e-15)  # 3.6 km/h = 1000 m / 1000 s
    assert 90.0 * KMH == pytest.approx(25.0, rel=1e-15)  # the case study's top speed
