"""The evidence records (presag_opt.design.evidence): their checks, the uplift each knows at a pre-sag (on
the safe side of a bracket), what is missing, and the crew tolerance's kinds."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design.evidence import (
    CREW_TOLERANCE,
    DeltaERule,
    DynamicRobust,
    DynamicUpliftCheck,
    Evidence,
    InstallationTolerance,
    QuasiStaticRobust,
    ValiditySweep,
    crew_tolerance,
)
from presag_opt.design.validity_limit import SweepLimit
from presag_opt.errors import ModelError

LIMIT = SweepLimit(kind="study", name="s", beta_star=0.49, resolution=0.03, grid_betas=(0.3, 0.5, 0.6),
                   holds_at=(True, False, False))


def sweep(uplift) -> ValiditySweep:
    return ValiditySweep(limit=LIMIT, presag_rel=(0.5e-3, 1.0e-3, 1.5e-3), static_forces=(70.0, 105.0, 140.0),
                         uplift=np.asarray(uplift, dtype=float))


def test_the_sweep_s_uplift_is_read_on_the_safe_side_of_a_bracket():
    s = sweep([[0.050, 0.060, 0.070], [0.055, 0.065, 0.090], [0.052, 0.062, 0.072]])
    assert s.uplift_at(1.0e-3) == 0.090  # a swept S: its largest over the static forces
    assert s.uplift_at(1.2e-3) == 0.090  # between 1.0 and 1.5 ‰: the larger of the two
    assert s.uplift_at(0.4e-3) is None and s.uplift_at(1.6e-3) is None  # outside the swept range
    assert s.highest_static_force(0.0835) == 140.0  # the 0.5 and 1.5 ‰ rows keep it at every force
    assert s.some_presag_keeps_uplift(0.0835) is True
    assert s.highest_static_force(0.061) == 105.0  # up to 105 N the 0.5 ‰ row keeps 61 mm
    assert s.highest_static_force(0.040) is None and s.some_presag_keeps_uplift(0.040) is False


def test_a_sweep_without_finished_runs_knows_no_uplift():
    s = sweep(np.full((3, 3), np.nan))
    assert not s.has_uplift and s.uplift_at(1e-3) is None
    assert s.highest_static_force(0.0835) is None and s.some_presag_keeps_uplift(0.0835) is None
    partly = sweep([[np.nan, 0.06, np.nan], [np.nan, np.nan, np.nan], [0.05, 0.07, 0.08]])
    assert partly.uplift_at(1.0e-3) == 0.08  # the empty row's finished neighbours, the larger


def test_records_refuse_what_is_not_a_pre_sag_or_an_interval():
    with pytest.raises(ModelError, match=r"presag_rel = 7 ‰ is outside the model's valid range 0–5 ‰"):
        DeltaERule(presag_rel=7e-3, presag_rel_range=(0.0, 1e-3), static_uplift=0.05, support_elasticity=3e-4)
    with pytest.raises(ModelError, match="not an interval"):
        QuasiStaticRobust(presag_rel=1e-3, tolerance=(1.2e-3, 0.9e-3), within=0.1)
    with pytest.raises(ModelError, match="uplift has shape"):
        ValiditySweep(limit=LIMIT, presag_rel=(1e-3,), static_forces=(70.0, 140.0), uplift=np.zeros((2, 2)))
    with pytest.raises(ModelError, match="increasing order"):
        ValiditySweep(limit=LIMIT, presag_rel=(1e-3, 0.5e-3), static_forces=(70.0,), uplift=np.zeros((2, 1)))
    with pytest.raises(ModelError, match=r"crew tolerance = 60 mm is outside the valid range \[0, 50\] mm"):
        crew_tolerance(0.06)
    with pytest.raises(ModelError, match="kind 'guess'"):
        InstallationTolerance(half_width=0.002, kind="guess", source="x")
    with pytest.raises(ModelError, match="at least one simulated pre-sag"):
        DynamicUpliftCheck(simulated=(), where="x")


def test_crew_tolerance_is_the_assumed_default_or_a_crew_s_figure():
    assumed = crew_tolerance()
    assert (assumed.half_width, assumed.kind) == (CREW_TOLERANCE, "assumed") and "assumed" in assumed.source
    given = crew_tolerance(0.004)
    assert (given.half_width, given.kind) == (0.004, "setting")
    assert given.describe().startswith("±4.0 mm")


def base(**records) -> Evidence:
    return Evidence(wave_speed=96.0, speed_high=25.0, uplift_limit=0.0835, reference_span=60.0,
                    static_force_floor=70.0,
                    delta_e=DeltaERule(presag_rel=1e-3, presag_rel_range=(0.7e-3, 1.3e-3), static_uplift=0.054,
                                       support_elasticity=3.6e-4), **records)


def test_the_best_known_uplift_is_simulated_before_swept_before_static():
    dyn = DynamicRobust(presag_rel=0.8e-3, tolerance=(0.5e-3, 0.95e-3), within=0.1, uplift=0.06,
                        simulated=((0.5e-3, 0.058), (0.8e-3, 0.060), (0.95e-3, 0.061)), where="g")
    check = DynamicUpliftCheck(simulated=((0.9e-3, 0.070), (1.1e-3, 0.072)), where="c")
    s = sweep(np.full((3, 3), 0.080))
    e = base(dynamic_robust=dyn, dynamic_check=check, validity_sweep=s)
    assert e.uplift_at(0.9e-3) == (0.061, "dynamic")  # the dynamic design's bracket 0.8–0.95 ‰
    assert e.uplift_at(1.0e-3) == (0.072, "dynamic")  # the check's bracket
    assert e.uplift_at(1.3e-3) == (0.080, "dynamic")  # the sweep
    assert base().uplift_at(1.3e-3) == (0.054, "static estimate")


def test_missing_records_by_scope():
    assert base().missing() == ("quasi_static_robust", "validity_sweep", "dynamic_robust", "installation_monte_carlo")
    line = Evidence(**{**base().__dict__, "scope": "line"})
    assert "dynamic_check" in line.missing()
    with pytest.raises(ModelError, match="scope 'section'"):
        Evidence(**{**base().__dict__, "scope": "section"})
    with pytest.raises(ModelError, match="at least one answer"):
        Evidence(**{**base().__dict__, "delta_e": None})
    with pytest.raises(ModelError, match=r"reference_span = 200 m is outside the valid range \[5, 120\] m"):
        Evidence(**{**base().__dict__, "reference_span": 200.0})
