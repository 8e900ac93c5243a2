"""Simulation cases: catenary, pantograph, operating point and analysis window in one model file.

A case file (``models/cases/*.toml``) has three sections::

    [case]        name, description, catenary and pantograph (built-in names, or paths relative to
                  the case file)
    [operation]   static_force, aero_coefficient, speeds, optionally spacings (several pantographs)
    [analysis]    analysed_spans, lead_in_spans, run_out, cutoff_frequency (all optional)

Every number is a ``{ value, unit, source, note }`` table, read and range-checked by the same
loader helpers as the catenary and pantograph files: the ranges are those of
:class:`~presag_opt.dynamics.settings.Operation` and
:class:`~presag_opt.dynamics.settings.SimulationSettings`.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from presag_opt.dynamics.pantograph import Pantograph, load_pantograph
from presag_opt.dynamics.run_plan import RunPlan, plan_run
from presag_opt.dynamics.settings import Operation, SimulationSettings
from presag_opt.dynamics.simulate import SimulationResult, simulate
from presag_opt.errors import ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.system.catenary import Catenary
from presag_opt.system.components import Provenance
from presag_opt.system.loader import (
    load_catenary,
    load_model_file,
    parse_quantity,
    parse_section,
    resolve_model_path,
)
from presag_opt.system.quantity import check_value

CASE_SECTIONS = ("case", "operation", "analysis")
ANALYSIS_KEYS = ("analysed_spans", "lead_in_spans", "run_out", "cutoff_frequency", "numerics")


@dataclass(frozen=True, kw_only=True)
class SimulationCase:
    """A named dynamic-simulation case.

    Attributes
    ----------
    name : str
        Display name.
    description : str
        Free text.
    catenary : Catenary
        The catenary system.
    pantograph : Pantograph
        The pantograph model (the same at every position when there are several).
    operation : Operation
        Static force, aerodynamic coefficient and spacings; its speed is the first of ``speeds``.
    speeds : tuple of float
        The case's speeds. [m/s]
    settings : SimulationSettings
        Defaults with the case's analysis window (analysed spans, lead-in, run-out, cut-off).
    provenance : dict
        Dotted key -> :class:`~presag_opt.system.components.Provenance` of the case's own numbers.
    """

    name: str
    description: str
    catenary: Catenary
    pantograph: Pantograph
    operation: Operation
    speeds: tuple[float, ...]
    settings: SimulationSettings
    provenance: dict[str, Provenance] = field(default_factory=dict, compare=False, repr=False)

    def plan(self, speed: float, settings: SimulationSettings | None = None) -> RunPlan:
        """Check the case at one speed without running it (see :func:`~presag_opt.dynamics.run_plan.plan_run`).

        Parameters
        ----------
        speed : float
            Train speed. [m/s]
        settings : SimulationSettings, optional
            Numerical settings; default :attr:`settings`.
        """
        return plan_run(self.catenary, speed=speed, settings=settings or self.settings, **self._inputs())

    def run(
        self,
        speed: float,
        *,
        state: EquilibriumState | None = None,
        settings: SimulationSettings | None = None,
    ) -> SimulationResult:
        """Simulate the case at one speed.

        Parameters
        ----------
        speed : float
            Train speed. [m/s]
        state : EquilibriumState, optional
            Form-found state of :attr:`catenary` to reuse across speeds.
        settings : SimulationSettings, optional
            Numerical settings; default :attr:`settings`.
        """
        system = state if state is not None else self.catenary
        return simulate(system, speed=speed, settings=settings or self.settings, **self._inputs())

    def _inputs(self) -> dict[str, Any]:
        op = self.operation
        return {
            "pantograph": self.pantograph,
            "static_force": op.static_force,
            "aero_coefficient": op.aero_coefficient,
            "spacings": op.spacings,
        }


def load_case(name_or_path: str | Path) -> SimulationCase:
    """Load a case file (a path, or a built-in name such as ``en50318_2002``).

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        File path, or the name of a file in ``models/cases``.

    Returns
    -------
    SimulationCase

    Raises
    ------
    ModelError
        For any malformed or out-of-range content, in the case file or in the catenary and
        pantograph files it names; the message starts with the file name.
    """
    path = resolve_model_path(name_or_path, "cases")
    return load_model_file(path, "cases", functools.partial(case_from_dict, base=path.parent))


def case_from_dict(data: Mapping[str, Any], base: Path | None = None) -> SimulationCase:
    """Build a :class:`SimulationCase` from the parsed content of a case file.

    Parameters
    ----------
    data : mapping
        Sections ``[case]``, ``[operation]`` and, optionally, ``[analysis]``.
    base : pathlib.Path, optional
        Folder that relative model paths are taken from (the case file's folder).
    """
    unknown = [k for k in data if k not in CASE_SECTIONS]
    if unknown:
        raise ModelError(f"unknown section [{unknown[0]}]; valid sections: {', '.join(CASE_SECTIONS)}")
    for required in CASE_SECTIONS[:2]:
        if required not in data:
            raise ModelError(f"missing section [{required}]")
    header = data["case"]
    required = {"name", "catenary", "pantograph"}
    if not isinstance(header, Mapping) or set(header) - required - {"description"} or not required <= set(header):
        raise ModelError(
            "[case] needs 'name', 'catenary' and 'pantograph' (and optionally 'description') and nothing else"
        )

    provenance: dict[str, Provenance] = {}
    operation, speeds = _parse_operation(data["operation"], provenance)
    analysis = data.get("analysis", {})
    if not isinstance(analysis, Mapping):
        raise ModelError("[analysis] must be a table")
    extra = [k for k in analysis if k not in ANALYSIS_KEYS]
    if extra:
        raise ModelError(f"[analysis]: unknown key {extra[0]!r}; valid keys: {', '.join(ANALYSIS_KEYS)}")
    settings = parse_section(SimulationSettings, analysis, "analysis", provenance)
    return SimulationCase(
        name=str(header["name"]),
        description=str(header.get("description", "")),
        catenary=load_catenary(_model_path(header["catenary"], base)),
        pantograph=load_pantograph(_model_path(header["pantograph"], base)),
        operation=operation,
        speeds=speeds,
        settings=settings,
        provenance=provenance,
    )


def _parse_operation(table: Any, provenance: dict[str, Provenance]) -> tuple[Operation, tuple[float, ...]]:
    """The [operation] section: Operation's fields, with a list of ``speeds`` instead of ``speed``."""
    if not isinstance(table, Mapping):
        raise ModelError("[operation] must be a table")
    table = dict(table)
    if "speeds" not in table:
        raise ModelError("[operation]: missing required key(s) speeds")
    spec = Operation.__dataclass_fields__["speed"].metadata["quantity"]
    value = parse_quantity(table.pop("speeds"), spec, "operation.speeds", provenance)
    speeds = value if isinstance(value, tuple) else (value,)
    for i, speed in enumerate(speeds):
        check_value(f"operation.speeds[{i}]", speed, spec)
    return parse_section(Operation, table, "operation", provenance, speed=speeds[0]), speeds


def _model_path(name: Any, base: Path | None) -> str | Path:
    """A model named in a case: a path relative to the case file if such a file exists, else as given."""
    if not isinstance(name, str):
        raise ModelError(f"[case]: model name {name!r} must be a string")
    if base is not None and (base / name).is_file():
        return base / name
    return name

