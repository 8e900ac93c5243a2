"""Extra swept parameters: any numeric model or settings field named by a dotted path.

A study may sweep, besides pre-sag, speed and static force, any field of the catenary, the
pantograph or the simulation settings that is declared as a validated quantity
(:func:`presag_opt.system.quantity.quantity`). The field is named by a dotted path from one of three
roots:

- ``catenary.<field>[.<field>...]``, e.g. ``catenary.droppers.max_spacing`` (dropper spacing),
  ``catenary.damping.ratio`` (structural damping), ``catenary.contact_wire.tension``;
- ``pantograph.<stage name>.<field>`` for a stage, e.g. ``pantograph.frame.friction`` (frame
  friction) or ``pantograph.head.damping``, and ``pantograph.contact.stiffness``;
- ``settings.<field>[.<field>...]``, e.g. ``settings.friction.velocity`` or
  ``settings.integrator.time_step``;
- ``train.second_pantograph_at``, the spacing of a second raised pantograph (every run then has two).

The pre-sag itself (``catenary.presag_rel``) is the study's own grid axis and cannot be an extra
parameter. Values are SI inside; a study file gives them with a unit of the field's dimension.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from presag_opt.errors import ModelError

ROOTS = ("catenary", "pantograph", "settings", "train")
"""Objects a parameter path may start from."""

GRID_FIELDS = {"catenary.presag_rel": "the pre-sag is the study's own grid axis ([grid] presag)"}
"""Paths that are axes of the study grid already, with the reason they cannot be swept again."""


@dataclass(frozen=True, kw_only=True)
class ParameterSweep:
    """One extra swept parameter.

    Attributes
    ----------
    name : str
        Dotted path of the field (see the module notes).
    values : tuple of float
        Values to sweep, SI (the unit of the field). [SI unit of the field]
    """

    name: str
    values: tuple[float, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "values", tuple(float(v) for v in self.values))
        if not self.values:
            raise ModelError(f"parameters.{self.name}: the list of values is empty; give at least one value")
        if len(set(self.values)) != len(self.values):
            raise ModelError(f"parameters.{self.name}: values {list(self.values)} repeat a value")

    @property
    def root(self) -> str:
        """``"catenary"``, ``"pantograph"`` or ``"settings"``."""
        return self.name.split(".", 1)[0]


def parameter_spec(name: str, roots: dict[str, Any]) -> dict[str, Any]:
    """The quantity spec (dimension, display unit, range) of the field a dotted path names.

    Parameters
    ----------
    name : str
        Dotted path, e.g. ``pantograph.frame.friction``.
    roots : dict
        ``{"catenary": Catenary, "pantograph": Pantograph, "settings": SimulationSettings}``.

    Returns
    -------
    dict
        The field's quantity metadata (see :func:`presag_opt.system.quantity.quantity`).

    Raises
    ------
    ModelError
        If the path does not lead to a numeric quantity field; the message lists the valid names at
        the level where the path went wrong.
    """
    if name in GRID_FIELDS:
        raise ModelError(f"parameters: {name!r} cannot be swept: {GRID_FIELDS[name]}")
    parts = name.split(".")
    if parts[0] not in roots or len(parts) < 2:
        raise ModelError(
            f"parameters: unknown parameter {name!r}; a name starts with one of {', '.join(ROOTS)} "
            "followed by a dotted field path (e.g. pantograph.frame.friction)"
        )
    obj = roots[parts[0]]
    for depth, part in enumerate(parts[1:], start=1):
        obj, field = _child(obj, part, name)
        if depth == len(parts) - 1:
            spec = field.metadata.get("quantity") if field is not None else None
            if spec is None:
                raise ModelError(f"parameters: {name!r} is not a numeric quantity and cannot be swept")
            return spec
    raise AssertionError("unreachable: the loop returns at the last part")


def apply_parameter(obj: Any, path: list[str], value: float, name: str) -> Any:
    """Copy of ``obj`` with the field at ``path`` set to ``value`` (validated on construction).

    Parameters
    ----------
    obj : dataclass instance
        The root object (catenary, pantograph or settings).
    path : list of str
        Field path below the root; on a pantograph the first part may be a stage name.
    value : float
        New value, SI. [SI unit of the field]
    name : str
        Full dotted name, for messages.

    Returns
    -------
    dataclass instance
        The modified copy.

    Raises
    ------
    ModelError
        If the path is unknown or the model rejects the value (named as ``parameters.<name>``).
    """
    head, rest = path[0], path[1:]
    child, _ = _child(obj, head, name)
    new_child = value if not rest else apply_parameter(child, rest, value, name)
    try:
        if hasattr(obj, "stages") and child in obj.stages:
            stages = tuple(new_child if s is child else s for s in obj.stages)
            return dataclasses.replace(obj, stages=stages)
        return dataclasses.replace(obj, **{head: new_child})
    except ModelError as exc:
        raise ModelError(f"parameters.{name}: {exc}") from None


def _child(obj: Any, part: str, name: str) -> tuple[Any, dataclasses.Field | None]:
    """The attribute ``part`` of ``obj`` and its dataclass field (a pantograph's stages by name)."""
    if obj is None or not dataclasses.is_dataclass(obj):
        raise ModelError(f"parameters: unknown parameter {name!r}: {part!r} is below a value without fields")
    fields = {f.name: f for f in dataclasses.fields(obj) if f.name not in ("provenance", "stages")}
    stages = {s.name: s for s in getattr(obj, "stages", ())}
    if part in stages:
        return stages[part], None
    if part in fields:
        return getattr(obj, part), fields[part]
    raise ModelError(
        f"parameters: unknown parameter {name!r}: {part!r} is not one of {', '.join([*stages, *fields])}"
    )
