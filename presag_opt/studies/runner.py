"""Running a study: local worker processes or a Dask cluster, progress, resume, one writer.

:func:`run_study` checks the definition against any existing store, skips the units already on
disk, sends the rest to the workers, writes each finished unit as it arrives (see
:mod:`presag_opt.studies.store`) and, once every unit is on disk, assembles and writes the store.
Local workers come from :func:`~presag_opt.processes.worker_pool` (its policy chooses how they
start; they stop with the command, even one killed with SIGKILL); a Dask scheduler address runs the
very same :func:`~presag_opt.studies.work.run_units` on that cluster instead (a lost Dask worker's
units are run again elsewhere by the scheduler). Only the parent process writes files, and only one
command at a time per store (:func:`~presag_opt.studies.store.hold_store`).
"""

from __future__ import annotations

import operator
import os
from collections.abc import Callable, Iterator
from concurrent.futures import as_completed
from dataclasses import dataclass
from pathlib import Path

from presag_opt.cluster import results_on_dask
from presag_opt.dynamics.cost import WorkEstimate
from presag_opt.errors import ModelError
from presag_opt.processes import WorkerPolicy, run_job, worker_pool
from presag_opt.speed import check_speed_limit
from presag_opt.studies.definition import StudyDefinition
from presag_opt.studies.store import (
    assemble,
    check_store,
    finished_units,
    hold_store,
    load_unit,
    prepare_units,
    save_unit,
    units_directory,
    write_store,
)
from presag_opt.studies.work import (
    UnitResult,
    UnitRunner,
    WorkUnit,
    all_units,
    task_groups,
)


@dataclass(frozen=True, kw_only=True)
class StudyRun:
    """What :func:`run_study` did.

    Attributes
    ----------
    store : pathlib.Path
        The netCDF store written.
    units_total : int
        Units of the study. [-]
    units_computed : int
        Units computed in this call (the others were on disk already). [-]
    runs_total : int
        Simulation runs of the study. [-]
    runs_failed : int
        Runs that did not finish (NaN in the store, with their reason). [-]
    """

    store: Path
    units_total: int
    units_computed: int
    runs_total: int
    runs_failed: int


def run_study(
    definition: StudyDefinition,
    store: str | Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[str], None] | None = None,
    allow_supercritical: bool = False,
) -> StudyRun:
    """Run (or resume) a study and write its store.

    Parameters
    ----------
    definition : StudyDefinition
        The study.
    store : str or pathlib.Path
        Output netCDF file; its units directory is ``<store>.units`` beside it.
    workers : int, optional
        Local worker processes; default: the CPU count (at most the number of pending units).
        Not with ``scheduler``. [-]
    scheduler : str, optional
        Address of a Dask distributed scheduler (e.g. ``tcp://10.0.0.5:8786``) to run the units on.
    progress : callable, optional
        Called with a short message before the first pending unit and after each finished one.
    allow_supercritical : bool
        Accept speeds at or above the EN 50119 limit β = 0.7 (see :func:`~presag_opt.speed.check_speed_limit`).

    Returns
    -------
    StudyRun

    Raises
    ------
    ModelError
        Bad arguments, a speed at or above β = 0.7 not accepted, a store or units directory written
        by a different definition (then nothing is changed on disk), or another command running the
        same store.
    StorageError
        A file cannot be written; the units finished so far are kept, and the same call resumes.
    """
    store = Path(store)
    if workers is not None and scheduler is not None:
        raise ModelError("give either local workers or a Dask scheduler, not both")
    if workers is not None and not 1 <= workers <= 1024:
        raise ModelError(f"workers = {workers} is outside the valid range [1, 1024]")
    if progress is not None and not callable(progress):
        raise ModelError(f"progress = {progress!r} must be a callable taking a message, or None")
    check_study_path(store)
    check_study_speeds(definition, allow_supercritical)
    check_store(store, definition)
    with hold_store(store):
        folder = prepare_units(store, definition)
        units = all_units(definition)
        done = finished_units(folder)
        pending = [u for u in units if u.key not in done]
        runs = len(definition.grid.static_forces)
        finished = len(units) - len(pending)
        if progress and pending:
            progress(f"{definition.name[:40]}: {finished * runs}/{len(units) * runs} runs")
        source = _dask_results if scheduler is not None else _local_results
        for result in source(definition, pending, scheduler if scheduler is not None else workers):
            save_unit(folder, result)
            finished += 1
            if progress:
                progress(f"{definition.name[:40]}: {finished * runs}/{len(units) * runs} runs")
        results = [load_unit(folder, u) for u in units]
        dataset = assemble(definition, results)
        write_store(dataset, store)
    return StudyRun(
        store=store,
        units_total=len(units),
        units_computed=len(pending),
        runs_total=definition.run_count,
        runs_failed=int(dataset["failed"].sum()),
    )


def check_study_path(store: Path) -> None:
    """Refuse a store path whose folder is missing or a file, or that is itself a folder.

    Raises
    ------
    ModelError
        One line naming the path.
    """
    if store.parent.exists() and not store.parent.is_dir():
        raise ModelError(f"{store}: {store.parent} is a file, not a folder; give another output path")
    if not store.parent.is_dir():
        raise ModelError(f"{store}: the folder {store.parent} does not exist")
    if store.is_dir():
        raise ModelError(f"{store}: is a folder; give a file name such as {store / 'study.nc'}")


def check_study_speeds(definition: StudyDefinition, allow_supercritical: bool = False) -> None:
    """Refuse a study whose fastest speed is at or above β = 0.7 on any of its catenaries, unless
    accepted (see :func:`~presag_opt.speed.check_speed_limit`)."""
    if allow_supercritical:
        return
    fastest = max(definition.grid.speeds)
    for variant in definition.variants():
        check_speed_limit(fastest, variant.catenary.contact_wire.wave_speed,
                          accept="--allow-supercritical (allow_supercritical=True)")


def estimate_study(definition: StudyDefinition, store: str | Path, *, workers: int | None = None) -> WorkEstimate:
    """Time and memory of the units of a study not yet on disk, run on ``workers`` local processes.

    Parameters
    ----------
    definition : StudyDefinition
        The study.
    store : str or pathlib.Path
        Its netCDF store (units already finished beside it are not counted).
    workers : int, optional
        Local worker processes; default the CPU count. [-]

    Returns
    -------
    WorkEstimate
        Wall time with the workers side by side, and the memory of all of them together (see
        :mod:`presag_opt.dynamics.cost` for the rates).
    """
    from presag_opt.dynamics.cost import (
        BASE_MEMORY,
        BATCH_SECONDS_PER_NODE_STEP,
        FORM_FINDING_BYTES_PER_NODE,
    )
    from presag_opt.dynamics.run_plan import plan_run
    from presag_opt.static.run_time import form_find_estimate

    folder = units_directory(Path(store))
    done = finished_units(folder) if folder.is_dir() else set()
    pending = [u for u in all_units(definition) if u.key not in done]
    grid = definition.grid
    nodes, form_finding, run_seconds, memory = [], 0.0, 0.0, 0.0
    for group in task_groups(pending):
        variant = definition.variant(group[0].parameter_indices)
        presag = grid.presags[group[0].presag_index]
        catenary = variant.catenary.with_presag(presag / max(variant.catenary.layout.span_lengths))
        found = set()
        for unit in group:
            # automatic numerics: each speed's element length is its own form-finding (run_units)
            static = variant.settings.for_speed(grid.speeds[unit.speed_index], catenary.contact_wire.wave_speed).static
            n_nodes, seconds = form_find_estimate(catenary, static)
            if static not in found:
                found.add(static)
                nodes.append(n_nodes)
                form_finding += seconds
                memory = max(memory, BASE_MEMORY + FORM_FINDING_BYTES_PER_NODE * n_nodes)
            plan = plan_run(catenary, variant.pantograph, speed=grid.speeds[unit.speed_index],
                            static_force=grid.static_forces[0], aero_coefficient=grid.aero_coefficient,
                            spacings=variant.train.spacings, settings=variant.settings)
            steps = plan.step_count(plan.settings.integrator.time_step)
            run_seconds += BATCH_SECONDS_PER_NODE_STEP * n_nodes * steps * len(grid.static_forces)
    count = max(1, min(int(workers or os.cpu_count() or 1), len(pending) or 1))
    return WorkEstimate(nodes=tuple(sorted(set(nodes))), form_finding_seconds=form_finding / count,
                        runs=len(pending) * len(grid.static_forces), run_seconds=run_seconds / count,
                        memory=memory * count)


def _local_results(definition: StudyDefinition, pending: list[WorkUnit], workers: object) -> Iterator[UnitResult]:
    """Results of the pending units from local worker processes, in the order they finish."""
    if not pending:
        return
    count = min(int(workers or os.cpu_count() or 1), len(pending))
    # An error or an interrupt drops the queued units and stops the workers (what is stored stays).
    with worker_pool(count, WorkerPolicy.PICKLED, job=UnitRunner()) as pool:
        futures = [pool.submit(run_job, definition, group) for group in task_groups(pending)]
        for future in as_completed(futures):
            yield from future.result()


def _dask_results(definition: StudyDefinition, pending: list[WorkUnit], address: object) -> Iterator[UnitResult]:
    """Results of the pending units from a Dask distributed cluster, in the order they finish (a unit
    whose worker dies is run again by the scheduler)."""
    tasks = [(None, (definition, group)) for group in task_groups(pending)]
    for _, unit_results in results_on_dask(tasks, str(address), UnitRunner(), operator.call):
        yield from unit_results
