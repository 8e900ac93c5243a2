"""Every ``presag`` command written in a code block of the documentation (``docs/**/*.md`` and the
README) is accepted by the live argument parser, and every ``python`` block runs: a renamed option,
verb or function fails here, not in a reader's terminal. Parsing runs each option's type check
(bands, lists, numbers) but no command."""

from __future__ import annotations

import contextlib
import io
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from presag_opt.cli import build_parser

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ("_build", "api", "notebooks", "jupyter_execute")
"""Folders of ``docs/`` written by the build (not sources)."""

FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)
COMMAND = re.compile(r"(?:^|&&\s*)(?:\S*/)?presag\s+(.*?)(?:\s+#.*)?$")


def pages() -> list[Path]:
    docs = [p for p in (ROOT / "docs").rglob("*.md")
            if not set(p.relative_to(ROOT / "docs").parts[:-1]) & set(GENERATED)]
    return sorted(docs) + [ROOT / "README.md"]


def commands_in(path: Path) -> list[str]:
    """The argument strings of every ``presag`` command in the page's bash and console blocks."""
    out = []
    for language, body in FENCE.findall(path.read_text(encoding="utf-8")):
        if language not in ("bash", "sh", "console", "shell", ""):
            continue
        for line in body.splitlines():
            match = COMMAND.search(line.strip())
            if match:
                out.append(match.group(1))
    return out


def parse_error(arguments: str) -> str | None:
    """The parser's complaint about ``presag ARGUMENTS``, or None when it accepts them."""
    stderr = io.StringIO()
    try:
        with contextlib.redirect_stderr(stderr), contextlib.redirect_stdout(io.StringIO()):
            build_parser().parse_args(shlex.split(arguments))
    except SystemExit as stop:
        if stop.code:
            return stderr.getvalue().strip().splitlines()[-1]
    return None


def test_the_pages_hold_commands():
    found = {path.name: len(commands_in(path)) for path in pages()}
    assert sum(found.values()) > 25, found
    assert found["README.md"] >= 2 and found["getting_started.md"] >= 5


def test_the_check_catches_a_wrong_option():
    assert parse_error("recommend --no-such-option") is not None
    assert parse_error("empirical --span sixty") is not None  # a type check runs at parse time
    assert parse_error("recommend --static-force 70:140") is None


@pytest.mark.parametrize("path", pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_command_in_the_page_parses(path):
    problems = []
    for arguments in commands_in(path):
        error = parse_error(arguments)
        if error is not None:
            problems.append(f"presag {arguments}: {error}")
    assert not problems, "\n".join(problems)


def python_examples() -> list[tuple[Path, str]]:
    return [(path, body) for path in pages() for language, body in FENCE.findall(path.read_text(encoding="utf-8"))
            if language == "python"]


def test_the_pages_hold_python_examples():
    assert len(python_examples()) >= 3


@pytest.mark.parametrize(("path", "code"), python_examples(), ids=lambda v: v.name if isinstance(v, Path) else "")
def test_every_python_example_runs(path, code, tmp_path):
    """Each ``python`` block of the pages runs as written, in a fresh interpreter outside the checkout."""
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                            cwd=tmp_path, check=False)
    assert result.returncode == 0, f"{path.name}:\n{code}\n{result.stderr[-3000:]}"
