"""Work units of a study and the pure function that computes one.

A unit is one (extra-parameter combination, pre-sag, speed), all static forces of the grid at that
speed; it is what the store saves atomically. A task (:func:`task_groups`) is a few units of one
pre-sag and parameter combination, run as one :func:`~presag_opt.dynamics.batch.simulate_many`
batch on one form-found catenary. :func:`run_units` is the only function a worker runs, locally or
on a Dask cluster (through a :class:`UnitRunner`, whose memo keeps the worker's recent form-found
states); its result depends on its arguments alone (the memo only saves recomputing a form-found
state) and is a plain :class:`UnitResult` that the parent writes to disk.

Besides the dynamic statistics, a unit computes the quasi-static pre-sag of the Δe and mid/mast
rules at each run's nominal mean contact force F_m = F_stat + α_ae v², from the elasticity of the
catenary built with the unit's pre-sag (the analysis needs the rule on the same geometry family as
the dynamic runs).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import Any

from presag_opt.contact_force import mean_force
from presag_opt.design.band import force_levels_for_band
from presag_opt.design.section import SectionElasticity, section_elasticity
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.errors import ConvergenceError, ModelError, failure_reason
from presag_opt.processes import WorkerMemo
from presag_opt.speed import speed_ratio
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import form_find
from presag_opt.studies.definition import StudyDefinition
from presag_opt.system.catenary import Catenary

CACHE_SIZE = 4
"""Form-found states a :class:`UnitRunner` keeps: units arrive sorted by pre-sag, so a few suffice. [-]"""

RULE_METHODS = {"presag_delta_e": "delta-e", "presag_mid_mast": "mid-mast"}
"""Result field of each quasi-static rule, and the rule's method name in :mod:`presag_opt.design.quasi_static`."""

@dataclass(frozen=True, kw_only=True, order=True)
class WorkUnit:
    """One unit of a study: an extra-parameter combination, a pre-sag and a speed.

    Attributes
    ----------
    parameter_indices : tuple of int
        Index into each extra parameter's values. [-]
    presag_index : int
        Index into the grid's pre-sags. [-]
    speed_index : int
        Index into the grid's speeds. [-]
    """

    parameter_indices: tuple[int, ...]
    presag_index: int
    speed_index: int

    @property
    def key(self) -> str:
        """File-name stem of the unit, unique in its study, e.g. ``p0-1_s2_v5``."""
        extra = "p" + "-".join(map(str, self.parameter_indices)) + "_" if self.parameter_indices else ""
        return f"{extra}s{self.presag_index}_v{self.speed_index}"


@dataclass(frozen=True, kw_only=True)
class UnitResult:
    """Results of one unit, one entry per static force of the grid.

    The statistics fields are the leading pantograph's; with a second raised pantograph
    (:attr:`StudyDefinition.two_pantographs <presag_opt.studies.definition.StudyDefinition.two_pantographs>`)
    ``trailing`` holds the same fields for the trailing one.

    Attributes
    ----------
    unit : WorkUnit
        The unit.
    mean_force, std_force, statistical_max, statistical_min, max_force, min_force : tuple of float
        Contact-force statistics (NaN where the run failed). [N]
    loss_of_contact : tuple of float
        Share of the analysis window without contact. [-]
    uplift_max : tuple of float
        Largest steady-arm uplift. [m]
    speed_ratio : float
        β = v / c_CW of the unit's speed. [-]
    failure : tuple of str
        Why each run failed; empty where it finished.
    presag_delta_e, presag_mid_mast : tuple of float
        Quasi-static pre-sag of the Δe and mid/mast rules at each nominal F_m (NaN if the rule
        could not be evaluated; see ``rule_failure``). [m]
    rule_failure : str
        Why the rules could not be evaluated; empty if they were.
    trailing : dict or None
        The trailing pantograph's statistics, by the names of :data:`STATISTICS` (units as above:
        [N], loss of contact [-]); None with one pantograph.
    """

    unit: WorkUnit
    mean_force: tuple[float, ...]
    std_force: tuple[float, ...]
    statistical_max: tuple[float, ...]
    statistical_min: tuple[float, ...]
    max_force: tuple[float, ...]
    min_force: tuple[float, ...]
    loss_of_contact: tuple[float, ...]
    uplift_max: tuple[float, ...]
    speed_ratio: float
    failure: tuple[str, ...]
    presag_delta_e: tuple[float, ...]
    presag_mid_mast: tuple[float, ...]
    rule_failure: str
    trailing: dict[str, tuple[float, ...]] | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready content (floats round-trip exactly through JSON)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> UnitResult:
        """Inverse of :meth:`to_dict`."""
        values = {f.name: data[f.name] for f in fields(cls) if f.name != "trailing"}
        trailing = data.get("trailing")  # absent in the files of a single-pantograph study
        if trailing is not None:
            values["trailing"] = {name: tuple(v) for name, v in trailing.items()}
        unit = values.pop("unit")
        unit = WorkUnit(parameter_indices=tuple(unit["parameter_indices"]), presag_index=unit["presag_index"],
                        speed_index=unit["speed_index"])
        return cls(unit=unit, **{k: tuple(v) if isinstance(v, list) else v for k, v in values.items()})


def _statistics(runs: list[Any], pantograph: int) -> dict[str, tuple[float, ...]]:
    """The :data:`STATISTICS` of one pantograph (0 leading, 1 trailing) of each run, NaN where it failed."""
    return {name: tuple(getattr(r.statistics[pantograph], name) if r.ok else math.nan for r in runs)
            for name in STATISTICS}


STATISTICS = ("mean_force", "std_force", "statistical_max", "statistical_min", "max_force", "min_force",
              "loss_of_contact")
"""Fields of :class:`~presag_opt.dynamics.statistics.ContactForceStatistics` a unit keeps."""


def all_units(definition: StudyDefinition) -> list[WorkUnit]:
    """Every unit of a study, sorted so that units sharing a form-found state come together."""
    return sorted(
        WorkUnit(parameter_indices=variant.indices, presag_index=s, speed_index=v)
        for variant in definition.variants()
        for s in range(len(definition.grid.presags))
        for v in range(len(definition.grid.speeds))
    )


def nominal_mean_force(definition: StudyDefinition, speed: float, static_force: float) -> float:
    """F_m = F_stat + α_ae v², the force the quasi-static rules are evaluated at. [N]

    Parameters
    ----------
    definition : StudyDefinition
        The study (its aerodynamic coefficient).
    speed : float
        Train speed. [m/s]
    static_force : float
        Static uplift force. [N]
    """
    return mean_force(static_force, speed, definition.grid.aero_coefficient)


TASK_UNITS = 4
"""Units (speeds of one pre-sag and parameter combination) computed together in one task: their
static forces run as one batch (32 runs on the paper's grid), which the compiled engine advances
faster per run than a batch of 8; results do not depend on the grouping. [-]"""


def task_groups(units: list[WorkUnit], size: int = TASK_UNITS) -> list[list[WorkUnit]]:
    """Split sorted units into tasks of at most ``size`` units that share a form-found state.

    Parameters
    ----------
    units : list of WorkUnit
        Units sorted as :func:`all_units` sorts them.
    size : int
        Most units per task. [-]
    """
    groups: list[list[WorkUnit]] = []
    for unit in units:
        last = groups[-1] if groups else None
        if (last and len(last) < size and last[0].parameter_indices == unit.parameter_indices
                and last[0].presag_index == unit.presag_index):
            last.append(unit)
        else:
            groups.append([unit])
    return groups


class UnitRunner:
    """The job of a study's workers: :func:`run_units` with a memo of the last :data:`CACHE_SIZE`
    form-found states and their elasticity, kept from one task to the next of the worker that holds
    it (it travels to a worker empty; see :class:`~presag_opt.processes.WorkerMemo`)."""

    def __init__(self) -> None:
        self.memo = WorkerMemo(CACHE_SIZE)

    def __call__(self, definition: StudyDefinition, units: list[WorkUnit]) -> list[UnitResult]:
        return run_units(definition, units, self.memo)


def run_units(definition: StudyDefinition, units: list[WorkUnit], memo: WorkerMemo | None = None) -> list[UnitResult]:
    """Compute units of one pre-sag and parameter combination: all their speeds × static forces in
    one batch, and the quasi-static rules.

    Parameters
    ----------
    definition : StudyDefinition
        The study.
    units : list of WorkUnit
        Units sharing ``parameter_indices`` and ``presag_index``.
    memo : WorkerMemo, optional
        Form-found states and their elasticity kept between calls (a :class:`UnitRunner`'s); None:
        each call form-finds afresh.

    Returns
    -------
    list of UnitResult
        One per unit, in order: statistics per static force; a run (or every run, if the catenary
        cannot be form-found or the batch raises, e.g. ``MemoryError``) that fails is NaN with its
        reason. Such a unit is stored as failed: remove its file from the units directory to run it
        again.
    """
    grid = definition.grid
    first = units[0]
    if any((u.parameter_indices, u.presag_index) != (first.parameter_indices, first.presag_index) for u in units):
        raise ModelError("run_units: the units of one task must share the pre-sag and parameter combination")
    variant = definition.variant(first.parameter_indices)
    presag = grid.presags[first.presag_index]
    catenary = variant.catenary.with_presag(presag / max(variant.catenary.layout.span_lengths))
    n = len(grid.static_forces)
    nan = (math.nan,) * n
    speeds = [grid.speeds[u.speed_index] for u in units]
    statics = [variant.settings.for_speed(v, catenary.contact_wire.wave_speed).static for v in speeds]
    if len(set(statics)) > 1:  # automatic numerics: one form-found state per element length
        groups: dict[Any, list[WorkUnit]] = {}
        for unit, static in zip(units, statics):
            groups.setdefault(static, []).append(unit)
        done = {r.unit: r for group in groups.values() for r in run_units(definition, group, memo)}
        return [done[u] for u in units]
    bases = [{"unit": u, "speed_ratio": speed_ratio(v, catenary.contact_wire.wave_speed)} for u, v in zip(units, speeds)]

    two = variant.train.spacings is not None

    def failed(reason: str) -> list[UnitResult]:
        trailing = {name: nan for name in STATISTICS} if two else None
        return [UnitResult(**base, **{name: nan for name in (*STATISTICS, "uplift_max", *RULE_METHODS)},
                           failure=(reason,) * n, rule_failure=reason, trailing=trailing) for base in bases]

    try:
        state, section = _form_found(definition, catenary, statics[0], memo or WorkerMemo(1))
    except Exception as exc:  # noqa: BLE001 - recorded as the reason: one unit must not stop a study
        return failed(f"form-finding: {failure_reason(exc)}")
    points = [OperatingPoint(speed=v, static_force=f, aero_coefficient=grid.aero_coefficient)
              for v in speeds for f in grid.static_forces]
    try:
        batch = simulate_many(state, variant.pantograph, points, spacings=variant.train.spacings,
                              settings=variant.settings)
    except Exception as exc:  # noqa: BLE001 - e.g. MemoryError: recorded, the study goes on
        return failed(f"simulation: {failure_reason(exc)}")
    results = []
    for i, (base, speed) in enumerate(zip(bases, speeds)):
        runs = batch.runs[i * n : (i + 1) * n]
        stats = _statistics(runs, 0)
        rules, rule_failure = _rules(definition, section, catenary, speed)
        results.append(UnitResult(
            **base, **stats, **rules,
            uplift_max=tuple(r.uplift_max if r.ok else math.nan for r in runs),
            failure=tuple(r.error or "" for r in runs),
            rule_failure=rule_failure,
            trailing=_statistics(runs, 1) if two else None,
        ))
    return results


def _rules(definition: StudyDefinition, section: SectionElasticity | str, catenary: Catenary,
           speed: float) -> tuple[dict[str, tuple[float, ...]], str]:
    """Quasi-static pre-sag of each rule at each nominal F_m, as the mid-span pre-sag of the longest span.

    ``section`` is the reason instead when the elasticity could not be computed.
    """
    longest = max(catenary.layout.span_lengths)
    forces = [nominal_mean_force(definition, speed, f) for f in definition.grid.static_forces]
    try:
        if isinstance(section, str):
            raise ModelError(section)
        rules = {name: tuple(section.presag(f, method).presag_rel_mean * longest for f in forces)
                 for name, method in RULE_METHODS.items()}
    except (ConvergenceError, ModelError) as exc:
        return {name: (math.nan,) * len(forces) for name in RULE_METHODS}, str(exc).splitlines()[0]
    return rules, ""


def _force_levels(definition: StudyDefinition) -> tuple[float, ...]:
    """Elasticity force levels that bracket every nominal F_m of the study. [N]"""
    grid = definition.grid
    forces = [nominal_mean_force(definition, v, f) for v in grid.speeds for f in grid.static_forces]
    return force_levels_for_band(min(forces), max(forces))


def _form_found(
    definition: StudyDefinition, catenary: Catenary, static: StaticSettings, memo: WorkerMemo
) -> tuple[EquilibriumState, SectionElasticity | str]:
    """The form-found state at the static settings ``static`` (the element length of the unit's
    speeds) and its elasticity curves (or why they failed), kept in ``memo``.

    A failing form-finding raises (every run of the unit fails); failing elasticity only leaves the
    rules undefined, so its reason is returned in place of the curves.
    """
    levels = _force_levels(definition)

    def compute() -> tuple[EquilibriumState, SectionElasticity | str]:
        state = form_find(catenary, static)
        try:
            section: SectionElasticity | str = section_elasticity(state, force_levels=levels)
        except (ConvergenceError, ModelError) as exc:
            section = f"elasticity: {str(exc).splitlines()[0]}"
        return state, section

    return memo.get((catenary, static, levels), compute)
