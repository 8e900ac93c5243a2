"""One decision: which pre-sag to build, from the evidence the toolkit has, with its margins and reason.

The answers to "which S?" are the quasi-static Δe rule, the quasi-static robust design (with its
tolerance interval) and the dynamic robust design (with its dynamic tolerance interval); the
evidence (:mod:`presag_opt.design.evidence`) also holds a validity sweep, a dynamic check and the
crew's build tolerance. :func:`decide` runs once per command, in this order:

1. **Validity.** The one statement of :mod:`presag_opt.design.validity_limit`: the quasi-static
   answers are trusted where the band's largest β is at or below the low end of the limit in force.
2. **Uplift compatibility.** Where no pre-sag keeps the steady-arm uplift within its limit over the
   band (read from the validity sweep, the dynamic robust design, or the answers' uplifts), the
   status is ``uplift-bound`` and the decision gives the highest static force at which one does (the
   static force is then set by uplift compatibility, not by contact dynamics).
3. **The answer to build from.** A trusted quasi-static answer (the robust design before the Δe
   rule: it carries a tolerance of its own); where the quasi-static answers are not trusted, the
   dynamic robust design; without it the decision is ``provisional`` and shows the quasi-static one.
4. **Margin.** The tolerance intervals in force are the dynamic one and, where the quasi-static
   answers are trusted and it overlaps the dynamic one, the quasi-static one. The answer is built
   where its margin to every end of their intersection is at least the crew's build tolerance;
   otherwise the pre-sag with the largest margin inside the intersection (and the uplift within its
   limit) is built instead, and the reason says so. Where the intersection is narrower than twice the
   crew tolerance the status is ``tolerance-bound``: the band cannot be met with that crew, and the
   pre-sag with the largest margin is still named.
5. **Status.** ``decided`` where the dynamic tolerance is known; ``provisional`` where it was not
   computed (the quasi-static interval alone is not a dynamic check).

Every answer is shown beside the choice, with its margins.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: sections 5–6
(validity up to about 40 % of the wave speed, uplift limit 83.5 mm, static force set by uplift).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.design.evidence import RECORDS, Evidence
from presag_opt.design.validity_limit import ValidityStatement
from presag_opt.display import data_frame, html_summary

DELTA_E_RULE = "quasi-static Δe rule"
QUASI_STATIC_ROBUST = "quasi-static robust design"
DYNAMIC_ROBUST = "dynamic robust design"
METHOD_ORDER = (QUASI_STATIC_ROBUST, DELTA_E_RULE, DYNAMIC_ROBUST)
"""Answers in order of preference among those that qualify."""

LARGEST_MARGIN = "the largest margin inside the tolerance intervals"
"""The basis of a pre-sag built at the largest margin rather than at one method's answer."""

STATUSES = ("decided", "provisional", "tolerance-bound", "uplift-bound")
"""What a decision can be: final; waiting for the dynamic tolerance; not buildable within the crew's
tolerance; not buildable within the uplift limit."""

QUASI_STATIC_TOLERANCE = "quasi-static tolerance"
DYNAMIC_TOLERANCE = "dynamic tolerance"

_GRID = 801
"""Points across the intersection searched for the largest margin (a 7 mm interval at < 0.01 mm). [-]"""


@dataclass(frozen=True, kw_only=True)
class Answer:
    """One method's answer to "which S?".

    Attributes
    ----------
    method : str
        One of :data:`METHOD_ORDER`.
    presag_rel : float
        Its S_rel. [-]
    uplift : float or None
        Best-known largest steady-arm uplift over the band at this S. [m]
    uplift_kind : str
        ``"dynamic"`` or ``"static estimate"`` (empty if unknown).
    """

    method: str
    presag_rel: float
    uplift: float | None
    uplift_kind: str


@dataclass(frozen=True, kw_only=True)
class Interval:
    """A tolerance interval of S_rel the decision knows.

    Attributes
    ----------
    name : str
        :data:`QUASI_STATIC_TOLERANCE` or :data:`DYNAMIC_TOLERANCE`.
    low, high : float
        Its ends. [-]
    in_force : bool
        Whether the built pre-sag must keep a margin to it.
    why_not : str
        Why it is not in force (empty where it is).
    """

    name: str
    low: float
    high: float
    in_force: bool
    why_not: str = ""

    def margins(self, presag_rel: float) -> tuple[float, float]:
        """Distance of a pre-sag above the low end and below the high end (negative: outside). [-]

        Parameters
        ----------
        presag_rel : float
            S_rel. [-]
        """
        return (presag_rel - self.low, self.high - presag_rel)


@dataclass(frozen=True, kw_only=True)
class Decision:
    """The pre-sag to build and why.

    Attributes
    ----------
    presag_rel : float
        S_rel to build (or, for ``uplift-bound``, the answer shown). [-]
    basis : str
        The method whose answer is built, or :data:`LARGEST_MARGIN`.
    status : str
        One of :data:`STATUSES`.
    reason : str
        Why, in one or two sentences.
    answers : tuple of Answer
        Every method's answer, in :data:`METHOD_ORDER`.
    intervals : tuple of Interval
        Every tolerance interval known.
    uplift : float or None
        Best-known steady-arm uplift at the built pre-sag. [m]
    uplift_kind : str
        ``"dynamic"`` or ``"static estimate"``.
    highest_static_force : float or None
        For ``uplift-bound``: the highest static force at which some pre-sag keeps the limit, if known. [N]
    validity : ValidityStatement
        The validity statement of the band.
    evidence : Evidence
        What the decision was made from.
    """

    presag_rel: float
    basis: str
    status: str
    reason: str
    answers: tuple[Answer, ...]
    intervals: tuple[Interval, ...]
    uplift: float | None
    uplift_kind: str
    highest_static_force: float | None
    validity: ValidityStatement
    evidence: Evidence

    @property
    def reference_span(self) -> float:
        """Span length on which pre-sags are quoted in mm. [m]"""
        return self.evidence.reference_span

    @property
    def missing(self) -> tuple[str, ...]:
        """The kinds of evidence not computed (:meth:`Evidence.missing`)."""
        return self.evidence.missing()

    def answer(self, method: str) -> Answer | None:
        """One method's answer, or None if it was not computed."""
        return next((a for a in self.answers if a.method == method), None)

    def margin(self) -> float | None:
        """Smallest margin of the built pre-sag to an interval in force (None without one). [-]"""
        values = [m for i in self.intervals if i.in_force for m in i.margins(self.presag_rel)]
        return min(values) if values else None

    def mm(self, presag_rel: float) -> float:
        """A relative pre-sag in mm on the reference span. [mm]

        Parameters
        ----------
        presag_rel : float
            S_rel. [-]
        """
        return presag_rel * self.reference_span * 1e3

    def headline(self, span_lengths: Sequence[float] | None = None, built: str | None = None) -> str:
        """One line: what to build, by which basis, and the status.

        Parameters
        ----------
        span_lengths : sequence of float, optional
            A line's span lengths: the pre-sag is then S_rel × span length, with its range in mm. [m]
        built : str, optional
            What is built, said by the caller instead (a line built span by span by its own rule).
        """
        if built is not None:
            size = built
        elif span_lengths:
            lo, hi = min(span_lengths), max(span_lengths)
            size = (f"{self.presag_rel * 1e3:.2f} ‰ × span length ({self.presag_rel * lo * 1e3:.0f}–"
                    f"{self.presag_rel * hi * 1e3:.0f} mm on {lo:g}–{hi:g} m spans)" if hi > lo else
                    f"{self.presag_rel * 1e3:.2f} ‰ × span length ({self.presag_rel * lo * 1e3:.0f} mm on {lo:g} m "
                    "spans)")
        else:
            size = f"{self.presag_rel * 1e3:.2f} ‰ = {self.mm(self.presag_rel):.0f} mm on {self.reference_span:g} m"
        text = f"{size} ({self.basis})"
        return {
            "decided": f"Pre-sag to build: {text}",
            "provisional": f"Pre-sag to build (provisional): {text}",
            "tolerance-bound": (f"The band cannot be met with a crew tolerance of "
                                f"±{self.evidence.installation.half_width * 1e3:.1f} mm; largest margin at {text}"),
            "uplift-bound": f"No pre-sag keeps the steady-arm uplift limit over this band (best answer shown: {text})",
        }[self.status]

    def not_checked(self, options: Mapping[str, str]) -> list[str]:
        """What was not checked, each with the option of the running command that would supply it.

        Parameters
        ----------
        options : mapping of str to str
            Evidence name (a key of :data:`~presag_opt.design.evidence.RECORDS`) to the option or
            command that supplies it; a missing name is shown as not offered by this command.
        """
        return [f"{RECORDS[key]} ({options.get(key, 'not offered by this command')})" for key in self.missing]

    def lines(self, options: Mapping[str, str] | None = None, span_lengths: Sequence[float] | None = None) -> list[str]:
        """The decision as printed: headline, reason, margins, validity, uplift, what was not checked,
        the alternatives.

        Parameters
        ----------
        options : mapping of str to str, optional
            See :meth:`not_checked`.
        span_lengths : sequence of float, optional
            See :meth:`headline`. [m]
        """
        out = [self.headline(span_lengths), f"  why: {self.reason}"]
        crew = self.evidence.installation
        margins = [self._margin_text(i, self.presag_rel) for i in self.intervals]
        out.append("  margins: " + ("; ".join(margins) if margins else "no tolerance interval known")
                   + f"; crew tolerance {crew.describe()}")
        out.append(f"  {self.validity.sentence()}")
        if self.validity.note:
            out.append(f"  validity sweep not in force: {self.validity.note}")
        limit = self.evidence.uplift_limit * 1e3
        if self.uplift is not None:
            out.append(f"  steady-arm uplift: {self.uplift * 1e3:.1f} mm ({self.uplift_kind}; limit {limit:g} mm)")
        if self.highest_static_force is not None:
            out.append(f"  highest static force keeping the uplift limit: {self.highest_static_force:.0f} N")
        missing = self.not_checked(options or {})
        if missing:
            out.append("  not checked: " + "; ".join(missing))
        for a in self.answers:
            chosen = abs(a.presag_rel - self.presag_rel) <= 1e-12 and a.method == self.basis
            if chosen:
                continue
            where = "; ".join(self._margin_text(i, a.presag_rel) for i in self.intervals)
            uplift = "" if a.uplift is None else f", uplift {a.uplift * 1e3:.1f} mm ({a.uplift_kind})"
            out.append(f"  alternative: {a.method} {a.presag_rel * 1e3:.2f} ‰ = {self.mm(a.presag_rel):.1f} mm"
                       + uplift + (f"; {where}" if where else ""))
        return out

    def table(self) -> list[dict]:
        """Every method's answer as rows (S in ‰ and mm, uplift in mm, the smallest margin to an interval
        in force in mm; ``built`` marks the decision's basis)."""
        in_force = [i for i in self.intervals if i.in_force]
        return [{"method": a.method, "S_rel [‰]": a.presag_rel * 1e3, "S [mm]": self.mm(a.presag_rel),
                 "uplift [mm]": None if a.uplift is None else a.uplift * 1e3, "uplift kind": a.uplift_kind,
                 "margin [mm]": (min(self.mm(m) for i in in_force for m in i.margins(a.presag_rel))
                                 if in_force else None),
                 "built": a.method == self.basis} for a in self.answers]

    def _repr_html_(self) -> str:
        return html_summary(self.headline(), self.lines()[1:], self.table())

    def to_frame(self):
        """:meth:`table` as a pandas DataFrame."""
        return data_frame(self.table())

    def _margin_text(self, interval: Interval, presag_rel: float) -> str:
        below, above = (self.mm(m) for m in interval.margins(presag_rel))
        status = "" if interval.in_force else f", not in force: {interval.why_not}"
        inside = "inside" if min(below, above) >= 0 else "OUTSIDE"
        return (f"{interval.name} {self.mm(interval.low):.1f}–{self.mm(interval.high):.1f} mm: {inside}, "
                f"{below:+.1f} / {above:+.1f} mm to its ends{status}")

    def to_dict(self, span_lengths: Sequence[float] | None = None) -> dict:
        """JSON-ready content in ‰, mm and N.

        Parameters
        ----------
        span_lengths : sequence of float, optional
            See :meth:`headline`. [m]
        """
        def answer(a: Answer) -> dict:
            return {"method": a.method, "presag_rel_permille": a.presag_rel * 1e3, "presag_mm": self.mm(a.presag_rel),
                    "uplift_mm": None if a.uplift is None else a.uplift * 1e3, "uplift_kind": a.uplift_kind,
                    "margins_mm": [[self.mm(m) for m in i.margins(a.presag_rel)] for i in self.intervals]}

        crew = self.evidence.installation
        margin = self.margin()
        return {
            "status": self.status, "headline": self.headline(span_lengths), "reason": self.reason,
            "basis": self.basis, "presag_rel_permille": self.presag_rel * 1e3, "presag_mm": self.mm(self.presag_rel),
            "reference_span_m": self.reference_span,
            "intervals": [{"name": i.name, "low_mm": self.mm(i.low), "high_mm": self.mm(i.high),
                           "in_force": i.in_force, "why_not": i.why_not,
                           "margins_mm": [self.mm(m) for m in i.margins(self.presag_rel)]} for i in self.intervals],
            "margin_mm": None if margin is None else self.mm(margin),
            "crew_tolerance_mm": crew.half_width * 1e3, "crew_tolerance_kind": crew.kind,
            "crew_tolerance_source": crew.source,
            "uplift_mm": None if self.uplift is None else self.uplift * 1e3, "uplift_kind": self.uplift_kind,
            "uplift_limit_mm": self.evidence.uplift_limit * 1e3, "highest_static_force_N": self.highest_static_force,
            "validity": self.validity.to_dict(), "answers": [answer(a) for a in self.answers],
            "not_checked": list(self.missing),
        }


def decide(evidence: Evidence) -> Decision:
    """Pick the pre-sag to build (the procedure of the module docstring).

    Parameters
    ----------
    evidence : Evidence
        The records of the band and what every decision needs.

    Returns
    -------
    Decision
    """
    validity = evidence.validity()
    limit = evidence.uplift_limit
    answers = _answers(evidence)
    intervals = _intervals(evidence, validity)

    def result(presag_rel: float, basis: str, status: str, reason: str, highest: float | None = None) -> Decision:
        uplift, kind = evidence.uplift_at(presag_rel)
        if basis == DYNAMIC_ROBUST:
            uplift, kind = evidence.dynamic_robust.uplift, "dynamic"
        return Decision(presag_rel=presag_rel, basis=basis, status=status, reason=reason, answers=answers,
                        intervals=intervals, uplift=uplift, uplift_kind=kind, highest_static_force=highest,
                        validity=validity, evidence=evidence)

    # 2. uplift compatibility
    if _no_presag_keeps_uplift(evidence, answers):
        known = [a for a in answers if a.uplift is not None]
        best = min(known, key=lambda a: a.uplift) if known else answers[0]
        highest = (evidence.validity_sweep.highest_static_force(limit)
                   if evidence.validity_sweep is not None and evidence.validity_sweep.has_uplift
                   else evidence.static_force_estimate)
        tail = (f"; the highest static force at which one does is {highest:.0f} N" if highest is not None
                else f"; not even at the band's lowest static force, {evidence.static_force_floor:.0f} N")
        shown = f" (the answers' uplift: at least {best.uplift * 1e3:.1f} mm, {best.uplift_kind})" if best.uplift else ""
        return result(best.presag_rel, best.method, "uplift-bound",
                      f"no pre-sag checked keeps the steady-arm uplift within the limit {limit * 1e3:g} mm over the "
                      f"band{shown}{tail}: the static force is set by uplift compatibility here, not by contact "
                      "dynamics", highest)

    # 3. the answer to build from
    quasi = [a for a in answers if a.method != DYNAMIC_ROBUST]
    dynamic = next((a for a in answers if a.method == DYNAMIC_ROBUST), None)
    if validity.trusted and quasi:
        preferred, why = quasi[0], "the quasi-static answers hold over the band"
    elif dynamic is not None:
        preferred, why = dynamic, ("the quasi-static answers are not trusted at this band's speeds: the dynamic "
                                   "robust design decides")
    else:
        preferred, why = quasi[0], ("the quasi-static answers are not trusted at this band's speeds, and the dynamic "
                                    "robust design, which decides there, was not computed")

    # 4. margin
    crew = evidence.installation.half_width / evidence.reference_span
    in_force = [i for i in intervals if i.in_force]
    provisional = evidence.dynamic_robust is None
    status = "provisional" if provisional else "decided"
    if not in_force:
        return result(preferred.presag_rel, preferred.method, status, f"{why}; no tolerance interval is known, so "
                      "no margin could be checked")
    low, high = max(i.low for i in in_force), min(i.high for i in in_force)
    names = " and ".join(f"{i.name} ({_mm(evidence, i.low)}–{_mm(evidence, i.high)} mm)" for i in in_force)
    grid = np.linspace(low, high, _GRID)
    keeps = np.array([_keeps(evidence, s) for s in grid])

    def margin_at(s: float) -> float:
        """Distance to the nearest end of the intersection or to a pre-sag whose uplift is over the limit."""
        near = min(s - low, high - s)
        return min(near, float(np.abs(grid[~keeps] - s).min())) if (~keeps).any() and near > 0 else near

    crew_mm = evidence.installation.half_width * 1e3
    margin = margin_at(preferred.presag_rel)
    if margin >= crew - 1e-12 and _keeps(evidence, preferred.presag_rel):
        return result(preferred.presag_rel, preferred.method, status,
                      f"{why}; {preferred.method} keeps a margin of {_mm(evidence, margin)} mm to the {names}, at least "
                      f"the crew's ±{crew_mm:.1f} mm")
    if not keeps.any():
        return result(preferred.presag_rel, preferred.method, "uplift-bound",
                      f"{why}; no pre-sag inside the {names} keeps the steady-arm uplift within "
                      f"{limit * 1e3:g} mm", evidence.static_force_estimate)
    margins = np.array([margin_at(g) if k else -np.inf for g, k in zip(grid, keeps)])
    best = float(grid[np.lexsort((np.abs(grid - preferred.presag_rel), -np.round(margins, 12)))[0]])
    best_margin = float(margin_at(best))
    uplift_edge = " or of the pre-sags that keep the uplift limit" if (~keeps).any() else ""
    if min(preferred.presag_rel - low, high - preferred.presag_rel) < 0:
        place = "lies outside the intersection of"
    elif not _keeps(evidence, preferred.presag_rel):
        place = "has its steady-arm uplift over the limit inside"
    else:
        place = f"lies {_mm(evidence, margin)} mm from the nearest end{uplift_edge} of"
    moved = f"{why}; {preferred.method} ({_mm(evidence, preferred.presag_rel)} mm) {place} the {names}"
    if best_margin < crew - 1e-12:
        return result(best, LARGEST_MARGIN, "tolerance-bound",
                      f"{moved}; the pre-sags inside them that keep the uplift limit leave at most "
                      f"{_mm(evidence, best_margin)} mm of margin, less than the crew's ±{crew_mm:.1f} mm: the largest "
                      f"margin is at {_mm(evidence, best)} mm")
    return result(best, LARGEST_MARGIN, status,
                  f"{moved}; built at {_mm(evidence, best)} mm instead, the largest margin inside them "
                  f"({_mm(evidence, best_margin)} mm, at least the crew's ±{crew_mm:.1f} mm)")


def _mm(evidence: Evidence, presag_rel: float) -> str:
    return f"{presag_rel * evidence.reference_span * 1e3:.1f}"


def _keeps(evidence: Evidence, presag_rel: float) -> bool:
    """Whether the best-known uplift at a pre-sag is within the limit (unknown counts as kept)."""
    uplift, _ = evidence.uplift_at(presag_rel)
    return uplift is None or uplift <= evidence.uplift_limit


def _answers(evidence: Evidence) -> tuple[Answer, ...]:
    """Every method's answer with its best-known uplift, in :data:`METHOD_ORDER`."""
    out = []
    for method, record in ((QUASI_STATIC_ROBUST, evidence.quasi_static_robust), (DELTA_E_RULE, evidence.delta_e),
                           (DYNAMIC_ROBUST, evidence.dynamic_robust)):
        if record is None:
            continue
        if method == DYNAMIC_ROBUST:
            uplift, kind = record.uplift, "dynamic"
        else:
            uplift, kind = evidence.uplift_at(record.presag_rel)
        out.append(Answer(method=method, presag_rel=record.presag_rel, uplift=uplift, uplift_kind=kind))
    return tuple(out)


def _intervals(evidence: Evidence, validity: ValidityStatement) -> tuple[Interval, ...]:
    """The known tolerance intervals and whether each is in force (see the module docstring)."""
    out = []
    dynamic = evidence.dynamic_robust
    if dynamic is not None:
        out.append(Interval(name=DYNAMIC_TOLERANCE, low=dynamic.tolerance[0], high=dynamic.tolerance[1], in_force=True))
    quasi = evidence.quasi_static_robust
    if quasi is not None:
        low, high = quasi.tolerance
        why_not = ("" if validity.trusted else "the quasi-static answers are not trusted at this band's speeds")
        if not why_not and dynamic is not None and (high < dynamic.tolerance[0] or low > dynamic.tolerance[1]):
            why_not = "it does not overlap the dynamic tolerance, which the simulation decides"
        out.append(Interval(name=QUASI_STATIC_TOLERANCE, low=low, high=high, in_force=not why_not, why_not=why_not))
    return tuple(out)


def _no_presag_keeps_uplift(evidence: Evidence, answers: Sequence[Answer]) -> bool:
    """Whether the evidence shows that no pre-sag keeps the uplift limit over the band."""
    limit = evidence.uplift_limit
    if evidence.dynamic_robust is not None and evidence.dynamic_robust.uplift <= limit:
        return False  # the dynamic search keeps the limit as a constraint: a pre-sag that keeps it exists
    sweep = evidence.validity_sweep
    if sweep is not None and sweep.has_uplift:
        return not sweep.some_presag_keeps_uplift(limit)
    known = [a for a in answers if a.uplift is not None and a.uplift_kind == "dynamic"]
    known = known or [a for a in answers if a.uplift is not None]
    return bool(known) and all(a.uplift > limit for a in known)
