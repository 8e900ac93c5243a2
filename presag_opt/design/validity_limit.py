"""The one statement of where the quasi-static pre-sag rule holds: the limit in force, its source, and
the speed it means on a contact wire.

Every command that answers "which pre-sag?" states validity with :func:`validity_statement`, so the
same band gets the same sentence everywhere.

**The limit in force** is an interval of the speed ratio β = v/c_CW, [low, high]:

- *The paper's* (the default): the σ/F_m benefit of pre-sag becomes less distinct towards β = 0.35
  and is gone at 0.41, and the Δe rule lies in the dynamically optimal range of S for β < 0.4
  (Schick, Liu & Stichel 2025, section 5.2 and conclusions). Its interval is [0.35, 0.40].
- *A validity study's* β* ± u (u, half the β step of its grid: the sweep's resolution), read by
  :func:`presag_opt.studies.validity_analysis.validity_analysis`. Its interval is [β* − u, β* + u].
  A stored study (``presag sweep``) of this contact wire is in force as it reads. A *reduced* sweep
  (run for a report, with coarse numerics) is in force only where it is stricter than the paper: it
  may lower the limit, not raise it. A sweep with no speed below the band's top speed (within
  :data:`SAME_SPEED`) is *indicative*: it cannot place the limit below the band, so it never
  replaces the paper's.

**The verdict** compares the band's largest β with the interval: *holds* at or below its low end,
*beyond* above its high end, and *at the limit* between them ("within the sweep's resolution" for a
study; "where the paper's σ/F_m minimum already weakens" for the paper). A comparison never turns on
round-off: a value within the interval is "at the limit", whichever side of β* it lies.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: section 5.2 (Fig. 6:
the σ/F_m minimum less distinct towards β = 0.35, gone at 0.41; Fig. 7: Δe rule inside the optimal
range for β < 0.4) and the conclusions (applicable up to 40 % of c_CW).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from presag_opt.errors import ModelError
from presag_opt.units import KMH

PAPER_ONSET = 0.35
"""β from which the paper's σ/F_m minimum becomes less distinct: the low end of its limit. [-]"""

PAPER_LIMIT = 0.40
"""β up to which the paper finds the Δe rule inside the dynamically optimal range: the high end. [-]"""

VERDICTS = ("holds", "at the limit", "beyond")
"""The band's largest β at or below the limit's low end; inside the limit's interval; above it."""

SAME_SPEED = 0.01
"""Relative difference of speed ratio within which a sweep's speed counts as the band's top speed (a
sweep rounds its speeds to km/h, and its section's wave speed may differ from the line's in the last
digits). [-]"""

SWEEP_KINDS = ("study", "reduced")
"""A stored validity study, or a reduced sweep run for a report."""


@dataclass(frozen=True, kw_only=True)
class ValidityLimit:
    """The validity limit of the quasi-static rule as an interval of β, and where it comes from.

    Attributes
    ----------
    low, high : float
        The interval's ends: the rule is trusted at or below ``low``, not above ``high``. [-]
    source : str
        Where it comes from, in words (the paper, or a study with its β* and resolution).
    from_sweep : bool
        Whether a sweep of this model set it (else the paper's).
    """

    low: float
    high: float
    source: str
    from_sweep: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.low) and math.isfinite(self.high) and 0.0 <= self.low <= self.high):
            raise ModelError(f"validity limit: β interval [{self.low:g}, {self.high:g}] is not 0 ≤ low ≤ high")


PAPER = ValidityLimit(
    low=PAPER_ONSET, high=PAPER_LIMIT,
    source=f"the paper's limit (σ/F_m benefit weakening from β = {PAPER_ONSET:g}, Δe rule in the optimal range "
           f"below β = {PAPER_LIMIT:g})",
)
"""The paper's limit, in force unless a validity study sets another."""


@dataclass(frozen=True, kw_only=True)
class SweepLimit:
    """What a validity sweep says about the limit (filled from a study's analysis).

    Attributes
    ----------
    kind : {"study", "reduced"}
        A stored study, or a reduced sweep run for a report.
    name : str
        The sweep, as the output names it (a file, or "the report's reduced sweep").
    beta_star : float or None
        β* where the rule stops holding, None where the sweep places none. [-]
    resolution : float
        Half the β step around β* (0 without β*). [-]
    grid_betas : tuple of float
        The sweep's speed ratios, increasing. [-]
    holds_at : tuple of bool
        Whether the Δe rule holds at each of ``grid_betas``.
    """

    kind: str
    name: str
    beta_star: float | None
    resolution: float
    grid_betas: tuple[float, ...]
    holds_at: tuple[bool, ...]

    def __post_init__(self) -> None:
        if self.kind not in SWEEP_KINDS:
            raise ModelError(f"sweep kind {self.kind!r} is not one of {', '.join(SWEEP_KINDS)}")
        if len(self.grid_betas) != len(self.holds_at) or not self.grid_betas:
            raise ModelError("sweep limit: give one verdict per grid β, and at least one β")

    def reading(self) -> str:
        """What the sweep reads, in words (β* ± resolution, or where the rule held on its grid)."""
        if self.beta_star is not None:
            return f"β* = {self.beta_star:.2f} ± {self.resolution:.2f}"
        if not any(self.holds_at):
            return f"the Δe rule holds at none of its speeds (β {self.grid_betas[0]:.2f}–{self.grid_betas[-1]:.2f})"
        top = max(b for b, h in zip(self.grid_betas, self.holds_at) if h)
        return f"the Δe rule holds up to its highest β that holds, {top:.2f}; no limit below it"

    def interval(self) -> tuple[float, float] | None:
        """The β interval the sweep places the limit in, or None where its grid places none below its top.

        With β*: [β* − u, β* + u]. Where the rule holds at none of the grid's speeds: [0, lowest β]
        (the limit lies somewhere below the grid). Where it holds up to the top of the grid: None (a
        stored study then trusts the rule up to its top β, and between it and the paper's limit the
        band is "at the limit").
        """
        if self.beta_star is not None:
            return (max(0.0, self.beta_star - self.resolution), self.beta_star + self.resolution)
        if not any(self.holds_at):
            return (0.0, self.grid_betas[0])
        return None


def limit_in_force(sweep: SweepLimit | None, beta_max: float) -> tuple[ValidityLimit, str]:
    """The limit in force for a band, and a note on a sweep that was read but is not in force.

    Parameters
    ----------
    sweep : SweepLimit or None
        A validity sweep of this model, if one was read.
    beta_max : float
        The band's largest speed ratio (a sweep with no grid β below it is indicative). [-]

    Returns
    -------
    (ValidityLimit, str)
        The limit, and an empty note or one sentence on why the sweep's reading is not in force.
    """
    if sweep is None:
        return PAPER, ""
    reading = f"{sweep.name} reads {sweep.reading()}"
    if sweep.grid_betas[0] >= beta_max * (1.0 - SAME_SPEED):
        return PAPER, f"{reading}; it has no speed below the band's top speed, so it is indicative only"
    interval = sweep.interval()
    if interval is None:
        if sweep.kind == "reduced":
            return PAPER, f"{reading}; a reduced sweep does not raise the paper's limit"
        top = max(b for b, h in zip(sweep.grid_betas, sweep.holds_at) if h)
        return ValidityLimit(low=top, high=max(top, PAPER_LIMIT), from_sweep=True,
                             source=f"{reading}; above it, up to the paper's β = {PAPER_LIMIT:g}"), ""
    low, high = interval
    if sweep.kind == "reduced" and 0.5 * (low + high) >= PAPER_LIMIT:
        return PAPER, f"{reading}; a reduced sweep does not raise the paper's limit"
    what = "within the sweep's resolution" if sweep.beta_star is not None else "below its lowest speed"
    return ValidityLimit(low=low, high=high, source=f"{reading} ({what})", from_sweep=True), ""


@dataclass(frozen=True, kw_only=True)
class ValidityStatement:
    """Where a band lies against the limit in force, and the sentence every command prints.

    Attributes
    ----------
    limit : ValidityLimit
        The limit in force.
    wave_speed : float
        Contact-wire wave speed c_CW. [m/s]
    speed_high : float
        The band's top speed. [m/s]
    beta_max : float
        The band's largest speed ratio v/c_CW. [-]
    verdict : str
        One of :data:`VERDICTS`.
    note : str
        On a sweep read but not in force (empty otherwise).
    """

    limit: ValidityLimit
    wave_speed: float
    speed_high: float
    beta_max: float
    verdict: str
    note: str = ""

    @property
    def trusted(self) -> bool:
        """Whether the quasi-static answers hold over the whole band."""
        return self.verdict == "holds"

    @property
    def limit_speeds(self) -> tuple[float, float]:
        """The limit's ends as speeds on this contact wire. [m/s]"""
        return (self.limit.low * self.wave_speed, self.limit.high * self.wave_speed)

    def sentence(self) -> str:
        """The validity statement in one sentence (speeds in km/h); the same for the same band and limit,
        whatever else a command computed (a sweep read but not in force is :attr:`note`)."""
        lo, hi = (v / KMH for v in self.limit_speeds)
        where = (f"β = {self.limit.low:.2f}–{self.limit.high:.2f}, {lo:.0f}–{hi:.0f} km/h"
                 if self.limit.high > self.limit.low else f"β = {self.limit.low:.2f}, {lo:.0f} km/h")
        band = f"the band's top speed {self.speed_high / KMH:.0f} km/h is β = {self.beta_max:.2f}"
        verdict = {
            "holds": "the quasi-static rule holds over the band",
            "at the limit": ("at the limit, within the sweep's resolution" if self.limit.from_sweep
                             else "at the limit, where the paper's σ/F_m minimum already weakens"),
            "beyond": "beyond the limit: the quasi-static rule does not hold there",
        }[self.verdict]
        return (f"Validity: limit {where} on this contact wire (c_CW = {self.wave_speed / KMH:.0f} km/h; "
                f"{self.limit.source}); {band}: {verdict}")

    def to_dict(self) -> dict:
        """JSON-ready content (β, km/h)."""
        lo, hi = (v / KMH for v in self.limit_speeds)
        return {"beta_limit": [self.limit.low, self.limit.high], "limit_speed_kmh": [lo, hi],
                "source": self.limit.source, "from_sweep": self.limit.from_sweep,
                "wave_speed_kmh": self.wave_speed / KMH, "speed_high_kmh": self.speed_high / KMH,
                "beta_max": self.beta_max, "verdict": self.verdict, "note": self.note, "sentence": self.sentence()}


def validity_statement(wave_speed: float, speed_high: float, sweep: SweepLimit | None = None) -> ValidityStatement:
    """The validity statement of a band on a contact wire (see the module docstring).

    Parameters
    ----------
    wave_speed : float
        Contact-wire wave speed c_CW = sqrt(T_CW/ρ_CW). [m/s]
    speed_high : float
        The band's top speed. [m/s]
    sweep : SweepLimit, optional
        A validity sweep of this model (default: the paper's limit alone).

    Raises
    ------
    ModelError
        A wave speed that is not positive, or a speed that is negative or not below it.
    """
    if not (math.isfinite(wave_speed) and wave_speed > 0.0):
        raise ModelError(f"wave_speed = {wave_speed:g} m/s is outside the valid range (0, ∞) m/s")
    if not (math.isfinite(speed_high) and 0.0 <= speed_high < wave_speed):
        raise ModelError(f"speed_high = {speed_high / KMH:g} km/h is outside the valid range "
                         f"[0, {wave_speed / KMH:.0f}) km/h (below the contact-wire wave speed)")
    beta_max = speed_high / wave_speed
    limit, note = limit_in_force(sweep, beta_max)
    close = 1e-9  # the interval's ends as written (0.49 − 0.03 is 0.45999… in binary)
    verdict = ("holds" if beta_max <= limit.low + close else "beyond" if beta_max > limit.high + close
               else "at the limit")
    return ValidityStatement(limit=limit, wave_speed=wave_speed, speed_high=speed_high, beta_max=beta_max,
                             verdict=verdict, note=note)
