"""The dropper type a crew cuts: the allowances between a designed dropper length and the wire cut.

The static model's dropper length is the unstretched length between the clamp points on the messenger
(or stitch) wire and on the contact wire. A crew cuts more wire than that: at each end, the wire that
goes into the terminal (a crimp sleeve) and the loop round the clamp's eye. So

    cut length = clamp-to-clamp length + 2 · (terminal allowance + loop allowance),

rounded to the step the crew cuts to (:func:`rounded`: to the nearest multiple of the step, a half
step up; step 0 keeps the exact length). A dropper type is model data (``models/droppers/*.toml``), each number with
its provenance.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.system.components import Provenance
from presag_opt.system.loader import load_model_file, parse_section
from presag_opt.system.quantity import quantity, validate_fields

DEFAULT_DROPPER_TYPE = "crimped_bronze"
"""The built-in dropper type used unless another is given."""

MAX_ROUND_STEP = 0.05
"""Largest cutting step accepted. [m]"""


@dataclass(frozen=True, kw_only=True)
class DropperType:
    """A dropper type's allowances (the same at both ends).

    Attributes
    ----------
    name : str
        What it is.
    terminal_allowance : float
        Wire inside one terminal (crimp sleeve), per end. [m]
    loop_allowance : float
        Wire of one loop round the clamp's eye, per end. [m]
    provenance : dict
        Source of every number, by key.
    """

    name: str
    terminal_allowance: float = quantity("length", 0.0, 500.0, display="mm")
    loop_allowance: float = quantity("length", 0.0, 500.0, display="mm")
    provenance: dict[str, Provenance] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        validate_fields(self)

    @property
    def allowance(self) -> float:
        """Wire added to the clamp-to-clamp length: both ends' terminal and loop. [m]"""
        return 2.0 * (self.terminal_allowance + self.loop_allowance)

    def cut_length(self, clamp_length: float | np.ndarray, step: float = 0.0) -> float | np.ndarray:
        """The length to cut: the clamp-to-clamp length plus :attr:`allowance`, rounded to ``step``.

        Parameters
        ----------
        clamp_length : float or ndarray
            Unstretched length between the clamp points. [m]
        step : float
            The crew's cutting step (0: not rounded). [m]
        """
        return rounded(np.asarray(clamp_length, dtype=float) + self.allowance, step)

    def describe(self) -> str:
        """The allowances in mm with their sources."""
        sources = sorted({p.source for p in self.provenance.values()}) or ["given"]
        return (f"{self.name}: terminal {self.terminal_allowance * 1e3:g} mm + loop {self.loop_allowance * 1e3:g} mm "
                f"per end ({', '.join(sources)})")


def check_step(step: float) -> float:
    """The cutting step, checked (one line naming the option and the valid range).

    Parameters
    ----------
    step : float
        The crew's cutting step. [m]
    """
    if not (isinstance(step, (int, float)) and math.isfinite(step) and 0.0 <= step <= MAX_ROUND_STEP):
        shown = f"{step * 1e3:g}" if isinstance(step, (int, float)) else repr(step)
        raise ModelError(f"--round = {shown} mm is outside the valid range [0, {MAX_ROUND_STEP * 1e3:g}] mm "
                         "(0: cut lengths not rounded)")
    return float(step)


def rounded(length: float | np.ndarray, step: float) -> float | np.ndarray:
    """``length`` to the nearest multiple of ``step``, a half step up (unchanged for step 0). [m]

    Parameters
    ----------
    length : float or ndarray
        Lengths. [m]
    step : float
        The step. [m]
    """
    check_step(step)
    if step == 0.0:
        return length
    # in whole micrometres, so that a 5 mm step lands on exact multiples of 5 mm; a half step rounds up
    micro = round(step * 1e6)
    out = np.floor(np.round(np.asarray(length) * 1e6) / micro + 0.5) * micro * 1e-6
    return float(out) if np.ndim(out) == 0 else out


def dropper_type_from_dict(data: Mapping[str, Any]) -> DropperType:
    """A :class:`DropperType` from a model file's content (one ``[dropper_type]`` table)."""
    unknown = [k for k in data if k != "dropper_type"]
    if unknown or "dropper_type" not in data:
        raise ModelError("a dropper type file holds one [dropper_type] table (name, terminal_allowance, "
                         "loop_allowance)")
    table = dict(data["dropper_type"])
    name = table.pop("name", None)
    if not isinstance(name, str) or not name.strip():
        raise ModelError("[dropper_type]: missing 'name'")
    provenance: dict[str, Provenance] = {}
    parsed = parse_section(DropperType, table, "dropper_type", provenance, name=name)
    return dataclasses.replace(parsed, provenance=provenance)


def load_dropper_type(name_or_path: str | Path = DEFAULT_DROPPER_TYPE) -> DropperType:
    """Read a dropper type (a file, or the name of one in ``models/droppers``).

    Parameters
    ----------
    name_or_path : str or Path
        File path or built-in name (default :data:`DEFAULT_DROPPER_TYPE`).
    """
    return load_model_file(name_or_path, "droppers", dropper_type_from_dict)
