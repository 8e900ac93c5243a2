"""robust/installation.py: the error sizes (validated, with units) and the seeded, common-random-number draws."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.robust.installation import InstallationErrors, draw_installation_errors


def test_error_sizes_are_validated_with_unit_and_range():
    with pytest.raises(ModelError, match=r"dropper_length = -1 mm is outside the valid range \[0, 100\] mm"):
        InstallationErrors(dropper_length=-1e-3)
    with pytest.raises(ModelError, match="distribution = 'triangular' is not one of normal, uniform"):
        InstallationErrors(distribution="triangular")
    with pytest.raises(ModelError, match=r"samples = 0 is outside the valid range"):
        draw_installation_errors(0, 3, 2)
    # a uniform ±t has the standard deviation t/√3
    assert InstallationErrors(dropper_length=3e-3, distribution="uniform").standard_deviations[0] == pytest.approx(
        3e-3 / np.sqrt(3), rel=1e-12)


def test_draws_are_reproducible_and_common_across_sizes(counts):
    a = draw_installation_errors(50, *counts, seed=7)
    b = draw_installation_errors(50, *counts, seed=7)
    c = draw_installation_errors(50, *counts, seed=8)
    assert np.array_equal(a.dropper, b.dropper) and np.array_equal(a.messenger, b.messenger)
    assert not np.array_equal(a.dropper, c.dropper)
    five, ten = a.scaled(InstallationErrors(dropper_length=5e-3)), a.scaled(InstallationErrors(dropper_length=10e-3))
    assert np.array_equal(2.0 * five.dropper, ten.dropper)  # exact: a power-of-two scale
    uniform = draw_installation_errors(2000, *counts, distribution="uniform", seed=1)
    assert np.abs(uniform.dropper).max() <= 1.0
    # σ of a unit uniform on [−1, 1] is 1/√3; 140 000 draws estimate it to about 0.2 % (1σ)
    assert uniform.dropper.std() == pytest.approx(1 / np.sqrt(3), rel=0.01)
