"""The studies in notebooks/: committed without outputs, each documents its modes, and each runs in
fast mode and passes its closing assertion (the README's test command runs them, as CI does)."""

from __future__ import annotations

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))

STUDIES = ["01_empirical_and_quasi_static", "02_dynamic_model_validation", "03_validity_study",
           "04_robust_presag_and_tolerance", "05_curved_track"]


def test_the_five_studies_are_there():
    assert [p.stem for p in NOTEBOOKS] == STUDIES


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_is_committed_without_outputs_and_documents_its_modes(path):
    book = nbformat.read(path, as_version=4)
    code = [c for c in book.cells if c.cell_type == "code"]
    assert all(c.outputs == [] and c.execution_count is None for c in code), "clear the outputs before committing"
    first = book.cells[0]
    assert first.cell_type == "markdown" and "PRESAG_NOTEBOOK_MODE" in first.source
    assert "fast" in first.source and "full" in first.source
    assert "assert" in code[-1].source and "headline holds" in code[-1].source


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs_in_fast_mode_and_its_headline_holds(path, monkeypatch):
    monkeypatch.setenv("PRESAG_NOTEBOOK_MODE", "fast")
    book = nbformat.read(path, as_version=4)
    NotebookClient(book, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(path.parent)}}).execute()
    last = book.cells[-1].outputs
    assert any("headline holds" in out.get("text", "") for out in last), last
