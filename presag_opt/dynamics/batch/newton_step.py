"""Each batch run's Newton iteration on its few nonlinear DOFs (numba).

:func:`newton_step` solves one run's step once the sweeps of :mod:`presag_opt.dynamics.batch.kernel` have
formed the linear solution δ_lin of all runs. Its parts, in order, each in the module that says what
it holds:

- the pantographs' predictor, the state and the residual at the predictor
  (:mod:`presag_opt.dynamics.batch.predictor`);
- the nonlinear forces of contact, pantograph friction and slack droppers, with the laws of
  :mod:`presag_opt.dynamics.laws` compiled as kernel parts (:mod:`presag_opt.dynamics.batch.forces`);
- the Woodbury correction from the cached columns of K_eff⁻¹
  (:mod:`presag_opt.dynamics.batch.woodbury`);
- the new iterate and its residual, the integrator's residual test, and the step's end
  (:mod:`presag_opt.dynamics.batch.update`).

The arrays are the named tuples of :mod:`presag_opt.dynamics.batch.kernel_data`, whose ``STATUS_*``
values a run's status takes (re-exported here).
"""

from __future__ import annotations

import numpy as np

from presag_opt.dynamics.batch.forces import nonlinear_forces
from presag_opt.dynamics.batch.kernel_data import STATUS_NOT_CONVERGED, STATUS_NOT_FINITE, STATUS_OK, STATUS_RUNNING
from presag_opt.dynamics.batch.predictor import pantograph_predictor, predictor_state, residual_at_predictor
from presag_opt.dynamics.batch.update import close_run_step, fail_run, update_iterate
from presag_opt.dynamics.batch.woodbury import woodbury_correction
from presag_opt.native.jit import kernel_part

__all__ = ["STATUS_NOT_CONVERGED", "STATUS_NOT_FINITE", "STATUS_OK", "STATUS_RUNNING", "newton_step"]


@kernel_part
def newton_step(b, step, scalars, shared, runs, state, out, work, scratch):
    """Newton iteration of run ``b`` for record ``step`` (see the module notes).

    Between the sweeps the catenary's ``state.u``, ``.v`` and ``.r`` hold the step's ũ, ṽ and α r_n
    and ``work.delta`` holds δ_lin. Leaves φ's catenary part in ``work`` (columns and coefficients
    s φ) for the state update, the pantographs' new state in ``state``, and stops a run whose
    iteration fails.

    Parameters
    ----------
    b, step : int
        The run (the column of the batch arrays) and the record (time step) being computed. [-]
    scalars, shared, runs, state, out, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    """
    s, a1 = scalars.scheme.s, scalars.scheme.a1
    pan, drop = scratch.pantograph, scratch.droppers
    pantograph_predictor(b, scalars, shared, runs, state, scratch)
    predictor_state(b, step, shared, runs, state, work, scratch, pan)
    count, slack = nonlinear_forces(b, step, a1, scalars, shared, runs, scratch)
    largest_term, largest = residual_at_predictor(b, s, shared, state, work, scratch, pan)
    limit = scalars.tolerance * largest_term
    n_phi = 0
    taken = 0
    while largest > limit:
        if taken == scalars.max_iterations or not np.isfinite(largest):
            fail_run(b, step, largest, count, taken, out, scratch)
            return
        n_phi = woodbury_correction(b, s, count, n_phi, taken, shared, work, scratch, pan)
        taken += 1
        count, slack, largest = update_iterate(b, step, n_phi, scalars, shared, runs, state, work, scratch, pan, drop)
    out.iterations[b] += taken
    close_run_step(b, step, taken, count, n_phi, slack, scalars, shared, state, out, work, scratch, pan)
