"""The evidence a pre-sag decision is made from: one frozen record per method that answers "which S?".

Each method's producer returns its record and nothing else builds it:

==============================  ==========================================================================
record                          produced by
==============================  ==========================================================================
:class:`DeltaERule`             :meth:`presag_opt.design.recommendation.Recommendation.evidence`
:class:`QuasiStaticRobust`      :meth:`presag_opt.robust.study.RobustStudy.evidence`
:class:`ValiditySweep`          :func:`presag_opt.studies.validity_evidence.validity_sweep`
:class:`DynamicUpliftCheck`     :func:`presag_opt.pipeline.line.line_dynamic_check`
:class:`DynamicRobust`          :meth:`presag_opt.robust.dynamic_study.DynamicRobustStudy.evidence`
:class:`InstallationTolerance`  :func:`crew_tolerance` (a setting) or
                                :func:`presag_opt.robust.monte_carlo.installation_tolerance` (Monte Carlo)
==============================  ==========================================================================

:class:`Evidence` holds the records of one band (or line) with what every decision needs (wave speed,
top speed, uplift limit, the span pre-sag is quoted on); :func:`presag_opt.design.decision.decide`
turns it into a decision. What was *not* checked is simply the records that are missing
(:meth:`Evidence.missing`); the command that renders the decision names its own option for each.

All pre-sags are relative, S_rel = S/l [-]; uplifts and tolerances in metres.

**The crew's tolerance** (:data:`CREW_TOLERANCE`, assumed): ±2.5 mm on the mid-span pre-sag. No
public figure for the build tolerance of a pre-sag was found; ±2.5 mm is half of a 5 mm cutting step,
the rounding error alone of a crew that cuts droppers to the nearest 5 mm. Set a crew's own figure,
or derive it from per-dropper errors by Monte Carlo (``--dropper-error``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from presag_opt.design.validity_limit import SweepLimit, ValidityStatement, validity_statement
from presag_opt.errors import ModelError

CREW_TOLERANCE = 2.5e-3
"""Assumed build tolerance of the mid-span pre-sag (± this), see the module docstring. [m]"""

MAX_CREW_TOLERANCE = 0.05
"""Largest crew tolerance accepted: ±50 mm (more is not a pre-sag tolerance). [m]"""


def check_uplift_limit(limit: float) -> float:
    """A steady-arm uplift limit, checked (one line with its value and range in mm). [m]

    Parameters
    ----------
    limit : float
        Largest allowed steady-arm uplift. [m]

    Raises
    ------
    ModelError
        Outside [1, 1000] mm (the range of the dynamic design's objective).
    """
    if not (math.isfinite(limit) and 1e-3 <= limit <= 1.0):
        raise ModelError(f"uplift_limit = {limit * 1e3:g} mm is outside the valid range [1, 1000] mm")
    return limit


def _check_rel(name: str, value: float) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and 0.0 <= value <= 0.005):
        shown = f"{value * 1e3:g} ‰" if isinstance(value, (int, float)) else repr(value)
        raise ModelError(f"{name} = {shown} is outside the model's valid range 0–5 ‰ (a pre-sag the models can "
                         "take); narrow the force band")
    return float(value)


def _check_interval(name: str, interval: tuple[float, float]) -> tuple[float, float]:
    low, high = (_check_rel(name, float(v)) for v in interval)
    if low > high:
        raise ModelError(f"{name} = [{low * 1e3:g}, {high * 1e3:g}] ‰ is not an interval (low > high)")
    return (low, high)


@dataclass(frozen=True, kw_only=True)
class DeltaERule:
    """The quasi-static Δe rule over the band: the mean of the layouts' S_rel range ends.

    Attributes
    ----------
    presag_rel : float
        The rule's S_rel (the paper's "mean value" of the ranges over the F_m band). [-]
    presag_rel_range : tuple of float
        The envelope of the layouts' S_rel ranges over the band. [-]
    static_uplift : float
        Largest static steady-arm uplift estimate F_m,max·e_support of the layouts (it does not
        depend on S). [m]
    support_elasticity : float
        The elasticity at a support behind it. [m/N]
    """

    presag_rel: float
    presag_rel_range: tuple[float, float]
    static_uplift: float
    support_elasticity: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "presag_rel", _check_rel("Δe rule presag_rel", self.presag_rel))
        object.__setattr__(self, "presag_rel_range", _check_interval("Δe rule range", self.presag_rel_range))


@dataclass(frozen=True, kw_only=True)
class QuasiStaticRobust:
    """The quasi-static robust design: the minimax parabola of the path waviness over the F_m band.

    Attributes
    ----------
    presag_rel : float
        Its S_rel. [-]
    tolerance : tuple of float
        The S_rel interval whose worst-case waviness stays within ``within`` of the optimum. [-]
    within : float
        Allowed loss of that interval. [-]
    """

    presag_rel: float
    tolerance: tuple[float, float]
    within: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "presag_rel", _check_rel("quasi-static robust presag_rel", self.presag_rel))
        object.__setattr__(self, "tolerance", _check_interval("quasi-static tolerance", self.tolerance))


@dataclass(frozen=True, kw_only=True)
class ValiditySweep:
    """A dynamic sweep over pre-sags × speeds × static forces: its validity limit and its uplift.

    Attributes
    ----------
    limit : SweepLimit
        What it reads about the validity limit.
    presag_rel : tuple of float
        The swept S_rel, increasing. [-]
    static_forces : tuple of float
        The swept static forces, increasing. [N]
    uplift : ndarray, shape (presag, static force)
        Largest steady-arm uplift over the swept speeds up to the band's top speed (NaN: no run). [m]
    note : str
        A caveat on reading it for this line (e.g. another contact wire), empty if none.
    """

    limit: SweepLimit
    presag_rel: tuple[float, ...]
    static_forces: tuple[float, ...]
    uplift: np.ndarray
    note: str = ""

    def __post_init__(self) -> None:
        uplift = np.asarray(self.uplift, dtype=float)
        if uplift.shape != (len(self.presag_rel), len(self.static_forces)):
            raise ModelError(f"validity sweep: uplift has shape {uplift.shape}, expected "
                             f"({len(self.presag_rel)}, {len(self.static_forces)})")
        if list(self.presag_rel) != sorted(self.presag_rel) or list(self.static_forces) != sorted(self.static_forces):
            raise ModelError("validity sweep: give the swept pre-sags and static forces in increasing order")
        object.__setattr__(self, "uplift", uplift)

    @property
    def has_uplift(self) -> bool:
        """Whether any run of the sweep finished (its uplift is known)."""
        return bool(np.isfinite(self.uplift).any())

    def uplift_at(self, presag_rel: float) -> float | None:
        """Largest swept uplift at a pre-sag: at the swept S, or the larger of the two swept S that bracket
        it (an uplift limit is checked on the safe side, not interpolated); None outside the swept range
        or without runs. [m]

        Parameters
        ----------
        presag_rel : float
            S_rel. [-]
        """
        return _bracketed(self.presag_rel, _nanmax(self.uplift, axis=1), presag_rel)

    def highest_static_force(self, uplift_limit: float) -> float | None:
        """The largest swept static force up to which (from the lowest) some swept S keeps the limit. [N]

        Parameters
        ----------
        uplift_limit : float
            The steady-arm uplift limit. [m]
        """
        if not self.has_uplift:
            return None
        up_to = np.fmax.accumulate(np.where(np.isfinite(self.uplift), self.uplift, -np.inf), axis=1)
        keeps = up_to.min(axis=0) <= uplift_limit
        return float(np.asarray(self.static_forces)[keeps].max()) if keeps.any() else None

    def some_presag_keeps_uplift(self, uplift_limit: float) -> bool | None:
        """Whether some swept S keeps the limit at every swept static force (None without runs).

        Parameters
        ----------
        uplift_limit : float
            The steady-arm uplift limit. [m]
        """
        if not self.has_uplift:
            return None
        return bool((_nanmax(self.uplift, axis=1) <= uplift_limit).any())


@dataclass(frozen=True, kw_only=True)
class DynamicUpliftCheck:
    """A line's worst section simulated at the band's worst points, at the pre-sags the decision may build.

    Attributes
    ----------
    simulated : tuple of (float, float)
        Every simulated pre-sag: (S_rel [-], largest steady-arm uplift of its runs [m]), increasing in S.
    where : str
        What was simulated (e.g. a line's worst section at the band's top speed).
    """

    simulated: tuple[tuple[float, float], ...]
    where: str

    def __post_init__(self) -> None:
        if not self.simulated:
            raise ModelError("dynamic check: give at least one simulated pre-sag")
        object.__setattr__(self, "simulated", tuple(sorted((float(s), float(u)) for s, u in self.simulated)))

    def uplift_at(self, presag_rel: float) -> float | None:
        """Simulated uplift at a pre-sag: at a simulated S, or the larger of the two that bracket it; None
        outside the simulated range. [m]

        Parameters
        ----------
        presag_rel : float
            S_rel. [-]
        """
        return _bracketed([s for s, _ in self.simulated], np.array([u for _, u in self.simulated]), presag_rel)


@dataclass(frozen=True, kw_only=True)
class DynamicRobust:
    """The dynamic robust design: S chosen by batched simulation over the band's static forces × speeds.

    Attributes
    ----------
    presag_rel : float
        Its S_rel. [-]
    tolerance : tuple of float
        The S_rel interval whose objective stays within ``within`` of the optimum, by simulation. [-]
    within : float
        Allowed loss of that interval. [-]
    uplift : float
        Its largest steady-arm uplift over the grid. [m]
    simulated : tuple of (float, float)
        Every simulated pre-sag: (S_rel [-], largest uplift over the grid [m]), increasing in S.
    where : str
        What was simulated, with the grid.
    """

    presag_rel: float
    tolerance: tuple[float, float]
    within: float
    uplift: float
    simulated: tuple[tuple[float, float], ...]
    where: str

    def __post_init__(self) -> None:
        object.__setattr__(self, "tolerance", _check_interval("dynamic tolerance", self.tolerance))
        object.__setattr__(self, "simulated", tuple(sorted((float(s), float(u)) for s, u in self.simulated)))

    def uplift_at(self, presag_rel: float) -> float | None:
        """Simulated uplift at a pre-sag: at a simulated S, or the larger of the two that bracket it; None
        outside the simulated range. [m]

        Parameters
        ----------
        presag_rel : float
            S_rel. [-]
        """
        return _bracketed([s for s, _ in self.simulated], np.array([u for _, u in self.simulated]), presag_rel)


INSTALLATION_KINDS = ("assumed", "setting", "monte-carlo")
"""Where a crew tolerance comes from: the toolkit's assumed default, a crew's own figure, or a Monte
Carlo of per-dropper errors."""


@dataclass(frozen=True, kw_only=True)
class InstallationTolerance:
    """How exactly a crew builds the mid-span pre-sag: ± ``half_width``.

    Attributes
    ----------
    half_width : float
        The build tolerance of the mid-span pre-sag. [m]
    kind : str
        One of :data:`INSTALLATION_KINDS`.
    source : str
        Where it comes from, in words (the assumption's reason, or the Monte Carlo's errors and level).
    """

    half_width: float
    kind: str
    source: str

    def __post_init__(self) -> None:
        w = self.half_width
        if not (isinstance(w, (int, float)) and math.isfinite(w) and 0.0 <= w <= MAX_CREW_TOLERANCE):
            raise ModelError(f"crew tolerance = {f'{w * 1e3:g}' if isinstance(w, (int, float)) else repr(w)} mm is outside "
                             f"the valid range [0, {MAX_CREW_TOLERANCE * 1e3:g}] mm")
        if self.kind not in INSTALLATION_KINDS:
            raise ModelError(f"installation tolerance kind {self.kind!r} is not one of {', '.join(INSTALLATION_KINDS)}")

    def describe(self) -> str:
        """± the tolerance in mm with its source."""
        return f"±{self.half_width * 1e3:.1f} mm ({self.source})"


def crew_tolerance(half_width: float | None = None) -> InstallationTolerance:
    """The crew's build tolerance as a setting: the assumed default, or a crew's own figure.

    Parameters
    ----------
    half_width : float, optional
        ± tolerance of the mid-span pre-sag (default :data:`CREW_TOLERANCE`, assumed). [m]
    """
    if half_width is None:
        return InstallationTolerance(half_width=CREW_TOLERANCE, kind="assumed",
                                     source="assumed: half of a 5 mm cutting step")
    return InstallationTolerance(half_width=half_width, kind="setting", source="the crew's figure as given")


RECORDS = {
    "delta_e": "the quasi-static Δe rule",
    "quasi_static_robust": "the quasi-static robust design and its tolerance",
    "validity_sweep": "a dynamic validity sweep (its validity limit and the dynamic steady-arm uplift by pre-sag)",
    "dynamic_check": "a dynamic check of the built pre-sag",
    "dynamic_robust": "the dynamic robust design and its dynamic tolerance",
    "installation_monte_carlo": "the installation tolerance from per-dropper errors by Monte Carlo",
}
"""What each kind of evidence is, by its name in :class:`Evidence` (the Monte Carlo is the
installation tolerance where it is not a setting)."""


@dataclass(frozen=True, kw_only=True)
class Evidence:
    """Everything known about one band's (or line's) pre-sag, and what every decision needs.

    Attributes
    ----------
    wave_speed : float
        Contact-wire wave speed c_CW of the system. [m/s]
    speed_high : float
        The band's top speed. [m/s]
    uplift_limit : float
        Largest allowed steady-arm uplift. [m]
    reference_span : float
        Span length on which pre-sags are quoted in mm and the crew's tolerance is compared (a
        line takes its shortest sized span: a crew's error in mm is the largest share of S there). [m]
    static_force_floor : float
        Lowest static force of the band (the decision's floor when no force keeps the uplift). [N]
    static_force_estimate : float or None
        Highest static force whose static uplift estimate keeps the limit at the top speed (None
        where not computed). [N]
    delta_e : DeltaERule or None
        The Δe rule (None where not computed).
    quasi_static_robust : QuasiStaticRobust or None
        The quasi-static robust design with its tolerance (None where not computed).
    validity_sweep : ValiditySweep or None
        A validity sweep (None where none was read or run).
    dynamic_check : DynamicUpliftCheck or None
        A line's dynamic check (None where not run).
    dynamic_robust : DynamicRobust or None
        The dynamic robust design (None where not run).
    installation : InstallationTolerance
        The crew's build tolerance (a setting, or the Monte Carlo's).
    scope : {"band", "line"}
        What is decided for: an operating band on system models, or a surveyed line (only a line's
        built pre-sag has a dynamic check of its own; a band's uplift comes from its other records).
    """

    wave_speed: float
    speed_high: float
    uplift_limit: float
    reference_span: float
    static_force_floor: float
    static_force_estimate: float | None = None
    delta_e: DeltaERule | None = None
    quasi_static_robust: QuasiStaticRobust | None = None
    validity_sweep: ValiditySweep | None = None
    dynamic_check: DynamicUpliftCheck | None = None
    dynamic_robust: DynamicRobust | None = None
    installation: InstallationTolerance = crew_tolerance()
    scope: str = "band"

    def __post_init__(self) -> None:
        if self.scope not in ("band", "line"):
            raise ModelError(f"evidence scope {self.scope!r} is not one of band, line")
        check_uplift_limit(self.uplift_limit)
        if not 5.0 <= self.reference_span <= 120.0:
            raise ModelError(f"reference_span = {self.reference_span:g} m is outside the valid range [5, 120] m")
        if self.delta_e is None and self.quasi_static_robust is None and self.dynamic_robust is None:
            raise ModelError("evidence: give at least one answer (the Δe rule, or a quasi-static or dynamic robust design)")

    def validity(self) -> ValidityStatement:
        """The validity statement of the band with the sweep, if any (:func:`validity_statement`)."""
        sweep = None if self.validity_sweep is None else self.validity_sweep.limit
        return validity_statement(self.wave_speed, self.speed_high, sweep)

    def missing(self) -> tuple[str, ...]:
        """Names of the kinds of evidence not present (keys of :data:`RECORDS`)."""
        out = [f.name for f in fields(self) if f.name in RECORDS and getattr(self, f.name) is None
               and (f.name != "dynamic_check" or self.scope == "line")]
        if self.installation.kind != "monte-carlo":
            out.append("installation_monte_carlo")
        return tuple(out)

    def uplift_at(self, presag_rel: float) -> tuple[float | None, str]:
        """The best-known steady-arm uplift at a pre-sag and its kind: simulated by the dynamic robust
        design, by the dynamic check (at its S), by the validity sweep, else the static estimate.

        Parameters
        ----------
        presag_rel : float
            S_rel. [-]

        Returns
        -------
        (float or None, str)
            Uplift [m] (None if unknown) and ``"dynamic"`` or ``"static estimate"``.
        """
        for value in (None if self.dynamic_robust is None else self.dynamic_robust.uplift_at(presag_rel),
                      None if self.dynamic_check is None else self.dynamic_check.uplift_at(presag_rel),
                      None if self.validity_sweep is None else self.validity_sweep.uplift_at(presag_rel)):
            if value is not None and math.isfinite(value):
                return value, "dynamic"
        if self.delta_e is not None:
            return self.delta_e.static_uplift, "static estimate"
        return None, ""


def _nanmax(values: np.ndarray, axis: int) -> np.ndarray:
    """Largest finite value along an axis (NaN where there is none), without NumPy's all-NaN warning."""
    finite = np.where(np.isfinite(values), values, -np.inf)
    out = finite.max(axis=axis)
    return np.where(np.isneginf(out), np.nan, out)


def _bracketed(points, values: np.ndarray, at: float) -> float | None:
    """``values`` at ``at`` on the increasing ``points`` (finite values only): the value at a point there,
    else the larger of the nearest points on either side; None outside the points' range or where no
    point near it has a value."""
    points = np.asarray(points, dtype=float)
    values = np.asarray(values, dtype=float)
    known = np.isfinite(values)
    if points.size == 0 or at < points[0] * (1 - 1e-9) - 1e-12 or at > points[-1] * (1 + 1e-9) + 1e-12:
        return None
    same = np.isclose(points, at, rtol=1e-6, atol=0.0) & known
    if same.any():
        return float(values[same].max())
    below = np.flatnonzero(known & (points < at))
    above = np.flatnonzero(known & (points > at))
    near = values[[*below[-1:], *above[:1]]]
    return float(near.max()) if near.size else None
