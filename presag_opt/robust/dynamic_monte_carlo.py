"""Dynamic Monte Carlo of the installation errors: a built design simulated over an operating grid.

Each realisation of the installation errors is the re-solved installed line
(:func:`~presag_opt.robust.realisation.installed_state`, built from the design form-found with the
discretisation every speed of the grid needs) and all points of the grid run in one
:func:`~presag_opt.dynamics.batch.simulate_many` batch on it, as a pre-sag of the dynamic robust design
does (:mod:`presag_opt.robust.band_evaluation`). Per realisation the grid is reduced to three worst
cases: the largest σ/F_m, the smallest statistical minimum F_m − 3σ and the largest steady-arm uplift.

Reproducibility: the errors of all realisations are drawn in the calling process from one seeded
generator before any work is shared out; a run's result does not depend on the other runs of its
batch; so the results do not depend on the number of worker processes.

Batching: the batch engine shares one structure (stiffness, dropper preloads, static wire height)
between the runs of a batch, and a realisation is its own structure, so the batches are per
realisation (the grid's points, grouped by time step). Runs of several realisations in one batch
would need per-run static wire heights in the engine.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable
from concurrent.futures import as_completed
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import KMH
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.processes import WorkerPolicy, worker_pool
from presag_opt.robust.installation import (
    InstallationErrors,
    InstallationSample,
    draw_installation_errors,
)
from presag_opt.robust.monte_carlo import percentile_summary
from presag_opt.robust.operating_grid import OperatingGrid, band_static_settings
from presag_opt.robust.realisation import installed_state
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary

MEASURES = ("worst_sigma_over_fm", "smallest_statistical_min", "largest_uplift")
"""What each realisation is reduced to over the grid: max σ/F_m [-], min F_m − 3σ [N], max uplift [m]."""


@dataclass(frozen=True, kw_only=True)
class RealisationRuns:
    """The grid's worst cases of one realisation.

    Attributes
    ----------
    worst_sigma_over_fm : float
        Largest σ/F_m over the grid. [-]
    smallest_statistical_min : float
        Smallest F_m − 3σ over the grid. [N]
    largest_uplift : float
        Largest steady-arm uplift over the grid. [m]
    wall_time : float
        Re-solve and simulation of the realisation. [s]
    cpu_time : float
        Processor time of the same, in its process (the cost that does not depend on the load). [s]
    """

    worst_sigma_over_fm: float
    smallest_statistical_min: float
    largest_uplift: float
    wall_time: float
    cpu_time: float


@dataclass(frozen=True, kw_only=True)
class DynamicMonteCarloResult:
    """Distribution of a design's dynamic worst cases over realisations of the installation errors.

    Attributes
    ----------
    errors : InstallationErrors
        Error sizes. [m]
    seed : int
        Seed of the draws. [-]
    presag_rel : float
        Design pre-sag S_rel. [-]
    nominal : RealisationRuns
        The error-free design on the same grid.
    realisations : tuple of RealisationRuns
        One per sample, in the order drawn.
    percentiles : dict
        Per measure of :data:`MEASURES`, :class:`~presag_opt.robust.monte_carlo.Percentile` by level.
    wall_time : float
        Whole Monte Carlo, nominal included. [s]
    workers : int
        Processes used. [-]
    """

    errors: InstallationErrors
    seed: int
    presag_rel: float
    nominal: RealisationRuns
    realisations: tuple[RealisationRuns, ...]
    percentiles: dict
    wall_time: float
    workers: int

    @property
    def samples(self) -> int:
        """Realisations. [-]"""
        return len(self.realisations)

    def values(self, measure: str) -> np.ndarray:
        """One measure of every realisation (see :data:`MEASURES`)."""
        return np.array([getattr(r, measure) for r in self.realisations])


def _realisation_runs(catenary: Catenary, pantograph, grid: OperatingGrid, settings: SimulationSettings,
                      static_settings: StaticSettings, presag_rel: float, sample: InstallationSample,
                      spacings=None) -> list[RealisationRuns]:
    """Re-solve and simulate every realisation of ``sample`` (one worker's share) on the design,
    form-found once per process (:func:`_nominal_state`)."""
    nominal = _nominal_state(catenary, static_settings, presag_rel)
    points = grid.points()
    out = []
    for i in range(sample.samples):
        started, cpu = wallclock.perf_counter(), wallclock.process_time()
        state = installed_state(nominal, sample, i)
        batch = simulate_many(state, pantograph, points, spacings=spacings, settings=settings)
        for run in batch.runs:
            if not run.ok:
                p = run.point
                raise ConvergenceError(f"dynamic Monte Carlo: a run at {p.speed / KMH:g} km/h, F_stat "
                                       f"{p.static_force:g} N failed: {run.error}", {"error": run.error})
        means = np.array([[s.mean_force for s in run.statistics] for run in batch.runs])
        sigmas = np.array([[s.std_force for s in run.statistics] for run in batch.runs])
        out.append(RealisationRuns(
            worst_sigma_over_fm=float((sigmas / means).max()),
            smallest_statistical_min=float((means - 3.0 * sigmas).min()),
            largest_uplift=float(max(run.uplift_max for run in batch.runs)),
            wall_time=wallclock.perf_counter() - started,
            cpu_time=wallclock.process_time() - cpu,
        ))
    return out


_NOMINAL: dict = {}
"""The form-found design of this process, keyed by (catenary, static settings, S_rel): a worker
form-finds it once for all its tasks, not once per task."""


def _nominal_state(catenary: Catenary, static_settings: StaticSettings, presag_rel: float):
    """The design form-found with ``static_settings``, cached in this process (one entry).

    Parameters
    ----------
    catenary : Catenary
        System model (its pre-sag is replaced by ``presag_rel``).
    static_settings : StaticSettings
        Form-finding settings.
    presag_rel : float
        Design S_rel. [-]
    """
    key = (catenary, static_settings, float(presag_rel))
    if key not in _NOMINAL:
        _NOMINAL.clear()
        _NOMINAL[key] = form_find(catenary.with_presag(presag_rel), static_settings)
    return _NOMINAL[key]


def dynamic_monte_carlo(
    catenary: Catenary,
    pantograph: Pantograph,
    grid: OperatingGrid,
    presag_rel: float,
    errors: InstallationErrors,
    *,
    samples: int = 100,
    seed: int = 0,
    settings: SimulationSettings | None = None,
    spacings=None,
    workers: int = 1,
    chunk: int = 4,
    confidence: float = 0.95,
    progress: Callable[[str], None] | None = None,
) -> DynamicMonteCarloResult:
    """Simulate a parabolic design built with installation errors, realisation by realisation.

    Parameters
    ----------
    catenary : Catenary
        System model (its pre-sag is replaced by ``presag_rel``).
    pantograph : Pantograph or sequence of Pantograph
        Pantograph model(s), front to rear.
    grid : OperatingGrid
        Operating points (checked here before any work).
    presag_rel : float
        Design S_rel. [-]
    errors : InstallationErrors
        Error sizes and distribution. [m]
    samples : int
        Realisations. [-]
    seed : int
        Seed of the draws. [-]
    settings : SimulationSettings, optional
        Numerical settings; default automatic numerics.
    spacings : sequence of float, optional
        Distances between consecutive pantographs. [m]
    workers : int
        Processes sharing the realisations (the results do not depend on it). [-]
    chunk : int
        Realisations per task (a worker process form-finds the design once for all its tasks). [-]
    confidence : float
        Coverage of the percentile intervals. [-]
    progress : callable, optional
        Called with a short message as realisations finish.

    Raises
    ------
    ModelError
        Bad counts, or a grid the catenary cannot be simulated at.
    ConvergenceError
        A re-solve or a run failed.
    """
    started = wallclock.perf_counter()
    if workers != int(workers) or not 1 <= workers <= 64:
        raise ModelError(f"workers = {workers} is outside the valid range [1, 64]")
    if chunk != int(chunk) or not 1 <= chunk <= 1000:
        raise ModelError(f"chunk = {chunk} is outside the valid range [1, 1000]")
    settings = settings or SimulationSettings(numerics="auto")
    grid.check(catenary, pantograph, settings)
    static_settings = band_static_settings(catenary, grid.speeds, settings)
    probe = _nominal_state(catenary, static_settings, presag_rel)
    disc = probe.discretisation
    draws = draw_installation_errors(samples, len(disc.dropper_elements), len(disc.mast_station),
                                     distribution=errors.distribution, seed=seed)
    sample = draws.scaled(errors)
    zero = draws.scaled(InstallationErrors(distribution=errors.distribution))
    tasks = [zero.row(0)] + [_rows(sample, first, min(first + chunk, samples)) for first in range(0, samples, chunk)]
    common = (catenary, pantograph, grid, settings, static_settings, presag_rel)
    results: list[list[RealisationRuns]] = [None] * len(tasks)
    done = 0

    def finished(index: int, value) -> None:
        nonlocal done
        results[index] = value
        done += len(value) if index else 0
        if progress:
            elapsed = wallclock.perf_counter() - started
            progress(f"dynamic Monte Carlo: {done}/{samples} realisations ({elapsed:.0f} s)")

    if workers > 1:
        with worker_pool(min(workers, len(tasks)), WorkerPolicy.PICKLED) as pool:
            futures = {pool.submit(_realisation_runs, *common, task, spacings): k for k, task in enumerate(tasks)}
            for future in as_completed(futures):
                finished(futures[future], future.result())
    else:
        for k, task in enumerate(tasks):
            finished(k, _realisation_runs(*common, task, spacings))
    nominal = results[0][0]
    realisations = tuple(r for part in results[1:] for r in part)
    percentiles = {m: percentile_summary([getattr(r, m) for r in realisations], confidence=confidence)
                   for m in MEASURES}
    return DynamicMonteCarloResult(errors=errors, seed=seed, presag_rel=presag_rel, nominal=nominal,
                                   realisations=realisations, percentiles=percentiles,
                                   wall_time=wallclock.perf_counter() - started, workers=int(workers))


def _rows(sample: InstallationSample, first: int, last: int) -> InstallationSample:
    return InstallationSample(dropper=sample.dropper[first:last], contact_wire=sample.contact_wire[first:last],
                              messenger=sample.messenger[first:last])

