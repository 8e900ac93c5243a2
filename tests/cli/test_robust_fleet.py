"""``presag robust --dynamic --pantograph A,B`` (the fleet design): its input checks, before any work
(in-process). The design itself is tested at the API (tests/robust/test_fleet.py)."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--pantograph", "case_study_2mass_friction,en50318_2mass", "--fleet-shares", "1,2,3"],
         "--fleet-shares 1,2,3: give 2 non-negative shares, one per --pantograph type"),
        (["--pantograph", "case_study_2mass_friction,en50318_2mass", "--fleet-shares", "0,0"],
         "not all zero"),
        (["--pantograph", "case_study_2mass_friction,case_study_2mass_friction"], "repeat a name"),
        (["--pantograph", "case_study_2mass_friction,en50318_2mass", "--plot", "f.png"], "--plot is not drawn for a fleet"),
    ],
)
def test_bad_fleet_input_is_one_line(presag, tmp_path, args, message):
    result = presag("robust", "--dynamic", *args, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], result.stderr


def test_fleet_options_need_dynamic(presag, tmp_path):
    result = presag("robust", "--second-pantograph-at", "20", cwd=tmp_path)
    assert result.returncode == 2
    assert "--second-pantograph-at is an option of the dynamic design; add --dynamic" in result.stderr
