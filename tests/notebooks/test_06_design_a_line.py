"""Notebook 06 (design a line) runs in fast mode and its headline holds."""


import pytest

pytestmark = pytest.mark.notebook


def test_runs_in_fast_mode_and_its_headline_holds(run_notebook):
    run_notebook("06_design_a_line")
