"""The simulation job: pantographs under a catenary at constant speed, ``presag simulate``.

One operating point is run in full (time histories, every pantograph's statistics); a grid of speeds ×
static forces runs as batches on the compiled engine, one form-finding per element length. Every run
is checked before the first form-finding starts.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from presag_opt.display import html_summary
from presag_opt.errors import ModelError
from presag_opt.system.catenary import Catenary
from presag_opt.units import KMH

if TYPE_CHECKING:
    from presag_opt.dynamics.case import SimulationCase
    from presag_opt.dynamics.pantograph import Pantograph
    from presag_opt.dynamics.results import BatchResult
    from presag_opt.dynamics.settings import SimulationSettings
    from presag_opt.dynamics.simulate import SimulationResult

SCHEMES = {"hht": {"scheme": "hht", "hht_alpha": -0.005}, "newmark": {"scheme": "newmark"}}
"""Integration schemes by name, as :class:`~presag_opt.dynamics.integrator.IntegratorSettings` fields:
HHT-α with the paper's numerical damping α = −0.005, or average-acceleration Newmark."""


@dataclass(frozen=True, kw_only=True)
class SimulationAnswer:
    """The runs of a case: one operating point in full, or a grid of them.

    Attributes
    ----------
    case : SimulationCase
        The case simulated (catenary, pantograph, operation and settings as run).
    run : SimulationResult or None
        The single run (one speed and one static force), with its time histories.
    grid : BatchResult or None
        The runs of a grid of speeds × static forces, speeds outer.
    """

    case: SimulationCase
    run: SimulationResult | None = None
    grid: BatchResult | None = None

    def runs(self) -> list[dict]:
        """Each run's statistics as a JSON-ready dict (N, mm, km/h; a failed run of a grid says why)."""
        if self.run is not None:
            return [self.run.to_dict()]
        keys = dict(catenary=self.grid.catenary_name, pantograph=self.case.pantograph.name)
        return [run.to_dict(**keys) for run in self.grid.runs]

    def to_dict(self) -> dict:
        """JSON-ready result: the single run's dict, or the case name and the grid's (``presag simulate --json``)."""
        if self.run is not None:
            return self.run.to_dict()
        return {"case": self.case.name, **self.grid.to_dict()}

    def table(self) -> list[dict]:
        """One row per run: speed, static force, F_m, σ, σ/F_m, the statistical extremes, the loss of contact
        and the largest steady-arm uplift."""
        columns = (("v [km/h]", "speed_kmh"), ("F_stat [N]", "static_force_N"), ("F_m [N]", "Fm_N"),
                   ("σ [N]", "sigma_N"), ("σ/F_m", "sigma_over_Fm"), ("F_m+3σ [N]", "stat_max_N"),
                   ("F_m-3σ [N]", "stat_min_N"), ("loss [%]", "loss_of_contact_pct"),
                   ("uplift [mm]", "uplift_max_mm"))
        static = self.case.operation.static_force
        return [{name: run.get(key, static if key == "static_force_N" else None) for name, key in columns}
                for run in self.runs()]

    def to_frame(self):
        """:meth:`table` as a pandas DataFrame."""
        from presag_opt.display import data_frame

        return data_frame(self.table())

    def _repr_html_(self) -> str:
        count = 1 if self.run is not None else len(self.grid.runs)
        return html_summary(f"Dynamic simulation: {self.case.name}, {count} run{'s' if count != 1 else ''}",
                            [f"catenary {self.case.catenary.name}; pantograph {self.case.pantograph.name}; "
                             f"α_ae {self.case.operation.aero_coefficient * KMH**2:g} N/(km/h)²"], self.table())


def _as_tuple(value: float | Sequence[float] | None) -> tuple[float, ...] | None:
    if value is None:
        return None
    return tuple(float(v) for v in value) if isinstance(value, Sequence) else (float(value),)


def simulation_case(
    model: str | Path | Catenary | None = None,
    pantograph: str | Path | Pantograph | None = None,
    *,
    case: str | Path | SimulationCase | None = None,
    speed_kmh: float | Sequence[float] | None = None,
    static_force: float | Sequence[float] | None = None,
    aero_coefficient_kmh: float | None = None,
    presag_mm: float | None = None,
    spacing_m: Sequence[float] | None = None,
) -> SimulationCase:
    """The case of :func:`simulate`: a case (its values replaced where given), or one built from a catenary,
    a pantograph, speeds and static forces.

    Parameters
    ----------
    model : str, Path or Catenary, optional
        The catenary; or give ``case``.
    pantograph : str, Path or Pantograph, optional
        The pantograph (required with ``model``; with ``case``, replaces the case's).
    case : str, Path or SimulationCase, optional
        A case (built-in name, file or object).
    speed_kmh : float or sequence of float, optional
        Train speed(s); the first is the case's operating speed. [km/h]
    static_force : float or sequence of float, optional
        Static uplift force(s); the first is the case's. [N]
    aero_coefficient_kmh : float, optional
        Aerodynamic uplift coefficient α_ae. [N/(km/h)²]
    presag_mm : float, optional
        Mid-span pre-sag of the longest span, replacing the catenary's. [mm]
    spacing_m : sequence of float, optional
        Distances between consecutive pantographs. [m]

    Returns
    -------
    SimulationCase
        The case with every value given in place (SI inside).

    Examples
    --------
    The case study's case at another static force and pre-sag (its speeds kept):

    >>> from presag_opt.jobs.simulation import simulation_case
    >>> case = simulation_case(case="case_study_st98", static_force=120.0, presag_mm=45.0)
    >>> print(f"F_stat {case.operation.static_force:g} N, S_rel {case.catenary.presag_rel * 1e3:.2f} ‰, "
    ...       f"{len(case.speeds)} speeds")
    F_stat 120 N, S_rel 0.75 ‰, 10 speeds
    """
    from presag_opt.dynamics.case import SimulationCase, load_case
    from presag_opt.dynamics.pantograph import Pantograph, load_pantograph
    from presag_opt.dynamics.settings import Operation, SimulationSettings
    from presag_opt.system.loader import load_catenary

    speeds, forces = _as_tuple(speed_kmh), _as_tuple(static_force)
    panto = pantograph if pantograph is None or isinstance(pantograph, Pantograph) else load_pantograph(pantograph)
    if (case is None) == (model is None):
        raise ModelError("give either a catenary model or a case, not both" if case is not None else
                         "give a catenary model (e.g. 'st_9.8_ideal') or a case (e.g. 'case_study_st98')")
    if case is None:
        missing = [name for name, value in (("pantograph", panto), ("speed_kmh", speeds), ("static_force", forces))
                   if value is None]
        if missing:
            raise ModelError(f"{', '.join(missing)} required with a catenary model (or give a case)")
        catenary = model if isinstance(model, Catenary) else load_catenary(model)
        built = SimulationCase(name=catenary.name, description="", catenary=catenary, pantograph=panto,
                               operation=Operation(speed=speeds[0] * KMH, static_force=forces[0]),
                               speeds=tuple(v * KMH for v in speeds), settings=SimulationSettings())
    else:
        built = case if isinstance(case, SimulationCase) else load_case(case)
        if panto is not None:
            built = dataclasses.replace(built, pantograph=panto)
        if speeds is not None:
            built = dataclasses.replace(built, speeds=tuple(v * KMH for v in speeds))
    changes = {}
    if forces is not None:
        changes["static_force"] = forces[0]
    if aero_coefficient_kmh is not None:
        changes["aero_coefficient"] = aero_coefficient_kmh / KMH**2
    if spacing_m is not None:
        changes["spacings"] = tuple(spacing_m)
    built = dataclasses.replace(built, operation=dataclasses.replace(built.operation, **changes))
    if presag_mm is not None:
        catenary = built.catenary
        built = dataclasses.replace(built, catenary=catenary.with_presag(
            presag_mm * 1e-3 / max(catenary.layout.span_lengths)))
    return built


def simulate(
    model: str | Path | Catenary | None = None,
    pantograph: str | Path | Pantograph | None = None,
    *,
    case: str | Path | SimulationCase | None = None,
    speed_kmh: float | Sequence[float] | None = None,
    static_force: float | Sequence[float] | None = None,
    aero_coefficient_kmh: float | None = None,
    presag_mm: float | None = None,
    spacing_m: Sequence[float] | None = None,
    settings: SimulationSettings | None = None,
    scheme: str | None = None,
    time_step_ms: float | None = None,
    element_length: float | None = None,
    allow_supercritical: bool = False,
    announce: Callable[[str], None] | None = None,
    progress: Callable[[str], None] | None = None,
) -> SimulationAnswer:
    """Pantographs under a catenary at constant speed, with the EN 50367 statistics: the job of ``presag
    simulate``.

    One speed and one static force give one run in full (``answer.run``, with time histories); several
    give a grid, speeds × forces, run as batches on the compiled engine (``answer.grid``).

    Parameters
    ----------
    model : str, Path or Catenary, optional
        The catenary (built-in name, file or object); or give ``case``.
    pantograph : str, Path or Pantograph, optional
        The pantograph (required with ``model``; with ``case``, replaces the case's).
    case : str, Path or SimulationCase, optional
        A case (built-in name, file or object) that bundles catenary, pantograph, operation and speeds.
    speed_kmh : float or sequence of float, optional
        Train speed(s) (default with ``case``: the case's). [km/h]
    static_force : float or sequence of float, optional
        Static uplift force(s) (default with ``case``: the case's). [N]
    aero_coefficient_kmh : float, optional
        Aerodynamic uplift coefficient α_ae: F_m = F_stat + α_ae v² (default 0, or the case's). [N/(km/h)²]
    presag_mm : float, optional
        The catenary's pre-sag replaced: mid-span pre-sag of the longest span. [mm]
    spacing_m : sequence of float, optional
        Several pantographs: distances between consecutive pantographs. [m]
    settings : SimulationSettings, optional
        Numerics and analysis window (default: the case's, or those of
        :class:`~presag_opt.dynamics.settings.SimulationSettings`).
    scheme : {"hht", "newmark"}, optional
        Integration scheme replacing the settings' (:data:`SCHEMES`).
    time_step_ms, element_length : float, optional
        Fixed numerics: the time step [ms] and the longest element [m] (default: automatic from the speed
        where the settings say so).
    allow_supercritical : bool
        Accept a speed at or above β = 0.7 of the wave speed.
    announce : callable, optional
        Told beforehand what long work (a long form-finding, a long batch) will cost.
    progress : callable, optional
        Called with a short message as the work goes on.

    Returns
    -------
    SimulationAnswer
        The run or the grid, with the statistics over the analysed spans; shows itself in a notebook.

    Examples
    --------
    Five 60 m spans of the case study's system at 90 km/h, with coarse fixed numerics for a quick look
    (the default, automatic numerics resolve the speed; the run warns that these do not). Over one analysed
    span the mean contact force meets F_stat + α_ae v² to a few tenths of a percent, and at these numerics
    it moves by that much with the round-off of the form-found state, so it is printed to the newton:

    >>> from presag_opt import load_catenary, simulate
    >>> from presag_opt.dynamics.settings import SimulationSettings
    >>> from presag_opt.system.catenary import SpanLayout
    >>> five = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0,) * 5))
    >>> quick = SimulationSettings(analysed_spans=1, lead_in_spans=1).with_fixed_numerics(element_length=1.0,
    ...                                                                                 time_step=4e-3)
    >>> answer = simulate(five, "case_study_2mass_friction", speed_kmh=90, static_force=70,
    ...                   aero_coefficient_kmh=0.00097, settings=quick)
    >>> print(f"F_m = {answer.run.to_dict()['Fm_N']:.0f} N (F_stat + α_ae v² = 77.9 N)")
    F_m = 78 N (F_stat + α_ae v² = 77.9 N)
    """
    from presag_opt.dynamics.case_grid import form_find_states, plan_grid
    from presag_opt.dynamics.cost import (
        MIN_AUTO_ELEMENT_LENGTH,
        check_run_size,
        estimate_runs,
        form_finding_notice,
        work_notice,
    )
    from presag_opt.speed import check_speed_limit
    from presag_opt.static.run_time import form_find_estimate

    built = simulation_case(model, pantograph, case=case, speed_kmh=speed_kmh, static_force=static_force,
                            aero_coefficient_kmh=aero_coefficient_kmh, presag_mm=presag_mm, spacing_m=spacing_m)
    speeds = built.speeds
    forces = (built.operation.static_force,) if static_force is None else _as_tuple(static_force)
    chosen = _settings(settings or built.settings, scheme, time_step_ms, element_length)
    if not allow_supercritical:
        for speed in speeds:
            check_speed_limit(speed, built.catenary.contact_wire.wave_speed)
    plans = plan_grid(built, speeds, forces, chosen)  # every input is checked before the form-finding starts
    estimate = estimate_runs(built.catenary, list(plans.values()), batch=len(plans) > 1)
    check_run_size(list(plans.values()), estimate,
                   fix=f"element_length={MIN_AUTO_ELEMENT_LENGTH:g} (or longer) with time_step_ms")
    if announce:
        notices = [work_notice(estimate)] + [
            form_finding_notice(*form_find_estimate(built.catenary, static))
            for static in {p.settings.static.element_length: p.settings.static for p in plans.values()}.values()]
        for text in filter(None, notices):
            announce(text)
    if len(plans) == 1:
        states = form_find_states(built.catenary, plans, progress=progress)
        (speed, force), plan = next(iter(plans.items()))
        single = dataclasses.replace(built, operation=dataclasses.replace(built.operation, static_force=force))
        run = single.run(speed, state=states[plan.settings.static.element_length], settings=chosen)
        return SimulationAnswer(case=single, run=run)
    from presag_opt.dynamics.batch.first_use import compiling_ahead
    from presag_opt.dynamics.case_grid import simulate_grid

    with compiling_ahead():  # a grid runs in the batch engine: its first compilation beside the form-findings
        states = form_find_states(built.catenary, plans, progress=progress)
        if progress:
            progress(f"simulating {len(plans)} runs")
        return SimulationAnswer(case=built, grid=simulate_grid(built, plans, states, chosen, progress=progress))


def _settings(base: SimulationSettings, scheme: str | None, time_step_ms: float | None,
              element_length: float | None) -> SimulationSettings:
    """``base`` with the scheme replaced, and fixed numerics where an element length or a time step is given."""
    from presag_opt.dynamics.integrator import IntegratorSettings

    if scheme is not None:
        if scheme not in SCHEMES:
            raise ModelError(f"scheme = {scheme!r}: give one of {', '.join(sorted(SCHEMES))}")
        base = dataclasses.replace(base, integrator=IntegratorSettings(**SCHEMES[scheme],
                                                                        time_step=base.integrator.time_step))
    if time_step_ms is None and element_length is None:
        return base
    return base.with_fixed_numerics(element_length=element_length,
                                    time_step=None if time_step_ms is None else time_step_ms * 1e-3)
