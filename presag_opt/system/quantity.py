"""Validated physical quantities for the frozen input dataclasses.

A dataclass field declared with :func:`quantity` carries its SI unit, the unit it is shown in, and
its valid range. :func:`validate_fields` checks every such field of an instance (it is called from
``__post_init__``) and raises :class:`~presag_opt.errors.ModelError` naming the field, the value in
its display unit and the valid range. Unit conversion for model files lives here as well, in one
table, so the loader and the command line share it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

from presag_opt.errors import ModelError
from presag_opt.units import KMH

#: Accepted spellings of each dimension's units, with their factor to SI.
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "km": 1e3},
    "force": {"N": 1.0, "kN": 1e3, "MN": 1e6},
    "mass": {"kg": 1.0, "g": 1e-3},
    "mass_per_length": {"kg/m": 1.0, "g/m": 1e-3},
    "stiffness": {"N/m": 1.0, "kN/m": 1e3, "MN/m": 1e6, "N/mm": 1e3},
    "bending_stiffness": {"N*m^2": 1.0, "N·m²": 1.0, "Nm^2": 1.0, "N m^2": 1.0},
    "damping": {"N*s/m": 1.0, "Ns/m": 1.0, "N·s/m": 1.0},
    "ratio": {"-": 1.0, "%": 1e-2, "‰": 1e-3, "permille": 1e-3},
    "frequency": {"1/s": 1.0, "Hz": 1.0},
    "time": {"s": 1.0, "ms": 1e-3},
    "speed": {"m/s": 1.0, "km/h": KMH},
    # F = alpha * v^2: N/(km/h)^2 -> N/(m/s)^2 divides by KMH^2.
    "aero_coefficient": {"N/(m/s)^2": 1.0, "N/(km/h)^2": KMH**-2},
    "count": {"-": 1.0},
}

#: The SI unit of each dimension, used in messages when a value is shown in SI.
SI_UNIT = {dim: next(u for u, f in table.items() if f == 1.0) for dim, table in UNITS.items()}

SOURCES = ("paper", "standard", "secondary-source", "assumed")


def dimension_of(unit: str) -> str | None:
    """Return the dimension a unit spelling belongs to, or None if it is unknown."""
    for dim, table in UNITS.items():
        if unit in table:
            return dim
    return None


def to_si(value: float, unit: str, dimension: str, *, key: str) -> float:
    """Convert ``value`` given in ``unit`` to SI, checking that the unit has the right dimension.

    Parameters
    ----------
    value : float
        Value in ``unit``. [unit]
    unit : str
        Spelling of the unit (a key of ``UNITS[dimension]``).
    dimension : str
        Dimension of the quantity (e.g. ``"length"``).
    key : str
        Name of the input, for the message.

    Raises
    ------
    ModelError
        If the unit is not a known spelling of ``dimension``.
    """
    table = UNITS[dimension]
    if unit not in table:
        raise ModelError(
            f"{key}: unit {unit!r} is not a unit of {dimension.replace('_', ' ')}; "
            f"use one of {', '.join(table)}"
        )
    return float(value) * table[unit]


def quantity(
    dimension: str,
    low: float,
    high: float,
    *,
    display: str | None = None,
    low_open: bool = False,
    high_open: bool = False,
    default: Any = dataclasses.MISSING,
    allow_none: bool = False,
) -> Any:
    """Declare a dataclass field holding an SI value with a unit and a valid range.

    Parameters
    ----------
    dimension : str
        Key of :data:`UNITS` (``"force"``, ``"length"``, ...).
    low, high : float
        Valid range in the display unit. [display unit]
    display : str, optional
        Unit used in messages and ranges; defaults to the SI unit of ``dimension``.
    low_open, high_open : bool
        Whether the range excludes its end points.
    default : optional
        Default value (SI); fields without a default are required.
    allow_none : bool
        Whether ``None`` (not given) is a valid value.
    """
    display = display or SI_UNIT[dimension]
    meta = {
        "quantity": {
            "dimension": dimension,
            "display": display,
            "factor": UNITS[dimension][display],
            "low": low,
            "high": high,
            "low_open": low_open,
            "high_open": high_open,
            "allow_none": allow_none,
        }
    }
    if default is dataclasses.MISSING:
        return dataclasses.field(metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def range_text(spec: dict[str, Any]) -> str:
    """Human-readable valid range of a quantity spec, in its display unit."""
    lo = "(" if spec["low_open"] else "["
    hi = ")" if spec["high_open"] else "]"
    return f"{lo}{spec['low']:g}, {spec['high']:g}{hi} {spec['display']}"


def check_value(name: str, value: float, spec: dict[str, Any]) -> None:
    """Raise ModelError unless ``value`` (SI) is finite and inside the spec's range.

    Parameters
    ----------
    name : str
        Name of the quantity, for the message.
    value : float
        Value in SI units (the unit of the spec's dimension). [SI]
    spec : dict
        The quantity's spec: display unit and factor, range and its open ends.
    """
    shown = value / spec["factor"]
    unit = spec["display"]
    if not math.isfinite(value):
        raise ModelError(f"{name} = {shown} {unit} is not a finite number; valid range {range_text(spec)}")
    low, high = spec["low"], spec["high"]
    too_low = shown <= low if spec["low_open"] else shown < low
    too_high = shown >= high if spec["high_open"] else shown > high
    if too_low or too_high:
        raise ModelError(f"{name} = {shown:g} {unit} is outside the valid range {range_text(spec)}")


def validate_fields(obj: Any, prefix: str = "") -> None:
    """Check every :func:`quantity` field of a dataclass instance (scalars and sequences).

    Parameters
    ----------
    obj : dataclass instance
        The object to check.
    prefix : str
        Prepended to field names in messages (the model-file section, e.g. ``"contact_wire."``).
    """
    for f in dataclasses.fields(obj):
        spec = f.metadata.get("quantity")
        if spec is None:
            continue
        value = getattr(obj, f.name)
        name = prefix + f.name
        if value is None:
            if spec["allow_none"]:
                continue
            raise ModelError(f"{name} is required ({spec['dimension'].replace('_', ' ')} in {range_text(spec)})")
        if isinstance(value, Sequence) and not isinstance(value, str):
            if len(value) == 0:
                raise ModelError(f"{name} is an empty list; give at least one value in {range_text(spec)}")
            for i, item in enumerate(value):
                check_value(f"{name}[{i}]", _as_float(name, item), spec)
        else:
            check_value(name, _as_float(name, value), spec)


def _as_float(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ModelError(f"{name} = {value!r} is not a number")
    return float(value)


DEFAULT_RANGE_SHARE = 0.2
"""Half-width of the default plausible range of a value that declares none: value ± 20 %. [-]"""


def default_range(value: float, spec: dict[str, Any]) -> tuple[float, float] | None:
    """Plausible range of a value without a declared one: ±:data:`DEFAULT_RANGE_SHARE`, inside the valid range.

    Parameters
    ----------
    value : float
        The value, SI. [SI unit of the field]
    spec : dict
        The field's quantity spec (:func:`quantity`); the default range is cut to its valid range.

    Returns
    -------
    tuple of float or None
        (low, high), SI, or None where the range has no width (a value of zero). [SI unit of the field]
    """
    low = value - DEFAULT_RANGE_SHARE * abs(value)
    high = value + DEFAULT_RANGE_SHARE * abs(value)
    valid_low, valid_high = spec["low"] * spec["factor"], spec["high"] * spec["factor"]
    low, high = max(low, valid_low), min(high, valid_high)
    if spec["low_open"] and low <= valid_low:
        low = valid_low + 0.5 * (value - valid_low)
    if spec["high_open"] and high >= valid_high:
        high = valid_high - 0.5 * (valid_high - value)
    return (low, high) if high > low else None
