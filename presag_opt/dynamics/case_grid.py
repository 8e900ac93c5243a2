"""A case over a grid of speeds × static forces: every run checked first, one form-finding per
element length, one batch per form-found state.

With automatic numerics the element length follows the speed (:mod:`presag_opt.dynamics.numerics`),
so the runs of a grid can need several form-found states. :func:`plan_grid` checks every run
without form-finding (a bad speed or force is refused before any work), :func:`form_find_states`
form-finds once per element length, and :func:`simulate_grid` runs each state's points as one
:func:`~presag_opt.dynamics.batch.simulate_many` batch and returns one
:class:`~presag_opt.dynamics.results.BatchResult` in the order of the plans.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence

from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.case import SimulationCase
from presag_opt.dynamics.results import BatchResult
from presag_opt.dynamics.run_plan import RunPlan
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary


def plan_grid(case: SimulationCase, speeds: Sequence[float], forces: Sequence[float],
              settings: SimulationSettings) -> dict[tuple[float, float], RunPlan]:
    """Check every run of the grid without form-finding.

    Parameters
    ----------
    case : SimulationCase
        The case (its static force is replaced by each of ``forces``).
    speeds : sequence of float
        Train speeds. [m/s]
    forces : sequence of float
        Static uplift forces. [N]
    settings : SimulationSettings
        Numerical settings (automatic numerics: each speed's own).

    Returns
    -------
    dict
        (speed, force) -> :class:`~presag_opt.dynamics.run_plan.RunPlan`, speeds outer, forces inner.

    Raises
    ------
    ModelError
        A run that :func:`~presag_opt.dynamics.run_plan.plan_run` refuses.
    """
    plans: dict[tuple[float, float], RunPlan] = {}
    for speed in speeds:
        for force in forces:
            at_force = dataclasses.replace(case, operation=dataclasses.replace(case.operation, static_force=force))
            plans[speed, force] = at_force.plan(speed, settings)
    return plans


def form_find_states(catenary: Catenary, plans: Mapping[tuple[float, float], RunPlan],
                     progress: Callable[[str], None] | None = None) -> dict[float, EquilibriumState]:
    """One form-found state per element length the plans need, longest first.

    Parameters
    ----------
    catenary : Catenary
        The system.
    plans : mapping
        The runs (:func:`plan_grid`).
    progress : callable, optional
        Called with a short message before each form-finding.

    Returns
    -------
    dict
        Element length [m] -> the form-found state.
    """
    states = {}
    for plan in sorted(plans.values(), key=lambda p: -p.settings.static.element_length):
        length = plan.settings.static.element_length
        if length not in states:
            if progress:
                progress(f"form-finding with {length:g} m elements")
            states[length] = form_find(catenary, plan.settings.static)
    return states


def simulate_grid(case: SimulationCase, plans: Mapping[tuple[float, float], RunPlan],
                  states: Mapping[float, EquilibriumState], settings: SimulationSettings,
                  progress: Callable[[str], None] | None = None) -> BatchResult:
    """Run the grid: one batch per form-found state; the outcomes in the order of ``plans``.

    Parameters
    ----------
    case : SimulationCase
        The case (pantograph, aerodynamic coefficient, spacings).
    plans : mapping
        The runs (:func:`plan_grid`).
    states : mapping
        Element length [m] -> form-found state (:func:`form_find_states`).
    settings : SimulationSettings
        The settings the runs were planned with.
    progress : callable, optional
        Called with a short message as groups of runs finish.

    Returns
    -------
    BatchResult
        One outcome per plan, in order; ``wall_time`` is the sum over the batches. [s]
    """
    order = list(plans)
    aero = case.operation.aero_coefficient
    outcomes, wall, part = {}, 0.0, None
    for length, state in states.items():
        keys = [k for k in order if plans[k].settings.static.element_length == length]
        if not keys:
            continue
        points = [OperatingPoint(speed=v, static_force=f, aero_coefficient=aero) for v, f in keys]
        report = (lambda message, h=length: progress(f"{h:g} m elements: {message}")) if progress else None
        part = simulate_many(state, case.pantograph, points, spacings=case.operation.spacings, settings=settings,
                             progress=report)
        outcomes.update(zip(keys, part.runs))
        wall += part.wall_time
    if part is None:
        raise ModelError("states: no form-found state at the element length of any plan (see form_find_states)")
    return BatchResult(catenary_name=part.catenary_name, pantograph_names=part.pantograph_names,
                       runs=tuple(outcomes[k] for k in order), wall_time=wall, settings=settings)
