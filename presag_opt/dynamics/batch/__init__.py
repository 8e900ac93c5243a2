"""The compiled batch engine: many operating points on one catenary, all runs stepped together.

Entry points
    :func:`simulate_many` (operating points on one form-found state) and :func:`simulate_installed`
    (installed lines on one shared structure), both in :mod:`~presag_opt.dynamics.batch.simulation`.
The shared arrays and their integration
    :mod:`~presag_opt.dynamics.batch.system` — what the runs share, and the batch's integration;
    :mod:`~presag_opt.dynamics.batch.kernel_data` — the kernel's arrays as named tuples (each
    tuple documented there once; the kernel's parts name their arguments by these types);
    :mod:`~presag_opt.dynamics.batch.band_rows` — the nonzero entries of a band by rows.
The compiled kernel
    :mod:`~presag_opt.dynamics.batch.kernel` — the sweeps over all DOFs and the one driver loop;
    :mod:`~presag_opt.dynamics.batch.newton_step` — each run's Newton iteration on its nonlinear
    DOFs, from its parts: :mod:`~presag_opt.dynamics.batch.predictor` (the step's start),
    :mod:`~presag_opt.dynamics.batch.forces` (contact, friction and dropper force sets),
    :mod:`~presag_opt.dynamics.batch.woodbury` (the Woodbury correction) and
    :mod:`~presag_opt.dynamics.batch.update` (the iterate and the step's end);
    :mod:`presag_opt.native.sweeps` (with ``native/sweeps.c``) — the same sweeps in compiled C.
"""

from presag_opt.dynamics.batch.simulation import simulate_installed, simulate_many

__all__ = ["simulate_installed", "simulate_many"]
