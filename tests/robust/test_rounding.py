"""Rounding a per-dropper profile to the construction step (presag_opt.robust.rounding): the greedy
descent used when more than 12 depths are free."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import force_levels_for_band, section_elasticity
from presag_opt.robust import Buildability, build_path_model, robust_presag


@pytest.fixture(scope="module")
def two_span_path(st98, band):
    """Spans 5 and 6 of the ideal section: 14 droppers, all free when the profile may be asymmetric."""
    section = section_elasticity(st98, force_levels=force_levels_for_band(*band), spans=(4, 5),
                                 elasticity_method="active-set")
    return build_path_model(st98, section)


def test_greedy_rounding_of_fourteen_free_depths(two_span_path, scenarios):
    build = Buildability(symmetric=False)
    design = robust_presag(two_span_path, scenarios, shape="per-dropper", buildability=build)
    assert design.rounding == "greedy"  # 14 > 12 free depths: no enumeration
    steps = design.depths / build.step
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-9)  # on the 5 mm step (round-off only)
    # Rounding can only lose against the continuous optimum; the greedy descent starts from the
    # nearest rounding and only accepts improvements, so it is never worse than that start.
    assert design.objective >= design.continuous_objective - 1e-12
    nearest = robust_presag(two_span_path, scenarios, shape="per-dropper", buildability=Buildability(symmetric=False, step=0.0))
    start = np.round(nearest.depths / build.step) * build.step
    start_worst = two_span_path.waviness(start, scenarios.forces).max()
    assert design.worst_case_waviness <= start_worst + 1e-12
