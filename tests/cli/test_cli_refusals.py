"""The catalogue of refusals and announcements (issue 20): work the command line must not start
silently, run in-process from a folder outside the source tree (the announcement of long work,
stopped by SIGTERM, runs the installed console script: tier e2e). Each refusal is one line ``presag: error: …`` naming the limit and the setting that makes the
work feasible, with its exit status; each announcement is one line before the work starts; each
warning one line ``presag: warning: …`` (and in the JSON's ``warnings``). Never a traceback.

The storage faults on a real tmpfs are in ``tests/studies/test_store.py``; the workers
after a SIGKILL in ``tests/test_processes.py``.
"""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

SCRIPT = Path(sys.executable).parent / "presag"
MODELS = Path(__file__).resolve().parents[1] / "studies" / "models"

REFUSALS = {
    "speed at beta >= 0.7": (
        ["simulate", "--case", "case_study_st98", "--speed", "330"], 2,
        (r"speed = 330 km/h is β = 0\.96 of the contact-wire wave speed 345 km/h, at or above the EN 50119 limit "
        r"β < 0\.7 \(speeds below 241 km/h\); give --allow-supercritical to run it anyway")),
    "one speed of a list at beta >= 0.7": (
        ["simulate", "--case", "case_study_st98", "--speed", "160,250"], 2,
        r"speed = 250 km/h is β = 0\.73 .*give --allow-supercritical"),
    "accepted, but automatic elements below 0.05 m": (
        ["simulate", "--case", "case_study_st98", "--speed", "330", "--allow-supercritical"], 2,
        (r"speed = 330 km/h \(β = 0\.96\): automatic numerics need elements of 0\.02 m, below the limit 0\.05 m "
         r"\(1 run on 60 013 nodes: about .* and .* GB of memory on a 2-core machine\); give --element-length 0\.05 "
         r"\(or longer\) with --time-step MS to fix coarser numerics")),
    "fixed numerics needing more memory than the machine": (
        ["simulate", "--case", "case_study_st98", "--speed", "200", "--element-length", "0.01", "--time-step", "0.1"],
        2, (r"the runs need about \d+ GB of memory, more than this machine's \d+ GB \(1 run on 120 013 nodes: .*\); give "
           r"longer elements or time steps \(--element-length 0\.05 \(or longer\) with --time-step MS\), or fewer runs")),
    "speed above the wave speed (no option accepts it)": (
        ["simulate", "--case", "case_study_st98", "--speed", "400", "--allow-supercritical"], 2,
        r"speed = 400 km/h is outside the valid range \[0, 344\.\d+\) km/h"),
    "recommend with a band reaching beta >= 0.7": (
        ["recommend", "--max-speed", "260"], 2,
        r"speed = 260 km/h is β = 0\.75 of the contact-wire wave speed 345 km/h, .*give --allow-supercritical"),
    "report with a band reaching beta >= 0.7": (
        ["report", "--quick", "--max-speed", "300", "--out", "{tmp}/report"], 2,
        r"speed = 300 km/h is β = 0\.87 .*give --allow-supercritical to run it anyway"),
    "robust --dynamic with a speed band reaching beta >= 0.7": (
        ["robust", "--dynamic", "--max-speed", "250"], 2,
        r"speed = 250 km/h is β = 0\.73 .*give --allow-supercritical to run it anyway"),
    "robust --check-speeds at beta >= 0.7": (
        ["robust", "--check-speeds", "90,260"], 2,
        r"speed = 260 km/h is β = 0\.75 .*give --allow-supercritical to run it anyway"),
    "sweep whose grid reaches beta >= 0.7": (
        ["sweep", "{fast_study}", "--out", "{tmp}/fast.nc"], 2,
        r"speed = 260 km/h is β = 0\.75 .*give --allow-supercritical \(allow_supercritical=True\) to run it anyway"),
    "sweep into a folder that is a file": (
        ["sweep", str(MODELS / "small_grid.toml"), "--out", "{tmp}/plain/s.nc"], 2,
        r"{tmp}/plain/s\.nc: {tmp}/plain is a file, not a folder; give another output path"),
    "sweep onto a folder": (
        ["sweep", str(MODELS / "small_grid.toml"), "--out", "{tmp}"], 2,
        r"{tmp}: is a folder; give a file name such as {tmp}/study\.nc"),
    "sweep where a file holds the units folder's name": (
        ["sweep", str(MODELS / "small_grid.toml"), "--out", "{tmp}/blocked.nc"], 4,
        (r"{tmp}/blocked\.nc\.units: a file is where a folder should be; move it or give another output path, then "
        r"run the same command again: finished units are kept")),
    "sweep on a store another command holds": (
        ["sweep", str(MODELS / "small_grid.toml"), "--out", "{tmp}/held.nc"], 2,
        (r"{tmp}/held\.nc: another presag sweep \(pid {pid}\) is running this study; wait for it to finish \(or stop "
        r"it\) and run again — finished units are kept \(lock {tmp}/held\.nc\.units/lock\)")),
}
"""Case -> (arguments, exit status, the one line after ``presag: error: `` as a regular expression)."""


@pytest.fixture
def folder(tmp_path):
    """A folder outside the source tree with the files the cases need."""
    fast = (MODELS / "small_grid.toml").read_text().replace('"st_9.8_short.toml"', f'"{MODELS / "st_9.8_short.toml"}"')
    (tmp_path / "fast_grid.toml").write_text(fast.replace("value = [140, 180]", "value = [140, 260]"))
    (tmp_path / "plain").write_text("a file")
    (tmp_path / "blocked.nc.units").write_text("a file")
    held = tmp_path / "held.nc.units"
    held.mkdir()
    (held / "lock").write_text(f"{os.getpid()}@{socket.gethostname()}")  # this test process holds it
    return tmp_path


@pytest.mark.parametrize("case", list(REFUSALS))
def test_refusal_is_one_line_with_its_status(presag, case, folder):
    args, status, pattern = REFUSALS[case]
    if case.startswith("fixed numerics needing more memory"):
        from presag_opt.dynamics.cost import physical_memory

        if (physical_memory() or 0.0) > 80e9:
            pytest.skip("this machine has the 88 GB the case needs")
    fill = {"tmp": str(folder), "fast_study": str(folder / "fast_grid.toml"), "pid": str(os.getpid())}
    started = time.monotonic()
    result = presag(*[a.format(**fill) for a in args], cwd=folder)
    seconds = time.monotonic() - started
    assert result.returncode == status, result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert all(line.startswith(("presag: error: ", "presag: warning: ")) for line in lines), result.stderr
    assert lines[-1].startswith("presag: error: ") and len([x for x in lines if "error" in x[:15]]) == 1
    assert re.match(pattern.format(**{k: re.escape(v) for k, v in fill.items()}), lines[-1][15:]), lines[-1]
    # Refused before any work: the time of the imports and the plan (a form-finding would take minutes).
    assert seconds < 60, f"{case}: refused only after {seconds:.0f} s"
    assert (folder / "held.nc.units" / "lock").exists()  # nobody took over a live holder's lock


def test_the_near_critical_warning_is_one_line_and_in_the_json(presag, tmp_path):
    """A warning raised inside the package (speed.py) reaches the user once, as one line, and in --json."""
    result = presag("recommend", "--max-speed", "260", "--allow-supercritical", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    expected = ("speed ratio β = 0.75 exceeds 0.7 (EN 50119): wave reflections and the Doppler effect dominate the "
                "interaction")
    lines = result.stderr.strip().splitlines()
    assert lines.count(f"presag: warning: {expected}") == 1
    assert all(line.startswith("presag: warning: ") for line in lines), result.stderr
    warnings = json.loads(result.stdout)["warnings"]
    assert warnings.count(expected) == 1 and len(warnings) == len(set(warnings)) == len(lines)


@pytest.mark.e2e
@pytest.mark.parametrize("args", [
    ["simulate", "--case", "case_study_st98", "--speed", "200", "--element-length", "0.1", "--time-step", "0.5"],
    ["sweep", "paper_grid_st98_auto", "--out", "{tmp}/paper.nc", "--workers", "2"],
    ["tolerance", "--monte-carlo", "--dynamic", "--dropper-error", "5"],
], ids=["simulate", "sweep", "tolerance-monte-carlo"])
def test_long_work_is_announced_before_it_starts(args, tmp_path):
    """More than 2 minutes expected: one line with the time and the memory, then the work (stopped here
    with SIGTERM, which ends the command as Ctrl-C does)."""
    process = subprocess.Popen([str(SCRIPT), *[a.format(tmp=tmp_path) for a in args]], cwd=tmp_path, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        started = time.monotonic()
        line = process.stderr.readline()
        seconds = time.monotonic() - started
        process.send_signal(signal.SIGTERM)
        # the interrupt takes effect when the work in progress returns control to Python (a C-level
        # model build can hold it for a minute on a busy machine): wait for the exit, bounded against a hang
        _, err = process.communicate(timeout=600)
    finally:
        process.kill()
    assert re.fullmatch(r"presag: \d+ runs? on [\d ,]+ nodes: about \d+(\.\d)? (min|h) and \d+\.\d GB of memory on "
                        r"a 2-core machine \(Ctrl-C stops it\)\n", line), line
    assert seconds < 60
    assert process.returncode == 130 and err.strip().splitlines()[-1] == "presag: interrupted", err
    assert "Traceback" not in err


@pytest.mark.e2e  # the installed script and its two worker processes
def test_an_accepted_supercritical_sweep_warns_once_even_from_its_workers(presag_script, folder):
    """The study's β warning is raised in the parent and again in each worker as it plans its runs:
    the user sees it once, as one line (workers show no warnings of their own)."""
    result = presag_script("sweep", str(folder / "fast_grid.toml"), "--out", str(folder / "fast.nc"), "--workers",
                           "2", "--allow-supercritical", cwd=folder)
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines() == [
        "presag: warning: speed ratio β = 0.75 exceeds 0.7 (EN 50119): wave reflections and the Doppler effect "
        "dominate the interaction"]
