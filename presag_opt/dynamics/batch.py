"""Many operating points on one form-found catenary: the batch entry point of the simulator.

:func:`simulate_many` runs a list of :class:`OperatingPoint` (speed, static force, aerodynamic
coefficient) under one :class:`~presag_opt.static.equilibrium.EquilibriumState` and returns one
:class:`RunOutcome` per point, in the order given. Every run is independent of the others in its
batch: a run that fails (no convergence, a bad operating point) is reported as failed with its
reason, and the others finish unaffected.

This module holds the batch interface and its bookkeeping; the time stepping itself lives in
:mod:`presag_opt.dynamics.simulate` (single runs, the reference path).
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.simulate import SimulationResult, SimulationSettings, simulate
from presag_opt.dynamics.statistics import ContactForceStatistics
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.system.quantity import quantity, validate_fields


@dataclass(frozen=True, kw_only=True)
class OperatingPoint:
    """One operating point of a batch.

    Attributes
    ----------
    speed : float
        Train speed. [m/s]
    static_force : float
        Static uplift force of each pantograph. [N]
    aero_coefficient : float
        Aerodynamic uplift coefficient α_ae of F_m = F_stat + α_ae v². [N/(m/s)²]
    """

    speed: float = quantity("speed", 0.0, 600.0, display="km/h", low_open=True)
    static_force: float = quantity("force", 0.0, 500.0, low_open=True)
    aero_coefficient: float = quantity("aero_coefficient", 0.0, 0.01, display="N/(km/h)^2", default=0.0)

    def __post_init__(self) -> None:
        validate_fields(self)


@dataclass(frozen=True, kw_only=True)
class RunOutcome:
    """Result of one run of a batch: its statistics, or the reason it failed.

    Attributes
    ----------
    point : OperatingPoint
        The operating point.
    statistics : tuple of ContactForceStatistics
        Contact-force statistics of each pantograph, front to rear; empty if the run failed.
    uplift_max : float
        Largest contact-wire uplift at a steady arm / support of the analysed section; NaN if the
        run failed. [m]
    speed_ratio : float
        β = v / c. [-]
    doppler_factor : float
        (c − v)/(c + v). [-]
    error : str or None
        Why the run failed (one line), None if it finished.
    result : SimulationResult or None
        Full histories, kept only when asked for (``keep_histories=True``).
    """

    point: OperatingPoint
    statistics: tuple[ContactForceStatistics, ...]
    uplift_max: float
    speed_ratio: float
    doppler_factor: float
    error: str | None = None
    result: SimulationResult | None = None

    @property
    def ok(self) -> bool:
        """Whether the run finished."""
        return self.error is None


@dataclass(frozen=True, kw_only=True)
class BatchResult:
    """Result of :func:`simulate_many`.

    Attributes
    ----------
    catenary_name : str
        Name of the catenary.
    runs : tuple of RunOutcome
        One per operating point, in the order given.
    wall_time : float
        Wall-clock time of the whole batch. [s]
    settings : SimulationSettings
        Settings used.
    """

    catenary_name: str
    runs: tuple[RunOutcome, ...]
    wall_time: float
    settings: SimulationSettings

    @property
    def failed(self) -> tuple[RunOutcome, ...]:
        """The runs that did not finish."""
        return tuple(r for r in self.runs if not r.ok)


def simulate_many(
    state: EquilibriumState,
    pantograph: Pantograph | Sequence[Pantograph],
    points: Sequence[OperatingPoint],
    *,
    spacings: Sequence[float] | None = None,
    settings: SimulationSettings | None = None,
    keep_histories: bool = False,
    progress: Callable[[int], None] | None = None,
) -> BatchResult:
    """Run many operating points on one form-found catenary.

    Parameters
    ----------
    state : EquilibriumState
        The form-found catenary shared by all runs.
    pantograph : Pantograph or sequence of Pantograph
        As in :func:`~presag_opt.dynamics.simulate.simulate`.
    points : sequence of OperatingPoint
        The operating points; at least one.
    spacings : sequence of float, optional
        Distances between consecutive pantographs, front to rear, for every run. [m]
    settings : SimulationSettings, optional
        Numerical settings and analysis window shared by all runs.
    keep_histories : bool
        Keep each run's full :class:`SimulationResult` (memory grows with the batch).
    progress : callable, optional
        Called with the number of runs just finished.

    Returns
    -------
    BatchResult
        One outcome per point, in order.

    Raises
    ------
    ModelError
        An empty list of points (a bad single point is reported in its outcome instead).
    """
    started = wallclock.perf_counter()
    settings = settings or SimulationSettings()
    points = list(points)
    if not points:
        raise ModelError("operating points: the list is empty; give at least one (speed, static force)")
    runs = []
    for point in points:
        runs.append(_run_one(state, pantograph, point, spacings, settings, keep_histories))
        if progress is not None:
            progress(1)
    return BatchResult(
        catenary_name=state.catenary.name,
        runs=tuple(runs),
        wall_time=wallclock.perf_counter() - started,
        settings=settings,
    )


def _run_one(
    state: EquilibriumState,
    pantograph: Pantograph | Sequence[Pantograph],
    point: OperatingPoint,
    spacings: Sequence[float] | None,
    settings: SimulationSettings,
    keep_histories: bool,
) -> RunOutcome:
    wave_speed = state.catenary.contact_wire.wave_speed
    ratio = point.speed / wave_speed
    doppler = (wave_speed - point.speed) / (wave_speed + point.speed)
    try:
        result = simulate(
            state, pantograph, speed=point.speed, static_force=point.static_force,
            aero_coefficient=point.aero_coefficient, spacings=spacings, settings=settings,
        )
    except (ConvergenceError, ModelError) as exc:
        return RunOutcome(point=point, statistics=(), uplift_max=float("nan"), speed_ratio=ratio,
                          doppler_factor=doppler, error=str(exc).splitlines()[0])
    return RunOutcome(
        point=point,
        statistics=tuple(p.statistics for p in result.pantographs),
        uplift_max=result.uplift_max,
        speed_ratio=ratio,
        doppler_factor=doppler,
        result=result if keep_histories else None,
    )
