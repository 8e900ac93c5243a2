"""Helpers of the notebook tests: each study has its own test file, so that pytest-xdist (one file per
worker) runs the five studies side by side instead of one after another on one worker."""

from __future__ import annotations

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOK_FOLDER = Path(__file__).resolve().parents[2] / "notebooks"

STUDIES = ["01_empirical_and_quasi_static", "02_dynamic_model_validation", "03_validity_study",
           "04_robust_presag_and_tolerance", "05_curved_track", "06_design_a_line", "07_sensitivity",
           "08_stitched_catenary"]


def run_in_fast_mode(stem: str, monkeypatch) -> None:
    """Execute ``notebooks/<stem>.ipynb`` in fast mode and check that its last cell says its headline holds."""
    path = NOTEBOOK_FOLDER / f"{stem}.ipynb"
    monkeypatch.setenv("PRESAG_NOTEBOOK_MODE", "fast")
    book = nbformat.read(path, as_version=4)
    NotebookClient(book, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(path.parent)}}).execute()
    last = book.cells[-1].outputs
    assert any("headline holds" in out.get("text", "") for out in last), last


@pytest.fixture
def run_notebook(monkeypatch):
    """:func:`run_in_fast_mode` for a notebook's stem."""
    return lambda stem: run_in_fast_mode(stem, monkeypatch)


@pytest.fixture
def studies() -> list[str]:
    """Stems of the five studies, in order."""
    return STUDIES
