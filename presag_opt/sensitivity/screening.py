"""The shipped Morris screening of the case-study recommendation, for reports ("what this answer depends on").

A screening of the recommendation costs minutes (about 180 evaluations of the ideal and mixed
sections), too much for every report. The one shipped in ``data/recommendation_morris.json`` was
made by ``benchmarks/bench_sensitivity.py --part recommendation --save DIR`` (the same as
``presag sensitivity --quantity recommendation --method morris --samples 10 --seed 0 --json``) on
the built-in ST 9,8/9,8 models; it holds for them only and says so. Re-run it after changing their
values or ranges.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources

SHIPPED = "recommendation_morris.json"
"""File name of the shipped screening in :mod:`presag_opt.sensitivity`'s ``data`` folder."""


@dataclass(frozen=True, kw_only=True)
class Dependence:
    """The inputs one value of the recommendation depends on most (Morris μ*).

    Attributes
    ----------
    value : str
        The value screened (e.g. ``presag_rel``).
    unit : str
        Its unit.
    rows : tuple of (str, float, float, str)
        Input name, μ* [unit], μ* relative to the largest [-] and the range varied (text), largest first.
    note : str
        What the screening is (method, sample, models) and how to repeat it.
    """

    value: str
    unit: str
    rows: tuple[tuple[str, float, float, str], ...]
    note: str


def recommendation_dependence(top: int = 5, value: str = "presag_rel") -> Dependence | None:
    """The ``top`` inputs of a value of the shipped screening, or None if none is shipped.

    Parameters
    ----------
    top : int
        How many inputs, by μ*. [-]
    value : str
        The screened value, e.g. ``presag_rel``.
    """
    try:
        data = json.loads(resources.files("presag_opt.sensitivity").joinpath("data", SHIPPED).read_text())
    except FileNotFoundError:
        return None
    table = next(t for t in data["indices"] if t["output"] == value)
    ranges = {i["name"]: f"{i['low']:g}–{i['high']:g} {i['unit']}" for i in data["inputs"]}
    rows = tuple((r["input"], r["mu_star"], r["mu_star_relative"], ranges.get(r["input"], ""))
                 for r in table["ranked"][:top])
    note = (f"Morris screening (r = {data['samples']} trajectories, {data['evaluations']} evaluations, seed "
            f"{data['seed']}) of the case study's recommendation on the built-in ST 9,8/9,8 ideal and mixed models over "
            f"{len(data['inputs'])} assumed inputs, each over its declared range (or ±20 %); μ* is the change of "
            f"{value} per change of the input over its whole range. Precomputed for the built-in models; "
            "repeat for changed models with `presag sensitivity --quantity recommendation`.")
    return Dependence(value=value, unit=table["unit"], rows=rows, note=note)
