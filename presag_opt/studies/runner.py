"""Running a study: local worker processes or a Dask cluster, progress, resume, one writer.

:func:`run_study` checks the definition against any existing store, skips the units already on
disk, sends the rest to the workers, writes each finished unit as it arrives (see
:mod:`presag_opt.studies.store`) and, once every unit is on disk, assembles and writes the store.
Local workers are a :class:`concurrent.futures.ProcessPoolExecutor` started with ``spawn`` (a fork
of a process that runs the progress-bar thread could deadlock); a Dask scheduler address runs the
very same :func:`~presag_opt.studies.work.run_units` on that cluster instead. Only the parent process
writes files.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from concurrent.futures import as_completed
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from presag_opt.errors import ModelError
from presag_opt.processes import worker_pool
from presag_opt.studies.definition import StudyDefinition
from presag_opt.studies.store import (
    assemble,
    check_store,
    finished_units,
    load_unit,
    prepare_units,
    save_unit,
    write_store,
)
from presag_opt.studies.work import UnitResult, WorkUnit, all_units, run_units, task_groups


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
    progress: bool | None = None,
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
    progress : bool, optional
        Show a progress bar with ETA on standard error; default: only if standard error is a terminal.

    Returns
    -------
    StudyRun

    Raises
    ------
    ModelError
        Bad arguments, or a store or units directory written by a different definition (then nothing
        is changed on disk).
    """
    store = Path(store)
    if workers is not None and scheduler is not None:
        raise ModelError("give either local workers or a Dask scheduler, not both")
    if workers is not None and not 1 <= workers <= 1024:
        raise ModelError(f"workers = {workers} is outside the valid range [1, 1024]")
    if not store.parent.is_dir():
        raise ModelError(f"{store}: the folder {store.parent} does not exist")
    check_store(store, definition)
    folder = prepare_units(store, definition)
    units = all_units(definition)
    done = finished_units(folder)
    pending = [u for u in units if u.key not in done]
    forces = len(definition.grid.static_forces)
    show = sys.stderr.isatty() if progress is None else progress
    with tqdm(total=len(units) * forces, initial=(len(units) - len(pending)) * forces, unit="run",
              desc=definition.name[:40], file=sys.stderr, disable=not show, dynamic_ncols=True) as bar:
        source = _dask_results if scheduler is not None else _local_results
        for result in source(definition, pending, scheduler if scheduler is not None else workers):
            save_unit(folder, result)
            bar.update(forces)
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


def _local_results(definition: StudyDefinition, pending: list[WorkUnit], workers: object) -> Iterator[UnitResult]:
    """Results of the pending units from local worker processes, in the order they finish."""
    if not pending:
        return
    count = min(int(workers or os.cpu_count() or 1), len(pending))
    # An error or an interrupt drops the queued units and stops the workers (what is stored stays).
    with worker_pool(count, "spawn") as pool:
        futures = [pool.submit(run_units, definition, group) for group in task_groups(pending)]
        for future in as_completed(futures):
            yield from future.result()


def _dask_results(definition: StudyDefinition, pending: list[WorkUnit], address: object) -> Iterator[UnitResult]:
    """Results of the pending units from a Dask distributed cluster, in the order they finish."""
    if not pending:
        return
    try:
        from distributed import Client, as_completed as dask_completed
    except ImportError:
        raise ModelError("--scheduler needs Dask distributed: pip install 'presag-opt[cluster]'") from None
    try:
        client = Client(str(address), timeout="20s")
    except (OSError, TimeoutError) as exc:
        raise ModelError(f"scheduler {address}: cannot connect ({str(exc).splitlines()[0]})") from None
    with client:
        scattered = client.scatter(definition, broadcast=True)
        futures = [client.submit(run_units, scattered, group, pure=False) for group in task_groups(pending)]
        try:
            for future in dask_completed(futures):
                yield from future.result()
        finally:
            client.cancel(futures)
