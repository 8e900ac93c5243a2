"""``presag_opt.contact_force``: F_m = F_stat + α_ae v², eq. (4) of doi:10.1108/RS-05-2025-0016, and the
km/h constant."""

from __future__ import annotations

import math

import numpy as np
import pytest

from presag_opt.contact_force import mean_force
from presag_opt.units import KMH


def test_the_mean_contact_force():
    """F_m = F_stat + α_ae v²: the case study's 0.00097 N/(km/h)² at 100 km/h adds 9.7 N."""
    assert mean_force(95.0, 100 * KMH, 0.00097 / KMH**2) == pytest.approx(104.7, rel=1e-12)
    assert mean_force(95.0, 0.0, 0.5) == 95.0
    np.testing.assert_allclose(mean_force(np.array([70.0, 120.0]), 50.0, 0.01), [95.0, 145.0], rtol=1e-15)
    assert KMH == pytest.approx(1.0 / 3.6, rel=1e-15) and math.isclose(100 * KMH, 27.7777777777, rel_tol=1e-10)



def test_the_case_study_band_of_mean_forces():
    """The paper's case study (doi:10.1108/RS-05-2025-0016, section 5.2): F_stat 70–140 N up to 90 km/h with
    α_ae = 0.00097 N/(km/h)²: F_m from 70 N to 140 + 0.00097·90² = 147.857 N (published rounded: 148 N)."""
    assert mean_force(140.0, 90 * KMH, 0.00097 / KMH**2) == pytest.approx(147.857, rel=1e-12)
    assert round(mean_force(140.0, 90 * KMH, 0.00097 / KMH**2)) == 148
    assert mean_force(70.0, 0.0, 0.00097 / KMH**2) == 70.0
