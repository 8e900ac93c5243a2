"""The ``>>>`` examples of the public API run as doctests, in the test run's runtime (its form-finding cache):
every example a reader copies into a notebook works and prints what its docstring says."""

from __future__ import annotations

import doctest
import importlib
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "presag_opt"

MODULES = tuple(sorted(
    ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    for path in PACKAGE.rglob("*.py") if ">>>" in path.read_text(encoding="utf-8")))
"""Every module with an example runs here (found by its ``>>>``, so a new one cannot be left out): the jobs,
the laws (F_m, the Δe rule, contact, friction, the tension-only dropper, the HHT constants, the robust
objective), the band in the designer's units, the notebook display, the runtime."""


def test_the_examples_are_found():
    """At least the jobs and the laws carry examples (measured: 10 modules)."""
    assert {"presag_opt.jobs.band", "presag_opt.dynamics.laws", "presag_opt.robust.lp"} <= set(MODULES)


FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _examples(module: str) -> list[doctest.DocTest]:
    return [t for t in doctest.DocTestFinder().find(importlib.import_module(module)) if t.examples]


@pytest.mark.parametrize("module", MODULES)
def test_examples_print_what_their_docstrings_say(module):
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    tests = _examples(module)
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert tests and result.failed == 0, f"{result.failed} of {result.attempted} examples of {module} failed (above)"
