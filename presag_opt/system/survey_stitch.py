"""The ``stitched`` column of a survey: which supports carry a stitch wire.

:func:`stitched_value` reads one cell (``yes``/``no``, ``true``/``false``, ``1``/``0`` in any case,
spreadsheet booleans and numbers 1/0; empty: not given); :func:`section_stitch_wire` turns the
marks of a tension section into the system's stitch wire at the marked inner masts
(:attr:`~presag_opt.system.stitch.StitchWire.masts`). Without a mark in a section the system decides
(a stitched system file: every inner mast); with one, exactly the masts marked yes are stitched.
The stitch wire's data (length, tension, mass, EA, stitch droppers) are always the system file's
``[stitch_wire]``: a survey says only where it is fitted. The end masts of a section are never
stitched in the model (their far clamp would lie outside the section).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

from presag_opt.system.catenary import Catenary
from presag_opt.system.stitch import StitchWire

STITCHED_VALUES = {"yes": True, "true": True, "1": True, "no": False, "false": False, "0": False}
"""Accepted ``stitched`` values (any case) and their meaning."""


def stitched_value(label: str, value: object) -> tuple[bool | None, list[str]]:
    """One ``stitched`` cell as True, False or None (empty), and its error if it is none of these.

    Parameters
    ----------
    label : str
        Where the cell was read (``file, row n``), for the message.
    value : object
        The cell: text, a spreadsheet boolean or number, or None.

    Returns
    -------
    value : bool or None
        The mark; None when the cell is empty or bad.
    errors : list of str
        One line naming file, row, column, value and the valid values; empty when the cell is good.
    """
    if value is None or (isinstance(value, str) and value.strip() == ""):
        return None, []
    if isinstance(value, bool):
        return value, []
    if isinstance(value, (int, float)) and float(value) in (0.0, 1.0):
        text = str(int(value))
    else:
        text = str(value).strip()
    if text.lower() in STITCHED_VALUES:
        return STITCHED_VALUES[text.lower()], []
    return None, [f"{label}, column 'stitched': {text!r} is not a valid value (valid: yes, no, true, false, 1, 0; "
                  "empty: not given)"]


def section_stitch_wire(base: Catenary, masts: Sequence[Any]) -> tuple[StitchWire | None, str]:
    """The base system's stitch wire at the masts of a section marked stitched.

    Parameters
    ----------
    base : Catenary
        The system (its ``stitch_wire``, or None).
    masts : sequence of SurveyMast
        The section's masts in track order (their ``stitched``, ``mast`` and ``row``).

    Returns
    -------
    stitch_wire : StitchWire or None
        The section's stitch wire: the system's when no mast is marked, the system's at the marked
        inner masts otherwise, None when no inner mast is marked yes.
    problem : str
        Empty, or one line: a mast marked stitched while the system has no stitch-wire data.
    """
    if all(m.stitched is None for m in masts):
        return base.stitch_wire, ""
    marked = [m for m in masts if m.stitched]
    if marked and base.stitch_wire is None:
        first = marked[0]
        where = first.row or f"mast {first.mast!r}"
        return None, (f"{where}, column 'stitched': mast {first.mast!r} is stitched but the system {base.name!r} has "
                      "no stitch-wire data (give a --system file with a [stitch_wire] section, or mark the mast no)")
    inner = tuple(i for i, m in enumerate(masts[1:-1], start=1) if m.stitched)
    if not inner:
        return None, ""
    return dataclasses.replace(base.stitch_wire, masts=inner), ""
