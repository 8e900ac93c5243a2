"""The batch simulator's compiled sweeps (``sweeps.c``) against the numba kernel: the same records to
the last bit, for a batch that fills one block of lanes and starts a second, and for a block with
six dead lanes, with runs that stop at different steps and a run that fails; and the fallback to
numba without a compiler.

The section is the 5-span ST 9,8/9,8 of ``batch/test_simulation.py`` (one lead-in span, the central span
analysed), which keeps each batch to a few seconds.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.native import sweeps as native_sweeps

AERO = 0.00097 * 3.6**2  # the case study's α_ae [N/(m/s)²]


@pytest.fixture(scope="module")
def settings(case):
    return dataclasses.replace(case.settings, lead_in_spans=1, analysed_spans=1, numerics="fixed")


def _both(state, pantograph, points, settings, monkeypatch):
    """The batch with the compiled sweeps, then with the numba kernel."""
    assert native_sweeps.available(), "the compiled sweeps were not built (no C compiler?): nothing is compared"
    compiled = simulate_many(state, pantograph, points, settings=settings, keep_histories=True)
    with monkeypatch.context() as patch:
        patch.setattr(native_sweeps, "available", lambda: False)
        numba = simulate_many(state, pantograph, points, settings=settings, keep_histories=True)
    return compiled, numba


def _assert_identical(compiled, numba):
    for a, b in zip(compiled.runs, numba.runs, strict=True):
        assert a.ok == b.ok and a.error == b.error
        if a.ok:
            assert np.array_equal(a.contact_force, b.contact_force)
            assert a.statistics == b.statistics
            assert a.uplift_max == b.uplift_max and a.slack_droppers_max == b.slack_droppers_max
            assert a.newton_iterations == b.newton_iterations


def test_two_blocks_of_lanes_with_friction_give_the_numba_results_bit_for_bit(short_state, case, settings,
                                                                             monkeypatch):
    """Nine runs (lanes 0–7 in one block, run 8 in a second block padded with seven dead lanes), at
    speeds from 120 to 200 km/h, so that the runs stop at different steps and the active prefix
    shrinks; with the pantograph's friction and slack droppers at the top speed."""
    points = [OperatingPoint(speed=v / 3.6, static_force=f, aero_coefficient=AERO)
              for v, f in ((200, 60), (190, 140), (180, 100), (170, 70), (160, 120), (150, 90), (140, 55),
                           (130, 150), (120, 80))]
    compiled, numba = _both(short_state, case.pantograph, points, settings, monkeypatch)
    assert all(run.ok for run in compiled.runs)
    assert max(run.slack_droppers_max for run in compiled.runs) > 0, "no slack dropper: the nonlinear path is not exercised"
    _assert_identical(compiled, numba)


def test_a_failed_run_beside_a_finished_one_gives_the_numba_results_bit_for_bit(short_state, case, settings,
                                                                              monkeypatch):
    """Two runs in one block (six dead lanes): the fast run fails (one Newton correction per step is
    too few where droppers go slack) while the slow one finishes."""
    tight = dataclasses.replace(settings, integrator=dataclasses.replace(settings.integrator, max_iterations=1))
    pair = [OperatingPoint(speed=200 / 3.6, static_force=100.0, aero_coefficient=AERO),
            OperatingPoint(speed=60 / 3.6, static_force=50.0, aero_coefficient=AERO)]
    frictionless = dataclasses.replace(
        case.pantograph, stages=tuple(dataclasses.replace(s, friction=0.0) for s in case.pantograph.stages))
    compiled, numba = _both(short_state, frictionless, pair, tight, monkeypatch)
    assert not compiled.runs[0].ok and compiled.runs[1].ok
    _assert_identical(compiled, numba)


def test_lanes_are_padded_to_whole_blocks():
    assert [native_sweeps.lanes_for(n) for n in (1, 7, 8, 9, 16, 17)] == [8, 8, 8, 16, 16, 24]


def test_without_a_compiler_the_numba_kernel_runs(short_state, case, settings, monkeypatch):
    """No compiler on the path: nothing is built, and the batch runs on the numba kernel."""
    monkeypatch.setenv("CC", "/nonexistent/cc")
    assert not native_sweeps.available()
    point = OperatingPoint(speed=100 / 3.6, static_force=90.0, aero_coefficient=AERO)
    run = simulate_many(short_state, case.pantograph, [point], settings=settings).runs[0]
    assert run.ok and 80.0 < run.statistics[0].mean_force < 110.0
    monkeypatch.undo()
    assert native_sweeps.available()  # the compiler back: the library again (read from the environment each time)
