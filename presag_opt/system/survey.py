"""A surveyed line: one row per mast in track order, read from CSV, xlsx, TOML or given through the API.

Columns (the unit is in each name; the order is free):

==========================  ===========================================================================
``mast``                    mast id (unique)
``chainage_m``              position along the line, strictly increasing [m]
``stagger_mm``              signed lateral offset of the contact wire at the mast, + to the left
                            looking towards increasing chainage; within the pantograph's working width
                            setting (default ±400 mm) [mm]
``contact_wire_height_m``   contact-wire height above the rail at the mast [m]
``system_height_m``         messenger wire above the contact wire at the mast [m]
``curve_radius_m``          radius of the span that starts at this mast, + for a left-hand curve,
                            0 or empty for straight track; at least 100 m in size [m]
``steady_arm``              ``pull-off`` (arm in tension) or ``push-off`` (arm in compression)
``section``                 optional: tension-section id (default: one section); a section's masts are
                            consecutive rows
``cant_mm``                 optional: cant of the track at the mast, the outer rail of the curve (of the
                            span that starts or ends there) raised by it, 0 to 200 mm; with cant the
                            stagger and the height are measured as the pantograph sees them, from the
                            axis perpendicular to the track plane (:mod:`presag_opt.system.cant`) [mm]
``stitched``                optional: whether the support carries a stitch wire: ``yes``/``no``,
                            ``true``/``false`` or ``1``/``0`` (any case; empty: not given). The stitch
                            wire is the system file's ``[stitch_wire]``; the end masts of a section are
                            never stitched in the model (a ``yes`` there is read but not modelled)
==========================  ===========================================================================

Without a ``stitched`` value in a section, the system decides (a stitched system file: a stitch wire
at every inner mast); with one, exactly the masts marked ``yes`` are stitched (unmarked masts are not).

Spans between consecutive masts of the same section belong to it; a span between masts of two
sections is an overlap span, which is not modelled (each section is designed on its own, with
balance weights at both ends and a mid-point anchor). Every value is checked as the table is read;
an error names the file, the row, the column, the value, its unit and the valid range, and no
:class:`Survey` is built from a table with an error. SI inside: the table's mm become m.
"""

from __future__ import annotations

import csv
import dataclasses
import itertools
import math
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from presag_opt.errors import ModelError
from presag_opt.system.cant import MAX_CANT, level_frame
from presag_opt.system.catenary import Catenary, SpanLayout
from presag_opt.system.masts import (
    CONTACT_WIRE_HEIGHT_RANGE,
    STAGGER_LIMIT,
    STEADY_ARM_TYPES,
    SYSTEM_HEIGHT_RANGE,
    MastGeometry,
)
from presag_opt.system.survey_stitch import section_stitch_wire, stitched_value

COLUMNS = ("mast", "chainage_m", "stagger_mm", "contact_wire_height_m", "system_height_m", "curve_radius_m",
           "steady_arm")
"""Required columns of a survey table."""

OPTIONAL_COLUMNS = ("section", "stitched", "cant_mm")
"""Optional columns of a survey table."""

DEFAULT_WORKING_WIDTH = 0.40
"""Default half working width of the pantograph: the largest stagger accepted in size. [m]"""

MIN_CURVE_RADIUS = 100.0
"""Smallest curve radius in size. [m]"""

SPAN_LENGTH_RANGE = (5.0, 120.0)
"""Valid span length (chainage difference within a section). [m]"""

DEFAULT_SECTION = "1"
"""Section id of a table without a ``section`` column."""



class SurveyError(ModelError):
    """A survey table with at least one bad value (the message lists every one, the first in full)."""


@dataclass(frozen=True, kw_only=True)
class SurveyMast:
    """One surveyed mast.

    Attributes
    ----------
    mast : str
        Mast id.
    chainage : float
        Position along the line. [m]
    stagger : float
        Signed lateral offset of the contact wire, + to the left. [m]
    contact_wire_height : float
        Contact-wire height above the rail. [m]
    system_height : float
        Messenger wire above the contact wire. [m]
    curve_radius : float
        Radius of the span that starts here, + left-hand, 0 straight. [m]
    steady_arm : str
        ``pull-off`` or ``push-off``.
    section : str
        Tension-section id.
    stitched : bool or None
        Whether the support carries a stitch wire; None: not given (the system decides).
    cant : float
        Cant of the track at the mast, the outer rail of the curve raised by it (0: none); the stagger and
        the height are then in the canted track frame (:mod:`presag_opt.system.cant`). [m]
    row : str
        Where the mast was read (``file, row n``), for messages.
    """

    mast: str
    chainage: float
    stagger: float
    contact_wire_height: float
    system_height: float
    curve_radius: float
    steady_arm: str
    section: str = DEFAULT_SECTION
    stitched: bool | None = None
    cant: float = 0.0
    row: str = ""

    def __post_init__(self) -> None:
        # The working width is a setting of the Survey, which checks it; a mast alone is held to the model's limit.
        errors = _mast_errors(dataclasses.asdict(self), STAGGER_LIMIT, "the model's limit")
        if errors:
            raise SurveyError(errors[0])


@dataclass(frozen=True, kw_only=True)
class SurveySection:
    """The masts of one tension section, in track order.

    Attributes
    ----------
    section : str
        Section id.
    masts : tuple of SurveyMast
        Its masts (spans + 1).
    """

    section: str
    masts: tuple[SurveyMast, ...]

    @property
    def span_lengths(self) -> tuple[float, ...]:
        """Chainage differences between consecutive masts. [m]"""
        return tuple(b.chainage - a.chainage for a, b in zip(self.masts[:-1], self.masts[1:]))

    @property
    def curve_radii(self) -> tuple[float, ...]:
        """Radius of each span (that of its first mast). [m]"""
        return tuple(m.curve_radius for m in self.masts[:-1])

    def cant_directions(self) -> tuple[float, ...]:
        """s_R of every mast: the sign of the curve of the span that starts there, else of the one that ends
        there (+1 left-hand, −1 right-hand, 0 on straight track; :mod:`presag_opt.system.cant`). [-]"""
        radii = self.curve_radii
        out = []
        for i in range(len(self.masts)):
            here = [r for r in (radii[i] if i < len(radii) else 0.0, radii[i - 1] if i else 0.0) if r]
            out.append(math.copysign(1.0, here[0]) if here else 0.0)
        return tuple(out)

    def mast_geometry(self) -> MastGeometry:
        """Per-mast stagger, heights and steady-arm types for the static model, in the level frame: a canted
        mast's surveyed stagger and height (in the track frame) turned by its cant
        (:func:`presag_opt.system.cant.level_frame`; the system height stays vertical)."""
        level = [level_frame(m.stagger, m.contact_wire_height, m.cant, d)
                 for m, d in zip(self.masts, self.cant_directions())]
        for m, (y, _) in zip(self.masts, level):
            if abs(y) > STAGGER_LIMIT:
                raise SurveyError(f"{m.row or f'mast {m.mast!r}'}, column 'cant_mm': {m.cant * 1e3:g} mm of cant puts the "
                                  f"contact wire {y * 1e3:.0f} mm from the vertical through the track centre, beyond the "
                                  f"model's ±{STAGGER_LIMIT * 1e3:g} mm; register the wire towards the outside of the curve")
        return MastGeometry(
            stagger=tuple(y for y, _ in level),
            contact_wire_height=tuple(z for _, z in level),
            system_height=tuple(m.system_height for m in self.masts),
            push_off=tuple(m.steady_arm == "push-off" for m in self.masts),
        )


@dataclass(frozen=True, kw_only=True)
class Survey:
    """A surveyed line: its masts in track order, checked on construction.

    Attributes
    ----------
    masts : tuple of SurveyMast
        The masts, chainage strictly increasing.
    source : str
        The file (or ``<api>``) it was read from.
    working_width : float
        Half working width of the pantograph: the largest stagger accepted in size. [m]
    """

    masts: tuple[SurveyMast, ...]
    source: str = "<api>"
    working_width: float = DEFAULT_WORKING_WIDTH

    def __post_init__(self) -> None:
        if not 0.1 <= self.working_width <= 0.5:
            raise SurveyError(f"working_width = {self.working_width * 1e3:g} mm is outside the valid range [100, 500] mm")
        object.__setattr__(self, "masts", tuple(self.masts))
        errors = _survey_errors(self.masts, self.working_width)
        if errors:
            raise SurveyError(_summary(errors))

    def sections(self) -> tuple[SurveySection, ...]:
        """The tension sections in track order."""
        groups: list[list[SurveyMast]] = []
        for mast in self.masts:
            if groups and groups[-1][0].section == mast.section:
                groups[-1].append(mast)
            else:
                groups.append([mast])
        return tuple(SurveySection(section=g[0].section, masts=tuple(g)) for g in groups)

    def overlap_spans(self) -> tuple[tuple[SurveyMast, SurveyMast], ...]:
        """The spans between two sections (not modelled): (last mast of one, first mast of the next)."""
        sections = self.sections()
        return tuple((a.masts[-1], b.masts[0]) for a, b in itertools.pairwise(sections))

    @property
    def length(self) -> float:
        """First to last chainage. [m]"""
        return self.masts[-1].chainage - self.masts[0].chainage


def section_catenary(base: Catenary, section: SurveySection, label: str = "") -> Catenary:
    """The base system (wires, tensions, droppers, supports, pre-sag rule) on a surveyed section.

    The survey replaces the layout (span lengths, curve radii) and the mast geometry (per-mast
    stagger, heights, steady-arm type); the scalar ``stagger``, ``contact_wire_height`` and
    ``system_height`` become the section's largest stagger, first-mast height and smallest system
    height (labels only: the model uses the per-mast values).

    Parameters
    ----------
    base : Catenary
        System model whose wires, tensions, droppers and supports are used.
    section : SurveySection
        Masts of the section (at least 4: three spans).
    label : str
        Layout label (e.g. the survey file).
    """
    geometry = section.mast_geometry()
    stitch, problem = section_stitch_wire(base, section.masts)
    if problem:
        raise SurveyError(problem)
    layout = SpanLayout(span_lengths=section.span_lengths, curve_radii=section.curve_radii,
                        label=label or f"surveyed section {section.section}")
    return dataclasses.replace(
        base,
        name=f"{base.name} · section {section.section}",
        layout=layout,
        masts=geometry,
        stagger=min(0.5, max(abs(s) for s in geometry.stagger)),
        contact_wire_height=geometry.contact_wire_height[0],
        system_height=min(geometry.system_height),
        stitch_wire=stitch,
    )


# ----- reading --------------------------------------------------------------------------------------


def load_survey(path: str | Path, *, working_width: float = DEFAULT_WORKING_WIDTH) -> Survey:
    """Read a survey table from a ``.csv``, ``.xlsx`` or ``.toml`` file.

    Parameters
    ----------
    path : str or Path
        The file; its suffix chooses the reader.
    working_width : float
        Half working width of the pantograph: the largest stagger accepted in size. [m]

    Raises
    ------
    SurveyError
        A missing file, a missing or unknown column, or any bad value (every one is listed).
    """
    path = Path(path)
    if not path.is_file():
        raise SurveyError(f"survey file {path} does not exist")
    suffix = path.suffix.lower()
    if suffix == ".csv":
        rows = _csv_rows(path)
    elif suffix == ".xlsx":
        rows = _xlsx_rows(path)
    elif suffix == ".toml":
        rows = _toml_rows(path)
    else:
        raise SurveyError(f"survey file {path}: unknown format {path.suffix!r} (give .csv, .xlsx or .toml)")
    return survey_from_rows(rows, source=path.name, working_width=working_width)


def survey_from_rows(rows: Iterable[tuple[str, Mapping[str, object]]], *, source: str = "<api>",
                     working_width: float = DEFAULT_WORKING_WIDTH) -> Survey:
    """A survey from rows of column -> value (table units: m, mm), each with where it was read.

    Parameters
    ----------
    rows : iterable of (str, mapping)
        ``(where, row)``: ``where`` names the row in messages (e.g. ``"row 3"``); ``row`` maps the
        column names of :data:`COLUMNS` (and optionally ``section``) to values (numbers or text).
    source : str
        File name (or ``<api>``) for messages.
    working_width : float
        Half working width of the pantograph: the largest stagger accepted in size. [m]
    """
    errors, masts = [], []
    for where, row in rows:
        label = f"{source}, {where}"
        unknown = sorted(set(row) - set(COLUMNS) - set(OPTIONAL_COLUMNS))
        if unknown:
            errors.append(f"{label}: unknown column {unknown[0]!r} (columns: {', '.join(COLUMNS + OPTIONAL_COLUMNS)})")
            continue
        missing = [c for c in COLUMNS if c not in row]
        if missing:
            errors.append(f"{label}: column {missing[0]!r} is missing (columns: {', '.join(COLUMNS)})")
            continue
        parsed, row_errors = _parse_row(label, row)
        if row_errors:
            errors.extend(row_errors)
            continue
        mast_errors = _mast_errors({**parsed, "row": label}, working_width)
        if mast_errors:
            errors.extend(mast_errors)
            continue
        masts.append(SurveyMast(**parsed, row=label))
    if not masts and not errors:
        errors.append(f"{source}: the survey has no masts")
    if errors:
        # Errors of the whole table (chainage order, sections) only when every row reads cleanly.
        raise SurveyError(_summary(errors))
    return Survey(masts=tuple(masts), source=source, working_width=working_width)


def _csv_rows(path: Path) -> list[tuple[str, dict]]:
    """The rows of a CSV survey; a header without commas but with semicolons (Excel in a locale whose decimal
    mark is a comma) is read with semicolons between the fields."""
    with path.open(newline="", encoding="utf-8-sig") as handle:
        first = handle.readline()
        handle.seek(0)
        delimiter = ";" if ";" in first and "," not in first else ","
        reader = csv.DictReader(handle, delimiter=delimiter)
        _check_header(path.name, reader.fieldnames or [])
        rows = []
        for row in reader:
            if not any((v or "").strip() for v in row.values()):
                continue
            rows.append((f"row {reader.line_num}", {k.strip(): v for k, v in row.items() if k is not None}))
        return rows


def _xlsx_rows(path: Path) -> list[tuple[str, dict]]:
    import openpyxl  # imported here: only an xlsx survey pays for it

    try:
        book = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as exc:  # openpyxl raises several types for files it cannot read
        raise SurveyError(f"survey file {path.name}: not a readable xlsx workbook ({exc})") from exc
    sheet = book["survey"] if "survey" in book.sheetnames else book.worksheets[0]
    lines = list(sheet.iter_rows(values_only=True))
    book.close()
    if not lines:
        raise SurveyError(f"survey file {path.name}: the sheet {sheet.title!r} is empty")
    header = [str(h).strip() if h is not None else "" for h in lines[0]]
    _check_header(f"{path.name}, sheet {sheet.title!r}", [h for h in header if h])
    rows = []
    for number, values in enumerate(lines[1:], start=2):
        if all(v is None or str(v).strip() == "" for v in values):
            continue
        rows.append((f"row {number}", {h: v for h, v in zip(header, values) if h}))
    return rows


def _toml_rows(path: Path) -> list[tuple[str, dict]]:
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise SurveyError(f"survey file {path.name}: not valid TOML ({exc})") from exc
    extra = sorted(set(data) - {"masts"})
    if extra:
        raise SurveyError(f"survey file {path.name}: unknown key {extra[0]!r} (give the masts as [[masts]] tables)")
    masts = data.get("masts")
    if not isinstance(masts, list) or not masts:
        raise SurveyError(f"survey file {path.name}: no [[masts]] tables")
    return [(f"masts[{i}]", row) for i, row in enumerate(masts)]


def _check_header(where: str, header: list[str]) -> None:
    names = [h.strip() for h in header]
    missing = [c for c in COLUMNS if c not in names]
    if missing and len(names) == 1 and (";" in names[0] or "\t" in names[0]):
        found = "semicolons" if ";" in names[0] else "tabs"
        raise SurveyError(f"survey file {where}: the header is one column holding {found} ({names[0][:60]!r}); "
                          "separate the columns with commas (or semicolons throughout, with none of the header's "
                          "names holding a comma)")
    if missing:
        raise SurveyError(f"survey file {where}: column {missing[0]!r} is missing (columns: {', '.join(COLUMNS)}, "
                          f"optionally {', '.join(OPTIONAL_COLUMNS)})")
    unknown = [h for h in names if h not in COLUMNS + OPTIONAL_COLUMNS]
    if unknown:
        raise SurveyError(f"survey file {where}: unknown column {unknown[0]!r} (columns: "
                          f"{', '.join(COLUMNS + OPTIONAL_COLUMNS)})")


# ----- checks ---------------------------------------------------------------------------------------

_NUMBERS = {  # column: (field, factor to SI, unit, may be empty)
    "chainage_m": ("chainage", 1.0, "m", False),
    "stagger_mm": ("stagger", 1e-3, "mm", False),
    "contact_wire_height_m": ("contact_wire_height", 1.0, "m", False),
    "system_height_m": ("system_height", 1.0, "m", False),
    "curve_radius_m": ("curve_radius", 1.0, "m", True),
    "cant_mm": ("cant", 1e-3, "mm", True),
}


def _parse_row(label: str, row: Mapping[str, object]) -> tuple[dict, list[str]]:
    """Column values to SurveyMast fields (SI); the errors of values that are not numbers."""
    out, errors = {}, []
    mast = "" if row["mast"] is None else str(row["mast"]).strip()
    if not mast:
        errors.append(f"{label}, column 'mast': the mast id is empty")
    out["mast"] = mast
    for column, (name, factor, unit, may_be_empty) in _NUMBERS.items():
        value = row.get(column)
        text = "" if value is None else str(value).strip()
        if text == "" and may_be_empty:
            out[name] = 0.0
            continue
        try:
            number = float(text.replace(",", ".") if isinstance(value, str) else value)
        except (TypeError, ValueError):
            errors.append(f"{label}, column {column!r}: {text!r} is not a number in {unit}")
            continue
        if not math.isfinite(number):
            errors.append(f"{label}, column {column!r}: {text!r} is not a finite number in {unit}")
            continue
        out[name] = number * factor
    out["steady_arm"] = "" if row["steady_arm"] is None else str(row["steady_arm"]).strip().lower()
    out["stitched"], stitched_error = stitched_value(label, row.get("stitched"))
    errors += stitched_error
    section = row.get("section")
    out["section"] = DEFAULT_SECTION if section is None or str(section).strip() == "" else _id_text(section)
    return out, errors


def _id_text(value: object) -> str:
    """A section id as text (a spreadsheet's 2.0 is section "2")."""
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value).strip()


def _mast_errors(v: Mapping[str, object], working_width: float,
                 width_name: str = "the pantograph's working width setting") -> list[str]:
    """Range errors of one mast's values (SurveyMast fields, SI), messages in table units."""
    label = v.get("row") or f"mast {v['mast']!r}"
    errors = []
    width_mm = working_width * 1e3
    if not abs(v["stagger"]) <= working_width + 1e-12:
        errors.append(f"{label}, column 'stagger_mm': {v['stagger'] * 1e3:g} mm is outside the valid range "
                      f"[{-width_mm:g}, {width_mm:g}] mm ({width_name})")
    for column, name, (low, high) in (("contact_wire_height_m", "contact_wire_height", CONTACT_WIRE_HEIGHT_RANGE),
                                      ("system_height_m", "system_height", SYSTEM_HEIGHT_RANGE)):
        if not low <= v[name] <= high:
            errors.append(f"{label}, column {column!r}: {v[name]:g} m is outside the valid range [{low:g}, {high:g}] m")
    r = v["curve_radius"]
    if r != 0.0 and not MIN_CURVE_RADIUS <= abs(r) <= 1e6:
        errors.append(f"{label}, column 'curve_radius_m': {r:g} m is outside the valid range: 0 or empty (straight), "
                      f"else {MIN_CURVE_RADIUS:g} to 1e6 m in size (+ left-hand, − right-hand)")
    cant = v.get("cant", 0.0)
    if not 0.0 <= cant <= MAX_CANT:
        errors.append(f"{label}, column 'cant_mm': {cant * 1e3:g} mm is outside the valid range [0, {MAX_CANT * 1e3:g}] mm "
                      "(the outer rail of the curve raised by it)")
    if v["steady_arm"] not in STEADY_ARM_TYPES:
        errors.append(f"{label}, column 'steady_arm': {v['steady_arm']!r} is not a steady-arm type "
                      f"(valid: {', '.join(STEADY_ARM_TYPES)})")
    return errors


def _survey_errors(masts: tuple[SurveyMast, ...], working_width: float) -> list[str]:
    """Errors of the whole table: ids, chainage order and span lengths, sections."""
    errors = [e for m in masts for e in _mast_errors(dataclasses.asdict(m), working_width)]
    seen: dict[str, SurveyMast] = {}
    for m in masts:
        where = m.row or f"mast {m.mast!r}"
        if m.mast in seen:
            errors.append(f"{where}, column 'mast': {m.mast!r} repeats the id of {seen[m.mast].row or 'an earlier mast'}")
        seen[m.mast] = m
    low, high = SPAN_LENGTH_RANGE
    for a, b in itertools.pairwise(masts):
        where = b.row or f"mast {b.mast!r}"
        step = b.chainage - a.chainage
        if step <= 0.0:
            errors.append(f"{where}, column 'chainage_m': {b.chainage:g} m does not increase from {a.chainage:g} m "
                          f"(mast {a.mast!r}); valid: > {a.chainage:g} m")
        elif a.section == b.section and not low <= step <= high:
            errors.append(f"{where}, column 'chainage_m': {b.chainage:g} m makes a span of {step:g} m from mast "
                          f"{a.mast!r}; valid span lengths: [{low:g}, {high:g}] m, i.e. chainage in "
                          f"[{a.chainage + low:g}, {a.chainage + high:g}] m")
    for i, m in enumerate(masts):
        curved = [n.curve_radius for n in (masts[i - 1] if i else None, m) if n is not None and n.section == m.section]
        if m.cant > 0.0 and not any(curved):
            errors.append(f"{m.row or m.mast}, column 'cant_mm': {m.cant * 1e3:g} mm of cant at a mast between straight "
                          "spans; cant belongs to a curve (give the curve_radius_m of the span) or is 0")
    order: list[str] = []
    for m in masts:
        if order and order[-1] == m.section:
            continue
        if m.section in order:
            errors.append(f"{m.row or m.mast}, column 'section': section {m.section!r} starts again after section "
                          f"{order[-1]!r}; a section's masts must be consecutive rows")
        order.append(m.section)
    for section in dict.fromkeys(order):
        group = [m for m in masts if m.section == section]
        if len(group) < 4:
            errors.append(f"{group[0].row or group[0].mast}, column 'section': section {section!r} has {len(group)} "
                          "masts; a tension section needs at least 4 (3 spans)")
    return errors


def _summary(errors: list[str]) -> str:
    """One line: the first error in full, how many more there are and where."""
    if len(errors) == 1:
        return errors[0]
    rest = "; ".join(e.split(":")[0] for e in errors[1:6])
    more = " …" if len(errors) > 6 else ""
    return f"{errors[0]} (and {len(errors) - 1} more: {rest}{more}); nothing was computed"
