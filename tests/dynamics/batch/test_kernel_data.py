"""The batch kernel's named arrays: sizes and initial values of the working arrays."""

from __future__ import annotations

import numpy as np

from presag_opt.dynamics.batch import kernel_data as kd
from presag_opt.dynamics.batch.first_use import sample_arguments


def test_the_largest_set_counts_every_dof_a_force_can_reach(synthetic_batch):
    shared = synthetic_batch().shared
    # 1 head × (2 wire nodes + head) + 2 pantograph DOFs twice (friction) + 6 per dropper + 1 spare
    assert kd.set_size(shared) == 3 + 4 + 6 + 1


def test_the_scratch_arrays(synthetic_batch):
    shared = synthetic_batch().shared
    scratch = kd.make_scratch(shared)
    size = kd.set_size(shared)
    assert scratch.tangent.shape == (size, size) and scratch.set_dofs.dtype == np.int64
    assert scratch.position.shape == (8,) and np.all(scratch.position == -1)  # no DOF in the set yet
    assert scratch.stretch.shape == scratch.rate.shape == (1,) and scratch.piece_dofs.shape == (6,)
    assert scratch.u_of.shape == scratch.v_of.shape == (8,)


def test_the_work_arrays_take_the_padded_lanes(synthetic_batch):
    shared = synthetic_batch().shared
    work = kd.make_work(shared, 3, lanes=8)
    assert work.delta.shape == (6, 8) and work.g.shape == work.linear.shape == (6, 8)
    assert work.scale.shape == work.first_residual.shape == (8,)
    assert work.phi_count.shape == (3,) and work.phi_column.shape == work.phi_coefficient.shape == (3, kd.set_size(shared))
    assert kd.make_work(shared, 3).delta.shape == (6, 3)  # unpadded by default
    places = {a.ctypes.data % 4096 for a in (work.delta, work.linear)}
    assert places == {kd.swept_array(name, 6, 8).ctypes.data % 4096 for name in ("delta", "linear")}


def test_the_swept_arrays_start_at_their_own_places_in_a_page():
    """Each of the sweeps' [DOF, lane] arrays starts on a cache line at its own offset modulo 4 KiB
    (no two rows j at the same address modulo 4 KiB: no 4K aliasing between their loads and stores)."""
    for n, lanes in ((7182, 16), (8502, 8), (5, 3)):
        arrays = [kd.swept_array(name, n, lanes) for name in kd.SWEPT_ARRAYS]
        offsets = [a.ctypes.data % 4096 for a in arrays]
        assert len(set(offsets)) == len(kd.SWEPT_ARRAYS)
        assert min((b - a) % 4096 for a in offsets for b in offsets if a != b) >= 576
        for a in arrays:
            assert a.shape == (n, lanes) and a.flags.c_contiguous and a.ctypes.data % 64 == 0 and not a.any()
    # a batch's own arguments: its state and work arrays are those, each at its own place
    arguments = sample_arguments()
    swept = [*arguments.state[:4], arguments.work.delta, arguments.work.linear]
    places = [a.ctypes.data % 4096 for a in swept]
    assert places == [kd.swept_array(name, *swept[0].shape).ctypes.data % 4096 for name in kd.SWEPT_ARRAYS]


def test_the_statuses_are_distinct_and_ok_is_zero():
    statuses = [kd.STATUS_RUNNING, kd.STATUS_OK, kd.STATUS_NOT_CONVERGED, kd.STATUS_NOT_FINITE]
    assert len(set(statuses)) == 4 and kd.STATUS_OK == 0


def test_the_tuples_name_every_field_the_sweeps_read():
    assert kd.Shared._fields[:5] == ("stiffness_band", "factor_band", "stiffness_rows", "lower_rows", "upper_rows")
    assert len(kd.Shared._fields) == 25
    # a run's static line is its own (installed lines share a structure), not the batch's
    assert {"cw_height", "dropper_preload"} <= set(kd.Runs._fields)
    assert not {"cw_height", "dropper_preload"} & set(kd.Shared._fields)
    assert kd.Scalars._fields[0] == "scheme" and "friction_velocity" in kd.Scalars._fields
