"""The dynamic robust design in the decision: what makes a provisional decision final.

The decision procedure (:mod:`presag_opt.design.decision`) says the dynamic robust design decides
where the quasi-static answers are not trusted, lie outside the dynamic tolerance interval or break
the uplift limit; without it the decision stays *provisional*. :func:`dynamic_robust_decision` runs
the same study as ``presag robust --dynamic``
(:func:`~presag_opt.robust.dynamic_study.dynamic_robust_study`: the quasi-static robust design, the
dynamic search from it and from the Δe rule, the dynamic tolerance by simulation) and
:func:`decision_with_dynamic` makes the decision again with its results: the dynamic robust design
as a candidate with its simulated uplift, the dynamic tolerance interval, and the quasi-static
robust design with its simulated uplift where the decision had none.

The simulated speeds: the band's, but from :data:`LOWEST_SIMULATED_SPEED` at the lowest (a
quasi-static band starts at 0 km/h, which the simulator cannot run; the paper's grid starts at
50 km/h), or from half the top speed where the top speed is not above 50 km/h. The case study's
0–90 km/h is simulated at 50–90 km/h, as ``presag robust --dynamic`` does.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.design.decision import (
    DYNAMIC_ROBUST,
    QUASI_STATIC_ROBUST,
    Candidate,
    Decision,
    decide,
    dynamic_candidate,
)
from presag_opt.dynamics.cost import WorkEstimate, estimate_runs
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.run_plan import plan_run
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.robust.dynamic_design import DynamicObjective
from presag_opt.robust.dynamic_study import QUASI_STATIC, DynamicRobustStudy, dynamic_robust_study
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.system.catenary import Catenary

LOWEST_SIMULATED_SPEED = 50.0 * KMH
"""Lowest speed the dynamic robust design simulates (the paper's lowest grid speed). [m/s]"""

TYPICAL_PRESAGS = 7
"""Pre-sags a dynamic robust design typically simulates (search and tolerance ends; 5 for the case
study, at most the search's 12 plus 2), for the announced cost. [-]"""


@dataclass(frozen=True, kw_only=True)
class DynamicDecision:
    """A decision made with the dynamic robust design.

    Attributes
    ----------
    decision : Decision
        The decision made again.
    study : DynamicRobustStudy
        The dynamic robust study it was made with.
    where : str
        What was simulated (the case, or the line's worst section).
    """

    decision: Decision
    study: DynamicRobustStudy
    where: str


def simulated_band(band: OperatingBand) -> OperatingBand:
    """The band with its lowest speed raised to what is simulated (see the module docstring).

    Parameters
    ----------
    band : OperatingBand
        Static forces, speeds and α_ae. [N], [m/s]
    """
    floor = LOWEST_SIMULATED_SPEED if band.speed_high > LOWEST_SIMULATED_SPEED else 0.5 * band.speed_high
    low = max(band.speed_low, floor)
    return dataclasses.replace(band, speed_low=low)


def dynamic_cost(catenary: Catenary, pantograph: Pantograph, band: OperatingBand, *, static_points: int = 4,
                 speed_points: int = 3, workers: int = 1) -> WorkEstimate:
    """Rough cost of :func:`dynamic_robust_decision` (:data:`TYPICAL_PRESAGS` pre-sags of the grid).

    Parameters
    ----------
    catenary : Catenary
        The system simulated.
    pantograph : Pantograph
        The pantograph.
    band : OperatingBand
        The band as simulated (:func:`simulated_band`). [N], [m/s]
    static_points, speed_points : int
        Grid points along each axis. [-]
    workers : int
        Processes simulating pre-sags side by side. [-]
    """
    grid = OperatingGrid.from_band(band, static_points=static_points, speed_points=speed_points)
    settings = SimulationSettings(numerics="auto")
    plans = [plan_run(catenary, pantograph, speed=v, static_force=f, aero_coefficient=band.aero_coefficient,
                      settings=settings) for f in grid.static_forces for v in grid.speeds]
    one = estimate_runs(catenary, plans, batch=True)
    share = TYPICAL_PRESAGS / max(1, min(workers, 2))
    return WorkEstimate(nodes=one.nodes, form_finding_seconds=share * one.form_finding_seconds,
                        runs=TYPICAL_PRESAGS * one.runs, run_seconds=share * one.run_seconds, memory=one.memory)


def decision_with_dynamic(decision: Decision, study: DynamicRobustStudy, where: str) -> Decision:
    """The decision made again with a dynamic robust study's results.

    Candidates: those of ``decision`` (a dynamic robust one replaced), the dynamic robust design with
    its tolerance and simulated uplift, and — where ``decision`` has no quasi-static robust design —
    the study's, with its simulated uplift. The dynamic tolerance interval enters the inputs, and
    what the study checked leaves the list of what was not checked.

    Parameters
    ----------
    decision : Decision
        The decision without the dynamic robust design.
    study : DynamicRobustStudy
        From :func:`~presag_opt.robust.dynamic_study.dynamic_robust_study`.
    where : str
        What was simulated, named in the decision's notes.
    """
    inputs = decision.inputs
    candidates = [c for c in inputs.candidates if c.method != DYNAMIC_ROBUST]
    if not any(c.method == QUASI_STATIC_ROBUST for c in candidates):
        quasi = study.method(QUASI_STATIC)
        candidates.append(Candidate(method=QUASI_STATIC_ROBUST, presag_rel=quasi.presag_rel, uplift=quasi.uplift_max,
                                    uplift_dynamic=True))
    candidates.append(dynamic_candidate(study.design, study.tolerance))
    grid = study.design.grid
    kept = tuple(n for n in inputs.not_checked
                 if "dynamic robust design" not in n and not n.startswith("the quasi-static robust design"))
    note = (f"the dynamic robust design is that of {where} ({len(grid.static_forces)} static forces × "
            f"{len(grid.speeds)} speeds, {grid.speeds[0] / KMH:.0f}–{grid.speeds[-1] / KMH:.0f} km/h)")
    return decide(dataclasses.replace(inputs, candidates=tuple(candidates),
                                      dynamic_tolerance=(study.tolerance.low, study.tolerance.high),
                                      not_checked=kept + (note,)))


def dynamic_robust_decision(decision: Decision, catenary: Catenary, pantograph: Pantograph, band: OperatingBand, *,
                            where: str, objective: DynamicObjective | None = None, workers: int = 1,
                            progress: Callable[[str], None] | None = None) -> DynamicDecision:
    """Run the dynamic robust design of a band on one system and make the decision again with it.

    Parameters
    ----------
    decision : Decision
        The decision without the dynamic robust design.
    catenary : Catenary
        The system simulated (its pre-sag is replaced by the designs').
    pantograph : Pantograph
        The pantograph.
    band : OperatingBand
        Static forces, speeds and α_ae; simulated as :func:`simulated_band`. [N], [m/s]
    where : str
        What is simulated, e.g. ``"the case study's ideal section"``.
    objective : DynamicObjective, optional
        Loss, risk and uplift limit (default: worst case of σ/F_m at the decision's uplift limit).
    workers : int
        Processes simulating pre-sags side by side. [-]
    progress : callable, optional
        Called with a short message before each expensive step.
    """
    objective = objective or DynamicObjective(uplift_limit=decision.inputs.uplift_limit)
    study = dynamic_robust_study(catenary, pantograph, simulated_band(band), objective=objective, workers=workers,
                                 progress=progress)
    return DynamicDecision(decision=decision_with_dynamic(decision, study, where), study=study, where=where)
