"""The ``>>>`` examples of the public API run as doctests, in the test run's runtime (its form-finding cache):
every example a reader copies into a notebook works and prints what its docstring says."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = (
    "presag_opt.display",
    "presag_opt.contact_force",
    "presag_opt.design.band",
    "presag_opt.design.quasi_static",
    "presag_opt.dynamics.laws",
    "presag_opt.robust.lp",
    "presag_opt.jobs.band",
    "presag_opt.jobs.line",
    "presag_opt.jobs.studies",
)
"""Modules whose examples run here: the jobs, the laws (F_m, the Δe rule, contact, friction, the tension-only
dropper, the HHT constants, the robust objective), the band in the designer's units, the notebook display."""

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
