"""Notebook 01 (empirical and quasi-static pre-sag) runs in fast mode and its headline holds."""


import pytest

pytestmark = pytest.mark.notebook


def test_runs_in_fast_mode_and_its_headline_holds(run_notebook):
    run_notebook("01_empirical_and_quasi_static")
