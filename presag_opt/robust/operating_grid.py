"""The operating points a pre-sag design is simulated at: a grid over a band of static forces and speeds.

Holds :class:`OperatingGrid` (static forces × speeds, evenly spaced over an
:class:`~presag_opt.design.band.OperatingBand`, with trapezoidal weights for means over the band),
its checks against a catenary before any work starts, :func:`band_static_settings`, the one
discretisation every run of a band shares, and :func:`band_work`, the cost announced for simulating
designs on the grid. The simulation of a design on the grid is :mod:`presag_opt.robust.band_evaluation`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import KMH, OperatingBand, mean_contact_force
from presag_opt.dynamics.cost import WorkEstimate, estimate_runs
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.run_plan import plan_run
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.catenary import Catenary

MAX_POINTS = 20
"""Most grid points along one axis of a band. [-]"""


@dataclass(frozen=True, kw_only=True)
class OperatingGrid:
    """Static forces × speeds a design is simulated at, every combination once.

    Attributes
    ----------
    static_forces : tuple of float
        Static uplift forces, increasing. [N]
    speeds : tuple of float
        Train speeds, increasing. [m/s]
    aero_coefficient : float
        α_ae of F_m = F_stat + α_ae v². [N/(m/s)²]
    """

    static_forces: tuple[float, ...]
    speeds: tuple[float, ...]
    aero_coefficient: float

    def __post_init__(self) -> None:
        for name, unit, scale in (("static_forces", "N", 1.0), ("speeds", "km/h", KMH)):
            values = np.asarray(getattr(self, name), dtype=float)
            if values.ndim != 1 or len(values) == 0 or not np.all(np.isfinite(values)) or np.any(values <= 0.0):
                raise ModelError(f"{name} = {list(values / scale)} {unit}: give at least one positive value")
            if np.any(np.diff(values) <= 0.0):
                raise ModelError(f"{name} = {list(values / scale)} {unit} must be strictly increasing")
            object.__setattr__(self, name, tuple(float(v) for v in values))

    @classmethod
    def from_band(cls, band: OperatingBand, *, static_points: int = 4, speed_points: int = 3) -> OperatingGrid:
        """Evenly spaced static forces and speeds over a band, its ends included.

        Parameters
        ----------
        band : OperatingBand
            Static force and speed band (both non-empty; the speeds above 0). [N], [m/s]
        static_points, speed_points : int
            Points along each axis, 2 to :data:`MAX_POINTS`. [-]

        Raises
        ------
        ModelError
            An empty band (low = high), a band starting at 0 km/h, or a point count out of range.
        """
        for name, count in (("static_points", static_points), ("speed_points", speed_points)):
            if count != int(count) or not 2 <= count <= MAX_POINTS:
                raise ModelError(f"{name} = {count} is outside the valid range [2, {MAX_POINTS}]")
        if band.static_force_high <= band.static_force_low:
            raise ModelError(
                f"static force band {band.static_force_low:g}:{band.static_force_high:g} N is empty; give LOW:HIGH "
                "with LOW < HIGH, e.g. 70:140"
            )
        if band.speed_high <= band.speed_low:
            raise ModelError(
                f"speed band {band.speed_low / KMH:g}:{band.speed_high / KMH:g} km/h is empty; give LOW:HIGH with "
                "LOW < HIGH, e.g. 50:90"
            )
        if band.speed_low <= 0.0:
            raise ModelError(
                f"speed band starts at {band.speed_low / KMH:g} km/h: a simulated speed must be above 0 km/h "
                "(runs get long below about 30 km/h, where the quasi-static design holds)"
            )
        return cls(
            static_forces=tuple(np.linspace(band.static_force_low, band.static_force_high, static_points)),
            speeds=tuple(np.linspace(band.speed_low, band.speed_high, speed_points)),
            aero_coefficient=band.aero_coefficient,
        )

    def points(self) -> list[OperatingPoint]:
        """Every (speed, static force), speed by speed. [m/s], [N]"""
        return [OperatingPoint(speed=v, static_force=f, aero_coefficient=self.aero_coefficient)
                for v in self.speeds for f in self.static_forces]

    @property
    def weights(self) -> np.ndarray:
        """Probability of each point for F_stat and v uniform and independent over the band: the
        trapezoidal rule along each axis, in the order of :meth:`points`. [-]"""
        def trapezoid(n: int) -> np.ndarray:
            w = np.ones(n) if n == 1 else np.r_[0.5, np.ones(n - 2), 0.5]
            return w / w.sum()

        return np.outer(trapezoid(len(self.speeds)), trapezoid(len(self.static_forces))).ravel()

    @property
    def mean_force_band(self) -> tuple[float, float]:
        """Nominal F_m = F_stat + α_ae v² at the lowest and the highest point. [N]"""
        return (float(mean_contact_force(self.static_forces[0], self.speeds[0], self.aero_coefficient)),
                float(mean_contact_force(self.static_forces[-1], self.speeds[-1], self.aero_coefficient)))

    def check(self, catenary: Catenary, pantograph: Pantograph, settings: SimulationSettings,
              spacings: tuple[float, ...] | None = None) -> None:
        """Refuse, before any work, a grid the catenary cannot be simulated at (with the pantograph
        spacings of the train, if several, in m).

        Parameters
        ----------
        catenary : Catenary
            System model.
        pantograph : Pantograph
            Pantograph model.
        settings : SimulationSettings
            Numerical settings of the runs.
        spacings : tuple of float, optional
            Distances between consecutive pantographs of the train, front to rear; None for one. [m]

        Raises
        ------
        ModelError
            A speed at or above the contact-wire wave speed, or a point :func:`plan_run` refuses
            (time step, section too short for the analysed spans); the message names the point.
        """
        wave_speed = catenary.contact_wire.wave_speed
        if self.speeds[-1] >= wave_speed:
            raise ModelError(
                f"speed = {self.speeds[-1] / KMH:g} km/h is at or above the contact-wire wave speed "
                f"{wave_speed / KMH:.1f} km/h of {catenary.name}; the valid range is (0, {wave_speed / KMH:.1f}) km/h"
            )
        for p in self.points():
            try:
                plan_run(catenary, pantograph, speed=p.speed, static_force=p.static_force,
                         aero_coefficient=p.aero_coefficient, spacings=spacings, settings=settings)
            except ModelError as exc:
                raise ModelError(f"operating point {p.speed / KMH:g} km/h, {p.static_force:g} N: {exc}") from None


def band_static_settings(catenary: Catenary, speeds, settings: SimulationSettings) -> StaticSettings:
    """Static settings of one form-finding shared by every run at the given speeds: with automatic
    numerics, the element length of the fastest (the finest any of them needs), so that no run is
    under-resolved; with fixed numerics, ``settings.static``.

    Parameters
    ----------
    catenary : Catenary
        System model (its wave speed).
    speeds : sequence of float
        Train speeds, each below the wave speed. [m/s]
    settings : SimulationSettings
        Numerical settings of the runs.
    """
    wave_speed = catenary.contact_wire.wave_speed
    finest = min(settings.for_speed(v, wave_speed).static.element_length for v in speeds)
    return dataclasses.replace(settings.static, element_length=finest)


def band_work(catenary: Catenary, pantograph: Pantograph, grid: OperatingGrid, *, evaluations: int, workers: int,
              settings: SimulationSettings | None = None) -> WorkEstimate:
    """Rough cost of simulating ``evaluations`` catenaries (pre-sags or realisations) on the grid, as
    :mod:`presag_opt.robust.band_evaluation` and the dynamic Monte Carlo do it: one form-finding and
    one batch each, every run on the band's shared discretisation (:func:`band_static_settings`) at
    the time step of its own speed, side by side in up to ``workers`` processes.

    Parameters
    ----------
    catenary : Catenary
        The system simulated (its nodes are counted at the shared element length).
    pantograph : Pantograph
        The pantograph.
    grid : OperatingGrid
        Static forces × speeds. [N], [m/s]
    evaluations : int
        Catenaries simulated on the whole grid. [-]
    workers : int
        Processes simulating them side by side. [-]
    settings : SimulationSettings, optional
        Numerical settings of the runs (default: automatic numerics).

    Returns
    -------
    WorkEstimate
        Wall time shared out over the processes; memory of the processes together.
    """
    settings = settings or SimulationSettings(numerics="auto")
    plans = [plan_run(catenary, pantograph, speed=p.speed, static_force=p.static_force,
                      aero_coefficient=p.aero_coefficient, settings=settings) for p in grid.points()]
    static = band_static_settings(catenary, grid.speeds, settings)  # after the plans' checks of every speed
    plans = [dataclasses.replace(p, settings=dataclasses.replace(p.settings, static=static)) for p in plans]
    one = estimate_runs(catenary, plans, batch=True)
    side_by_side = max(1, min(workers, evaluations))
    share = evaluations / side_by_side
    return WorkEstimate(nodes=one.nodes, form_finding_seconds=share * one.form_finding_seconds,
                        runs=evaluations * one.runs, run_seconds=share * one.run_seconds,
                        memory=one.memory * side_by_side)
