"""``presag design`` (presag_opt.cli.line) refuses bad decision options before any work, in-process; the whole
command runs in tests/cli/test_design.py."""

from __future__ import annotations

import time

import pytest


@pytest.mark.parametrize(("args", "message"), [
    (["--within", "0"], "within = 0 % is outside the valid range (0, 200] %"),
    (["--uplift-limit", "0.5"], "uplift_limit = 0.5 mm is outside the valid range [1, 1000] mm"),
    (["--crew-tolerance", "80"], "crew tolerance = 80 mm is outside the valid range [0, 50] mm"),
])
def test_bad_decision_options_are_refused_before_any_work(presag, tmp_path, args, message):
    survey = tmp_path / "line.csv"
    survey.write_text("mast,chainage_m,stagger_mm,contact_wire_height_m,system_height_m,curve_radius_m,steady_arm\n"
                      + "\n".join(f"M{i},{50.0 * i},{300 if i % 2 else -300},5.5,1.2,0,pull-off" for i in range(6))
                      + "\n")
    started = time.monotonic()
    run = presag("design", str(survey), "--system", "st_9.8_ideal", "--out", "out", *args, cwd=tmp_path)
    assert run.returncode == 2 and message in run.stderr.strip().splitlines()[-1], run.stderr
    assert time.monotonic() - started < 10  # no form-finding
    assert not (tmp_path / "out" / "spans.csv").exists()


def test_the_system_is_required(presag, tmp_path):
    run = presag("design", "line.csv", "--out", "out", cwd=tmp_path)
    assert run.returncode == 2 and "--system" in run.stderr
