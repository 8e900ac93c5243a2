"""Form-finding over the model's whole input space: random input sets, each solved, refused or failed.

The evidence that form-finding converges wherever its inputs are valid. :func:`draw_cases` draws input
sets (:class:`FuzzCase`) over

- every ``assumed`` number of the ST 9,8/9,8 and ST 7,1/7,1 systems over the range
  ``presag sensitivity`` varies it over (:func:`~presag_opt.sensitivity.inputs.model_inputs`: the
  range declared in the model file, else ±20 %);
- the section: 3 to 8 spans, all of one length in 40–65 m or each its own in 24.7–65 m (the mixed
  section's shortest span up to a little beyond the ideal one); straight track, or one curve of
  radius 300–3000 m in size (log-uniform, either hand) with the stagger alternating (as the model
  files write it) or registered to the outside of the curve at every mast (as built);
- the steady arms: all pull-off, or each a push-off arm with probability 0.3;
- the contact-wire height: constant, or changing by up to 0.5 m from mast to mast;
- the pre-sag: 0–2 ‰ (the designs the tool recommends lie within 0.5–1.8 ‰),

and :func:`solve_case` form-finds one at the default settings (0.5 m elements, 0.05 mm geometry
tolerance). Each set ends in one of the :data:`STATUSES`: *converged* (within the force and geometry
tolerances), *refused* before any solve with a one-line reason
(:func:`~presag_opt.static.form_finding.check_form_finding_inputs`), *refused after solving* (a dropper
the first guess put just above the shortest buildable one, found short by the solve), or *failed* (a
solver error). :func:`fuzz_table` summarises them: the shares, and the iterations
and time per solve as quantiles. ``benchmarks/bench_form_finding_fuzz.py`` runs it at scale and the
default tests a few sets.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ConvergenceError, ModelError, failure_reason
from presag_opt.sensitivity.inputs import apply_inputs, model_inputs
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import check_form_finding_inputs, form_find
from presag_opt.static.solver_statistics import QUANTILES, FormFindingStatistics
from presag_opt.system.catenary import Catenary, SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.masts import MastGeometry

FUZZ_SYSTEMS = ("st_9.8_ideal", "st_7.1_ideal")
"""The systems whose assumed inputs are drawn."""

SPAN_COUNTS = (3, 8)
"""Fewest and most spans of a section. [-]"""

EQUAL_SPAN_RANGE = (40.0, 65.0)
"""Span length of a section of equal spans. [m]"""

MIXED_SPAN_RANGE = (24.7, 65.0)
"""Span lengths of a section of mixed spans. [m]"""

RADIUS_RANGE = (300.0, 3000.0)
"""Curve radius in size. [m]"""

HEIGHT_STEP = 0.5
"""Largest change of the contact-wire height from mast to mast. [m]"""

HEIGHT_RANGE = (4.5, 6.5)
"""Contact-wire heights a changing height stays within (a low bridge to a level crossing). [m]"""

PRESAG_RANGE = (0.0, 2e-3)
"""Relative pre-sag S_rel. [-]"""

PUSH_OFF_SHARE = 0.3
"""Chance of a push-off arm at a mast of a section with push-off arms. [-]"""

STATUSES = ("converged", "refused", "refused after solving", "failed")
"""How an input set ends: converged; refused before any solve; refused by the checks of the solved
state (a dropper shorter than the shortest buildable one, which the first guess put within its margin,
:data:`~presag_opt.static.section_geometry.DROPPER_GUESS_MARGIN`); failed (a solver error)."""


@dataclass(frozen=True, kw_only=True)
class FuzzCase:
    """One input set of the study.

    Attributes
    ----------
    index : int
        Position in the draw. [-]
    system : str
        Built-in model whose wires, droppers and supports are used.
    inputs : dict
        Assumed input name -> value drawn, SI (names as ``presag sensitivity`` gives them).
    span_lengths : tuple of float
        Span lengths. [m]
    radius : float
        Curve radius of every span, + left, 0 straight. [m]
    outside : bool
        Stagger registered to the outside of the curve at every mast (else alternating).
    push_off : tuple of bool
        Push-off arm at each mast.
    heights : tuple of float
        Contact-wire height at each mast. [m]
    presag_rel : float
        Relative pre-sag. [-]
    """

    index: int
    system: str
    inputs: dict
    span_lengths: tuple[float, ...]
    radius: float
    outside: bool
    push_off: tuple[bool, ...]
    heights: tuple[float, ...]
    presag_rel: float

    def catenary(self) -> Catenary:
        """The section as a catenary (the assumed inputs applied, then the section's geometry).

        Raises
        ------
        ModelError
            An input the model refuses (a span too short for the dropper rule, say).
        """
        base = apply_inputs({"catenary": load_catenary(self.system)}, self.inputs)["catenary"]
        masts = len(self.span_lengths) + 1
        if self.radius != 0.0 and self.outside:
            stagger = (-math.copysign(base.stagger, self.radius),) * masts  # away from the curve's centre
        else:
            stagger = tuple(base.stagger * (1.0 if i % 2 == 0 else -1.0) for i in range(masts))
        geometry = MastGeometry(stagger=stagger, contact_wire_height=self.heights,
                                system_height=(base.system_height,) * masts, push_off=self.push_off)
        layout = SpanLayout(span_lengths=self.span_lengths, curve_radii=(self.radius,) * len(self.span_lengths),
                            label=f"fuzz set {self.index}")
        return dataclasses.replace(base, layout=layout, masts=geometry, presag_rel=self.presag_rel)

    def to_dict(self) -> dict:
        """The set in the units a designer writes (m, mm, ‰), JSON-ready."""
        return {"index": self.index, "system": self.system, "inputs": self.inputs,
                "span_lengths_m": list(self.span_lengths), "radius_m": self.radius,
                "stagger": "outside" if self.outside and self.radius else "alternating",
                "push_off": [i for i, p in enumerate(self.push_off) if p], "heights_m": list(self.heights),
                "presag_permille": self.presag_rel * 1e3}


def draw_cases(count: int, seed: int) -> list[FuzzCase]:
    """``count`` input sets drawn with ``seed`` (the same sets for the same count and seed).

    Parameters
    ----------
    count : int
        Input sets. [-]
    seed : int
        Seed of the draw. [-]
    """
    rng = np.random.default_rng(seed)
    ranges = {}
    for name in FUZZ_SYSTEMS:
        model = load_catenary(name)
        ranges[name] = model_inputs({"catenary": model}, {"catenary": model.provenance})
    cases = []
    for index in range(count):
        system = FUZZ_SYSTEMS[int(rng.integers(len(FUZZ_SYSTEMS)))]
        inputs = {n: float(rng.uniform(i.low, i.high)) for n, i in ranges[system].items()}
        n = int(rng.integers(SPAN_COUNTS[0], SPAN_COUNTS[1] + 1))
        if rng.random() < 0.5:
            spans = (round(float(rng.uniform(*EQUAL_SPAN_RANGE)), 1),) * n
        else:
            spans = tuple(round(float(s), 1) for s in rng.uniform(*MIXED_SPAN_RANGE, n))
        radius = 0.0
        if rng.random() < 2.0 / 3.0:
            size = math.exp(rng.uniform(math.log(RADIUS_RANGE[0]), math.log(RADIUS_RANGE[1])))
            radius = round(size, 0) * (1.0 if rng.random() < 0.5 else -1.0)
        outside = bool(rng.random() < 0.5)
        push_off = tuple(bool(p) for p in rng.random(n + 1) < PUSH_OFF_SHARE) if rng.random() < 0.5 else (False,) * (n + 1)
        heights = [5.5] * (n + 1)
        if rng.random() < 0.5:
            for i, step in enumerate(rng.uniform(-HEIGHT_STEP, HEIGHT_STEP, n)):
                # a step that would leave the usual heights is taken the other way
                heights[i + 1] = round(heights[i] + (step if HEIGHT_RANGE[0] <= heights[i] + step <= HEIGHT_RANGE[1]
                                                     else -step), 3)
        presag = float(rng.uniform(*PRESAG_RANGE))
        cases.append(FuzzCase(index=index, system=system, inputs=inputs, span_lengths=spans, radius=radius,
                              outside=outside, push_off=push_off, heights=tuple(heights), presag_rel=presag))
    return cases


@dataclass(frozen=True, kw_only=True)
class FuzzOutcome:
    """How one input set ended.

    Attributes
    ----------
    case : FuzzCase
        The set.
    status : str
        One of :data:`STATUSES`.
    reason : str
        One line: why it was refused or failed ("" when it converged).
    statistics : FormFindingStatistics or None
        The form-finding's counts and time (None unless converged).
    seconds : float
        Wall time of the attempt. [s]
    dropper_guess_error : float
        How far the first guess of the dropper lengths (the design state's, which the refusal of
        short droppers reads) lies above the form-found lengths at most; negative where it
        underestimates them (NaN unless converged). [m]
    """

    case: FuzzCase
    status: str
    reason: str
    statistics: FormFindingStatistics | None
    seconds: float
    dropper_guess_error: float = math.nan


def solve_case(case: FuzzCase, settings: StaticSettings | None = None) -> FuzzOutcome:
    """Form-find one input set: converged, refused before work, or failed.

    Parameters
    ----------
    case : FuzzCase
        The set.
    settings : StaticSettings, optional
        Numerical settings (default: the static model's).
    """
    settings = settings or StaticSettings()
    started = time.perf_counter()
    try:
        catenary = case.catenary()
        check_form_finding_inputs(catenary, settings)
    except ModelError as exc:
        return FuzzOutcome(case=case, status="refused", reason=failure_reason(exc), statistics=None,
                           seconds=time.perf_counter() - started)
    try:
        state = form_find(catenary, settings)
    except (ConvergenceError, ModelError) as exc:
        status = "refused after solving" if isinstance(exc, ModelError) else "failed"
        return FuzzOutcome(case=case, status=status, reason=failure_reason(exc), statistics=None,
                           seconds=time.perf_counter() - started)
    disc = state.discretisation
    drops = disc.dropper_elements
    guess = (disc.design_positions[disc.axial.node_b[drops], 2] - disc.design_positions[disc.axial.node_a[drops], 2])
    return FuzzOutcome(case=case, status="converged", reason="", statistics=state.form_finding,
                       seconds=time.perf_counter() - started,
                       dropper_guess_error=float(np.min(guess - state.dropper_lengths())))


def fuzz_table(outcomes: list[FuzzOutcome]) -> dict:
    """The study's table: shares of the statuses, and per converged solve the quantiles of its iterations,
    passes, restarts and wall time.

    Parameters
    ----------
    outcomes : list of FuzzOutcome
        The sets' outcomes.

    Returns
    -------
    dict
        ``sets``; ``share`` and ``count`` by status; ``quantiles`` (:data:`QUANTILES`) of ``ipopt_iterations``,
        ``newton_iterations``, ``passes``, ``restarts`` and ``seconds`` over the converged sets; and
        ``dropper_guess_error_m``, the range of :attr:`FuzzOutcome.dropper_guess_error`. [-], [s], [m]
    """
    counts = {s: sum(o.status == s for o in outcomes) for s in STATUSES}
    solved = [o.statistics for o in outcomes if o.statistics is not None]
    quantiles = {}
    for name in ("ipopt_iterations", "newton_iterations", "passes", "restarts", "seconds"):
        values = [getattr(s, name) for s in solved]
        quantiles[name] = {f"q{round(q * 100)}": float(np.quantile(values, q)) for q in QUANTILES} if values else {}
    guess = [o.dropper_guess_error for o in outcomes if o.statistics is not None]
    return {"sets": len(outcomes), "count": counts,
            "share": {s: c / max(1, len(outcomes)) for s, c in counts.items()}, "quantiles": quantiles,
            "dropper_guess_error_m": [float(min(guess)), float(max(guess))] if guess else []}


__all__ = ["FUZZ_SYSTEMS", "STATUSES", "FuzzCase", "FuzzOutcome", "draw_cases", "fuzz_table", "solve_case"]
