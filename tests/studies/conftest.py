"""Shared pieces of the study tests: the small study file, and synthetic datasets with known answers."""

from __future__ import annotations

from pathlib import Path

import pytest

from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.studies.definition import StudyDefinition, StudyGrid
from presag_opt.studies.store import assemble
from presag_opt.studies.work import UnitResult, all_units
from presag_opt.system.loader import load_catenary

MODELS = Path(__file__).parent / "models"
SMALL_STUDY = MODELS / "small_grid.toml"


@pytest.fixture(scope="session")
def small_study_path() -> Path:
    """The 2 x 2 x 2 test study file (5-span catenary, coarse numerics)."""
    return SMALL_STUDY


def synthetic_dataset(*, sigma, presags_mm, betas, static_forces, rule_mm, uplift=0.05, uplift_limit=0.0835):
    """A study dataset assembled from made-up unit results (the real assembly path, no simulation).

    Parameters
    ----------
    sigma : callable
        sigma(S [m], beta [-], F_stat [N], F_m [N]) -> σ [N].
    presags_mm : sequence of float
        Pre-sag grid. [mm]
    betas : sequence of float
        Speed ratios; the speeds are beta · c_CW of ST 9,8/9,8. [-]
    static_forces : sequence of float
        [N]
    rule_mm : callable
        rule(F_m [N]) -> Δe-rule pre-sag [mm], the same on every geometry (so the self-consistent
        value is exactly this).
    uplift : float or callable
        Steady-arm uplift [m], or uplift(S, beta, F_stat) -> [m].
    uplift_limit : float
        [m]
    """
    catenary = load_catenary("st_9.8_ideal")
    wave_speed = catenary.contact_wire.wave_speed
    grid = StudyGrid(presags=tuple(s * 1e-3 for s in presags_mm), speeds=tuple(b * wave_speed for b in betas),
                     static_forces=tuple(static_forces), aero_coefficient=0.0)
    definition = StudyDefinition(name="synthetic", catenary=catenary,
                                 pantograph=load_pantograph("case_study_2mass_friction"), grid=grid,
                                 uplift_limit=uplift_limit)
    results = []
    for unit in all_units(definition):
        s = grid.presags[unit.presag_index]
        beta = betas[unit.speed_index]
        f_m = list(grid.static_forces)  # aero 0: F_m = F_stat
        sig = [sigma(s, beta, f, f) for f in f_m]
        up = [uplift(s, beta, f) if callable(uplift) else uplift for f in f_m]
        rule = [rule_mm(f) * 1e-3 for f in f_m]
        results.append(UnitResult(
            unit=unit, mean_force=tuple(f_m), std_force=tuple(sig),
            statistical_max=tuple(f + 3 * x for f, x in zip(f_m, sig)),
            statistical_min=tuple(f - 3 * x for f, x in zip(f_m, sig)),
            max_force=tuple(f_m), min_force=tuple(f_m), loss_of_contact=(0.0,) * len(f_m),
            uplift_max=tuple(up), speed_ratio=beta, failure=("",) * len(f_m),
            presag_delta_e=tuple(rule), presag_mid_mast=tuple(0.8 * r for r in rule), rule_failure="",
        ))
    return assemble(definition, results)


@pytest.fixture(scope="session")
def make_dataset():
    """The :func:`synthetic_dataset` builder."""
    return synthetic_dataset
