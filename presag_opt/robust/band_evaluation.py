"""A parabolic pre-sag simulated over an operating grid: one form-finding, one batch of runs.

:func:`simulate_band` form-finds the catenary at a pre-sag (with the discretisation every speed of
the grid needs, :func:`~presag_opt.robust.operating_grid.band_static_settings`) and runs all points
of the grid in one :func:`~presag_opt.dynamics.batch.simulate_many` call. :class:`BandEvaluator`
keeps every pre-sag it simulated and counts the runs; several pre-sags asked for at once run side
by side in worker processes, and a pre-sag asked for alone (the search's steps) has its static
forces dealt out over the workers (:func:`split_grid`, joined back by :func:`join_parts`): a run's
numbers do not depend on the other runs of its batch, so the answer is the same to the last bit, and
the second core no longer waits while the first simulates. A :class:`BandEvaluation` holds the EN 50367 statistics of every point and the
filtered contact force inside each run's analysis window, from which the surrogate of
:mod:`presag_opt.robust.surrogate` interpolates other pre-sags. A run that fails stops the search
with its reason: a design is never chosen around a missing run.
"""

from __future__ import annotations

import contextlib
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from presag_opt.design.band import KMH
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.dynamics.statistics import lowpass_filter, window_mask
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.processes import WorkerPolicy, worker_pool
from presag_opt.robust.operating_grid import OperatingGrid, band_static_settings
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary

OBJECTIVES = ("sigma-over-fm", "sigma")
"""What a dynamic design minimises at each operating point: σ/F_m [-] or σ [N]."""


@dataclass(frozen=True, kw_only=True)
class BandStatistics:
    """Contact-force statistics of one pre-sag at every point of an operating grid.

    Attributes
    ----------
    presag_rel : float
        Relative pre-sag S_rel. [-]
    mean_force : ndarray
        F_m at each point, in the grid's order. [N]
    sigma : ndarray
        σ of the filtered contact force at each point. [N]
    uplift_max : ndarray
        Largest steady-arm uplift of the analysed section at each point. [m]
    simulated : bool
        From runs at this pre-sag (True) or interpolated by the surrogate (False).
    """

    presag_rel: float
    mean_force: np.ndarray
    sigma: np.ndarray
    uplift_max: np.ndarray
    simulated: bool = True

    @property
    def statistical_min(self) -> np.ndarray:
        """F_m − 3σ at each point; contact is kept where it is positive. [N]"""
        return self.mean_force - 3.0 * self.sigma

    def losses(self, objective: str) -> np.ndarray:
        """σ/F_m [-] or σ [N] at each point (see :data:`OBJECTIVES`)."""
        if objective not in OBJECTIVES:
            raise ModelError(f"objective = {objective!r} is not one of {', '.join(OBJECTIVES)}")
        return self.sigma / self.mean_force if objective == "sigma-over-fm" else self.sigma


@dataclass(frozen=True, kw_only=True)
class BandEvaluation:
    """One simulated pre-sag: statistics, the histories behind them, and what it cost.

    Attributes
    ----------
    statistics : BandStatistics
        Statistics at every point (``simulated`` True).
    histories : tuple of ndarray
        Filtered contact force of each pantograph inside its analysis window, in the grid's order
        (with several pantographs: every pantograph of a run, front to rear, before the next run):
        F_m and σ are their mean and standard deviation. [N]
    loss_of_contact : ndarray
        Share of each run's window without contact (raw force). [-]
    wall_time : float
        Form-finding and simulation. [s]
    warnings : tuple of str
        Under-resolution warnings of the runs.
    """

    statistics: BandStatistics
    histories: tuple[np.ndarray, ...]
    loss_of_contact: np.ndarray
    wall_time: float
    warnings: tuple[str, ...] = ()


def simulate_band(
    catenary: Catenary,
    pantograph: Pantograph,
    grid: OperatingGrid,
    settings: SimulationSettings,
    static_settings: StaticSettings,
    presag_rel: float,
    progress: Callable[[str], None] | None = None,
    spacings: tuple[float, ...] | None = None,
) -> BandEvaluation:
    """Form-find one parabolic pre-sag and run every point of the grid in one batch.

    With several pantographs (``spacings``) every pantograph of a run is a point of its own: its
    statistics, and the run's steady-arm uplift.

    Parameters
    ----------
    catenary : Catenary
        System model (its pre-sag is replaced by ``presag_rel``).
    pantograph : Pantograph
        Pantograph model.
    grid : OperatingGrid
        The operating points (checked beforehand, see :meth:`OperatingGrid.check`).
    settings : SimulationSettings
        Numerical settings of the runs.
    static_settings : StaticSettings
        Settings of the form-finding (:func:`~presag_opt.robust.operating_grid.band_static_settings`).
    presag_rel : float
        Relative pre-sag S_rel. [-]
    progress : callable, optional
        Called with a short message before the form-finding and after each batch of runs.
    spacings : tuple of float, optional
        Distances between consecutive pantographs of the train, front to rear. [m]

    Raises
    ------
    ModelError
        The pre-sag is outside the model's range (0–5 ‰).
    ConvergenceError
        The form-finding or a run failed; the message names the pre-sag and the point.
    """
    started = wallclock.perf_counter()
    label = f"S = {presag_rel * max(catenary.layout.span_lengths) * 1e3:.1f} mm"
    shaped = catenary.with_presag(presag_rel)
    if progress:
        progress(f"{label}: form-finding")
    try:
        state = form_find(shaped, static_settings)
    except ConvergenceError as exc:
        raise ConvergenceError(f"dynamic robust pre-sag: form-finding at {label} failed: "
                               f"{str(exc).splitlines()[0]}", exc.stats) from None
    points = grid.points()
    batch = simulate_many(state, pantograph, points, spacings=spacings, settings=settings, keep_histories=True,
                          progress=(lambda message: progress(f"{label}: {message}")) if progress else None)
    histories, loss, uplift = [], [], []
    for run in batch.runs:
        if not run.ok:
            p = run.point
            raise ConvergenceError(
                f"dynamic robust pre-sag: the run at {label}, {p.speed / KMH:g} km/h, F_stat {p.static_force:g} N "
                f"failed: {run.error}", {"presag_rel": presag_rel, "error": run.error})
        for j, stats in enumerate(run.statistics):
            filtered = lowpass_filter(run.time, run.contact_force[:, j], cutoff=settings.cutoff_frequency)
            histories.append(filtered[window_mask(run.time, stats.window_start, stats.window_end,
                                                  settings.cutoff_frequency)])
            loss.append(stats.loss_of_contact)
            uplift.append(run.uplift_max)
    return BandEvaluation(
        statistics=BandStatistics(
            presag_rel=presag_rel,
            mean_force=np.array([np.mean(h) for h in histories]),
            sigma=np.array([np.std(h) for h in histories]),
            uplift_max=np.array(uplift),
        ),
        histories=tuple(histories),
        loss_of_contact=np.array(loss),
        wall_time=wallclock.perf_counter() - started,
        warnings=tuple(dict.fromkeys(w for run in batch.runs for w in run.warnings)),
    )


def split_grid(grid: OperatingGrid, parts: int) -> tuple[OperatingGrid, ...]:
    """A grid's static forces dealt out over ``parts`` grids (every speed in each): the first, the
    (parts + 1)-th, … force to the first grid, and so on, so that the parts carry the same share of
    the band's forces and the same steps. As many parts as there are forces at most.

    Parameters
    ----------
    grid : OperatingGrid
        The grid.
    parts : int
        Grids wanted, at least 1. [-]
    """
    count = max(1, min(int(parts), len(grid.static_forces)))
    return tuple(replace(grid, static_forces=grid.static_forces[k::count]) for k in range(count))


def join_parts(grid: OperatingGrid, parts: tuple[OperatingGrid, ...], evaluations: list[BandEvaluation]
               ) -> BandEvaluation:
    """One pre-sag's evaluation over ``grid`` from its evaluations over the parts of :func:`split_grid`,
    in the grid's order of points (speed by speed, then static force; the pantographs of a run together).

    Parameters
    ----------
    grid : OperatingGrid
        The whole grid.
    parts : tuple of OperatingGrid
        Its parts, as evaluated.
    evaluations : list of BandEvaluation
        One per part, of the same pre-sag.
    """
    per_run = len(evaluations[0].statistics.sigma) // len(parts[0].points())  # pantographs of a run
    where = {}
    for k, part in enumerate(parts):
        for i, point in enumerate(part.points()):
            where[point.speed, point.static_force] = (k, i)
    order = [(k, i * per_run + p) for point in grid.points()
             for k, i in [where[point.speed, point.static_force]] for p in range(per_run)]

    def gathered(values: list[np.ndarray]) -> np.ndarray:
        return np.array([values[k][j] for k, j in order])

    statistics = [e.statistics for e in evaluations]
    return BandEvaluation(
        statistics=BandStatistics(
            presag_rel=statistics[0].presag_rel,
            mean_force=gathered([s.mean_force for s in statistics]),
            sigma=gathered([s.sigma for s in statistics]),
            uplift_max=gathered([s.uplift_max for s in statistics]),
        ),
        histories=tuple(evaluations[k].histories[j] for k, j in order),
        loss_of_contact=gathered([e.loss_of_contact for e in evaluations]),
        wall_time=max(e.wall_time for e in evaluations),
        warnings=tuple(dict.fromkeys(w for e in evaluations for w in e.warnings)),
    )


class BandEvaluator:
    """Simulates parabolic pre-sags over an operating grid, each pre-sag once.

    Parameters
    ----------
    catenary : Catenary
        System model (its pre-sag is replaced by each evaluated one).
    pantograph : Pantograph
        Pantograph model.
    grid : OperatingGrid
        The operating points; checked against the catenary here, before any work.
    settings : SimulationSettings, optional
        Numerical settings; default automatic numerics (element length and time step from the speed).
    workers : int
        Processes that simulate pre-sags side by side when several are asked for at once
        (:meth:`evaluate_many`), or the parts of one pre-sag's grid when fewer pre-sags than workers
        are asked for; 1 simulates in this process. [-]
    progress : callable, optional
        Called with a short message before each form-finding and after each batch of runs.
    spacings : tuple of float, optional
        Distances between consecutive pantographs of the train, front to rear (every pantograph of
        a run is then a point of the statistics). [m]

    Attributes
    ----------
    evaluations : dict
        S_rel -> :class:`BandEvaluation`, in the order simulated.
    runs_used : int
        Simulation runs so far. [-]

    Notes
    -----
    Used as a context manager (``with BandEvaluator(...) as evaluator:``), it keeps its worker
    processes from the first pre-sag it simulates with them to the end of the block, instead of
    starting them for every call (about a second each, importing and loading the compiled kernel);
    the workers are stopped with the block, also when it is interrupted.
    """

    def __init__(
        self,
        catenary: Catenary,
        pantograph: Pantograph,
        grid: OperatingGrid,
        *,
        settings: SimulationSettings | None = None,
        workers: int = 1,
        progress: Callable[[str], None] | None = None,
        spacings: tuple[float, ...] | None = None,
    ):
        if workers != int(workers) or not 1 <= workers <= 64:
            raise ModelError(f"workers = {workers} is outside the valid range [1, 64]")
        self.catenary = catenary
        self.pantograph = pantograph
        self.grid = grid
        self.settings = settings or SimulationSettings(numerics="auto")
        grid.check(catenary, pantograph, self.settings, spacings)
        self.static_settings = band_static_settings(catenary, grid.speeds, self.settings)
        self.workers = int(workers)
        self.progress = progress
        self.spacings = tuple(spacings) if spacings else None
        self.evaluations: dict[float, BandEvaluation] = {}
        self.runs_used = 0
        self._held: contextlib.ExitStack | None = None
        self._pool = None

    def __enter__(self) -> BandEvaluator:
        self._held = contextlib.ExitStack()
        return self

    def __exit__(self, *exc) -> bool:
        held, self._held, self._pool = self._held, None, None
        return bool(held is not None and held.__exit__(*exc))

    @property
    def reference_span(self) -> float:
        """Span the pre-sag is quoted on: the longest. [m]"""
        return float(max(self.catenary.layout.span_lengths))

    def __call__(self, presag_rel: float) -> BandEvaluation:
        """Simulate one pre-sag over the grid (or return it if simulated before); see
        :func:`simulate_band` for what it raises.

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel. [-]
        """
        return self.evaluate_many([presag_rel])[0]

    def evaluate_many(self, presags) -> list[BandEvaluation]:
        """Simulate several pre-sags (those not simulated before), side by side in up to
        :attr:`workers` processes; see :func:`simulate_band` for what it raises.

        Parameters
        ----------
        presags : sequence of float
            Relative pre-sags S_rel. [-]

        Returns
        -------
        list of BandEvaluation
            One per pre-sag, in order.
        """
        presags = [float(s) for s in presags]
        new = [s for s in dict.fromkeys(presags) if s not in self.evaluations]
        if self.workers == 1 or not new or (len(new) == 1 and len(self.grid.static_forces) == 1):
            for s in new:
                self._keep(s, simulate_band(*self._common, s, progress=self.progress, spacings=self.spacings))
            return [self.evaluations[s] for s in presags]
        parts = split_grid(self.grid, self.workers // len(new)) if len(new) < self.workers else (self.grid,)
        tasks = [(s, part) for s in new for part in parts]
        span = self.reference_span
        if self.progress:
            split = "" if len(parts) == 1 else f", each pre-sag's {len(self.grid.points())} runs in {len(parts)} parts"
            self.progress(f"S = {', '.join(f'{s * span * 1e3:.1f}' for s in new)} mm in "
                          f"{min(self.workers, len(tasks))} processes{split}")
        results = self._run_side_by_side(tasks)
        for k, s in enumerate(new):
            done = results[k * len(parts): (k + 1) * len(parts)]
            self._keep(s, done[0] if len(parts) == 1 else join_parts(self.grid, parts, done))
        return [self.evaluations[s] for s in presags]

    @property
    def _common(self) -> tuple:
        return self.catenary, self.pantograph, self.grid, self.settings, self.static_settings

    def _run_side_by_side(self, tasks: list[tuple[float, OperatingGrid]]) -> list[BandEvaluation]:
        """Each (pre-sag, grid) task in a worker process: the evaluator's own workers inside its
        ``with`` block, else a pool for this call."""
        catenary, pantograph, _, settings, static_settings = self._common

        def submitted(pool) -> list[BandEvaluation]:
            futures = [pool.submit(simulate_band, catenary, pantograph, grid, settings, static_settings, s, None,
                                   self.spacings) for s, grid in tasks]
            return [f.result() for f in futures]

        if self._held is None:
            with worker_pool(min(self.workers, len(tasks)), WorkerPolicy.PICKLED) as pool:
                return submitted(pool)
        if self._pool is None:
            self._pool = self._held.enter_context(worker_pool(self.workers, WorkerPolicy.PICKLED))
        return submitted(self._pool)

    def _keep(self, presag_rel: float, evaluation: BandEvaluation) -> None:
        self.evaluations[presag_rel] = evaluation
        self.runs_used += len(self.grid.static_forces) * len(self.grid.speeds)
