"""The installed ``presag`` console script, one process per command: it starts, lists every command,
and each command answers ``--help`` with its usage and exit status 0 (the smoke test of each entry
point; the commands' work is tested in-process beside each command's own tests, and what only a
process shows is tier e2e)."""

from __future__ import annotations

import pytest

from presag_opt.cli import COMMAND_MODULES, build_parser


def _commands() -> list[str]:
    (sub,) = [a for a in build_parser()._actions if a.dest == "command"]
    return sorted(sub.choices)


def test_the_script_lists_every_command(presag_script, tmp_path):
    done = presag_script("--help", cwd=tmp_path)
    assert done.returncode == 0 and done.stderr == ""
    assert all(f"    {name}" in done.stdout for name in _commands())
    assert len(_commands()) >= len(COMMAND_MODULES)


@pytest.mark.parametrize("command", _commands())
def test_each_command_answers_help(presag_script, tmp_path, command):
    done = presag_script(command, "--help", cwd=tmp_path)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    assert done.stdout.startswith(f"usage: presag {command} ")


def test_bad_input_ends_the_process_with_status_2_and_one_line(presag_script, tmp_path):
    done = presag_script("recommend", "--static-force", "0:140", cwd=tmp_path)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr == ("presag: error: static_force_low = 0 N is outside the valid range (0, 1000] N\n")
