"""The batch kernel's first compilation started when a command starts, not at its first batch.

A command that simulates (a report, a batch of runs) spends its first seconds on other work: the
form-findings of an empty cache, the quasi-static design, building the C libraries. On a first use
the kernel's compilation (:mod:`presag_opt.dynamics.batch.compilation`) only started at the first
batch: in a first ``presag report --quick`` at 6.1 s of 20.7 s. :func:`compiling_ahead` starts the
longest part of it, each run's Newton iteration
(:func:`~presag_opt.dynamics.batch.kernel.newton_steps`), in the compile helper when the command
starts, while the command does that other work; the first batch then finds it compiled, or waits on
its compile lock for the rest, and loads it from the cache.

The kernel's argument types are those of any batch: they do not depend on the catenary, the
pantograph, the number of runs or the sizes of the arrays, only on how
:func:`~presag_opt.dynamics.batch.system.kernel_arguments` builds them. :func:`sample_arguments`
builds them for a one-run batch on a short lone wire, by that same function, so that the helper
compiles what the real batches need (``tests/dynamics/batch/test_first_use.py`` compares them with
a catenary's). Nothing is started when the kernel has an entry in numba's cache already (the common
case: the check reads the cache's index), on one core, or with compiled code turned off in the
runtime.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from presag_opt import runtime
from presag_opt.dynamics.batch import kernel
from presag_opt.dynamics.batch.compilation import newton_steps_arguments, spare_core, start_helper, stop_helper
from presag_opt.dynamics.batch.system import BatchSystem, KernelArguments, StaticLine, kernel_arguments
from presag_opt.dynamics.pantograph import Pantograph, PantographStage
from presag_opt.dynamics.run_plan import plan_run
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.dynamics.structure import structural_model
from presag_opt.native.jit import has_cache_entries, signature
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import lone_wire_state
from presag_opt.system.components import Wire

SAMPLE_LENGTH = 10.0
"""Length of the sample's lone wire. [m]"""


def sample_arguments() -> KernelArguments:
    """The kernel's arguments for one run on a 10 m lone wire (1 m elements, spring supports, a
    two-stage pantograph at 20 m/s): a batch that takes a fraction of a second to build."""
    static = StaticSettings(element_length=1.0)
    wire = Wire(tension=10_000.0, mass_per_length=1.0, axial_stiffness=14.4e6)
    state = lone_wire_state(wire, SAMPLE_LENGTH, static, support_stiffness=1e9)
    pantograph = Pantograph(name="sample", stages=(PantographStage(name="head", mass=5.0),
                                                   PantographStage(name="frame", mass=10.0)))
    settings = SimulationSettings(analysed_spans=1, lead_in_spans=0, run_out=0.0, numerics="fixed", static=static)
    plan = plan_run(state, pantograph, speed=20.0, static_force=100.0, settings=settings)
    model = structural_model(state, settings=plan.settings.structure)
    system = BatchSystem.build(model, plan.pantographs, plan.settings)
    return kernel_arguments(state, system, [plan], plan.settings, [StaticLine.own(model)])


def newton_steps_types(arguments: KernelArguments) -> tuple:
    """The numba types :func:`~presag_opt.dynamics.batch.kernel.newton_steps` is compiled for, as a
    batch with these arguments calls it (:func:`~presag_opt.dynamics.batch.compilation.newton_steps_arguments`)."""
    a = arguments
    return signature(kernel.newton_steps,
                     *newton_steps_arguments(a.scalars, a.shared, a.runs, a.state, a.out, a.work, a.scratch))


@contextlib.contextmanager
def compiling_ahead() -> Iterator[bool]:
    """Compile the kernel's Newton iteration in a helper process while the block runs, if this is
    the kernel's first use here (see the module notes).

    The helper holds the function's compile lock until it has written the cache; a batch in the
    block waits for it there and loads the cache. Leaving the block kills a helper still compiling
    (the command needed no batch, or ended early): the next first use compiles again. The block's
    value says whether a helper was started.
    """
    helper = None
    if runtime.current().compile and spare_core() and not has_cache_entries(kernel.newton_steps):
        helper = start_helper(kernel.newton_steps, newton_steps_types(sample_arguments()))
    try:
        yield helper is not None
    finally:
        if helper is not None:
            stop_helper(helper)


__all__ = ["SAMPLE_LENGTH", "compiling_ahead", "newton_steps_types", "sample_arguments"]
