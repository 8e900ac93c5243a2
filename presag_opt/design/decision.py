"""One decision: which pre-sag to build, from the answers the toolkit has, with its reason.

The toolkit has several answers to "which S?" for an operating band: the quasi-static Δe rule (the
mean of the S_rel range ends over the band, the paper's case-study recommendation), the quasi-static
robust design (the minimax parabola of the path waviness over the F_m band) and the dynamic robust
design (chosen by batched dynamic simulation over the band's static forces and speeds). Each comes
with what is known about it: a tolerance interval (quasi-static from the robust LP, dynamic from the
dynamic design) and a steady-arm uplift (a static estimate F_m·e_mast, or the dynamic maximum).

The procedure (:func:`decide`), in order:

1. **Uplift compatibility.** If the uplift limit is exceeded by every answer whose uplift is known
   dynamically (or, without dynamic results, by the static estimate of every answer), no S keeps the
   limit over the band: the decision says so and gives the highest static force at which one does
   (the static force is then set by uplift compatibility, not by contact dynamics). The S shown is
   the best remaining answer, marked not buildable for this band.
2. **Validity.** The quasi-static answers are trusted where the band's largest speed ratio β_max lies
   at or below the lower end of the validity limit: β* − its uncertainty when a validity study was
   read, else the paper's onset of the weakening, β = 0.35 (its limit 0.4 with the σ/F_m minimum
   already weakening from 0.35).
3. **Tolerance and uplift.** A trusted quasi-static answer is built if it lies inside the dynamic
   tolerance interval and its uplift is within the limit (dynamic where known, else the static
   estimate); the robust design is preferred to the Δe rule, since it is the one that carries a
   tolerance interval of its own. Without a dynamic tolerance interval the decision is provisional.
4. **Otherwise the dynamic robust design**, if it was computed and keeps the uplift limit. If it was
   not computed (a fast command), the decision is *provisional*: the best quasi-static answer is
   shown with what was not checked and the command that checks it.

The alternatives are always listed beside the choice.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: sections 5–6
(validity up to about 40 % of the wave speed, uplift limit 83.5 mm, static force set by uplift).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from presag_opt.contact_force import mean_contact_force
from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT
from presag_opt.errors import ModelError

DELTA_E_RULE = "quasi-static Δe rule"
QUASI_STATIC_ROBUST = "quasi-static robust design"
DYNAMIC_ROBUST = "dynamic robust design"
METHOD_ORDER = (QUASI_STATIC_ROBUST, DELTA_E_RULE, DYNAMIC_ROBUST)
"""Answers in order of preference among those that qualify."""

PAPER_WEAKENING_BETA = 0.35
"""Speed ratio from which the paper's σ/F_m minimum weakens (gone by 0.41): the quasi-static answers
are trusted up to here when no validity study was read. [-]"""


@dataclass(frozen=True, kw_only=True)
class Candidate:
    """One answer to "which S?".

    Attributes
    ----------
    method : str
        One of :data:`METHOD_ORDER`.
    presag_rel : float
        Its relative pre-sag S/l. [-]
    tolerance : tuple of float or None
        Its own tolerance interval of S_rel, if it has one. [-]
    uplift : float or None
        Largest steady-arm uplift over the band at this S, if known. [m]
    uplift_dynamic : bool
        Whether ``uplift`` comes from dynamic simulation (else a static estimate F_m·e_mast).
    """

    method: str
    presag_rel: float
    tolerance: tuple[float, float] | None = None
    uplift: float | None = None
    uplift_dynamic: bool = False

    def __post_init__(self) -> None:
        if self.method not in METHOD_ORDER:
            raise ModelError(f"candidate method {self.method!r} is not one of {', '.join(METHOD_ORDER)}")
        if not 0.0 <= self.presag_rel <= 0.005:
            raise ModelError(f"{self.method}: presag_rel = {self.presag_rel * 1e3:g} ‰ is outside the valid range [0, 5] ‰")

    @property
    def quasi_static(self) -> bool:
        """Whether the answer rests on the quasi-static model."""
        return self.method != DYNAMIC_ROBUST


@dataclass(frozen=True, kw_only=True)
class DecisionInputs:
    """What the decision is made from.

    Attributes
    ----------
    candidates : tuple of Candidate
        The answers computed (at least one).
    beta_max : float
        Largest speed ratio v/c_CW of the band. [-]
    beta_limit : float or None
        Validity limit β* read from a study, None if none was read or it could not be read. [-]
    beta_limit_uncertainty : float
        Its uncertainty (half the β grid step). [-]
    beta_limit_source : str
        What ``beta_limit`` is, where it is not a β* read from a study (e.g. the lowest β of a study
        whose grid shows the rule holding at none of its speeds); empty for a β*.
    dynamic_tolerance : tuple of float or None
        S_rel interval within the allowed loss of the dynamic optimum, if computed. [-]
    uplift_limit : float
        Largest allowed steady-arm uplift. [m]
    highest_static_force : float or None
        Highest static force at which some S keeps the uplift limit over the band, if known. [N]
    lowest_static_force_checked : float or None
        Lowest static force the uplift was checked at, where ``highest_static_force`` is None because
        none kept the limit. [N]
    some_presag_keeps_uplift : bool or None
        Whether some pre-sag checked dynamically (not only the candidates) keeps the uplift limit over
        the whole band; None if unknown (then the candidates' uplifts decide).
    not_checked : tuple of str
        What was not computed (shown with the decision).
    """

    candidates: tuple[Candidate, ...]
    beta_max: float
    beta_limit: float | None = None
    beta_limit_uncertainty: float = 0.0
    beta_limit_source: str = ""
    dynamic_tolerance: tuple[float, float] | None = None
    uplift_limit: float = STEADY_ARM_UPLIFT_LIMIT
    highest_static_force: float | None = None
    lowest_static_force_checked: float | None = None
    some_presag_keeps_uplift: bool | None = None
    not_checked: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "candidates", tuple(self.candidates))
        if not self.candidates:
            raise ModelError("decision: give at least one candidate pre-sag")
        if not (math.isfinite(self.beta_max) and 0.0 <= self.beta_max < 1.0):
            raise ModelError(f"decision: beta_max = {self.beta_max:g} is outside the valid range [0, 1)")
        if not 0.0 < self.uplift_limit <= 1.0:
            raise ModelError(f"decision: uplift_limit = {self.uplift_limit * 1e3:g} mm is outside the valid range (0, 1000] mm")

    @property
    def trusted_beta(self) -> float:
        """β up to which the quasi-static answers are trusted (see the module docstring). [-]"""
        if self.beta_limit is None:
            return PAPER_WEAKENING_BETA
        return self.beta_limit - self.beta_limit_uncertainty


@dataclass(frozen=True, kw_only=True)
class Decision:
    """The pre-sag to build and why.

    Attributes
    ----------
    chosen : Candidate
        The answer to build (or, if ``status`` is not ``decided``, the one shown).
    status : str
        ``decided``; ``provisional`` (the answer that would decide was not computed); or
        ``uplift-bound`` (no S keeps the uplift limit over the band).
    reason : str
        Why, in one or two sentences.
    alternatives : tuple of Candidate
        The other answers.
    inputs : DecisionInputs
        What it was made from.
    """

    chosen: Candidate
    status: str
    reason: str
    alternatives: tuple[Candidate, ...]
    inputs: DecisionInputs

    def headline(self, span_length: float) -> str:
        """One line: what to build on a span of ``span_length``, by which method, and the status.

        Parameters
        ----------
        span_length : float
            Span length the relative pre-sag is applied to. [m]
        """
        c = self.chosen
        text = f"{c.presag_rel * 1e3:.2f} ‰ = {c.presag_rel * span_length * 1e3:.0f} mm on {span_length:g} m ({c.method})"
        if self.status == "uplift-bound":
            return f"No pre-sag keeps the steady-arm uplift limit over this band (best answer shown: {text})"
        if self.status == "provisional":
            return f"Pre-sag to build (provisional): {text}"
        return f"Pre-sag to build: {text}"

    def lines(self, span_length: float) -> list[str]:
        """The decision as printed: headline, reason, what was not checked, the alternatives.

        Parameters
        ----------
        span_length : float
            Span length the relative pre-sag is applied to. [m]
        """
        out = [self.headline(span_length), f"  why: {self.reason}"]
        details = (_uplift_text(self.chosen, self.inputs.uplift_limit) + _tolerance_text(self.chosen, span_length)).strip(", ")
        if details:
            out.append(f"  chosen: {details}")
        if self.inputs.not_checked:
            out.append("  not checked: " + "; ".join(self.inputs.not_checked))
        for c in self.alternatives:
            out.append(f"  alternative: {c.method} {c.presag_rel * 1e3:.2f} ‰ = {c.presag_rel * span_length * 1e3:.0f} mm"
                       + _uplift_text(c, self.inputs.uplift_limit) + _tolerance_text(c, span_length))
        return out

    def to_dict(self, span_length: float) -> dict:
        """JSON-ready content in ‰, mm and N.

        Parameters
        ----------
        span_length : float
            Span length the relative pre-sag is applied to. [m]
        """
        def one(c: Candidate) -> dict:
            return {"method": c.method, "presag_rel_permille": c.presag_rel * 1e3,
                    "presag_mm": c.presag_rel * span_length * 1e3,
                    "tolerance_mm": None if c.tolerance is None else [t * span_length * 1e3 for t in c.tolerance],
                    "uplift_mm": None if c.uplift is None else c.uplift * 1e3, "uplift_dynamic": c.uplift_dynamic}

        inputs = self.inputs
        return {"status": self.status, "headline": self.headline(span_length), "reason": self.reason,
                "span_length_m": span_length, "chosen": one(self.chosen),
                "alternatives": [one(c) for c in self.alternatives], "beta_max": inputs.beta_max,
                "beta_trusted_up_to": inputs.trusted_beta, "uplift_limit_mm": inputs.uplift_limit * 1e3,
                "highest_static_force_N": inputs.highest_static_force, "not_checked": list(inputs.not_checked)}


def decide(inputs: DecisionInputs) -> Decision:
    """Pick the pre-sag to build (the procedure of the module docstring).

    Parameters
    ----------
    inputs : DecisionInputs
        The candidates and what is known about the band.

    Returns
    -------
    Decision
    """
    order = sorted(inputs.candidates, key=lambda c: METHOD_ORDER.index(c.method))
    limit = inputs.uplift_limit
    dynamic = next((c for c in order if c.method == DYNAMIC_ROBUST), None)

    def alternatives(chosen: Candidate) -> tuple[Candidate, ...]:
        return tuple(c for c in order if c is not chosen)

    def result(chosen: Candidate, status: str, reason: str) -> Decision:
        return Decision(chosen=chosen, status=status, reason=reason, alternatives=alternatives(chosen), inputs=inputs)

    # 1. uplift compatibility: judged on dynamic uplifts where there are any, else on the static estimates
    known = [c for c in order if c.uplift is not None and c.uplift_dynamic] or [c for c in order if c.uplift is not None]
    all_over = bool(known) and all(c.uplift > limit for c in known)
    if inputs.some_presag_keeps_uplift is False or (inputs.some_presag_keeps_uplift is None and all_over):
        best = min(known, key=lambda c: c.uplift) if known else order[0]
        kind = "dynamic" if best.uplift_dynamic else "static estimate"
        force = inputs.highest_static_force
        floor = inputs.lowest_static_force_checked
        tail = (f"; the highest static force at which one does is {force:.0f} N" if force is not None
                else f"; not even at the lowest static force checked, {floor:.0f} N" if floor is not None
                else "; the highest static force at which one does was not computed")
        answers = (f" (the answers' uplift, {kind}: at least {best.uplift * 1e3:.1f} mm)" if best.uplift is not None
                   else "")
        return result(best, "uplift-bound",
                      f"no pre-sag checked keeps the steady-arm uplift within the limit {limit * 1e3:g} mm over the "
                      f"band{answers}{tail}: the static force is set by uplift compatibility here, not by contact "
                      "dynamics")

    # 2. validity of the quasi-static answers
    trusted = inputs.beta_max <= inputs.trusted_beta + 1e-12
    if inputs.beta_limit is None:
        source = f"the paper's onset of the limit, β = {PAPER_WEAKENING_BETA:g}"
    elif inputs.beta_limit_source:
        source = inputs.beta_limit_source
    else:
        source = f"the validity study's β* = {inputs.beta_limit:.2f} ± {inputs.beta_limit_uncertainty:.2f}"
    relation = "at or below" if trusted else "above" if inputs.beta_max > inputs.trusted_beta else "not below"
    beta_text = f"the band's β_max = {inputs.beta_max:.2f} is {relation} {source}"

    # 3. a trusted quasi-static answer inside the dynamic tolerance and within the uplift limit
    problems = {}
    for c in order:
        if not c.quasi_static:
            continue
        issues = []
        tol = inputs.dynamic_tolerance
        if tol is not None and not tol[0] - 1e-12 <= c.presag_rel <= tol[1] + 1e-12:
            issues.append(f"outside the dynamic tolerance {tol[0] * 1e3:.2f}–{tol[1] * 1e3:.2f} ‰")
        if c.uplift is not None and c.uplift > limit:
            issues.append(f"uplift {c.uplift * 1e3:.1f} mm over the limit {limit * 1e3:g} mm")
        problems[c.method] = issues
        if trusted and not issues:
            checked = "inside the dynamic tolerance" if tol is not None else "the dynamic tolerance was not computed"
            uplift = _uplift_text(c, limit).strip(", ")
            return result(c, "decided" if tol is not None else "provisional",
                          f"{beta_text}, so the quasi-static answers hold; {c.method}: {checked}"
                          + (f", {uplift}" if uplift else ""))
    # 4. the dynamic robust design
    why = "; ".join(([] if trusted else [beta_text]) + [f"{m}: {', '.join(i)}" for m, i in problems.items() if i])
    if dynamic is not None and (dynamic.uplift is None or dynamic.uplift <= limit):
        return result(dynamic, "decided", f"{why}: the dynamic robust design decides")
    if dynamic is not None:
        return result(dynamic, "uplift-bound", f"{why}; the dynamic robust design's uplift "
                      f"{dynamic.uplift * 1e3:.1f} mm is over the limit {limit * 1e3:g} mm")
    shown = next((c for c in order if not problems.get(c.method)), order[0])
    return result(shown, "provisional", f"{why}: the dynamic robust design decides here and was not computed "
                  "(presag robust --dynamic); the quasi-static answer is shown until then")


def _uplift_text(c: Candidate, limit: float) -> str:
    if c.uplift is None:
        return ""
    kind = "dynamic" if c.uplift_dynamic else "static estimate"
    return f", steady-arm uplift {c.uplift * 1e3:.1f} mm ({kind}; limit {limit * 1e3:g} mm)"


def _tolerance_text(c: Candidate, span_length: float) -> str:
    if c.tolerance is None:
        return ""
    return f", tolerance {c.tolerance[0] * span_length * 1e3:.0f}–{c.tolerance[1] * span_length * 1e3:.0f} mm"


def highest_static_force_static(support_elasticity: float, limit: float, aero_coefficient: float,
                                speed_high: float) -> float:
    """Highest static force whose static uplift estimate keeps the limit at the top speed. [N]

    F_m·e_mast ≤ limit with F_m = F_stat + α_ae·v², so F_stat ≤ limit/e_mast − α_ae·v².

    Parameters
    ----------
    support_elasticity : float
        Largest elasticity at a steady arm. [m/N]
    limit : float
        Steady-arm uplift limit. [m]
    aero_coefficient : float
        α_ae. [N s²/m²]
    speed_high : float
        Highest speed of the band. [m/s]
    """
    # F_m = F_stat + α_ae v² solved for F_stat at the largest F_m the limit allows
    return limit / support_elasticity - mean_contact_force(0.0, speed_high, aero_coefficient)


def dynamic_candidate(design, tolerance=None) -> Candidate:
    """The dynamic robust design as a candidate.

    Parameters
    ----------
    design : DynamicRobustDesign
        From :func:`presag_opt.robust.dynamic_design.dynamic_robust_presag` (read by its ``presag_rel``
        [-] and ``uplift_max`` [m]; the design layer does not import the robust one).
    tolerance : DynamicTolerance, optional
        From :func:`presag_opt.robust.dynamic_design.dynamic_tolerance` (its ``low`` and ``high`` [-]);
        pass it also as :attr:`DecisionInputs.dynamic_tolerance`.
    """
    return Candidate(method=DYNAMIC_ROBUST, presag_rel=float(design.presag_rel),
                     tolerance=None if tolerance is None else (float(tolerance.low), float(tolerance.high)),
                     uplift=float(design.uplift_max), uplift_dynamic=True)
