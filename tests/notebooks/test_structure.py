"""The studies in notebooks/: all six there, committed without outputs, each documenting its modes and
ending with a cell that asserts its headline (each is run in fast mode by its own test file here; the
README's test command runs them, as CI does)."""

from __future__ import annotations

from pathlib import Path

import nbformat
import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[2] / "notebooks").glob("*.ipynb"))


def test_the_six_studies_are_there(studies):
    assert [p.stem for p in NOTEBOOKS] == studies


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_is_committed_without_outputs_and_documents_its_modes(path):
    book = nbformat.read(path, as_version=4)
    code = [c for c in book.cells if c.cell_type == "code"]
    assert all(c.outputs == [] and c.execution_count is None for c in code), "clear the outputs before committing"
    first = book.cells[0]
    assert first.cell_type == "markdown" and "PRESAG_NOTEBOOK_MODE" in first.source
    assert "fast" in first.source and "full" in first.source
    assert "assert" in code[-1].source and "headline holds" in code[-1].source
