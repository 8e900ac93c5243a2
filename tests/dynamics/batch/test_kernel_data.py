"""The batch kernel's named arrays: sizes and initial values of the working arrays."""

from __future__ import annotations

import numpy as np

from presag_opt.dynamics.batch import kernel_data as kd


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
