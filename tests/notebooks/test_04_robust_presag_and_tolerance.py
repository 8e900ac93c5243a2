"""Notebook 04 (robust pre-sag and tolerance) runs in fast mode and its headline holds."""


import pytest

pytestmark = pytest.mark.notebook


def test_runs_in_fast_mode_and_its_headline_holds(run_notebook):
    run_notebook("04_robust_presag_and_tolerance")
