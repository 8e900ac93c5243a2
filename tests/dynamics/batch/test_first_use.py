"""The kernel's first compilation started with the command (:mod:`presag_opt.dynamics.batch.first_use`).

The sample batch must give the numba types of a real one (else the helper would compile a kernel no
batch calls); the helper is started only on a first use, on two cores or more, with compiled code
on, and a helper still compiling when the block ends is killed. In a fresh process with an empty
numba cache, a batch after ``compiling_ahead`` loads what the helper compiled and compiles no kernel
function twice (``test_compilation.py``, slow tier).
"""

from __future__ import annotations

import dataclasses
import os

import pytest

from presag_opt.dynamics.batch import first_use, system
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.runtime import current


class Stop(Exception):
    """Raised in place of the kernel's compilation: the batch's arguments are all a test needs."""


def test_the_sample_batch_has_the_types_of_a_catenary_batch(case, short_state, monkeypatch):
    """Two runs on five spans with droppers and the case-study pantograph against one run on a lone
    wire without droppers and a two-stage pantograph: the same numba types."""
    from presag_opt.dynamics.batch import simulate_many

    seen = []

    def capture(c_sweeps, scalars, shared, runs, state, out, work, scratch, progress=None):
        seen.append(system.KernelArguments(c_sweeps, scalars, shared, runs, state, out, work, scratch, 0))
        raise Stop

    monkeypatch.setattr(system, "compile_kernel", capture)
    points = [OperatingPoint(speed=s / 3.6, static_force=f) for s, f in ((100.0, 90.0), (120.0, 110.0))]
    with pytest.raises(Stop):
        simulate_many(short_state, case.pantograph, points,
                      settings=dataclasses.replace(case.settings, lead_in_spans=1, analysed_spans=1))
    sample = first_use.sample_arguments()
    assert first_use.newton_steps_types(seen[0]) == first_use.newton_steps_types(sample)
    assert len(seen[0].out.status) == 2 and len(sample.out.status) == 1  # the batches differ in size, not in type


class FakeHelper:
    """A helper process that is still compiling until told otherwise."""

    def __init__(self, running: bool):
        self.running, self.killed, self.waited = running, False, False

    def poll(self):
        return None if self.running else 0

    def kill(self):
        self.killed, self.running = True, False

    def wait(self):
        self.waited = True
        return 0


@pytest.mark.parametrize(("cached", "cores", "compiled_code", "started"), [
    (False, 2, True, True),   # a first use on two cores: the helper starts with the command
    (True, 2, True, False),   # the kernel is in the cache already: nothing to do
    (False, 1, True, False),  # one core: the first batch compiles it
    (False, 2, False, False),  # compiled code off (PRESAG_NO_COMPILE): no process
])
def test_a_helper_starts_only_on_a_first_use_with_two_cores_and_compiled_code(monkeypatch, cached, cores,
                                                                              compiled_code, started):
    helpers = []

    def start(dispatcher, types_):
        helpers.append(FakeHelper(running=False))
        return helpers[-1]

    monkeypatch.setattr(first_use, "has_cache_entries", lambda dispatcher: cached)
    monkeypatch.setattr(first_use, "start_helper", start)
    monkeypatch.setattr(os, "cpu_count", lambda: cores)
    with current().replace(compile=compiled_code), first_use.compiling_ahead() as ahead:
        assert ahead is started
    assert len(helpers) == int(started)
    assert all(h.waited and not h.killed for h in helpers)  # a finished helper is reaped, not killed


def test_a_helper_still_compiling_when_the_command_ends_is_killed(monkeypatch):
    helper = FakeHelper(running=True)
    monkeypatch.setattr(first_use, "has_cache_entries", lambda dispatcher: False)
    monkeypatch.setattr(first_use, "start_helper", lambda dispatcher, types_: helper)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    with pytest.raises(KeyboardInterrupt), current().replace(compile=True), first_use.compiling_ahead():
        raise KeyboardInterrupt
    assert helper.killed and helper.waited
