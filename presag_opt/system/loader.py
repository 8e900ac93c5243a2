"""Reading model files (TOML) into the validated dataclasses.

Every number in a model file is a table ``{ value = ..., unit = "...", source = "...", note = "..." }``
where ``source`` is one of ``paper``, ``standard``, ``secondary-source`` or ``assumed``. A single value
may carry its plausible range and the reason for it, ``range = [low, high], range_note = "..."`` in
the value's unit (what the global sensitivity analysis varies it over; see docs/assumptions.md §7). Unknown
sections and keys, missing units, unknown units, unknown sources and out-of-range values are errors
that name the file, the key, the value, its unit and the valid range.
"""

from __future__ import annotations

import dataclasses
import tomllib
from collections.abc import Callable, Mapping
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

from presag_opt.errors import ModelError
from presag_opt.system.catenary import Catenary, SpanLayout
from presag_opt.system.components import Damping, Droppers, PinSupport, Provenance, SpringSupport, SteadyArm, Wire
from presag_opt.system.quantity import SOURCES, check_value, range_text, to_si
from presag_opt.system.stitch import StitchWire

T = TypeVar("T")

BUILTIN_PACKAGE = "presag_opt.builtin_models"


def models_root() -> Any:
    """Folder of the built-in model files.

    An installed package carries them as ``presag_opt.builtin_models``; a source checkout (editable
    install) reads the repository's ``models/`` folder directly.
    """
    try:
        return resources.files(BUILTIN_PACKAGE)
    except ModuleNotFoundError:
        return Path(__file__).resolve().parents[2] / "models"


def builtin_model_names(kind: str = "catenaries") -> list[str]:
    """Names of the model files shipped with the package, e.g. ``st_9.8_ideal``."""
    folder = models_root().joinpath(kind)
    return sorted(p.name[: -len(".toml")] for p in folder.iterdir() if p.name.endswith(".toml"))


def resolve_model_path(name_or_path: str | Path, kind: str = "catenaries") -> Path:
    """Return the file for a path, or for the name of a built-in model of the given kind.

    Raises
    ------
    ModelError
        If neither a file nor a built-in model of that name exists.
    """
    if not isinstance(name_or_path, (str, Path)):
        raise ModelError(
            f"model = {name_or_path!r} ({type(name_or_path).__name__}): give a model file path or the name of a "
            f"built-in {_singular(kind)} model ({', '.join(builtin_model_names(kind))})"
        )
    path = Path(name_or_path)
    if path.is_file():
        return path
    candidate = models_root().joinpath(kind).joinpath(f"{name_or_path}.toml")
    if candidate.is_file():
        return Path(str(candidate))
    raise ModelError(
        f"model {str(name_or_path)!r} is neither a file nor a built-in {_singular(kind)} "
        f"model ({', '.join(builtin_model_names(kind))})"
    )


def _singular(kind: str) -> str:
    """``catenaries`` -> ``catenary``, ``cases`` -> ``case``."""
    return {"catenaries": "catenary", "studies": "study"}.get(kind, kind.removesuffix("s"))


def read_toml(path: Path) -> dict[str, Any]:
    """Parse a TOML file, turning syntax errors into a ModelError naming the file."""
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(f"{path.name}: not valid TOML ({exc})") from None
    except UnicodeDecodeError as exc:
        raise ModelError(f"{path.name}: not UTF-8 text (byte {exc.start}); save the model file as UTF-8") from None
    except OSError as exc:
        raise ModelError(f"{path.name}: cannot be read ({exc.strerror})") from None


def parse_quantity(entry: Any, spec: dict[str, Any], key: str, provenance: dict[str, Provenance]) -> Any:
    """Turn one ``{value, unit, source, note}`` table into an SI value (or tuple of values)."""
    if not isinstance(entry, Mapping):
        raise ModelError(
            f"{key} = {entry!r}: write it as {{ value = ..., unit = \"{spec['display']}\", source = \"...\" }} "
            f"(valid range {range_text(spec)})"
        )
    unknown = set(entry) - set(ENTRY_KEYS)
    if unknown:
        raise ModelError(f"{key}: unknown key(s) {', '.join(sorted(unknown))}; valid keys: {', '.join(ENTRY_KEYS)}")
    for required in ("value", "unit", "source"):
        if required not in entry:
            raise ModelError(f"{key}: missing '{required}' (valid range {range_text(spec)})")
    source = entry["source"]
    if source not in SOURCES:
        raise ModelError(f"{key}: source {source!r} is not one of {', '.join(SOURCES)}")
    value = entry["value"]
    unit = entry["unit"]
    if isinstance(value, list):
        parsed: Any = tuple(_number(f"{key}[{i}]", v, unit, spec, key) for i, v in enumerate(value))
    else:
        parsed = _number(key, value, unit, spec, key)
    plausible = _parse_range(entry, parsed, spec, key)
    provenance[key] = Provenance(source=source, note=str(entry.get("note", "")), range=plausible,
                                 range_note=str(entry.get("range_note", "")))
    return parsed


ENTRY_KEYS = ("value", "unit", "source", "note", "range", "range_note")
"""Keys of one number's table in a model file."""


def _parse_range(entry: Mapping[str, Any], value: Any, spec: dict[str, Any], key: str) -> tuple[float, float] | None:
    """The plausible range ``range = [low, high]`` declared beside a value, SI, or None.

    The range is in the value's unit, must hold the value, lie inside the field's valid range and
    carry its reason (``range_note``).
    """
    if "range" not in entry:
        if "range_note" in entry:
            raise ModelError(f"{key}: range_note is given without a range; add range = [low, high] in {entry['unit']}")
        return None
    unit = entry["unit"]
    bounds = entry["range"]
    shown = entry["value"]
    if isinstance(value, tuple):
        raise ModelError(f"{key}: a range can only be declared beside a single value, not a list of {len(value)}")
    if (not isinstance(bounds, list) or len(bounds) != 2
            or any(isinstance(b, bool) or not isinstance(b, (int, float)) for b in bounds)):
        raise ModelError(f"{key}: range = {bounds!r} must be two numbers [low, high] in {unit} "
                         f"(valid range {range_text(spec)})")
    low, high = (to_si(b, unit, spec["dimension"], key=key) for b in bounds)
    for end, si in zip(bounds, (low, high)):
        try:
            check_value(f"{key}.range", si, spec)
        except ModelError:
            raise ModelError(f"{key}: range end {end:g} {unit} is outside the valid range {range_text(spec)}") from None
    if not low < high:
        raise ModelError(f"{key}: range = [{bounds[0]:g}, {bounds[1]:g}] {unit} must have low < high")
    if not low <= value <= high:
        raise ModelError(f"{key}: range = [{bounds[0]:g}, {bounds[1]:g}] {unit} does not contain the value "
                         f"{shown:g} {unit}")
    if not str(entry.get("range_note", "")).strip():
        raise ModelError(f"{key}: range = [{bounds[0]:g}, {bounds[1]:g}] {unit} needs range_note, the reason for it")
    return (low, high)


def _number(name: str, value: Any, unit: str, spec: dict[str, Any], key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ModelError(f"{name} = {value!r} {unit} is not a number (valid range {range_text(spec)})")
    return to_si(value, unit, spec["dimension"], key=key)


def parse_section(cls: type[T], table: Any, section: str, provenance: dict[str, Provenance], **extra: Any) -> T:
    """Build dataclass ``cls`` from a model-file table, checking keys, units and ranges.

    Parameters
    ----------
    cls : type
        A frozen dataclass whose numeric fields are declared with
        :func:`presag_opt.system.quantity.quantity`.
    table : mapping
        The TOML table.
    section : str
        Its name in the file, used in messages.
    provenance : dict
        Filled with the provenance of every quantity read.
    extra
        Further keyword arguments for ``cls``.
    """
    if not isinstance(table, Mapping):
        raise ModelError(f"[{section}] must be a table")
    fields = {f.name: f for f in dataclasses.fields(cls) if f.name not in extra and f.name != "provenance"}
    unknown = [k for k in table if k not in fields]
    if unknown:
        raise ModelError(
            f"[{section}]: unknown key {unknown[0]!r}; valid keys: {', '.join(k for k in fields)}"
        )
    kwargs: dict[str, Any] = dict(extra)
    for name, value in table.items():
        spec = fields[name].metadata.get("quantity")
        key = f"{section}.{name}"
        kwargs[name] = parse_quantity(value, spec, key, provenance) if spec else value
    try:
        return cls(**kwargs)
    except ModelError as exc:
        raise ModelError(_prefixed(str(exc), section)) from None
    except TypeError as exc:
        missing = [f.name for f in fields.values() if f.name not in kwargs and _required(f)]
        if missing:
            raise ModelError(f"[{section}]: missing required key(s) {', '.join(missing)}") from None
        raise ModelError(f"[{section}]: {exc}") from None


def _required(f: dataclasses.Field) -> bool:
    return f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING


def _prefixed(message: str, section: str) -> str:
    head = message.split(" ", 1)[0]
    if head.startswith(section) or head.startswith("["):
        return message
    return f"{section}.{message}" if not message.startswith(section) else message


def parse_union(options: tuple[type, ...], table: Any, section: str, provenance: dict[str, Provenance]) -> Any:
    """Build one of several dataclasses chosen by the table's ``type`` key."""
    by_type = {next(f for f in dataclasses.fields(o) if f.name == "type").default: o for o in options}
    if not isinstance(table, Mapping) or "type" not in table:
        raise ModelError(f"[{section}]: missing 'type' (one of {', '.join(repr(t) for t in by_type)})")
    kind = table["type"]
    if kind not in by_type:
        raise ModelError(f"[{section}].type = {kind!r} is not one of {', '.join(repr(t) for t in by_type)}")
    rest = {k: v for k, v in table.items() if k != "type"}
    return parse_section(by_type[kind], rest, section, provenance)


CATENARY_SECTIONS = (
    "system",
    "layout",
    "geometry",
    "contact_wire",
    "messenger_wire",
    "droppers",
    "contact_wire_support",
    "messenger_wire_support",
    "damping",
    "stitch_wire",
)


def load_model_file(name_or_path: str | Path, kind: str, build: Callable[[Mapping[str, Any]], T]) -> T:
    """Read a model file of a kind (``catenaries``, ``pantographs``, ``cases``) and build its object.

    Parameters
    ----------
    name_or_path : str or Path
        File path, or the name of a built-in model of that kind.
    kind : str
        Sub-folder of the built-in models.
    build : callable
        Turns the parsed TOML content into the validated object.

    Raises
    ------
    ModelError
        For any malformed or out-of-range content; the message starts with the file name.
    """
    path = resolve_model_path(name_or_path, kind)
    data = read_toml(path)
    try:
        return build(data)
    except ModelError as exc:
        raise ModelError(f"{path.name}: {exc}") from None


def load_catenary(name_or_path: str | Path) -> Catenary:
    """Load a catenary model file (a path, or the name of a built-in model such as ``st_9.8_ideal``).

    Raises
    ------
    ModelError
        For any malformed or out-of-range content; the message starts with the file name.
    """
    return load_model_file(name_or_path, "catenaries", catenary_from_dict)


def catenary_from_dict(data: Mapping[str, Any]) -> Catenary:
    """Build a :class:`Catenary` from the parsed content of a model file."""
    unknown = [k for k in data if k not in CATENARY_SECTIONS]
    if unknown:
        raise ModelError(f"unknown section [{unknown[0]}]; valid sections: {', '.join(CATENARY_SECTIONS)}")
    for required in CATENARY_SECTIONS[:-2]:
        if required not in data:
            raise ModelError(f"missing section [{required}]")
    provenance: dict[str, Provenance] = {}

    system = data["system"]
    if not isinstance(system, Mapping) or set(system) - {"name", "description"} or "name" not in system:
        raise ModelError("[system] needs 'name' (and optionally 'description') and nothing else")

    layout = _parse_layout(data["layout"], provenance)
    geometry = dict(data["geometry"])
    presag_entry = geometry.pop("presag", None)
    presag_rel = _parse_presag(presag_entry, layout, provenance)

    kwargs: dict[str, Any] = {
        "name": str(system["name"]),
        "layout": layout,
        "contact_wire": parse_section(Wire, data["contact_wire"], "contact_wire", provenance),
        "messenger_wire": parse_section(Wire, data["messenger_wire"], "messenger_wire", provenance),
        "droppers": parse_section(Droppers, data["droppers"], "droppers", provenance),
        "contact_wire_support": parse_union(
            (SteadyArm, SpringSupport), data["contact_wire_support"], "contact_wire_support", provenance
        ),
        "messenger_wire_support": parse_union(
            (PinSupport, SpringSupport), data["messenger_wire_support"], "messenger_wire_support", provenance
        ),
        "damping": parse_section(Damping, data["damping"], "damping", provenance) if "damping" in data else None,
        "stitch_wire": (parse_section(StitchWire, data["stitch_wire"], "stitch_wire", provenance)
                        if "stitch_wire" in data else None),
    }
    geometry_keys = ("contact_wire_height", "system_height", "stagger")
    extra_geometry = [k for k in geometry if k not in geometry_keys]
    if extra_geometry:
        raise ModelError(
            f"[geometry]: unknown key {extra_geometry[0]!r}; valid keys: {', '.join(geometry_keys)}, presag"
        )
    fields = {f.name: f for f in dataclasses.fields(Catenary)}
    for key, value in geometry.items():
        kwargs[key] = parse_quantity(value, fields[key].metadata["quantity"], f"geometry.{key}", provenance)
    kwargs["presag_rel"] = presag_rel
    try:
        return Catenary(**kwargs, provenance=provenance)
    except ModelError as exc:
        message = str(exc)
        if message.split(" ", 1)[0] in geometry_keys:
            message = "geometry." + message
        elif message.startswith("presag_rel"):
            message = "geometry.presag" + message[len("presag_rel") :]
        raise ModelError(message) from None
    except TypeError:
        missing = [k for k in geometry_keys[:2] if k not in kwargs]
        raise ModelError(f"[geometry]: missing required key(s) {', '.join(missing)}") from None


def _parse_layout(table: Any, provenance: dict[str, Provenance]) -> SpanLayout:
    if not isinstance(table, Mapping):
        raise ModelError("[layout] must be a table")
    table = dict(table)
    count_entry = table.pop("span_count", None)
    if count_entry is None:
        return parse_section(SpanLayout, table, "layout", provenance)
    count_spec = {"dimension": "count", "display": "-", "factor": 1.0, "low": 3, "high": 200,
                  "low_open": False, "high_open": False, "allow_none": False}
    count = parse_quantity(count_entry, count_spec, "layout.span_count", provenance)
    if count != int(count) or not 3 <= count <= 200:
        raise ModelError(f"layout.span_count = {count:g} - is outside the valid range: a whole number in [3, 200]")
    repeated = dict(table)
    for key in ("span_lengths", "curve_radii"):
        entry = repeated.get(key)
        if isinstance(entry, Mapping) and isinstance(entry.get("value"), list):
            if len(entry["value"]) != 1:
                raise ModelError(
                    f"layout.span_count is given, so layout.{key} must hold one value (it holds {len(entry['value'])})"
                )
            repeated[key] = {**entry, "value": entry["value"] * int(count)}
    return parse_section(SpanLayout, repeated, "layout", provenance)


def _parse_presag(entry: Any, layout: SpanLayout, provenance: dict[str, Provenance]) -> float:
    """Pre-sag in mm (on the longest span, others in proportion) or as a ratio (‰)."""
    if entry is None:
        return 0.0
    if not isinstance(entry, Mapping) or "unit" not in entry:
        raise ModelError("geometry.presag: write it as { value = 30, unit = \"mm\", source = \"...\" } or in ‰")
    unit = entry["unit"]
    longest = max(layout.span_lengths)
    if unit in ("mm", "m", "cm"):
        spec = {"dimension": "length", "display": "mm", "factor": 1e-3, "low": 0.0, "high": 5e-3 * longest * 1e3,
                "low_open": False, "high_open": False, "allow_none": False}
        presag = parse_quantity(entry, spec, "geometry.presag", provenance)
        return presag / longest
    spec = {"dimension": "ratio", "display": "‰", "factor": 1e-3, "low": 0.0, "high": 5.0,
            "low_open": False, "high_open": False, "allow_none": False}
    return parse_quantity(entry, spec, "geometry.presag", provenance)


@dataclasses.dataclass(frozen=True, kw_only=True)
class ModelEntry:
    """One number of a model file as written there, with its provenance.

    Attributes
    ----------
    file : str
        File name.
    key : str
        Dotted key, e.g. ``contact_wire.tension`` or ``stages.frame.mass``.
    value : float or tuple of float
        The value as written (in ``unit``, not converted). [``unit``]
    unit : str
        Unit as written.
    source : str
        ``paper``, ``standard``, ``secondary-source`` or ``assumed``.
    note : str
        Where the number comes from, or why it was chosen.
    range : tuple of float or None
        Plausible range as written (in ``unit``), or None if none is declared. [``unit``]
    range_note : str
        Why that range.
    """

    file: str
    key: str
    value: float | tuple[float, ...]
    unit: str
    source: str
    note: str = ""
    range: tuple[float, float] | None = None
    range_note: str = ""


def model_entries(name_or_path: str | Path, kind: str = "catenaries") -> tuple[ModelEntry, ...]:
    """Every ``{value, unit, source, note}`` number of a model file, in file order, as written.

    Text settings (names, support types) are left out. The file is only read, not validated: load
    it with its loader for that.

    Parameters
    ----------
    name_or_path : str or Path
        File path, or the name of a built-in model of that kind.
    kind : str
        ``catenaries``, ``pantographs``, ``cases`` or ``studies``.
    """
    path = resolve_model_path(name_or_path, kind)
    out: list[ModelEntry] = []

    def walk(node: Any, key: str) -> None:
        if isinstance(node, Mapping) and "value" in node and "unit" in node:
            value = node["value"]
            out.append(ModelEntry(file=path.name, key=key, value=tuple(value) if isinstance(value, list) else value,
                                  unit=str(node["unit"]), source=str(node.get("source", "")),
                                  note=str(node.get("note", "")),
                                  range=tuple(node["range"]) if isinstance(node.get("range"), list) else None,
                                  range_note=str(node.get("range_note", ""))))
        elif isinstance(node, Mapping):
            for name, child in node.items():
                walk(child, f"{key}.{name}" if key else str(name))
        elif isinstance(node, list) and all(isinstance(item, Mapping) for item in node):
            for i, child in enumerate(node):
                walk(child, f"{key}.{child['name']}" if isinstance(child.get("name"), str) else f"{key}[{i}]")

    walk(read_toml(path), "")
    return tuple(out)
