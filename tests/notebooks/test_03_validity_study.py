"""Notebook 03 (validity study) runs in fast mode and its headline holds."""


import pytest

pytestmark = pytest.mark.notebook


def test_runs_in_fast_mode_and_its_headline_holds(run_notebook):
    run_notebook("03_validity_study")
