"""Uncertain inputs of a sensitivity analysis: which numbers, over which ranges, and how they are applied.

An input is named by the dotted path ``presag sweep`` uses (:mod:`presag_opt.studies.parameters`):
``catenary.<field>[.<field>]``, ``pantograph.<stage>.<field>``, ``settings.<field>``; and, for the
operating band, ``operation.aero_coefficient`` and ``operation.static_force``. Its range is the one
declared beside its value in the model file (``range = [low, high]`` with ``range_note``), or
±:data:`~presag_opt.system.quantity.DEFAULT_RANGE_SHARE` of the value where none is declared
(cut to the field's valid range). By default the inputs are every ``assumed`` number of the model
files; counts (the number of spans) are not varied.

One input is not a number of a file: :data:`SPAN_LIST` stands for the mixed section's span list,
which the paper does not publish. Its value u in [0, 1) picks one of :data:`SPAN_LIST_BANK` random
lists with the paper's count (31), total (1340.2 m), shortest (24.7 m) and longest (58.4 m) span
(:func:`random_span_list`); the bank is fixed by its seed, so u maps to the same list everywhere.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.studies.parameters import apply_parameter, parameter_spec
from presag_opt.system.quantity import default_range, range_text

SPAN_LIST = "catenary.layout.span_lengths"
"""Name of the span-list input (mixed sections only)."""

SPAN_LIST_BANK = 64
"""Random span lists the span-list input chooses from. [-]"""

SPAN_LIST_SEED = 20250516
"""Seed of the bank of random span lists (fixed: an input value must name the same list in every run)."""

PAPER_MIXED_SECTION = {"count": 31, "total": 1340.2, "shortest": 24.7, "longest": 58.4}
"""The paper's summary of its representative mixed section (its list itself is not published). [-, m, m, m]"""

OPERATION_FIELDS = ("aero_coefficient", "static_force")
"""Fields of the operating point that can be inputs (``operation.<field>``)."""

#: Model-file sections whose keys are not the dataclass path below ``catenary``.
_CATENARY_SECTION_PATHS = {"geometry": ""}


@dataclass(frozen=True, kw_only=True)
class SensitivityInput:
    """One uncertain input and the range it is varied over.

    Attributes
    ----------
    name : str
        Dotted path (see the module notes).
    value : float
        Value in the model, SI. [SI unit of the field]
    low, high : float
        Range, SI, low < high. [SI unit of the field]
    unit : str
        Display unit of the field (for tables).
    factor : float
        SI value per display unit. [-]
    reason : str
        Why this range (the model file's ``range_note``, or the default rule).
    declared : bool
        Whether the range is declared in the model file (else the ±20 % default or the command line).
    """

    name: str
    value: float
    low: float
    high: float
    unit: str
    factor: float
    reason: str
    declared: bool

    def __post_init__(self) -> None:
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ModelError(f"{self.name}: range [{self.low / self.factor:g}, {self.high / self.factor:g}] "
                             f"{self.unit} must have low < high")

    def to_dict(self) -> dict:
        """JSON-ready content in the display unit."""
        return {"name": self.name, "value": self.value / self.factor, "low": self.low / self.factor,
                "high": self.high / self.factor, "unit": self.unit, "reason": self.reason,
                "declared": self.declared}


def _path_of(root: str, key: str, stage_names: Sequence[str]) -> str | None:
    """Dotted input name of a model-file key (``stages[0].mass`` -> ``pantograph.head.mass``)."""
    section, _, field = key.partition(".")
    if root == "pantograph" and section.startswith("stages["):
        return f"pantograph.{stage_names[int(section[7:-1])]}.{field}"
    if root == "catenary" and section in _CATENARY_SECTION_PATHS:
        # the pre-sag is what is designed, not an uncertain input
        return None if field == "presag" else f"catenary.{field}"
    if root == "catenary" and section == "layout":
        return SPAN_LIST if field == "span_lengths" else None
    if root == "operation":
        return f"operation.{field}" if section == "operation" and field in OPERATION_FIELDS else None
    return f"{root}.{key}"


def model_inputs(roots: Mapping[str, Any], provenance: Mapping[str, Mapping[str, Any]],
                 *, assumed_only: bool = True) -> dict[str, SensitivityInput]:
    """Inputs of a model: its numbers with their ranges, by dotted name.

    Parameters
    ----------
    roots : mapping
        ``{"catenary": Catenary, "pantograph": Pantograph, "operation": Operation}`` (any subset).
    provenance : mapping
        Root name -> that object's provenance (model-file key -> Provenance).
    assumed_only : bool
        Keep only numbers tagged ``assumed`` (else every number with a finite range).

    Returns
    -------
    dict
        Name -> :class:`SensitivityInput`, in file order; numbers whose range has no width (a value
        of zero without a declared range), counts and lists other than the span list are left out.
    """
    out: dict[str, SensitivityInput] = {}
    stage_names = [s.name for s in getattr(roots.get("pantograph"), "stages", ())]
    for root, entries in provenance.items():
        for key, prov in entries.items():
            if assumed_only and prov.source != "assumed":
                continue
            name = _path_of(root, key, stage_names)
            if name is None:
                continue
            if name == SPAN_LIST:
                if len(set(roots["catenary"].layout.span_lengths)) > 1:
                    out[name] = span_list_input()
                continue
            item = _numeric_input(name, roots, prov)
            if item is not None:
                out[name] = item
    return out


def _numeric_input(name: str, roots: Mapping[str, Any], prov: Any) -> SensitivityInput | None:
    spec = input_spec(name, roots)
    if spec["dimension"] == "count":
        return None
    value = current_value(name, roots)
    if not isinstance(value, (int, float)):
        return None
    if prov.range is not None:
        low, high = prov.range
        reason, declared = prov.range_note, True
    else:
        rng = default_range(float(value), spec)
        if rng is None:
            return None
        (low, high), reason, declared = rng, "default: value ± 20 % (no range declared in the model file)", False
    return SensitivityInput(name=name, value=float(value), low=low, high=high, unit=spec["display"],
                            factor=spec["factor"], reason=reason, declared=declared)


def span_list_input() -> SensitivityInput:
    """The span-list input: u in [0, 1) picks one of the bank's random span lists."""
    return SensitivityInput(
        name=SPAN_LIST, value=0.0, low=0.0, high=1.0, unit="-", factor=1.0, declared=False,
        reason=(f"one of {SPAN_LIST_BANK} random span lists with the paper's count, total, shortest and longest "
                "span (the list itself is not published)"))


def input_spec(name: str, roots: Mapping[str, Any]) -> dict[str, Any]:
    """Quantity spec (dimension, unit, valid range) of the field an input names.

    Raises
    ------
    ModelError
        If the name does not lead to a numeric field of the given roots.
    """
    head = name.split(".", 1)[0]
    if head == "operation":
        field = name.split(".", 1)[1] if "." in name else ""
        if field not in OPERATION_FIELDS or "operation" not in roots:
            raise ModelError(f"unknown input {name!r}: the operating inputs are "
                             + ", ".join(f"operation.{f}" for f in OPERATION_FIELDS))
        return {f.name: f for f in dataclasses.fields(roots["operation"])}[field].metadata["quantity"]
    try:
        return parameter_spec(name, {k: v for k, v in roots.items() if k != "operation"})
    except ModelError as exc:
        raise ModelError(str(exc).replace("parameters: ", "", 1).replace("unknown parameter", "unknown input")) from None


def current_value(name: str, roots: Mapping[str, Any]) -> Any:
    """The value a dotted name has in the model (SI)."""
    obj: Any = roots[name.split(".", 1)[0]]
    for part in name.split(".")[1:]:
        stages = {s.name: s for s in getattr(obj, "stages", ())}
        obj = stages[part] if part in stages else getattr(obj, part)
    return obj


def parse_range_override(text: str, roots: Mapping[str, Any]) -> SensitivityInput:
    """An input from a command-line ``NAME=LOW:HIGH`` in the field's display unit.

    Raises
    ------
    ModelError
        For a malformed text, an unknown name, or ends outside the field's valid range.
    """
    name, sep, bounds = text.partition("=")
    low_text, sep2, high_text = bounds.partition(":")
    if not sep or not sep2:
        raise ModelError(f"--range {text!r}: write NAME=LOW:HIGH in the field's unit, e.g. pantograph.head.mass=5:10")
    spec = input_spec(name, roots)
    try:
        low, high = float(low_text), float(high_text)
    except ValueError:
        raise ModelError(f"--range {text!r}: LOW and HIGH must be numbers in {spec['display']}") from None
    for end in (low, high):
        if not spec["low"] <= end <= spec["high"]:
            raise ModelError(f"--range {name}: {end:g} {spec['display']} is outside the valid range {range_text(spec)}")
    if not low < high:
        raise ModelError(f"--range {name}: {low:g}:{high:g} {spec['display']} must have LOW < HIGH")
    value = current_value(name, roots)
    return SensitivityInput(name=name, value=float(value), low=low * spec["factor"], high=high * spec["factor"],
                            unit=spec["display"], factor=spec["factor"], reason="given on the command line",
                            declared=False)


def random_span_list(rng: np.random.Generator, *, count: int = 31, total: float = 1340.2, shortest: float = 24.7,
                     longest: float = 58.4) -> tuple[float, ...]:
    """A random span list with a given count, total, shortest and longest span (in random order).

    Two spans are the shortest and the longest; the others are drawn uniformly between them and
    scaled affinely about the shortest so that the total is met (redrawn while a span would leave
    [shortest, longest]); rounded to 0.1 m with the total kept exact.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness.
    count : int
        Spans, at least 3. [-]
    total, shortest, longest : float
        Total length, shortest and longest span. [m]

    Returns
    -------
    tuple of float
        The span lengths. [m]
    """
    inner = count - 2
    target = total - shortest - longest
    if not shortest * inner < target < longest * inner:
        raise ModelError(f"random_span_list: a total of {total:g} m cannot be met by {count} spans in "
                         f"[{shortest:g}, {longest:g}] m")
    for _ in range(1000):
        draw = rng.uniform(shortest, longest, inner)
        excess = draw - shortest
        spans = shortest + excess * (target - shortest * inner) / excess.sum()
        spans = np.round(spans, 1)
        spans[np.argmax(spans)] += round(target - spans.sum(), 1)
        if spans.min() >= shortest and spans.max() <= longest:
            out = np.concatenate([[shortest, longest], spans])
            rng.shuffle(out)
            return tuple(float(round(s, 1)) for s in out)
    raise ModelError("random_span_list: no list met the constraints in 1000 draws")


def span_list_bank() -> tuple[tuple[float, ...], ...]:
    """The fixed bank of random span lists the span-list input picks from (paper's summary values)."""
    rng = np.random.default_rng(SPAN_LIST_SEED)
    return tuple(random_span_list(rng, **PAPER_MIXED_SECTION) for _ in range(SPAN_LIST_BANK))


def span_list_of(u: float) -> tuple[float, ...]:
    """The span list the span-list input's value u in [0, 1] stands for. [m]

    Parameters
    ----------
    u : float
        Value of the span-list input, in [0, 1]. [-]
    """
    bank = span_list_bank()
    return bank[min(int(u * len(bank)), len(bank) - 1)]


def apply_inputs(roots: Mapping[str, Any], values: Mapping[str, float]) -> dict[str, Any]:
    """Copies of the roots with each named input set to its value (validated by the models).

    Parameters
    ----------
    roots : mapping
        Root name -> model object.
    values : mapping
        Input name -> value, SI (u in [0, 1) for the span list).

    Returns
    -------
    dict
        Root name -> modified copy.
    """
    out = dict(roots)
    for name, value in values.items():
        root, _, rest = name.partition(".")
        if name == SPAN_LIST:
            cat = out["catenary"]
            lengths = span_list_of(value)
            out["catenary"] = cat.with_layout(dataclasses.replace(cat.layout, span_lengths=lengths,
                                                                   curve_radii=None,
                                                                   label=f"random span list (u = {value:.4f})"))
            continue
        if root == "operation":
            out["operation"] = dataclasses.replace(out["operation"], **{rest: float(value)})
            continue
        out[root] = apply_parameter(out[root], rest.split("."), float(value), name)
    return out
