"""The dynamic robust study as evidence of the decision (presag_opt.robust.dynamic_study): its record, what
it simulated, and the band it simulates (no simulation here: the study's parts are stand-ins)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.band import KMH
from presag_opt.robust.dynamic_design import DynamicTolerance
from presag_opt.robust.dynamic_study import DynamicRobustStudy, simulated_band

SPAN = 60.0


def study() -> DynamicRobustStudy:
    """The case study's numbers (presag robust --dynamic): dynamic robust 45.1 mm, tolerance 28.0–56.1 mm,
    its uplift 52.9 mm; five simulated pre-sags."""
    grid = SimpleNamespace(static_forces=(70.0, 93.3, 116.7, 140.0), speeds=(50 * KMH, 70 * KMH, 90 * KMH))
    simulated = tuple(SimpleNamespace(presag_rel=mm * 1e-3 / SPAN, uplift_max=np.array([0.05, up * 1e-3]))
                      for mm, up in ((28.0, 51.0), (45.1, 52.9), (55.8, 53.4), (56.1, 53.5), (61.0, 54.0)))
    return DynamicRobustStudy(
        catenary_name="ST 9,8/9,8, ideal 60 m spans", pantograph_name="case study", band=CASE_STUDY_BAND,
        beta=(0.145, 0.261), design=SimpleNamespace(presag_rel=45.1e-3 / SPAN, uplift_max=0.0529, grid=grid),
        tolerance=DynamicTolerance(low=28.0e-3 / SPAN, high=56.1e-3 / SPAN, within=0.10, worst_case_min=0.0925,
                                   runs_used=0, wall_time=0.0),
        curve=(np.zeros(1), np.zeros(1), np.zeros(1)), simulated=simulated, runs_used=60, wall_time=40.0,
        methods=(), uplift_limit=0.0835)


def test_the_study_s_record_is_its_design_tolerance_and_every_simulated_uplift():
    record = study().evidence()
    assert record.presag_rel * SPAN * 1e3 == pytest.approx(45.1, rel=1e-12)
    assert [t * SPAN * 1e3 for t in record.tolerance] == pytest.approx([28.0, 56.1], rel=1e-12)
    assert (record.within, record.uplift) == (0.10, 0.0529)
    assert [s * SPAN * 1e3 for s, _ in record.simulated] == pytest.approx([28.0, 45.1, 55.8, 56.1, 61.0], rel=1e-12)
    assert record.uplift_at(50.0e-3 / SPAN) == pytest.approx(0.0534, rel=1e-12)  # between 45.1 and 55.8 mm: the larger
    assert "4 static forces 70–140 N × 3 speeds 50–90 km/h" in record.where


def test_the_simulated_band_starts_at_50_kmh():
    band = simulated_band(CASE_STUDY_BAND)
    assert band.speed_low == pytest.approx(50 * KMH, rel=1e-12) and band.speed_high == CASE_STUDY_BAND.speed_high
    slow = simulated_band(CASE_STUDY_BAND.__class__(static_force_low=70.0, static_force_high=140.0, speed_low=0.0,
                                                    speed_high=40 * KMH, aero_coefficient=0.0))
    assert slow.speed_low == pytest.approx(20 * KMH, rel=1e-12)
    assert np.isclose(simulated_band(CASE_STUDY_BAND.__class__(
        static_force_low=70.0, static_force_high=140.0, speed_low=60 * KMH, speed_high=90 * KMH,
        aero_coefficient=0.0)).speed_low, 60 * KMH)


def test_the_methods_pre_sags_are_simulated_by_the_study_s_workers_after_its_tolerance(monkeypatch):
    """The study simulates a start the search moved away from (the Δe rule 0.3 mm from the quasi-static
    design) after its tolerance is read, so that it does not shape it, and inside the evaluator's block,
    with the study's one set of workers, not a pool of its own afterwards."""
    import presag_opt.robust.dynamic_study as module
    from presag_opt.robust.band_evaluation import BandStatistics
    from presag_opt.system.loader import load_catenary

    events = []

    class Evaluator:
        def __init__(self, catenary, pantograph, grid, **options):
            self.grid, self.evaluations, self.runs_used, self.entered = grid, {}, 0, False

        def __enter__(self):
            self.entered = True
            return self

        def __exit__(self, *exc):
            self.entered = False
            events.append("block ends")
            return False

        def __call__(self, presag_rel):
            events.append(("simulated" if self.entered else "simulated after the block", round(presag_rel * SPAN * 1e3, 1)))
            points = len(self.grid.points())
            return SimpleNamespace(statistics=BandStatistics(
                presag_rel=presag_rel, mean_force=np.full(points, 100.0), sigma=np.full(points, 10.0),
                uplift_max=np.full(points, 0.05)))

    def tolerance(evaluator, objective, **options):
        events.append("tolerance")
        return DynamicTolerance(low=28.0e-3 / SPAN, high=56.2e-3 / SPAN, within=0.10, worst_case_min=0.1,
                                runs_used=0, wall_time=0.0)

    monkeypatch.setattr(module, "BandEvaluator", Evaluator)
    monkeypatch.setattr(module, "dynamic_robust_presag",
                        lambda *args, **options: SimpleNamespace(presag_rel=45.1e-3 / SPAN, wall_time=0.0))
    monkeypatch.setattr(module, "dynamic_tolerance", tolerance)
    monkeypatch.setattr(module, "band_curve", lambda *args: (np.zeros(1), np.zeros(1), np.zeros(1)))
    quasi = SimpleNamespace(robust_parabola=SimpleNamespace(presag_rel=55.8e-3 / SPAN),
                            nominal=SimpleNamespace(presag_rel=56.1e-3 / SPAN), wall_time=1.0)
    result = module.dynamic_robust_study(load_catenary("st_9.8_ideal"), SimpleNamespace(name="stand-in"),
                                         simulated_band(CASE_STUDY_BAND), quasi=quasi, workers=2)
    assert events == ["tolerance", ("simulated", 56.1), ("simulated", 55.8), ("simulated", 45.1), "block ends"]
    assert [m.presag_rel * SPAN * 1e3 for m in result.methods] == pytest.approx([56.1, 55.8, 45.1], rel=1e-12)
