"""``presag sweep`` and ``presag validity`` (``presag_opt.cli.studies``): the ``--select`` grammar and the
refusals made before any work. The validity command's output on synthetic stores whose answer is known
is tested beside those stores, in ``tests/studies/test_validity_analysis.py``; a sweep end to end in
``tests/studies/test_runner.py`` and the catalogue of its refusals in ``tests/cli/test_cli_refusals.py``."""

from __future__ import annotations

import pytest

from presag_opt.cli import main
from presag_opt.cli.studies import _selection
from presag_opt.errors import ModelError


def test_select_reads_name_equals_value_in_si():
    assert _selection(["catenary.contact_wire.tension = 9800", "settings.time_step=2e-3"]) == {
        "catenary.contact_wire.tension": 9800.0, "settings.time_step": 0.002}
    assert _selection([]) == {}


@pytest.mark.parametrize("item", ["tension", "tension=", "tension=high", "=9800x"])
def test_a_select_without_a_number_is_one_line_naming_it(item):
    with pytest.raises(ModelError) as caught:
        _selection([item])
    assert str(caught.value) == f"--select {item!r}: write NAME=VALUE with a number in SI units"


def test_a_sweep_onto_a_folder_is_refused_before_the_study_runs(tmp_path, capsys):
    assert main(["sweep", "paper_grid_st98", "--out", str(tmp_path), "--quiet"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err == f"presag: error: {tmp_path}: is a folder; give a file name such as {tmp_path / 'study.nc'}\n"


def test_validity_of_a_missing_store_is_one_line(presag, tmp_path):
    proc = presag("validity", str(tmp_path / "none.nc"), "--json")
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "no such study store" in proc.stderr

