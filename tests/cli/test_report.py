"""``presag report`` (``presag_opt.cli.report``): bad input is one line before any work. The report it
writes is tested in ``tests/report/`` (written once there by the ``case_study_report`` fixture)."""

from __future__ import annotations

import pytest

from presag_opt.cli import main


def test_bad_input_on_the_command_line_is_one_line(presag, tmp_path):
    result = presag("report", "no_such_model", "--out", "r", cwd=tmp_path)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    (line,) = result.stderr.strip().splitlines()
    assert line.startswith("presag: error: ") and "neither a file nor a built-in catenary model" in line



@pytest.mark.parametrize(("args", "words"), [
    (["--out", "{tmp}/file.txt"], "--out {tmp}/file.txt: is a file; give a folder"),
    (["--out", "{tmp}/r", "--within", "ten"], "--within"),
    (["--out", "{tmp}/r", "--static-force", "150:70"], "static_force_low = 150 N is above static_force_high = 70 N"),
    (["--out", "{tmp}/r", "--max-speed", "300"], "speed = 300 km/h is β = 0.87"),
])
def test_the_options_are_checked_before_the_report_is_computed(tmp_path, capsys, args, words):
    """Each refusal returns at once (the report's work would take tens of seconds even with --quick)."""
    (tmp_path / "file.txt").write_text("x")
    assert main(["report", "--quick", *[a.format(tmp=tmp_path) for a in args]]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert captured.err.startswith("presag: error: ") and words.format(tmp=tmp_path) in captured.err
