"""What dynamic work will cost before it starts: time and memory, and the limit of automatic numerics.

With automatic numerics (:mod:`presag_opt.dynamics.numerics`) the element length and time step
shrink with 1 − β, so the node count grows as 1/(1 − β) and the step count as 1/(1 − β) too: a run
near the wave speed can need hours and tens of gigabytes. :func:`estimate_runs` gives the order of
magnitude from the plans alone (no form-finding), and :func:`check_run_size` refuses automatic
numerics that need elements below :data:`MIN_AUTO_ELEMENT_LENGTH`, or work whose memory exceeds
the machine's, with one line naming the setting that makes it feasible.

The single-run rate is measured on a 2-core 2026 virtual machine with other work running (about
twice the time of an idle machine), on ST 9,8/9,8 with the case-study pantograph at 160 and
250 km/h: 1.4–2.4 µs per node and step. The batch rate is twice what whole commands take on an
idle 2-core AMD EPYC virtual machine (December 2026, caches warm, two workers): 0.017 µs per run,
node and step for the paper's 400-run grid (42 s), 0.016 µs for the dynamic Monte Carlo's 100
realisations (172 s) and 0.024 µs for ``presag robust --dynamic`` (19 s), form-findings and pool
start-up included (the kernel's first compilation, about 10 s once per machine, is not). Memory: a
form-finding peak of about 21 kB per node (179 MB at 2 413 nodes, 379 MB at 12 013), a single
run's histories about 16 bytes per node and step (560 MB at 3 853 nodes × 3 532 steps, 960 MB at
7 653 × 4 633). They are an order of magnitude, not a promise.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

from presag_opt.dynamics.run_plan import RunPlan
from presag_opt.errors import ModelError
from presag_opt.static.run_time import form_find_estimate
from presag_opt.system.catenary import Catenary
from presag_opt.units import KMH

MIN_AUTO_ELEMENT_LENGTH = 0.05
"""Shortest element automatic numerics may choose; shorter needs an explicit fixed setting. [m]"""

SINGLE_SECONDS_PER_NODE_STEP = 2.0e-6
"""Wall time of a single run per node and time step. [s]"""

BATCH_SECONDS_PER_NODE_STEP = 5e-8
"""Wall time of a batch per run, node and time step. [s]"""

BASE_MEMORY = 0.4e9
"""Memory of a process with the simulator loaded. [B]"""

FORM_FINDING_BYTES_PER_NODE = 21e3
"""Peak memory of a form-finding per node. [B]"""

SINGLE_RUN_BYTES_PER_NODE_STEP = 16.0
"""Memory of a single run's histories per node and time step. [B]"""


@dataclass(frozen=True, kw_only=True)
class WorkEstimate:
    """Rough cost of a set of dynamic runs.

    Attributes
    ----------
    nodes : tuple of int
        Node count of each form-finding the runs need (one per element length). [-]
    form_finding_seconds : float
        Time of those form-findings (0 for cached states). [s]
    runs : int
        Runs. [-]
    run_seconds : float
        Time of the runs. [s]
    memory : float
        Peak memory of the process. [B]
    """

    nodes: tuple[int, ...]
    form_finding_seconds: float
    runs: int
    run_seconds: float
    memory: float

    @property
    def seconds(self) -> float:
        """Total time. [s]"""
        return self.form_finding_seconds + self.run_seconds

    def describe(self) -> str:
        """One line: runs, nodes, time and memory."""
        nodes = ", ".join(f"{n:,}".replace(",", " ") for n in self.nodes)
        return (f"{self.runs} run{'s' if self.runs != 1 else ''} on {nodes} nodes: about {duration(self.seconds)} "
                f"and {self.memory / 1e9:.1f} GB of memory on a 2-core machine")


def estimate_runs(catenary: Catenary, plans: Sequence[RunPlan], *, batch: bool) -> WorkEstimate:
    """Time and memory of running ``plans`` on ``catenary`` (one form-finding per element length).

    Parameters
    ----------
    catenary : Catenary
        The system (discretised, not form-found, to count nodes).
    plans : sequence of RunPlan
        The runs, with the settings of their speed.
    batch : bool
        Whether the runs go through the batch engine (else one single run each, with histories).

    Returns
    -------
    WorkEstimate
    """
    lengths: dict[float, tuple[int, float]] = {}
    for plan in plans:
        static = plan.settings.static
        if static.element_length not in lengths:
            lengths[static.element_length] = form_find_estimate(catenary, static)
    run_seconds, memory = 0.0, 0.0
    for plan in plans:
        n_nodes = lengths[plan.settings.static.element_length][0]
        steps = plan.step_count(plan.settings.integrator.time_step)
        rate = BATCH_SECONDS_PER_NODE_STEP if batch else SINGLE_SECONDS_PER_NODE_STEP
        run_seconds += rate * n_nodes * steps
        histories = 0.0 if batch else SINGLE_RUN_BYTES_PER_NODE_STEP * n_nodes * steps
        memory = max(memory, BASE_MEMORY + FORM_FINDING_BYTES_PER_NODE * n_nodes, BASE_MEMORY + histories)
    return WorkEstimate(nodes=tuple(n for n, _ in lengths.values()),
                        form_finding_seconds=sum(s for _, s in lengths.values()),
                        runs=len(plans), run_seconds=run_seconds, memory=memory)


def check_run_size(plans: Sequence[RunPlan], estimate: WorkEstimate, *, fix: str) -> None:
    """Refuse runs whose automatic numerics need elements below :data:`MIN_AUTO_ELEMENT_LENGTH`, or
    whose memory exceeds this machine's.

    Parameters
    ----------
    plans : sequence of RunPlan
        The runs.
    estimate : WorkEstimate
        Their cost (:func:`estimate_runs`).
    fix : str
        The setting that fixes coarser numerics, named in the message (the command line passes its
        options). [-]

    Raises
    ------
    ModelError
        One line naming the speed, the element length, the cost and ``fix``.
    """
    for plan in plans:
        h = plan.settings.static.element_length
        if plan.settings.numerics == "auto" and h < MIN_AUTO_ELEMENT_LENGTH:
            raise ModelError(
                f"speed = {plan.operation.speed / KMH:g} km/h (β = {plan.speed_ratio:.2f}): automatic numerics need "
                f"elements of {h:g} m, below the limit {MIN_AUTO_ELEMENT_LENGTH:g} m ({estimate.describe()}); give "
                f"{fix} to fix coarser numerics (σ is then under-resolved, and flagged), or a lower speed"
            )
    available = physical_memory()
    if available and estimate.memory > available:
        raise ModelError(
            f"the runs need about {estimate.memory / 1e9:.0f} GB of memory, more than this machine's "
            f"{available / 1e9:.0f} GB ({estimate.describe()}); give longer elements or time steps ({fix}), "
            "or fewer runs"
        )


def physical_memory() -> float | None:
    """This machine's physical memory, or None where unknown. [B]"""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return None


def duration(seconds: float) -> str:
    """A duration for people: ``40 s``, ``12 min``, ``2.3 h``.

    Parameters
    ----------
    seconds : float
        The duration. [s]
    """
    if seconds < 90:
        return f"{seconds:.0f} s"
    return f"{seconds / 60:.0f} min" if seconds < 5400 else f"{seconds / 3600:.1f} h"


LONG_FORM_FINDING = 10.0
"""Expected form-finding time above which a job says beforehand how long it will take. [s]"""

LONG_WORK = 120.0
"""Expected time of a batch or a study above which a job says beforehand what it will cost. [s]"""


def work_notice(estimate: WorkEstimate) -> str:
    """What long work will cost, said before it starts; "" for work of :data:`LONG_WORK` or less.

    Parameters
    ----------
    estimate : WorkEstimate
        Or any object with ``seconds`` [s] and ``describe()``.
    """
    return f"{estimate.describe()} (Ctrl-C stops it)" if estimate.seconds > LONG_WORK else ""


def form_finding_notice(n_nodes: int, seconds: float) -> str:
    """How long a form-finding will take, said before it starts; "" for :data:`LONG_FORM_FINDING` or less.

    Parameters
    ----------
    n_nodes : int
        Nodes of the model to be form-found. [-]
    seconds : float
        Estimated run time (:func:`~presag_opt.static.run_time.form_find_estimate`). [s]
    """
    if seconds <= LONG_FORM_FINDING:
        return ""
    return f"form-finding {n_nodes} nodes takes about {duration(seconds)} on a typical machine (Ctrl-C stops it)"
