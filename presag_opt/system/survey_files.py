"""Survey files: the rows of a CSV, xlsx or TOML survey table, with where each was read.

What a survey's columns mean and how their values are checked is :mod:`presag_opt.system.survey`;
this module reads the files: a CSV with commas or (Excel in a locale whose decimal mark is a comma)
semicolons, the ``survey`` sheet (or the first) of a workbook, the ``[[masts]]`` tables of a TOML file.
A header that lacks a required column or holds an unknown one is refused before any row is read.
"""

from __future__ import annotations

import csv
import tomllib
from pathlib import Path

from presag_opt.errors import ModelError

SUFFIXES = (".csv", ".xlsx", ".toml")
"""File formats a survey is read from."""


class SurveyError(ModelError):
    """A survey table with at least one bad value (the message lists every one, the first in full)."""


def file_rows(path: Path, columns: tuple[str, ...], optional: tuple[str, ...]) -> list[tuple[str, dict]]:
    """The rows of a survey file as ``(where, column -> value)``, ``where`` naming the row for messages.

    Parameters
    ----------
    path : Path
        The file; its suffix chooses the reader (:data:`SUFFIXES`).
    columns, optional : tuple of str
        The required and the optional column names (a header is checked against them).

    Raises
    ------
    SurveyError
        A missing file, an unknown format, an unreadable file or a bad header.
    """
    path = Path(path)
    if not path.is_file():
        raise SurveyError(f"survey file {path} does not exist")
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return _csv_rows(path, columns, optional)
    if suffix == ".xlsx":
        return _xlsx_rows(path, columns, optional)
    if suffix == ".toml":
        return _toml_rows(path)
    raise SurveyError(f"survey file {path}: unknown format {path.suffix!r} (give .csv, .xlsx or .toml)")


def _csv_rows(path: Path, columns: tuple[str, ...], optional: tuple[str, ...]) -> list[tuple[str, dict]]:
    """The rows of a CSV survey; a header without commas but with semicolons (Excel in a locale whose decimal
    mark is a comma) is read with semicolons between the fields."""
    with path.open(newline="", encoding="utf-8-sig") as handle:
        first = handle.readline()
        handle.seek(0)
        delimiter = ";" if ";" in first and "," not in first else ","
        reader = csv.DictReader(handle, delimiter=delimiter)
        _check_header(path.name, reader.fieldnames or [], columns, optional)
        rows = []
        for row in reader:
            if not any((v or "").strip() for v in row.values()):
                continue
            rows.append((f"row {reader.line_num}", {k.strip(): v for k, v in row.items() if k is not None}))
        return rows


def _xlsx_rows(path: Path, columns: tuple[str, ...], optional: tuple[str, ...]) -> list[tuple[str, dict]]:
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
    _check_header(f"{path.name}, sheet {sheet.title!r}", [h for h in header if h], columns, optional)
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


def _check_header(where: str, header: list[str], columns: tuple[str, ...], optional: tuple[str, ...]) -> None:
    names = [h.strip() for h in header]
    missing = [c for c in columns if c not in names]
    if missing and len(names) == 1 and (";" in names[0] or "\t" in names[0]):
        found = "semicolons" if ";" in names[0] else "tabs"
        raise SurveyError(f"survey file {where}: the header is one column holding {found} ({names[0][:60]!r}); "
                          "separate the columns with commas (or semicolons throughout, with none of the header's "
                          "names holding a comma)")
    if missing:
        raise SurveyError(f"survey file {where}: column {missing[0]!r} is missing (columns: {', '.join(columns)}, "
                          f"optionally {', '.join(optional)})")
    unknown = [h for h in names if h not in columns + optional]
    if unknown:
        raise SurveyError(f"survey file {where}: unknown column {unknown[0]!r} (columns: "
                          f"{', '.join(columns + optional)})")
