"""Dynamic Monte Carlo of the installation errors: a built design simulated over an operating grid.

Each realisation of the installation errors is the re-solved installed line
(:func:`~presag_opt.robust.realisation.installed_state`, built from the design form-found with the
discretisation every speed of the grid needs) and all points of the grid run in one
:func:`~presag_opt.dynamics.batch.simulate_many` batch on it, as a pre-sag of the dynamic robust design
does (:mod:`presag_opt.robust.band_evaluation`). Per realisation the grid is reduced to three worst
cases: the largest σ/F_m, the smallest statistical minimum F_m − 3σ and the largest steady-arm uplift.

Failures: a realisation whose re-solve or one of whose runs fails is kept apart with its reason
(:attr:`DynamicMonteCarloResult.failures`) and the others go on; the percentiles rest on the
realisations that finished and say how many (``samples``). Only the error-free run must finish.

Resuming: every finished (or failed) realisation and the error-free run are kept as one small JSON
file each, written atomically (:class:`~presag_opt.evaluation_store.EvaluationStore`), under a key of
everything that decides them (system, pantograph, grid, numerics, design, error sizes, seed, sample
count): in the ``store`` folder given, else in a folder of this Monte Carlo in the cache directory
when one is set (:func:`presag_opt.static.cache.evaluation_folder`; the command line sets it). A
killed Monte Carlo run again with the same inputs reads them back and simulates only the rest; a
folder of another Monte Carlo is refused before any work.

Reproducibility: the errors of all realisations are drawn in the calling process from one seeded
generator before any work is shared out; a run's result does not depend on the other runs of its
batch; so the results do not depend on the number of worker processes.

Batching: the realisations of a task (``chunk`` of them) run together in one
:func:`~presag_opt.dynamics.batch.simulate_installed` batch on the design's structure: the stiffness,
mass, damping, factorised effective matrix and influence columns are the design's, formed once, and
each run brings its realisation's static contact-wire heights and dropper preloads. Four
realisations of the 12-point case-study grid fill six blocks of eight lanes, where one realisation
alone fills three blocks half. What sharing leaves out is the change of the tangent stiffness with
the errors; ``shared_structure=False`` simulates each realisation on its own re-linearised structure
instead (the tests and the benchmark compare the two).
"""

from __future__ import annotations

import dataclasses
import functools
import time as wallclock
from collections.abc import Callable
from concurrent.futures import as_completed
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from presag_opt.design.band import KMH
from presag_opt.dynamics.batch import simulate_installed, simulate_many
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ConvergenceError, ModelError, PresagError, failure_reason
from presag_opt.evaluation_store import Evaluation, EvaluationStore, analysis_key
from presag_opt.processes import WorkerMemo, WorkerPolicy, run_job, worker_pool
from presag_opt.robust.installation import (
    InstallationErrors,
    InstallationSample,
    draw_installation_errors,
)
from presag_opt.robust.monte_carlo import percentile_summary
from presag_opt.robust.operating_grid import OperatingGrid, band_static_settings
from presag_opt.robust.realisation import installed_state
from presag_opt.static import cache
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
    slack_at_rest : int
        Droppers the errors leave slack at rest (on the shared structure they start just taut with
        no tension: their slack length is not kept). [-]
    wall_time : float
        Re-solve and simulation of the realisation. [s]
    cpu_time : float
        Processor time of the same, in its process (the cost that does not depend on the load). [s]
    """

    worst_sigma_over_fm: float
    smallest_statistical_min: float
    largest_uplift: float
    slack_at_rest: int
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
        One per realisation that finished, in the order drawn.
    percentiles : dict
        Per measure of :data:`MEASURES`, :class:`~presag_opt.robust.monte_carlo.Percentile` by level
        (over the realisations that finished).
    wall_time : float
        Whole Monte Carlo, nominal included. [s]
    workers : int
        Processes used. [-]
    failures : tuple of Evaluation
        The realisations that failed, each with its index, the seed and the one-line reason.
    store : str
        Folder keeping every realisation ("" when none is kept).
    """

    errors: InstallationErrors
    seed: int
    presag_rel: float
    nominal: RealisationRuns
    realisations: tuple[RealisationRuns, ...]
    percentiles: dict
    wall_time: float
    workers: int
    failures: tuple[Evaluation, ...] = ()
    store: str = ""

    @property
    def samples(self) -> int:
        """Realisations that finished: the sample size of the percentiles. [-]"""
        return len(self.realisations)

    def failure_summary(self) -> str:
        """One line: how many realisations failed, the first one's reason and what is left ("" if none)."""
        if not self.failures:
            return ""
        first = self.failures[0]
        kept = f"; kept in {self.store}" if self.store else ""
        return (f"{len(self.failures)} of {len(self.failures) + self.samples} realisations failed (first: realisation "
                f"{first.index}, {first.failure}); the percentiles rest on the {self.samples} that finished{kept}")

    def values(self, measure: str) -> np.ndarray:
        """One measure of every realisation (see :data:`MEASURES`)."""
        return np.array([getattr(r, measure) for r in self.realisations])


def _realisation_runs(catenary: Catenary, pantograph, grid: OperatingGrid, settings: SimulationSettings,
                      static_settings: StaticSettings, presag_rel: float, sample: InstallationSample,
                      spacings=None, shared_structure: bool = True, memo: WorkerMemo | None = None,
                      ) -> list[RealisationRuns | str]:
    """Re-solve and simulate every realisation of ``sample`` (one worker's share) on the design,
    form-found once per memo (:func:`_nominal_state`; the memo of a worker's job serves all its
    tasks): all of them in one :func:`~presag_opt.dynamics.batch.simulate_installed` batch on the
    design's structure, or each on its own structure (``shared_structure=False``). A realisation
    whose re-solve or run fails gives the one-line reason instead of its worst cases."""
    nominal = _nominal_state(catenary, static_settings, presag_rel, memo or WorkerMemo(1))
    points = grid.points()
    started, cpu = wallclock.perf_counter(), wallclock.process_time()
    out: list[RealisationRuns | str] = []
    states = []
    for i in range(sample.samples):
        try:
            states.append(installed_state(nominal, sample, i))
            out.append("")
        except PresagError as exc:
            out.append(failure_reason(exc))
    if shared_structure:
        batches = (simulate_installed(nominal, states, pantograph, points, spacings=spacings, settings=settings)
                   if states else [])
    else:
        batches = []
        for state in states:
            try:
                batches.append(simulate_many(state, pantograph, points, spacings=spacings, settings=settings))
            except PresagError as exc:
                batches.append(failure_reason(exc))
    # the batches are shared, so is their cost: each realisation is charged an equal part
    wall, processor = wallclock.perf_counter() - started, wallclock.process_time() - cpu
    share = max(1, len(batches))
    finished = iter(zip(batches, states, strict=True))
    for i, failure in enumerate(out):
        if failure:
            continue
        batch, state = next(finished)
        out[i] = batch if isinstance(batch, str) else _worst_cases(batch, state.slack_dropper_count(), wall / share,
                                                                  processor / share)
    return out


def _worst_cases(batch, slack_at_rest: int, wall_time: float, cpu_time: float) -> RealisationRuns | str:
    """One realisation's grid reduced to its worst cases, or the reason of its first failed run."""
    for run in batch.runs:
        if not run.ok:
            p = run.point
            return f"the run at {p.speed / KMH:g} km/h, F_stat {p.static_force:g} N failed: {run.error}"
    means = np.array([[s.mean_force for s in run.statistics] for run in batch.runs])
    sigmas = np.array([[s.std_force for s in run.statistics] for run in batch.runs])
    return RealisationRuns(
        worst_sigma_over_fm=float((sigmas / means).max()),
        smallest_statistical_min=float((means - 3.0 * sigmas).min()),
        largest_uplift=float(max(run.uplift_max for run in batch.runs)),
        slack_at_rest=slack_at_rest,
        wall_time=wall_time,
        cpu_time=cpu_time,
    )


def _nominal_state(catenary: Catenary, static_settings: StaticSettings, presag_rel: float, memo: WorkerMemo):
    """The design form-found with ``static_settings``, kept in ``memo`` (a worker form-finds it once
    for all its tasks, not once per task).

    Parameters
    ----------
    catenary : Catenary
        System model (its pre-sag is replaced by ``presag_rel``).
    static_settings : StaticSettings
        Form-finding settings.
    presag_rel : float
        Design S_rel. [-]
    memo : WorkerMemo
        Where the state is kept.
    """
    return memo.get((catenary, static_settings, float(presag_rel)),
                    lambda: form_find(catenary.with_presag(presag_rel), static_settings))


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
    shared_structure: bool = True,
    confidence: float = 0.95,
    progress: Callable[[str], None] | None = None,
    store: Path | None = None,
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
        Realisations per task, simulated together in one batch on the design's structure (a worker
        process form-finds the design once for all its tasks). [-]
    shared_structure : bool
        Simulate the realisations of a task on the design's structure, each with its own static
        contact-wire heights and dropper preloads (default; the tests bound the difference), or
        each on its own re-linearised structure (slower: no batch is shared).
    confidence : float
        Coverage of the percentile intervals. [-]
    progress : callable, optional
        Called with a short message as realisations finish.
    store : pathlib.Path, optional
        Folder keeping every finished realisation (created if missing); a rerun with the same inputs
        reads them back and simulates only the others (see the module notes). Default: a folder of
        this Monte Carlo in the cache directory when one is set, else none.

    Raises
    ------
    ModelError
        Bad counts, a grid the catenary cannot be simulated at, or a store of another Monte Carlo.
    StorageError
        A realisation's file cannot be written (the finished ones are kept).
    ConvergenceError
        The error-free run failed, or every realisation did.
    """
    started = wallclock.perf_counter()
    if workers != int(workers) or not 1 <= workers <= 64:
        raise ModelError(f"workers = {workers} is outside the valid range [1, 64]")
    if chunk != int(chunk) or not 1 <= chunk <= 1000:
        raise ModelError(f"chunk = {chunk} is outside the valid range [1, 1000]")
    settings = settings or SimulationSettings(numerics="auto")
    grid.check(catenary, pantograph, settings)
    static_settings = band_static_settings(catenary, grid.speeds, settings)
    memo = WorkerMemo(1)
    probe = _nominal_state(catenary, static_settings, presag_rel, memo)
    disc = probe.discretisation
    draws = draw_installation_errors(samples, len(disc.dropper_elements), len(disc.mast_station),
                                     distribution=errors.distribution, seed=seed)
    sample = draws.scaled(errors)
    zero = draws.scaled(InstallationErrors(distribution=errors.distribution))
    key = analysis_key(catenary, pantograph, grid, settings, spacings, static_settings, float(presag_rel), errors,
                       int(seed), int(samples), bool(shared_structure))
    folder = Path(store) if store is not None else cache.evaluation_folder("monte-carlo", key)
    kept = (EvaluationStore.open(folder, key, f"dynamic Monte Carlo of {catenary.name}, S_rel {presag_rel * 1e3:.3f} ‰, "
                                 f"{samples} realisations, seed {seed}") if folder is not None else None)
    found = kept.read([NOMINAL, *range(samples)]) if kept else {}
    pending = [i for i in range(samples) if i not in found]
    tasks = [] if NOMINAL in found else [(NOMINAL, zero.row(0))]
    tasks += [(indices, _rows(sample, indices)) for indices in
              (pending[first:first + chunk] for first in range(0, len(pending), chunk))]
    job = functools.partial(_realisation_runs, catenary, pantograph, grid, settings, static_settings, presag_rel,
                            spacings=spacings, shared_structure=shared_structure, memo=memo)
    runs: dict[int, Evaluation] = dict(found)
    done = sum(i != NOMINAL for i in found)

    def finished(indices, value: list[RealisationRuns | str]) -> None:
        nonlocal done
        indices = [NOMINAL] if indices == NOMINAL else indices
        for i, realisation in zip(indices, value, strict=True):
            failed = isinstance(realisation, str)
            runs[i] = Evaluation(index=i, inputs={"realisation": i, "seed": int(seed)},
                                 values={} if failed else dataclasses.asdict(realisation),
                                 failure=realisation if failed else "")
            if kept:
                kept.write(runs[i])
        done += 0 if indices == [NOMINAL] else len(indices)
        if progress:
            elapsed = wallclock.perf_counter() - started
            progress(f"dynamic Monte Carlo: {done}/{samples} realisations ({elapsed:.0f} s)")

    if found and progress:
        progress(f"dynamic Monte Carlo: {done}/{samples} realisations read back from {folder}")
    if workers > 1 and len(tasks) > 1:
        with worker_pool(min(workers, len(tasks)), WorkerPolicy.PICKLED, job=job) as pool:
            futures = {pool.submit(run_job, rows): indices for indices, rows in tasks}
            for future in as_completed(futures):
                finished(futures[future], future.result())
    else:
        for indices, rows in tasks:
            finished(indices, job(rows))
    if not runs[NOMINAL].ok:
        raise ConvergenceError(f"dynamic Monte Carlo: the error-free design failed: {runs[NOMINAL].failure}")
    failures = tuple(runs[i] for i in range(samples) if not runs[i].ok)
    realisations = tuple(RealisationRuns(**runs[i].values) for i in range(samples) if runs[i].ok)
    if not realisations:
        raise ConvergenceError(f"dynamic Monte Carlo: all {samples} realisations failed (first: {failures[0].failure})")
    percentiles = {m: percentile_summary([getattr(r, m) for r in realisations], confidence=confidence)
                   for m in MEASURES}
    return DynamicMonteCarloResult(errors=errors, seed=seed, presag_rel=presag_rel,
                                   nominal=RealisationRuns(**runs[NOMINAL].values), realisations=realisations,
                                   percentiles=percentiles, wall_time=wallclock.perf_counter() - started,
                                   workers=int(workers), failures=failures, store=str(folder) if kept else "")


def _rows(sample: InstallationSample, indices: list[int]) -> InstallationSample:
    return InstallationSample(dropper=sample.dropper[indices], contact_wire=sample.contact_wire[indices],
                              messenger=sample.messenger[indices])


NOMINAL = -1
"""Index of the error-free run among the realisations of a Monte Carlo (and of its file in a store)."""
