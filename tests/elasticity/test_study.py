"""``presag_opt.elasticity.study``: the curves of one span at several forces (serial or forked, the same
numbers), the progress messages, and the warning for an uplift the model cannot represent."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.elasticity import elasticity_study
from presag_opt.elasticity.curves import ElasticityCurve
from presag_opt.elasticity.study import uplift_warnings
from presag_opt.errors import ModelError
from presag_opt.processes import WorkerPolicy, pool_available


def test_study_to_dict_has_the_documented_keys(st98):
    study = elasticity_study(st98, forces=(100.0,), step=2.0, linear=True)
    data = study.to_dict()
    assert set(data) >= {"x_m", "curves"}
    assert [c["force_N"] for c in data["curves"]] == [100.0, None]
    for c in data["curves"]:
        assert set(c) >= {"force_N", "elasticity_mm_per_N", "e_mid_mm_per_N", "e_mast_mm_per_N",
                          "e_max_mm_per_N", "e_min_mm_per_N"}



def _curve(force, e_max):
    x = np.linspace(0.0, 60.0, 7)
    return ElasticityCurve(span=0, span_length=60.0, force=force, position=x, elasticity=np.full(7, e_max))


def test_an_uplift_reaching_the_system_height_is_one_warning_per_curve():
    """F·e_max ≥ system height 1.2 m: 200 N × 0.9 mm/N = 0.18 m does not, 2000 N × 0.9 mm/N = 1.8 m does."""
    curves = [_curve(200.0, 0.9e-3), _curve(2000.0, 0.9e-3), _curve(None, 5e-3), _curve(1200.0, 1e-3)]
    assert uplift_warnings(curves, 1.2) == (
        "F = 2000 N lifts the contact wire by up to 1800 mm, beyond the system height 1200 mm; the model (no "
        "contact between the wires) is not valid there",
        "F = 1200 N lifts the contact wire by up to 1200 mm, beyond the system height 1200 mm; the model (no "
        "contact between the wires) is not valid there")  # equal to the height counts (≥)


def test_nothing_to_compute_is_refused(st98):
    with pytest.raises(ModelError, match="^forces is empty and linear is off: nothing to compute$"):
        elasticity_study(st98, forces=())


def test_the_curves_come_by_increasing_force_with_their_progress_and_forked_ones_are_the_same(st98):
    messages = []
    serial = elasticity_study(st98, forces=(150.0, 100.0), step=10.0, linear=True, linear_step=10.0,
                              progress=messages.append)
    assert [c.force for c in serial.curves] == [100.0, 150.0, None]
    assert serial.linear is serial.curves[-1] and serial.nonlinear == serial.curves[:2]
    assert serial.span == st98.catenary.layout.central_span and serial.warnings == ()
    assert messages == ["elasticity at 100 N (1/2)", "elasticity at 150 N (2/2)", "linear elasticity"]
    if not pool_available(WorkerPolicy.INHERITED):
        pytest.skip("no fork on this platform: the forked path is not taken")
    forked = elasticity_study(st98, forces=(150.0, 100.0), step=10.0, workers=2)
    for a, b in zip(forked.curves, serial.nonlinear):
        assert a.force == b.force
        np.testing.assert_array_equal(a.elasticity, b.elasticity)  # the same computation in another process
