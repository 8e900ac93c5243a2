"""Evaluating a design row by row: the store read back, a failed row kept with its inputs and reason while
the others go on, an error that is not the package's raised, chunks and Dask giving the rows in order."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.evaluation_store import EvaluationStore
from presag_opt.sensitivity.evaluation import evaluate_rows
from presag_opt.sensitivity.methods import morris_design
from presag_opt.sensitivity.reference import ishigami
from tests.sensitivity.test_methods import ISHIGAMI


def test_a_store_keeps_every_evaluation_and_a_rerun_reads_it_back(tmp_path):
    rows = morris_design(ISHIGAMI, 4, seed=2)
    store = EvaluationStore.open(tmp_path / "s", "key-a")
    first = evaluate_rows(ishigami, rows, inputs=ISHIGAMI, store=store)
    assert len(list((tmp_path / "s").glob("evaluation_*.json"))) == len(rows)
    # a function that would fail proves nothing is recomputed
    again = evaluate_rows(lambda row: 1 / 0, rows, store=EvaluationStore.open(tmp_path / "s", "key-a"))
    assert np.array_equal(again.values, first.values)
    with pytest.raises(ModelError, match="holds the evaluations of another analysis"):
        EvaluationStore.open(tmp_path / "s", "key-b")


def fails_in_the_corner(row):
    """Ishigami, except where x1 and x2 are both above 1: a solver that does not converge there."""
    if row[0] > 1.0 and row[1] > 1.0:
        raise ConvergenceError("form-finding did not converge: IPOPT status 'Maximum_Iterations_Exceeded'\ndetail")
    return ishigami(row)


def test_a_failed_evaluation_is_kept_with_its_inputs_and_reason_and_the_others_go_on(tmp_path):
    rows = morris_design(ISHIGAMI, 20, seed=4)
    corner = (rows[:, 0] > 1.0) & (rows[:, 1] > 1.0)
    assert 0 < corner.sum() < len(rows)  # the design reaches the corner, not only it
    store = EvaluationStore.open(tmp_path / "s", "corner")
    done = evaluate_rows(fails_in_the_corner, rows, inputs=ISHIGAMI, value_names=["f"], workers=2, store=store)
    assert [e.index for e in done.failures] == list(np.flatnonzero(corner))
    first = done.failures[0]
    assert first.failure == "form-finding did not converge: IPOPT status 'Maximum_Iterations_Exceeded'"
    assert first.inputs == pytest.approx(dict(zip(["x1", "x2", "x3", "x4"], rows[first.index])), abs=0.0)
    assert np.all(np.isnan(done.values[corner])) and np.all(np.isfinite(done.values[~corner]))
    # a rerun reads the failures back too: the same inputs with the same code fail the same way
    again = evaluate_rows(lambda row: 1 / 0, rows, value_names=["f"], store=EvaluationStore.open(tmp_path / "s", "corner"))
    assert [e.index for e in again.failures] == [e.index for e in done.failures]
    # an error that is not the package's is a defect, not a sample: it is raised
    with pytest.raises(ZeroDivisionError):
        evaluate_rows(lambda row: 1 / 0, rows[:2])


@pytest.mark.e2e  # worker processes and a Dask cluster
def test_chunks_and_a_dask_cluster_give_the_rows_in_order():
    """Rows run in chunks (one task each) and on a Dask cluster come back as evaluated one by one."""
    distributed = pytest.importorskip("distributed")
    rows = morris_design(ISHIGAMI, 3, seed=1)
    one = evaluate_rows(ishigami, rows).values
    done = []
    chunked = evaluate_rows(ishigami, rows, chunk=5, workers=2, progress=done.append).values
    assert np.array_equal(chunked, one)
    assert done[-1] == f"evaluations: {len(rows)}/{len(rows)}" and len(done) == -(-len(rows) // 5)  # one call per chunk
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster:
        on_dask = evaluate_rows(ishigami, rows, scheduler=cluster.scheduler_address, chunk=4).values
    assert np.array_equal(on_dask, one)
    with pytest.raises(ModelError, match=r"chunk = 0 is outside the valid range \[1, 15\] rows"):
        evaluate_rows(ishigami, rows, chunk=0)
