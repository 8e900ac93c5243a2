"""Study definition: the grid of a validity study, its models and numerics, from a TOML file.

A study file (``models/studies/*.toml``) has these sections (see ``docs/studies.md``)::

    [study]        name, description, catenary, pantograph (built-in names, or paths relative to
                   the study file)
    [grid]         presags (mid-span pre-sag of the longest span), speeds, static_forces,
                   aero_coefficient
    [[parameters]] optional, repeated: name (dotted path, see presag_opt.studies.parameters) and
                   values
    [numerics]     optional: time_step, scheme, hht_alpha, element_length, analysed_spans,
                   lead_in_spans, run_out, cutoff_frequency, numerics ("fixed", or "auto": the
                   element length and time step of each speed, presag_opt.dynamics.numerics)
    [limits]       optional: steady_arm_uplift
    [train]        optional: second_pantograph_at (a second raised pantograph that far behind the
                   leading one; every run then has two pantographs, and the store both statistics)

Every number is a ``{ value, unit, source, note }`` table, read and range-checked by the model-file
loader helpers. :class:`StudyDefinition` checks the whole grid before anything is form-found: every
speed below the contact-wire wave speed of every variant, the analysis window inside the section,
the time step fine enough for the pantograph.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import itertools
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT
from presag_opt.dynamics.integrator import IntegratorSettings
from presag_opt.dynamics.pantograph import Pantograph, load_pantograph
from presag_opt.dynamics.run_plan import plan_run
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.studies.parameters import ParameterSweep, apply_parameter, parameter_spec
from presag_opt.system.catenary import Catenary
from presag_opt.system.components import Provenance
from presag_opt.system.loader import load_catenary, load_model_file, parse_quantity, parse_section, resolve_model_path
from presag_opt.system.quantity import SI_UNIT, check_value, quantity, validate_fields
from presag_opt.units import KMH

STUDY_SECTIONS = ("study", "grid", "parameters", "numerics", "limits", "train")
NUMERICS_KEYS = ("time_step", "scheme", "hht_alpha", "element_length", "analysed_spans", "lead_in_spans",
                 "run_out", "cutoff_frequency", "numerics")


@dataclass(frozen=True, kw_only=True)
class StudyGrid:
    """The grid axes every study has.

    Attributes
    ----------
    presags : tuple of float
        Mid-span pre-sag of the longest span (others in proportion to their length). [m]
    speeds : tuple of float
        Train speeds. [m/s]
    static_forces : tuple of float
        Static uplift forces. [N]
    aero_coefficient : float
        Aerodynamic uplift coefficient α_ae of F_m = F_stat + α_ae v². [N/(m/s)²]
    """

    presags: tuple[float, ...] = quantity("length", 0.0, 300.0, display="mm")
    speeds: tuple[float, ...] = quantity("speed", 0.0, 600.0, display="km/h", low_open=True)
    static_forces: tuple[float, ...] = quantity("force", 0.0, 500.0, low_open=True)
    aero_coefficient: float = quantity("aero_coefficient", 0.0, 0.01, display="N/(km/h)^2", default=0.0)

    def __post_init__(self) -> None:
        for name in ("presags", "speeds", "static_forces"):
            values = getattr(self, name)
            if not isinstance(values, (tuple, list)):
                values = (values,)
            object.__setattr__(self, name, tuple(values))
        validate_fields(self, prefix="grid.")
        for name in ("presags", "speeds", "static_forces"):
            values = getattr(self, name)
            if any(b <= a for a, b in zip(values, values[1:])):
                spec = self.__dataclass_fields__[name].metadata["quantity"]
                shown = [v / spec["factor"] for v in values]
                raise ModelError(f"grid.{name} = {shown} {spec['display']} must be strictly increasing")


@dataclass(frozen=True, kw_only=True)
class StudyTrain:
    """The raised pantographs of every run of a study: one, or two at a spacing.

    The range of the spacing covers the pantographs of one unit (from 5 m) to those of two coupled
    multiple units (up to 500 m); the section must hold the train (checked with the grid).

    Attributes
    ----------
    second_pantograph_at : float or None
        Distance of a second raised pantograph behind the leading one; None for one pantograph. [m]
    """

    second_pantograph_at: float | None = quantity("length", 5.0, 500.0, default=None, allow_none=True)

    def __post_init__(self) -> None:
        validate_fields(self, prefix="train.")

    @property
    def spacings(self) -> tuple[float, ...] | None:
        """Distances between consecutive pantographs, front to rear (None for one). [m]"""
        return None if self.second_pantograph_at is None else (float(self.second_pantograph_at),)


@dataclass(frozen=True, kw_only=True)
class StudyDefinition:
    """A validity study: grid, swept extra parameters, models, numerics and the uplift limit.

    Attributes
    ----------
    name : str
        Display name.
    description : str
        Free text.
    catenary : Catenary
        The catenary; its pre-sag is replaced by each grid value.
    pantograph : Pantograph
        The pantograph (the model of every raised pantograph of the train).
    grid : StudyGrid
        Pre-sag, speed and static-force axes and the aerodynamic coefficient.
    parameters : tuple of ParameterSweep
        Extra swept parameters, each one more grid axis (outermost first).
    settings : SimulationSettings
        Numerics and analysis window of every run.
    uplift_limit : float
        Largest allowed steady-arm uplift. [m]
    train : StudyTrain
        One raised pantograph, or two at a spacing (``train.second_pantograph_at`` may also be swept).
    provenance : dict
        Dotted key -> :class:`~presag_opt.system.components.Provenance` of the study file's numbers.
    """

    name: str
    description: str = ""
    catenary: Catenary
    pantograph: Pantograph
    grid: StudyGrid
    parameters: tuple[ParameterSweep, ...] = ()
    settings: SimulationSettings = field(default_factory=SimulationSettings)
    uplift_limit: float = quantity("length", 1.0, 1000.0, display="mm", default=STEADY_ARM_UPLIFT_LIMIT)
    train: StudyTrain = field(default_factory=StudyTrain)
    provenance: dict[str, Provenance] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "parameters", tuple(self.parameters))
        validate_fields(self)
        names = [p.name for p in self.parameters]
        if len(set(names)) != len(names):
            raise ModelError(f"parameters: {names} name a parameter twice")
        roots = self._roots()
        for sweep in self.parameters:
            spec = parameter_spec(sweep.name, roots)
            for i, value in enumerate(sweep.values):
                check_value(f"parameters.{sweep.name}[{i}]", value, spec)
        for variant in self.variants():
            self._check_variant(variant)

    @property
    def shape(self) -> tuple[int, ...]:
        """Grid shape: extra parameters (in order), pre-sag, speed, static force."""
        g = self.grid
        return (*(len(p.values) for p in self.parameters), len(g.presags), len(g.speeds), len(g.static_forces))

    @property
    def two_pantographs(self) -> bool:
        """Whether the runs have a trailing pantograph (a spacing given or swept)."""
        return self.train.second_pantograph_at is not None or any(p.root == "train" for p in self.parameters)

    def _roots(self) -> dict[str, Any]:
        return {"catenary": self.catenary, "pantograph": self.pantograph, "settings": self.settings,
                "train": self.train}

    @property
    def run_count(self) -> int:
        """Number of simulation runs of the whole grid."""
        return int(functools.reduce(lambda a, b: a * b, self.shape, 1))

    def variants(self) -> list[StudyVariant]:
        """Every combination of the extra parameters, as models and settings to run."""
        combos = itertools.product(*(range(len(p.values)) for p in self.parameters))
        return [self.variant(indices) for indices in combos]

    def variant(self, indices: tuple[int, ...]) -> StudyVariant:
        """The models and settings at one combination of the extra parameters.

        Parameters
        ----------
        indices : tuple of int
            Index into each extra parameter's values, in order. [-]
        """
        roots: dict[str, Any] = self._roots()
        for sweep, i in zip(self.parameters, indices, strict=True):
            parts = sweep.name.split(".")
            roots[parts[0]] = apply_parameter(roots[parts[0]], parts[1:], sweep.values[i], sweep.name)
        return StudyVariant(indices=tuple(indices), **roots)

    def parameter_unit(self, name: str) -> str:
        """SI unit of an extra parameter's values, e.g. ``N`` for ``pantograph.frame.friction``."""
        return SI_UNIT[parameter_spec(name, self._roots())["dimension"]]

    def to_dict(self) -> dict[str, Any]:
        """Plain, JSON-ready description of everything that determines the results (SI units).

        Provenance and other fields excluded from comparison are left out: they do not change a
        result, so they do not change :meth:`digest` either. A train of one pantograph is left out
        too, so that a single-pantograph study keeps the hash it had before trains existed.
        """
        plain = _plain(self)
        if self.train.second_pantograph_at is None:
            del plain["train"]
        return plain

    def to_json(self) -> str:
        """:meth:`to_dict` as canonical JSON (sorted keys, shortest round-trip floats)."""
        return json.dumps(self.to_dict(), sort_keys=True, separators=(",", ":"))

    def digest(self) -> str:
        """SHA-256 of :meth:`to_json`: equal for equal definitions, whatever file they came from."""
        return hashlib.sha256(self.to_json().encode()).hexdigest()

    def _check_variant(self, variant: StudyVariant) -> None:
        """Every speed of the grid is a valid run of this variant (fast: nothing is form-found)."""
        where = "" if not self.parameters else " with " + ", ".join(
            f"{p.name} = {p.values[i]:g}" for p, i in zip(self.parameters, variant.indices)
        )
        for i, speed in enumerate(self.grid.speeds):
            try:
                plan_run(variant.catenary, variant.pantograph, speed=speed, static_force=self.grid.static_forces[0],
                         aero_coefficient=self.grid.aero_coefficient, spacings=variant.train.spacings,
                         settings=variant.settings)
            except ModelError as exc:
                raise ModelError(f"grid.speeds[{i}] = {speed / KMH:g} km/h{where}: {exc}") from None


@dataclass(frozen=True, kw_only=True)
class StudyVariant:
    """Models and settings at one combination of the extra parameters.

    Attributes
    ----------
    indices : tuple of int
        Index into each extra parameter's values. [-]
    catenary : Catenary
        Catenary (pre-sag still the file's; the grid sets it per run).
    pantograph : Pantograph
        Pantograph.
    settings : SimulationSettings
        Numerics.
    train : StudyTrain
        The raised pantographs.
    """

    indices: tuple[int, ...]
    catenary: Catenary
    pantograph: Pantograph
    settings: SimulationSettings
    train: StudyTrain = field(default_factory=StudyTrain)


def load_study(name_or_path: str | Path) -> StudyDefinition:
    """Load a study file (a path, or a built-in name such as ``paper_grid_st98``).

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        File path, or the name of a file in ``models/studies``.

    Returns
    -------
    StudyDefinition

    Raises
    ------
    ModelError
        For any malformed or out-of-range content; the message starts with the file name.
    """
    path = resolve_model_path(name_or_path, "studies")
    return load_model_file(path, "studies", functools.partial(study_from_dict, base=path.parent))


def study_from_dict(data: Mapping[str, Any], base: Path | None = None) -> StudyDefinition:
    """Build a :class:`StudyDefinition` from the parsed content of a study file.

    Parameters
    ----------
    data : mapping
        The sections of the file (see the module notes).
    base : pathlib.Path, optional
        Folder that relative model paths are taken from (the study file's folder).
    """
    unknown = [k for k in data if k not in STUDY_SECTIONS]
    if unknown:
        raise ModelError(f"unknown section [{unknown[0]}]; valid sections: {', '.join(STUDY_SECTIONS)}")
    for required in ("study", "grid"):
        if required not in data:
            raise ModelError(f"missing section [{required}]")
    header = data["study"]
    needed = {"name", "catenary", "pantograph"}
    if not isinstance(header, Mapping) or set(header) - needed - {"description"} or not needed <= set(header):
        raise ModelError("[study] needs 'name', 'catenary' and 'pantograph' (and optionally 'description') "
                         "and nothing else")
    provenance: dict[str, Provenance] = {}
    catenary = load_catenary(_model_path(header["catenary"], base))
    pantograph = load_pantograph(_model_path(header["pantograph"], base))
    grid = parse_section(StudyGrid, _table(data["grid"], "grid"), "grid", provenance)
    settings = _numerics(_table(data.get("numerics", {}), "numerics"), provenance)
    train = parse_section(StudyTrain, _table(data.get("train", {}), "train"), "train", provenance)
    roots = {"catenary": catenary, "pantograph": pantograph, "settings": settings, "train": train}
    parameters = tuple(_parameter(entry, i, roots, provenance) for i, entry in enumerate(_parameter_list(data)))
    limits = dict(_table(data.get("limits", {}), "limits"))
    extra = [k for k in limits if k != "steady_arm_uplift"]
    if extra:
        raise ModelError(f"[limits]: unknown key {extra[0]!r}; valid keys: steady_arm_uplift")
    kwargs: dict[str, Any] = {}
    if "steady_arm_uplift" in limits:
        spec = StudyDefinition.__dataclass_fields__["uplift_limit"].metadata["quantity"]
        kwargs["uplift_limit"] = parse_quantity(limits["steady_arm_uplift"], spec, "limits.steady_arm_uplift",
                                                provenance)
    return StudyDefinition(
        name=str(header["name"]), description=str(header.get("description", "")), catenary=catenary,
        pantograph=pantograph, grid=grid, parameters=parameters, settings=settings, train=train,
        provenance=provenance, **kwargs,
    )


def _numerics(table: Mapping[str, Any], provenance: dict[str, Provenance]) -> SimulationSettings:
    """The [numerics] section on top of the simulator's defaults (HHT-α, α = −0.005, 2 ms, 0.5 m)."""
    unknown = [k for k in table if k not in NUMERICS_KEYS]
    if unknown:
        raise ModelError(f"[numerics]: unknown key {unknown[0]!r}; valid keys: {', '.join(NUMERICS_KEYS)}")
    table = dict(table)
    defaults = SimulationSettings()
    integrator_keys = {k: table.pop(k) for k in ("time_step", "scheme", "hht_alpha") if k in table}
    integrator = parse_section(IntegratorSettings, {**integrator_keys}, "numerics", provenance,
                               **{k: getattr(defaults.integrator, k) for k in ("scheme", "hht_alpha", "time_step")
                                  if k not in integrator_keys})
    static = parse_section(StaticSettings, {k: table.pop(k) for k in ("element_length",) if k in table},
                           "numerics", provenance)
    return parse_section(SimulationSettings, table, "numerics", provenance, integrator=integrator, static=static)


def _parameter_list(data: Mapping[str, Any]) -> list[Any]:
    entries = data.get("parameters", [])
    if not isinstance(entries, list):
        raise ModelError("[[parameters]] must be an array of tables (write each as [[parameters]])")
    return entries


def _parameter(entry: Any, index: int, roots: dict[str, Any], provenance: dict[str, Provenance]) -> ParameterSweep:
    if not isinstance(entry, Mapping) or set(entry) != {"name", "values"}:
        raise ModelError(f"parameters[{index}] needs exactly 'name' (a dotted path) and 'values'")
    name = entry["name"]
    if not isinstance(name, str):
        raise ModelError(f"parameters[{index}].name = {name!r} is not a string")
    spec = parameter_spec(name, roots)
    values = parse_quantity(entry["values"], spec, f"parameters.{name}", provenance)
    return ParameterSweep(name=name, values=values if isinstance(values, tuple) else (values,))


def _table(value: Any, section: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise ModelError(f"[{section}] must be a table")
    return value


def _model_path(name: Any, base: Path | None) -> str | Path:
    """A model named in a study: a path relative to the study file if such a file exists, else as given."""
    if not isinstance(name, str):
        raise ModelError(f"[study]: model name {name!r} must be a string")
    if base is not None and (base / name).is_file():
        return base / name
    return name


def _plain(obj: Any) -> Any:
    """Dataclasses, tuples and numbers as JSON-ready values; fields with ``compare=False`` left out."""
    if dataclasses.is_dataclass(obj):
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj) if f.compare}
    if isinstance(obj, (tuple, list)):
        return [_plain(v) for v in obj]
    return obj
