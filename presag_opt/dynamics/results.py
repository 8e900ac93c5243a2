"""The results of the simulator: one run's time histories and statistics, a batch's outcomes, and
the one summary (the ``--json`` keys) that both give.

:class:`SimulationResult` is what :func:`~presag_opt.dynamics.simulate.simulate` returns (time
histories per pantograph in :class:`PantographHistory`); :class:`RunOutcome` one run of
:func:`~presag_opt.dynamics.batch.simulate_many` (statistics only, or the reason it failed), collected
in :class:`BatchResult`. :func:`run_summary` builds the headline numbers of a run, with units in the
key names, for both: a run gives the same keys and numbers whichever engine ran it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.dynamics.settings import OperatingPoint, Operation, SimulationSettings
from presag_opt.dynamics.statistics import ContactForceStatistics
from presag_opt.units import KMH


def run_summary(
    *,
    catenary: str,
    pantographs: Sequence[str],
    offsets: Sequence[float],
    point: OperatingPoint,
    statistics: Sequence[ContactForceStatistics],
    uplift_max: float,
    slack_droppers_max: int,
    speed_ratio: float,
    doppler_factor: float,
    wave_speed: float,
    analysed_spans: Sequence[int],
    analysed_section: Sequence[float],
    time_step: float,
    wall_time: float,
    warnings: Sequence[str],
    error: str | None = None,
) -> dict:
    """The headline numbers of one run, with units in the key names (the ``--json`` output).

    Parameters
    ----------
    catenary : str
        Catenary name.
    pantographs : sequence of str
        Pantograph names, front to rear.
    offsets : sequence of float
        Each pantograph's distance behind the leading one. [m]
    point : OperatingPoint
        Speed [m/s], static force [N] and α_ae [N/(m/s)²].
    statistics : sequence of ContactForceStatistics
        Each pantograph's, front to rear; empty for a failed run.
    uplift_max : float
        Largest support uplift of the analysed section. [m]
    slack_droppers_max : int
        Most recorded droppers slack at once. [-]
    speed_ratio, doppler_factor : float
        β = v/c and (c − v)/(c + v). [-]
    wave_speed : float
        Contact-wire wave speed. [m/s]
    analysed_spans : sequence of int
        Spans (from 0) of the analysed section; reported from 1. [-]
    analysed_section : sequence of float
        Its start and end stations. [m]
    time_step : float
        [s]
    wall_time : float
        [s]
    warnings : sequence of str
        One line per under-resolving setting.
    error : str, optional
        Why the run failed; its statistics are then left out.
    """
    ok = error is None
    out = {
        "catenary": catenary,
        "pantograph": pantographs[0],
        "speed_kmh": point.speed / KMH,
        "static_force_N": point.static_force,
        "aero_force_N": point.aero_force,
    }
    if ok:
        out.update(statistics[0].to_dict())
        out["uplift_max_mm"] = uplift_max * 1e3
    out.update({
        "beta": speed_ratio,
        "doppler_factor": doppler_factor,
        "wave_speed_kmh": wave_speed / KMH,
        "analysed_spans": [s + 1 for s in analysed_spans],
        "analysed_section_m": list(analysed_section),
    })
    if ok:
        out["slack_droppers_max"] = slack_droppers_max
    out["time_step_ms"] = time_step * 1e3
    out["wall_time_s"] = wall_time
    out["warnings"] = list(warnings)
    if not ok:
        out["error"] = error
    elif len(statistics) > 1:
        out["pantographs"] = [
            {"name": name, "offset_m": offset, **s.to_dict()} for name, offset, s in zip(pantographs, offsets, statistics)
        ]
    return out


def analysed_supports(support_station: np.ndarray, section: tuple[float, float]) -> np.ndarray:
    """The supports (masts) inside the analysed section, both ends included (1 nm of round-off
    allowed), whose uplift a run reports.

    Parameters
    ----------
    support_station : ndarray
        Station of every support along the track. [m]
    section : (float, float)
        Start and end of the analysed section along the track. [m]

    Returns
    -------
    ndarray of int
        Indices into ``support_station``. [-]
    """
    start, end = section
    return np.flatnonzero((support_station >= start - 1e-9) & (support_station <= end + 1e-9))



@dataclass(frozen=True, kw_only=True)
class PantographHistory:
    """Time histories and statistics of one pantograph.

    Attributes
    ----------
    name : str
        Pantograph model name.
    offset : float
        Distance behind the leading pantograph. [m]
    position : ndarray
        Station of the contact point (distance from the first mast). [m]
    contact_force : ndarray
        Raw contact force. [N]
    contact_force_filtered : ndarray
        Contact force low-pass filtered (zero phase) at the cut-off frequency. [N]
    wire_uplift : ndarray
        Contact-wire uplift at the contact point from the static equilibrium. [m]
    displacement : ndarray, shape (n_times, n_stages)
        Displacement of each stage (head first) from the pressed rest state, z up. [m]
    velocity : ndarray, shape (n_times, n_stages)
        Velocity of each stage. [m/s]
    window : tuple of float
        Times the contact point enters and leaves the analysed section. [s]
    statistics : ContactForceStatistics
        Statistics over ``window``.
    """

    name: str
    offset: float
    position: np.ndarray
    contact_force: np.ndarray
    contact_force_filtered: np.ndarray
    wire_uplift: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    window: tuple[float, float]
    statistics: ContactForceStatistics


@dataclass(frozen=True, kw_only=True)
class SimulationResult:
    """Result of :func:`simulate`.

    Attributes
    ----------
    catenary_name : str
        Name of the catenary.
    operation : Operation
        Speed, static force, aerodynamic coefficient and spacings.
    wave_speed : float
        Contact-wire wave speed sqrt(T/ρ). [m/s]
    speed_ratio : float
        β = v / c. [-]
    doppler_factor : float
        (c − v)/(c + v). [-]
    time : ndarray
        Sample times. [s]
    pantographs : tuple of PantographHistory
        Front to rear.
    analysed_spans : tuple of int
        Spans (from 0) of the analysed section. [-]
    analysed_section : tuple of float
        Stations where the analysed section starts and ends. [m]
    support_station : ndarray
        Station of every mast. [m]
    support_uplift : ndarray, shape (n_times, n_masts)
        Contact-wire uplift at every steady arm / support from the static equilibrium. [m]
    dropper_station : ndarray
        Station of each recorded dropper. [m]
    dropper_span : ndarray of int
        Span (from 0) of each recorded dropper. [-]
    dropper_force : ndarray, shape (n_times, n_recorded)
        Tensile force of each recorded dropper; zero when slack. [N]
    dropper_static_force : ndarray
        Static force of each recorded dropper. [N]
    newton_iterations : ndarray of int
        Newton corrections per time step. [-]
    stepping_time : float
        Wall-clock time of the time stepping. [s]
    total_time : float
        Wall-clock time of the whole call (form-finding included if it ran). [s]
    settings : SimulationSettings
        Settings used.
    warnings : tuple of str
        One line per numerical setting that under-resolves the run (see :func:`run_warnings`).
    """

    catenary_name: str
    operation: Operation
    wave_speed: float
    speed_ratio: float
    doppler_factor: float
    time: np.ndarray
    pantographs: tuple[PantographHistory, ...]
    analysed_spans: tuple[int, ...]
    analysed_section: tuple[float, float]
    support_station: np.ndarray
    support_uplift: np.ndarray
    dropper_station: np.ndarray
    dropper_span: np.ndarray
    dropper_force: np.ndarray
    dropper_static_force: np.ndarray
    newton_iterations: np.ndarray
    stepping_time: float
    total_time: float
    settings: SimulationSettings
    warnings: tuple[str, ...] = ()

    @property
    def statistics(self) -> ContactForceStatistics:
        """Contact-force statistics of the leading pantograph."""
        return self.pantographs[0].statistics

    @property
    def analysed_supports(self) -> np.ndarray:
        """Indices of the masts inside the analysed section (:func:`analysed_supports`)."""
        return analysed_supports(self.support_station, self.analysed_section)

    @property
    def uplift_max(self) -> float:
        """Largest contact-wire uplift at a steady arm / support of the analysed section. [m]"""
        return float(self.support_uplift[:, self.analysed_supports].max())

    @property
    def slack(self) -> np.ndarray:
        """True where a recorded dropper is slack, shape (n_times, n_recorded)."""
        return self.dropper_force <= 0.0

    def to_dict(self) -> dict:
        """Headline numbers with units in the key names (the ``--json`` output of the CLI; see
        :func:`run_summary`)."""
        return run_summary(
            catenary=self.catenary_name, pantographs=tuple(p.name for p in self.pantographs),
            offsets=tuple(p.offset for p in self.pantographs), point=self.operation,
            statistics=tuple(p.statistics for p in self.pantographs), uplift_max=self.uplift_max,
            slack_droppers_max=int(self.slack.sum(axis=1).max()) if self.slack.size else 0,
            speed_ratio=self.speed_ratio, doppler_factor=self.doppler_factor, wave_speed=self.wave_speed,
            analysed_spans=self.analysed_spans, analysed_section=self.analysed_section,
            time_step=self.settings.integrator.time_step, wall_time=self.total_time, warnings=self.warnings,
        )


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
    slack_droppers_max : int
        Most droppers of the analysed section slack at the same time. [-]
    speed_ratio : float
        β = v / c. [-]
    doppler_factor : float
        (c − v)/(c + v). [-]
    wave_speed : float
        Contact-wire wave speed. [m/s]
    analysed_spans : tuple of int
        Spans (from 0) of the analysed section. [-]
    analysed_section : tuple of float
        Stations where the analysed section starts and ends. [m]
    newton_iterations : int
        Newton corrections over the whole run. [-]
    wall_time : float
        The run's share of the wall-clock time of the kernel call it ran in (that call's time
        divided by its runs). [s]
    time_step : float
        The run's time step. [s]
    warnings : tuple of str
        One line per numerical setting that under-resolves the run.
    offsets : tuple of float
        Each pantograph's distance behind the leading one. [m]
    error : str or None
        Why the run failed (one line), None if it finished.
    time : ndarray or None
        Record times, kept with ``keep_histories``. [s]
    contact_force : ndarray or None
        Raw contact force of each pantograph, shape (n_times, n_pantographs), kept with
        ``keep_histories``. [N]
    """

    point: OperatingPoint
    statistics: tuple[ContactForceStatistics, ...]
    uplift_max: float
    slack_droppers_max: int
    speed_ratio: float
    doppler_factor: float
    wave_speed: float
    analysed_spans: tuple[int, ...]
    analysed_section: tuple[float, float]
    newton_iterations: int
    wall_time: float
    time_step: float
    warnings: tuple[str, ...] = ()
    offsets: tuple[float, ...] = (0.0,)
    error: str | None = None
    time: np.ndarray | None = None
    contact_force: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        """Whether the run finished."""
        return self.error is None

    def to_dict(self, *, catenary: str, pantograph: str | Sequence[str]) -> dict:
        """Headline numbers with units in the key names: the keys of the single-run ``--json`` output
        (:func:`run_summary`).

        Parameters
        ----------
        catenary : str
            Catenary name.
        pantograph : str or sequence of str
            Name of every pantograph, front to rear, or one name for all.
        """
        names = (pantograph,) * len(self.offsets) if isinstance(pantograph, str) else tuple(pantograph)
        return run_summary(
            catenary=catenary, pantographs=names, offsets=self.offsets, point=self.point,
            statistics=self.statistics, uplift_max=self.uplift_max, slack_droppers_max=self.slack_droppers_max,
            speed_ratio=self.speed_ratio, doppler_factor=self.doppler_factor, wave_speed=self.wave_speed,
            analysed_spans=self.analysed_spans, analysed_section=self.analysed_section, time_step=self.time_step,
            wall_time=self.wall_time, warnings=self.warnings, error=self.error,
        )


@dataclass(frozen=True, kw_only=True)
class BatchResult:
    """Result of :func:`simulate_many`.

    Attributes
    ----------
    catenary_name : str
        Name of the catenary.
    pantograph_names : tuple of str
        Pantograph models, front to rear.
    runs : tuple of RunOutcome
        One per operating point, in the order given.
    wall_time : float
        Wall-clock time of the whole batch. [s]
    settings : SimulationSettings
        Settings used.
    """

    catenary_name: str
    pantograph_names: tuple[str, ...]
    runs: tuple[RunOutcome, ...]
    wall_time: float
    settings: SimulationSettings

    def to_dict(self) -> dict:
        """All runs as the ``--json`` output of ``presag simulate`` with several operating points."""
        keys = {"catenary": self.catenary_name, "pantograph": self.pantograph_names}
        return {
            "catenary": self.catenary_name,
            "pantographs": list(self.pantograph_names),
            "wall_time_s": self.wall_time,
            "failed_runs": len(self.failed),
            "runs": [r.to_dict(**keys) for r in self.runs],
        }

    @property
    def failed(self) -> tuple[RunOutcome, ...]:
        """The runs that did not finish."""
        return tuple(r for r in self.runs if not r.ok)


