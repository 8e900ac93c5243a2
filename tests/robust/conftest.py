"""The case-study band and the path model of ST 9,8/9,8, shared by the robust-design tests."""

from __future__ import annotations

import pytest

from presag_opt.design import CASE_STUDY_BAND, force_levels_for_band, section_elasticity
from presag_opt.robust import ForceScenarios, build_path_model


@pytest.fixture(scope="package")
def band():
    return CASE_STUDY_BAND.mean_force_band()


@pytest.fixture(scope="package")
def path(st98, band):
    section = section_elasticity(st98, force_levels=force_levels_for_band(*band), elasticity_method="active-set")
    return build_path_model(st98, section)


@pytest.fixture(scope="package")
def scenarios(band):
    return ForceScenarios.band(*band)


@pytest.fixture(scope="package")
def design(path, scenarios):
    """The quasi-static robust design of the case-study band (the installation-error tests' design)."""
    from presag_opt.robust import robust_presag

    return robust_presag(path, scenarios)


@pytest.fixture(scope="package")
def monte_carlo(path, design, scenarios):
    """The quasi-static Monte Carlo of that design."""
    from presag_opt.robust.monte_carlo import QuasiStaticMonteCarlo

    return QuasiStaticMonteCarlo(path, design.depths, scenarios)


@pytest.fixture(scope="package")
def counts(path):
    """Droppers and masts of the path model's line. [-]"""
    disc = path.state.discretisation
    return len(disc.dropper_elements), len(disc.mast_station)
