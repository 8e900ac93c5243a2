"""Design rules checked on a surveyed, designed section.

Public examples from Bane NOR's technical regulations for contact line systems (limits as stated
there; each applies in the speed range given, and is reported as a guide outside it):

- stagger at most 400 mm for design speeds up to 200 km/h;
- the shortest dropper, terminals included, at least 500 mm at 160–200 km/h;
- dropper spacing at most 11 m;
- system-height change between neighbouring masts at most 0.15 m above 200 km/h;
- the contact-wire gradient and its change between consecutive spans within the limits of EN 50119's
  table by line speed (:data:`GRADIENT_LIMITS`).

And one of the model's own: the contact wire stays within the pantograph's working width along
every span (on a curve the chord between two registrations cuts inside the arc by l²/(8R) at
mid-span).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.system.catenary import Catenary
from presag_opt.system.survey import SurveyMast, SurveySection

MAX_STAGGER = 0.400
"""Largest stagger up to 200 km/h (Bane NOR example). [m]"""

MIN_DROPPER_LENGTH = 0.500
"""Shortest dropper, terminals included, at 160–200 km/h (Bane NOR example). [m]"""

MAX_DROPPER_SPACING = 11.0
"""Largest dropper spacing (Bane NOR example). [m]"""

MAX_SYSTEM_HEIGHT_CHANGE = 0.15
"""Largest system-height change between neighbouring masts above 200 km/h (Bane NOR example). [m]"""


GRADIENT_LIMITS = (
    (50.0, 1 / 40, 1 / 80),
    (60.0, 1 / 50, 1 / 100),
    (100.0, 1 / 167, 1 / 333),
    (120.0, 1 / 250, 1 / 500),
    (160.0, 1 / 300, 1 / 600),
    (200.0, 1 / 500, 1 / 1000),
    (250.0, 1 / 1000, 1 / 2000),
    (math.inf, 0.0, 0.0),
)
"""Largest contact-wire gradient relative to the track and largest change of gradient between consecutive
spans, by line speed: (up to speed [km/h], gradient [-], change [-]). EN 50119's table of contact-wire
gradients as railway technical regulations quote it (the change half the gradient; no gradient above
250 km/h); provenance: standard, as recalled by this project — not checked against the standard's text
here, so the limits are reported as a guide beside the speed they hold at."""


def gradient_limits(speed: float) -> tuple[float, float, float]:
    """The gradient limits at a line speed: (gradient, change, the table's speed it holds up to).

    Parameters
    ----------
    speed : float
        Line speed (the band's top speed). [km/h]
    """
    for up_to, gradient, change in GRADIENT_LIMITS:
        if speed <= up_to + 1e-9:
            return gradient, change, up_to
    raise AssertionError("GRADIENT_LIMITS ends at infinity")


def span_gradients(section: SurveySection) -> tuple[np.ndarray, np.ndarray]:
    """Contact-wire gradient of every span, (h_b − h_a)/l, and its change between consecutive spans. [-]

    Parameters
    ----------
    section : SurveySection
        The surveyed masts (heights of the contact wire above the rail at each).
    """
    heights = np.array([m.contact_wire_height for m in section.masts])
    gradients = np.diff(heights) / np.asarray(section.span_lengths)
    return gradients, np.abs(np.diff(gradients))


def gradient_status(value: float | None, limit: float) -> str:
    """``""`` within the limit (or no value), else ``over 1/N`` in words. [-]

    Parameters
    ----------
    value : float or None
        A gradient or change of gradient (its size counts). [-]
    limit : float
        The largest allowed. [-]
    """
    if value is None or abs(value) <= limit + 1e-12:
        return ""
    return f"over {_ratio(limit)}"


@dataclass(frozen=True, kw_only=True)
class RuleCheck:
    """One design rule on one section.

    Attributes
    ----------
    section : str
        Section id.
    rule : str
        The rule in words, with its limit.
    applies : bool
        Whether the band's top speed lies in the speed range the rule is stated for.
    passed : bool
        Whether the section meets it.
    worst : str
        The worst value found and where.
    """

    section: str
    rule: str
    applies: bool
    passed: bool
    worst: str

    @property
    def status(self) -> str:
        """``ok``, ``FAILS`` (applies and not met) or ``below guide`` (not met where it does not apply)."""
        if self.passed:
            return "ok"
        return "FAILS" if self.applies else "not met (guide only at this speed)"


def check_rules(section: SurveySection, catenary: Catenary, droppers: Sequence, band: OperatingBand,
                working_width: float) -> tuple[RuleCheck, ...]:
    """Check the design rules of the module docstring on one built section.

    Parameters
    ----------
    section : SurveySection
        The surveyed masts.
    catenary : Catenary
        The section's model (dropper rule, spans, radii).
    droppers : sequence of DropperDesign
        The built droppers (their cut lengths).
    band : OperatingBand
        The band (its top speed decides which rules apply).
    working_width : float
        Half working width of the pantograph. [m]
    """
    v = band.speed_high / KMH
    masts = section.masts
    sid = section.section
    out = []

    stagger = np.array([abs(m.stagger) for m in masts])
    i = int(np.argmax(stagger))
    out.append(RuleCheck(section=sid, rule=f"stagger ≤ {MAX_STAGGER * 1e3:.0f} mm (up to 200 km/h)", applies=v <= 200.0,
                         passed=bool(stagger[i] <= MAX_STAGGER + 1e-9),
                         worst=f"{stagger[i] * 1e3:.0f} mm at mast {masts[i].mast}"))

    lengths = np.array([d.length for d in droppers])
    j = int(np.argmin(lengths))
    d = droppers[j]
    out.append(RuleCheck(section=sid, rule=f"shortest dropper ≥ {MIN_DROPPER_LENGTH * 1e3:.0f} mm (160–200 km/h)",
                         applies=160.0 <= v <= 200.0, passed=bool(lengths[j] >= MIN_DROPPER_LENGTH),
                         worst=f"{lengths[j] * 1e3:.0f} mm, span {d.span} ({d.from_mast}–{d.to_mast}) dropper {d.dropper}"))

    spacing, where = 0.0, ""
    for s, length in enumerate(catenary.layout.span_lengths):
        gaps = np.diff(catenary.droppers.positions_in_span(length))
        if len(gaps) and gaps.max() > spacing:
            spacing, where = float(gaps.max()), f"span {s + 1} ({masts[s].mast}–{masts[s + 1].mast})"
    out.append(RuleCheck(section=sid, rule=f"dropper spacing ≤ {MAX_DROPPER_SPACING:g} m", applies=True,
                         passed=spacing <= MAX_DROPPER_SPACING + 1e-9, worst=f"{spacing:.2f} m in {where}"))

    change = np.abs(np.diff([m.system_height for m in masts]))
    k = int(np.argmax(change))
    out.append(RuleCheck(section=sid, rule=f"system-height change ≤ {MAX_SYSTEM_HEIGHT_CHANGE:g} m between masts "
                         "(above 200 km/h)", applies=v > 200.0, passed=bool(change[k] <= MAX_SYSTEM_HEIGHT_CHANGE + 1e-9),
                         worst=f"{change[k]:.2f} m between {masts[k].mast} and {masts[k + 1].mast}"))

    gradient_limit, change_limit, up_to = gradient_limits(v)
    held = f"up to {up_to:g} km/h" if math.isfinite(up_to) else "above 250 km/h"
    gradients, changes = span_gradients(section)
    i = int(np.argmax(np.abs(gradients)))
    out.append(RuleCheck(section=sid, rule=f"contact-wire gradient ≤ {_ratio(gradient_limit)} ({held}, EN 50119 "
                         "table as recalled)", applies=True, passed=not gradient_status(gradients[i], gradient_limit),
                         worst=f"{gradients[i] * 1e3:+.2f} ‰ in span {masts[i].mast}–{masts[i + 1].mast}"))
    if len(changes):
        k = int(np.argmax(changes))
        out.append(RuleCheck(section=sid, rule=f"change of contact-wire gradient ≤ {_ratio(change_limit)} ({held})",
                             applies=True, passed=not gradient_status(changes[k], change_limit),
                             worst=f"{changes[k] * 1e3:.2f} ‰ at mast {masts[k + 1].mast}"))

    offset, where = lateral_excursion(section)
    out.append(RuleCheck(section=sid, rule=f"contact wire within the working width ±{working_width * 1e3:.0f} mm "
                         "along every span", applies=True, passed=offset <= working_width + 1e-9,
                         worst=f"{offset * 1e3:.0f} mm {where}"))
    return tuple(out)


def _ratio(limit: float) -> str:
    return "0" if limit == 0 else f"1/{1 / limit:.0f}"


def lateral_excursion(section: SurveySection) -> tuple[float, str]:
    """Largest lateral offset of the contact wire from the track centre line between masts, and where.

    In a span of length l and radius R the wire runs on the chord between the registrations
    (staggers s_a, s_b, + to the left); a chord lies inside its arc, so the wire departs from the
    track centre line by x(l − x)/(2R) towards the curve's centre (+ to the left for R > 0): the
    offset is s_a + (s_b − s_a)·x/l + x(l − x)/(2R) (small-angle), largest in size at a mast or at
    its stationary point.

    Returns
    -------
    offset : float
        Largest |offset|. [m]
    where : str
        Span and position.
    """
    best, where = 0.0, ""
    for a, b in zip(section.masts[:-1], section.masts[1:]):
        x = np.linspace(0.0, b.chainage - a.chainage, 201)
        y = np.abs(lateral_offset(a, b, x))
        k = int(np.argmax(y))
        if y[k] > best:
            best, where = float(y[k]), f"at {x[k]:.1f} m from mast {a.mast}"
    return best, where


def lateral_offset(a: SurveyMast, b: SurveyMast, x: np.ndarray) -> np.ndarray:
    """Lateral offset of the contact wire from the track centre line in the span from mast ``a`` to ``b``,
    + to the left: s_a + (s_b − s_a)·x/l + x(l − x)/(2R) (small-angle; :func:`lateral_excursion`). [m]

    Parameters
    ----------
    a, b : SurveyMast
        The span's masts (``a`` carries its curve radius).
    x : ndarray
        Distances from ``a``. [m]
    """
    length = b.chainage - a.chainage
    x = np.asarray(x, dtype=float)
    curve = 0.0 if a.curve_radius == 0.0 else x * (length - x) / (2.0 * a.curve_radius)
    return a.stagger + (b.stagger - a.stagger) * x / length + curve
