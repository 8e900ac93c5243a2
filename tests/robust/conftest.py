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
