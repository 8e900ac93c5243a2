"""An elasticity study: the curves of one span at several force levels, in worker processes if asked.

The force levels are independent; with ``workers > 1`` each runs in a forked worker process
(:func:`presag_opt.processes.worker_pool`), which inherits the form-found state from the parent
instead of receiving it pickled (it holds compiled CasADi functions and the factorisations the
serial run would reuse, so the curves are the same to the last bit).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from concurrent.futures import as_completed

from presag_opt.elasticity.curves import ElasticityCurve, ElasticityStudy
from presag_opt.elasticity.methods import linear_elasticity, nonlinear_elasticity
from presag_opt.errors import ModelError
from presag_opt.processes import WorkerPolicy, pool_available, run_job, worker_pool
from presag_opt.static.equilibrium import EquilibriumState

DEFAULT_FORCES = (50.0, 100.0, 150.0, 200.0)
"""Force levels of the nonlinear elasticity curves. [N]"""


def elasticity_study(
    state: EquilibriumState,
    *,
    span: int | None = None,
    forces: Sequence[float] = DEFAULT_FORCES,
    step: float = 0.5,
    linear: bool = False,
    linear_step: float = 0.1,
    method: str = "newton",
    progress: Callable[[str], None] | None = None,
    workers: int = 1,
) -> ElasticityStudy:
    """Nonlinear elasticity curves at several forces, and optionally the linear curve.

    Parameters
    ----------
    state : EquilibriumState
        Form-found equilibrium.
    span : int, optional
        Span index from 0 (0 is the first span, ``n_spans − 1`` the last); default the central span. [-]
    forces : sequence of float
        Force levels. [N]
    step : float
        Point spacing of the nonlinear curves. [m]
    linear : bool
        Also compute the linear (tangent-stiffness) curve.
    linear_step : float
        Point spacing of the linear curve. [m]
    method : {"newton", "active-set"}
        Method of the nonlinear curves (see :func:`nonlinear_elasticity`).
    progress : callable, optional
        Called with a short message as the curves are computed.
    workers : int
        Processes for the nonlinear curves (forked, so only where ``fork`` is available; the curves
        are independent, the result is the same). [-]

    Returns
    -------
    ElasticityStudy
        With ``warnings`` for curves whose uplift the model cannot represent (:func:`uplift_warnings`).
    """
    span = state.catenary.layout.central_span if span is None else span
    if not forces and not linear:
        raise ModelError("forces is empty and linear is off: nothing to compute")
    levels = sorted(forces)
    if workers > 1 and len(levels) > 1 and pool_available(WorkerPolicy.INHERITED):
        curves = _parallel_curves(state, levels, span, step, method, workers, progress)
    else:
        curves = []
        for i, force in enumerate(levels):
            if progress:
                progress(f"elasticity at {force:g} N ({i + 1}/{len(levels)})")
            curves.append(nonlinear_elasticity(state, force, span, step, method))
    if linear:
        if progress:
            progress("linear elasticity")
        curves.append(linear_elasticity(state, span, linear_step))
    return ElasticityStudy(catenary_name=state.catenary.name, span=span, curves=tuple(curves),
                           warnings=uplift_warnings(curves, state.catenary.system_height))


def _parallel_curves(state, levels, span, step, method, workers, progress) -> list[ElasticityCurve]:
    """The nonlinear curves of :func:`elasticity_study`, one forked process per level at a time (the
    state is the pool's job, inherited by the forked workers: it holds compiled CasADi functions,
    which cannot be pickled)."""
    job = functools.partial(nonlinear_elasticity, state)
    with worker_pool(min(workers, len(levels)), WorkerPolicy.INHERITED, job=job) as pool:
        futures = [pool.submit(run_job, force, span, step, method) for force in levels]
        for done, _ in enumerate(as_completed(futures), start=1):
            if progress:
                progress(f"elasticity curves done: {done}/{len(levels)}")
        return [f.result() for f in futures]


def uplift_warnings(curves: Sequence[ElasticityCurve], system_height: float) -> tuple[str, ...]:
    """One line per nonlinear curve whose largest uplift F·e_max reaches the system height.

    The model has no contact between the wires: an uplift of the contact wire that reaches the
    messenger wire (the system height above it at the supports) is outside its validity. Such a
    curve is still returned, with this warning, since the elasticity up to that point is sound.

    Parameters
    ----------
    curves : sequence of ElasticityCurve
        Curves to check (the linear one has no force and is skipped).
    system_height : float
        Messenger wire above the contact wire at the supports. [m]
    """
    return tuple(
        f"F = {c.force:g} N lifts the contact wire by up to {c.force * c.e_max * 1e3:.0f} mm, beyond the system "
        f"height {system_height * 1e3:.0f} mm; the model (no contact between the wires) is not valid there"
        for c in curves
        if c.force is not None and c.force * c.e_max >= system_height
    )
