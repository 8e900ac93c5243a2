"""Evaluating a sample design row by row: worker processes or Dask, a store, and failed rows kept apart.

:func:`evaluate_rows` runs a picklable function at every row of a design, in worker processes or on a
Dask cluster, and returns :class:`RowEvaluations` in row order, so that the indices do not depend on
the worker count. A row whose evaluation raises one of the package's errors (a form-finding that
does not converge, a sample the model refuses) or gives a non-finite value is a *failed*
evaluation: kept with its inputs and the one-line reason, its values NaN, and the others go on.
What a failure does to an estimate is the method's to say
(:func:`~presag_opt.sensitivity.methods.morris_indices` drops the trajectory,
:func:`~presag_opt.sensitivity.methods.sobol_indices` the base sample). With an
:class:`~presag_opt.evaluation_store.EvaluationStore` every finished or failed row is kept as it
arrives, and a rerun evaluates only the rows not yet kept. Every row's form-findings are counted
(:func:`presag_opt.static.solver_statistics.recording`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from concurrent.futures import as_completed
from dataclasses import dataclass

import numpy as np

from presag_opt.cluster import results_on_dask
from presag_opt.errors import ModelError, PresagError, failure_reason
from presag_opt.evaluation_store import Evaluation, EvaluationStore
from presag_opt.processes import WorkerPolicy, worker_pool
from presag_opt.sensitivity.inputs import SensitivityInput
from presag_opt.static.solver_statistics import FormFindingStatistics, recording, statistics_summary


@dataclass(frozen=True)
class RowEvaluations:
    """The evaluations of a design, in row order.

    Attributes
    ----------
    evaluations : tuple of Evaluation
        One per row (values by the names given, or ``value_0``, ``value_1``, …).
    value_names : tuple of str
        Names of the values, in the order of the columns of :attr:`values`.
    """

    evaluations: tuple[Evaluation, ...]
    value_names: tuple[str, ...]

    @property
    def values(self) -> np.ndarray:
        """Values of every row, shape (rows, values); NaN in a failed row. [units of the output]"""
        return np.array([[e.values.get(n, np.nan) if e.ok else np.nan for n in self.value_names]
                         for e in self.evaluations], dtype=float).reshape(len(self.evaluations), len(self.value_names))

    @property
    def failures(self) -> tuple[Evaluation, ...]:
        """The failed evaluations, in row order."""
        return tuple(e for e in self.evaluations if not e.ok)

    def solver_summary(self) -> dict:
        """Counts and quantiles of the rows' form-findings (:func:`~presag_opt.static.solver_statistics.statistics_summary`)."""
        return statistics_summary([FormFindingStatistics.from_dict(s) for e in self.evaluations
                                   for s in e.solver.get("form_findings", ())])


@dataclass(frozen=True)
class _Outcome:
    """What a worker returns for one row."""

    values: np.ndarray | None
    failure: str
    form_findings: tuple[FormFindingStatistics, ...]
    seconds: float


def evaluate_block(function: Callable[[np.ndarray], np.ndarray], rows: np.ndarray) -> list[_Outcome]:
    """``function`` at each row, in order, in this process (one task of :func:`evaluate_rows`).

    A row whose evaluation raises one of the package's errors, or gives a non-finite value, is a failed
    one (the reason kept); any other error (a defect, not a sample) is raised.

    Parameters
    ----------
    function : callable
        Maps one row to a 1-D array of outputs.
    rows : ndarray, shape (n, k)
        Input values. [SI units of the inputs]
    """
    out = []
    for row in rows:
        started = time.perf_counter()
        with recording() as found:
            try:
                values, failure = np.atleast_1d(np.asarray(function(row), dtype=float)), ""
                if not np.all(np.isfinite(values)):
                    values, failure = None, "the output has no finite value here"
            except PresagError as exc:
                values, failure = None, failure_reason(exc)
        out.append(_Outcome(values, failure, tuple(found), time.perf_counter() - started))
    return out


def evaluate_rows(function: Callable[[np.ndarray], np.ndarray], rows: np.ndarray, *,
                  inputs: Sequence[SensitivityInput] | None = None, value_names: Sequence[str] | None = None,
                  workers: int = 1, scheduler: str | None = None, chunk: int = 1,
                  progress: Callable[[str], None] | None = None,
                  store: EvaluationStore | None = None) -> RowEvaluations:
    """Evaluate ``function`` at every row, in worker processes or on a Dask cluster, results in row order.

    Parameters
    ----------
    function : callable
        Picklable; maps one row of input values to a 1-D array of outputs.
    rows : ndarray, shape (n, k)
        Input values. [SI units of the inputs]
    inputs : sequence of SensitivityInput, optional
        The inputs of the columns: a failed row's record gives its values by name in their display
        units (default ``x0``, ``x1``, … as given).
    value_names : sequence of str, optional
        Names of the function's outputs (default ``value_0``, ``value_1``, …).
    workers : int
        Processes; 1 runs here. [-]
    scheduler : str, optional
        Address of a Dask distributed scheduler to run the rows on instead of local processes.
    chunk : int
        Rows ``chunk·j … chunk·(j + 1) − 1`` run as one task, one after the other in one process, so
        that an evaluator can reuse work between consecutive rows (a Morris trajectory: ``k + 1``). [-]
    progress : callable, optional
        Called with a message (``"evaluations: done/total"``) after each task.
    store : EvaluationStore, optional
        Keeps each finished or failed row as it arrives; the rows it holds already are read back
        instead of evaluated.

    Returns
    -------
    RowEvaluations
    """
    if not 1 <= workers <= 1024:
        raise ModelError(f"workers = {workers} is outside the valid range [1, 1024]")
    if not 1 <= chunk <= max(1, len(rows)):
        raise ModelError(f"chunk = {chunk} is outside the valid range [1, {max(1, len(rows))}] rows")
    labels = ([(i.name, i.factor) for i in inputs] if inputs is not None
              else [(f"x{j}", 1.0) for j in range(rows.shape[1] if rows.ndim == 2 else 0)])
    results: dict[int, Evaluation] = store.read(range(len(rows))) if store is not None else {}
    pending = [i for i in range(len(rows)) if i not in results]
    tasks: dict[int, list[int]] = {}
    for i in pending:
        tasks.setdefault(i // chunk, []).append(i)
    done = len(rows) - len(pending)

    def finish(indices: list[int], outcomes: list[_Outcome]) -> None:
        nonlocal done
        for i, outcome in zip(indices, outcomes, strict=True):
            values = {}
            if outcome.values is not None:
                names = value_names or [f"value_{j}" for j in range(len(outcome.values))]
                values = dict(zip(names, map(float, outcome.values), strict=True))
            evaluation = Evaluation(
                index=i, inputs={name: float(v) / factor for (name, factor), v in zip(labels, rows[i])},
                values=values, failure=outcome.failure, seconds=outcome.seconds,
                solver={"form_findings": [s.to_dict() for s in outcome.form_findings]})
            results[i] = evaluation
            if store is not None:
                store.write(evaluation)
        done += len(indices)
        if progress:
            progress(f"evaluations: {done}/{len(rows)}")

    batches = [(indices, rows[indices]) for indices in tasks.values()]
    if scheduler is not None:
        for indices, outcomes in results_on_dask([(tuple(indices), (block,)) for indices, block in batches],
                                                 scheduler, function, evaluate_block):
            finish(list(indices), outcomes)
    elif workers == 1 or len(batches) <= 1:
        for indices, block in batches:
            finish(indices, evaluate_block(function, block))
    else:
        with worker_pool(min(workers, len(batches)), WorkerPolicy.PICKLED) as pool:
            futures = {pool.submit(evaluate_block, function, block): indices for indices, block in batches}
            for future in as_completed(futures):
                finish(futures[future], future.result())
    ordered = tuple(results[i] for i in range(len(rows)))
    if value_names is None:
        finished = next((e for e in ordered if e.ok), None)
        value_names = list(finished.values) if finished is not None else []
    return RowEvaluations(ordered, tuple(value_names))


__all__ = ["RowEvaluations", "evaluate_block", "evaluate_rows"]
