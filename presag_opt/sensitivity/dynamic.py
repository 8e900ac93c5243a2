"""Dynamic outputs of a sensitivity analysis, run through the studies machinery.

Every sample of the design becomes a reduced validity study (:func:`presag_opt.studies.reduced.reduced_study`)
of its own catenary, pantograph and operating point. Their units run together on local worker
processes or a Dask cluster (:func:`run_definitions`); with ``out`` each sample's units are kept in
``OUT/sample_NNNNN.nc.units`` as a study store keeps them (:mod:`presag_opt.studies.store`), so a
killed analysis resumes where it stopped and a finished one is read back without computing. A
run's result depends on its inputs alone, so neither the order nor the worker count changes a number.

Outputs (:class:`DynamicOutput`):

- ``dynamic``: σ [N] and σ/F_m [-] of the front pantograph at the model's pre-sag and static force,
  at each given speed;
- ``minima``: at one speed, over pre-sags 30/50/70 mm and static forces 50–150 N (25 N steps), how
  distinct the minimum of σ/F_m over F_m is (its mean rise to the lower end of the curve, the share of
  pre-sags with a distinct minimum) and whether the minima of σ/F_m and of σ move with S (1 if
  distinct at two pre-sags or more with locations rising by more than :data:`MOVE_THRESHOLD`, else 0);
- ``validity``: β* of the validity analysis over pre-sags 30/50/70 mm, the given speeds and static
  forces 65–155 N (30 N steps), censored at the grid's lowest or highest β when it lies outside.
"""

from __future__ import annotations

import dataclasses
import operator
from collections.abc import Callable, Sequence
from concurrent.futures import as_completed
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from presag_opt.cluster import results_on_dask
from presag_opt.errors import ModelError
from presag_opt.processes import WorkerPolicy, run_job, worker_pool
from presag_opt.sensitivity.inputs import apply_inputs
from presag_opt.studies.definition import StudyDefinition
from presag_opt.studies.reduced import reduced_study
from presag_opt.studies.store import (
    assemble,
    check_store,
    finished_units,
    load_unit,
    prepare_units,
    save_unit,
)
from presag_opt.studies.validity_analysis import validity_analysis
from presag_opt.studies.work import UnitRunner, all_units, task_groups
from presag_opt.units import KMH

MOVE_THRESHOLD = 5.0
"""Rise of the optimal F_m between the smallest and largest pre-sag above which a minimum "moves". [N]"""

MINIMA_PRESAGS = (0.030, 0.050, 0.070)
"""Pre-sags of the ``minima`` and ``validity`` outputs (the paper's grid ends and middle). [m]"""

MINIMA_FORCES = (50.0, 75.0, 100.0, 125.0, 150.0)
"""Static forces of the ``minima`` output: the span of the paper's grid (50–155 N) in five steps. [N]"""

VALIDITY_FORCES = (65.0, 95.0, 125.0, 155.0)
"""Static forces of the ``validity`` output. [N]"""


@dataclass(frozen=True, kw_only=True)
class Resolution:
    """Numerical resolution of the dynamic outputs (a reduced study; see :mod:`presag_opt.studies.reduced`).

    Attributes
    ----------
    span_count : int
        Central spans kept (one lead-in, one analysed). [-]
    element_length : float
        Longest element. [m]
    time_step : float
        Integration time step. [s]
    """

    span_count: int = 5
    element_length: float = 1.0
    time_step: float = 4e-3

    def text(self) -> str:
        """Short description, e.g. ``5 spans, 1 m elements, 4 ms``."""
        return f"{self.span_count} spans, {self.element_length:g} m elements, {self.time_step * 1e3:g} ms"


@dataclass(frozen=True, kw_only=True)
class DynamicOutput:
    """A dynamic output: what each sample's study is and which values are read from it.

    Attributes
    ----------
    kind : {"dynamic", "minima", "validity"}
        See the module notes.
    speeds : tuple of float
        Speeds. [m/s]
    resolution : Resolution
        Numerics of the runs.
    """

    kind: str
    speeds: tuple[float, ...]
    resolution: Resolution = Resolution()

    def __post_init__(self) -> None:
        if self.kind not in ("dynamic", "minima", "validity"):
            raise ModelError(f"dynamic output kind {self.kind!r} is not one of dynamic, minima, validity")
        if not self.speeds or (self.kind == "minima" and len(self.speeds) != 1):
            raise ModelError(f"output {self.kind}: give {'one speed' if self.kind == 'minima' else 'speeds'}")
        if self.kind == "validity" and len(self.speeds) < 2:
            raise ModelError("output validity: give at least two speeds (beta* lies between two of them)")

    @property
    def value_names(self) -> tuple[tuple[str, str], ...]:
        """(name, unit) of each value read from a sample's study."""
        if self.kind == "dynamic":
            return tuple(pair for v in self.speeds for pair in
                         ((f"sigma@{v / KMH:g}kmh", "N"), (f"sigma_over_F_m@{v / KMH:g}kmh", "-")))
        if self.kind == "minima":
            return (("ratio_rise", "-"), ("ratio_distinct_share", "-"), ("ratio_moves", "-"), ("sigma_moves", "-"))
        return (("beta_star", "-"), ("beta_star_censored", "-"))

    def definition(self, base: StudyDefinition, roots: dict, names: Sequence[str], row: np.ndarray) -> StudyDefinition:
        """The reduced study of one sample (its inputs applied to the model).

        Parameters
        ----------
        base : StudyDefinition
            The study the sample's is reduced from (:func:`base_study`).
        roots : dict
            Root name -> model object the inputs are applied to.
        names : sequence of str
            Input names, in the order of ``row``.
        row : ndarray, shape (k,)
            The sample's input values. [SI units of the inputs]
        """
        model = apply_inputs(roots, dict(zip(names, (float(v) for v in row))))
        operation = model["operation"]
        if self.kind == "dynamic":
            presags = (model["catenary"].presag_rel * max(model["catenary"].layout.span_lengths),)
            forces = (operation.static_force,)
        else:
            presags, forces = MINIMA_PRESAGS, MINIMA_FORCES if self.kind == "minima" else VALIDITY_FORCES
        r = self.resolution
        return reduced_study(base, presags=presags, speeds=self.speeds, static_forces=forces,
                             catenary=model["catenary"], pantograph=model["pantograph"],
                             aero_coefficient=operation.aero_coefficient, span_count=r.span_count,
                             element_length=r.element_length, time_step=r.time_step)

    def values(self, dataset: xr.Dataset) -> np.ndarray:
        """The output values of one sample's study dataset."""
        if self.kind == "dynamic":
            sigma = dataset["sigma"].values[0, :, 0]
            ratio = dataset["sigma_over_F_m"].values[0, :, 0]
            return np.ravel(np.column_stack([sigma, ratio]))
        if self.kind == "minima":
            ratio = dataset["sigma_over_F_m"].values[:, 0, :]
            sigma = dataset["sigma"].values[:, 0, :]
            dataset["F_m"].values[:, 0, :]
            rises = [_rise(y) for y in ratio]
            return np.array([float(np.mean(rises)), float(np.mean([r > 0.0 for r in rises])),
                             _moves(validity_analysis(dataset), "ratio"), _moves(validity_analysis(dataset), "sigma")])
        result = validity_analysis(dataset)
        betas = sorted(float(b) for b in dataset["beta"].isel(presag=0).values)
        if result.beta_limit is not None:
            return np.array([result.beta_limit, 0.0])
        holds_somewhere = any(v.holds for v in result.per_beta)
        return np.array([betas[-1] if holds_somewhere else betas[0], 1.0])


def _rise(y: np.ndarray) -> float:
    """Rise of a curve from its smallest grid value to the lower of its two ends (0 if the minimum is at an end). [-]"""
    i = int(np.nanargmin(y))
    if i in (0, len(y) - 1) or not np.all(np.isfinite(y)):
        return 0.0
    return float(min(y[0], y[-1]) / y[i] - 1.0)


def _moves(result, which: str) -> float:
    """1 if the minimum over F_m (of ``which``) is distinct at two pre-sags or more and rises with S by more than the threshold."""
    located = [(o.presag, getattr(o, which).location) for o in result.force_optima if getattr(o, which).distinct]
    if len(located) < 2:
        return 0.0
    located.sort()
    return float(located[-1][1] - located[0][1] > MOVE_THRESHOLD)


def run_definitions(definitions: Sequence[StudyDefinition], *, out: str | Path | None = None, workers: int = 1,
                    scheduler: str | None = None,
                    progress: Callable[[str], None] | None = None) -> list[xr.Dataset]:
    """Run the studies of all samples together and return their datasets, in sample order.

    Parameters
    ----------
    definitions : sequence of StudyDefinition
        One study per sample.
    out : str or Path, optional
        Folder of the resumable per-sample stores (created if missing); None keeps nothing on disk.
    workers : int
        Local worker processes (1 runs here). [-]
    scheduler : str, optional
        Address of a Dask distributed scheduler instead of local workers.
    progress : callable, optional
        Called with a message (``"runs: done/total"``) after each task.
    """
    folders: list[Path | None] = []
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        for i, definition in enumerate(definitions):
            store = out / f"sample_{i:05d}.nc"
            check_store(store, definition)
            folders.append(prepare_units(store, definition))
    else:
        folders = [None] * len(definitions)
    results: list[dict] = [{} for _ in definitions]
    tasks = []
    for i, (definition, folder) in enumerate(zip(definitions, folders)):
        done = finished_units(folder) if folder is not None else set()
        for unit in all_units(definition):
            if unit.key in done:
                results[i][unit.key] = load_unit(folder, unit)
        pending = [u for u in all_units(definition) if u.key not in done]
        tasks += [(i, group) for group in task_groups(pending)]
    total = sum(d.run_count for d in definitions)
    finished = total - sum(len(g) * len(definitions[i].grid.static_forces) for i, g in tasks)

    def collect(i: int, unit_results: list) -> None:
        nonlocal finished
        for result in unit_results:
            if folders[i] is not None:
                save_unit(folders[i], result)
            results[i][result.unit.key] = result
        finished += len(unit_results) * len(definitions[i].grid.static_forces)
        if progress:
            progress(f"runs: {finished}/{total}")

    if scheduler is not None:
        for i, unit_results in results_on_dask([(i, (definitions[i], group)) for i, group in tasks], scheduler,
                                               UnitRunner(), operator.call):
            collect(i, unit_results)
    elif workers == 1 or len(tasks) <= 1:
        runner = UnitRunner()
        for i, group in tasks:
            collect(i, runner(definitions[i], group))
    else:
        with worker_pool(min(workers, len(tasks)), WorkerPolicy.PICKLED, job=UnitRunner()) as pool:
            futures = {pool.submit(run_job, definitions[i], group): i for i, group in tasks}
            for future in as_completed(futures):
                collect(futures[future], future.result())
    return [assemble(d, [results[i][u.key] for u in all_units(d)]) for i, d in enumerate(definitions)]


def base_study(case) -> StudyDefinition:
    """The study a case's samples are reduced from: the paper's grid with the case's models and settings.

    Parameters
    ----------
    case : SimulationCase
        The case (its pantograph, settings and operation's α_ae are taken).
    """
    from presag_opt.studies.definition import load_study

    base = load_study("paper_grid_st98")
    # the catenary is set per sample by reduced_study (the paper's section stays here only to be valid)
    return dataclasses.replace(base, pantograph=case.pantograph, settings=case.settings,
                               grid=dataclasses.replace(base.grid, aero_coefficient=case.operation.aero_coefficient))
