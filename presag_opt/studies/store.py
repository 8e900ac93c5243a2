"""On-disk state of a study: finished units, and the netCDF store assembled from them.

Beside the store ``PATH`` lies the units directory ``PATH.units/``: a manifest ``study.json`` (the
definition and its hash) and one JSON file per finished unit. Every file is written atomically: to
a temporary file in the same directory, flushed and fsynced, then renamed over its final name with
:func:`os.replace` and the directory fsynced. A killed study therefore leaves only complete files
(and perhaps a stray temporary, removed on the next start), and a re-run skips every unit whose file
exists.

The store is an xarray Dataset written with the h5netcdf engine, only by the parent process, and
only after every unit is finished. It is assembled from the unit files by their indices, not in the
order they finished, and holds no timing data: the same definition gives the same dataset whatever
the worker count or scheduler. A store or units directory made by a different definition is refused
before anything is written.
"""

from __future__ import annotations

import json
import os
import tempfile
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from presag_opt.errors import ModelError
from presag_opt.studies.definition import StudyDefinition
from presag_opt.studies.work import UnitResult, WorkUnit

ENGINE = "h5netcdf"
MANIFEST = "study.json"
TEMPORARY_SUFFIX = ".partial"

VARIABLES = {
    "F_m": ("mean_force", "N", "mean contact force (front pantograph)"),
    "sigma": ("std_force", "N", "standard deviation of the contact force"),
    "stat_max": ("statistical_max", "N", "statistical maximum F_m + 3 sigma"),
    "stat_min": ("statistical_min", "N", "statistical minimum F_m - 3 sigma"),
    "max_force": ("max_force", "N", "actual maximum of the filtered contact force"),
    "min_force": ("min_force", "N", "actual minimum of the filtered contact force"),
    "loss_of_contact": ("loss_of_contact", "1", "share of the analysis window without contact"),
    "uplift_max": ("uplift_max", "m", "maximum steady-arm uplift"),
    "presag_delta_e": ("presag_delta_e", "m", "quasi-static pre-sag F_m * delta_e at the nominal F_m"),
    "presag_mid_mast": ("presag_mid_mast", "m", "quasi-static pre-sag F_m * (e_mid - e_mast) at the nominal F_m"),
}
"""Dataset variable -> (UnitResult field, unit, description); all per run."""


def units_directory(store: Path) -> Path:
    """The units directory beside a store: ``PATH.units``."""
    return store.with_name(store.name + ".units")


def package_version() -> str:
    """Installed version of presag-opt (``unknown`` when run from an uninstalled checkout)."""
    try:
        return metadata.version("presag-opt")
    except metadata.PackageNotFoundError:
        return "unknown"


def check_store(store: Path, definition: StudyDefinition) -> None:
    """Refuse a store or units directory written by another definition (nothing is changed).

    Parameters
    ----------
    store : pathlib.Path
        The netCDF store.
    definition : StudyDefinition
        The study about to run.

    Raises
    ------
    ModelError
        One line naming the path and both hashes, if either was made by a different definition or
        is not a study store at all.
    """
    digest = definition.digest()
    if store.exists():
        found = _store_digest(store)
        if found != digest:
            raise ModelError(
                f"{store}: written by a different study definition (hash {found[:12]}, this study {digest[:12]}); "
                "give another output path or remove it"
            )
    manifest = units_directory(store) / MANIFEST
    if manifest.exists():
        try:
            found = json.loads(manifest.read_text())["study_hash"]
        except (OSError, ValueError, KeyError):
            raise ModelError(f"{manifest}: not a study manifest; give another output path") from None
        if found != digest:
            raise ModelError(
                f"{units_directory(store)}: units of a different study definition (hash {found[:12]}, this study "
                f"{digest[:12]}); give another output path or remove it"
            )


def prepare_units(store: Path, definition: StudyDefinition) -> Path:
    """Create the units directory and its manifest if missing; remove stray temporary files.

    Temporaries are left only by a study killed while writing: those of units in the units
    directory, and those of the store beside it.

    Call after :func:`check_store`. Returns the units directory.
    """
    folder = units_directory(store)
    folder.mkdir(parents=True, exist_ok=True)
    for stray in [*folder.glob(f"*{TEMPORARY_SUFFIX}"), *store.parent.glob(f"{store.name}.*{TEMPORARY_SUFFIX}")]:
        stray.unlink()
    manifest = folder / MANIFEST
    if not manifest.exists():
        content = {"study_hash": definition.digest(), "study_definition": definition.to_dict()}
        write_atomic(manifest, json.dumps(content, sort_keys=True).encode())
    return folder


def finished_units(folder: Path) -> set[str]:
    """Keys of the units whose result file exists."""
    return {p.stem for p in folder.glob("*.json") if p.name != MANIFEST}


def save_unit(folder: Path, result: UnitResult) -> None:
    """Write one unit's result atomically."""
    write_atomic(folder / f"{result.unit.key}.json", json.dumps(result.to_dict(), sort_keys=True).encode())


def load_unit(folder: Path, unit: WorkUnit) -> UnitResult:
    """Read one unit's result."""
    return UnitResult.from_dict(json.loads((folder / f"{unit.key}.json").read_text()))


def write_atomic(path: Path, content: bytes) -> None:
    """Write ``content`` to ``path`` so that the file is either absent, old, or complete.

    Parameters
    ----------
    path : pathlib.Path
        Final file name.
    content : bytes
        The file content.
    """
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=TEMPORARY_SUFFIX)
    try:
        with os.fdopen(handle, "wb") as fh:
            fh.write(content)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    _fsync_directory(path.parent)


def assemble(definition: StudyDefinition, results: list[UnitResult]) -> xr.Dataset:
    """Build the study dataset from unit results, placing each by its indices.

    Parameters
    ----------
    definition : StudyDefinition
        The study.
    results : list of UnitResult
        One per unit, in any order.

    Returns
    -------
    xarray.Dataset
        Dims: the extra parameters (by their dotted names), ``presag`` [m], ``speed`` [m/s],
        ``static_force`` [N]; the variables of :data:`VARIABLES` plus ``sigma_over_F_m`` [-],
        ``beta`` [-], ``failed`` and ``failure`` per run, ``rule_failure`` per unit and
        ``F_m_nominal`` [N]; the attributes described in ``docs/studies.md``.
    """
    grid = definition.grid
    dims = (*(p.name for p in definition.parameters), "presag", "speed", "static_force")
    shape = definition.shape
    arrays = {name: np.full(shape, np.nan) for name in VARIABLES}
    failure = np.full(shape, "", dtype=object)
    rule_failure = np.full(shape[:-1], "", dtype=object)
    beta = np.full(shape[:-1], np.nan)
    for r in results:
        index = (*r.unit.parameter_indices, r.unit.presag_index, r.unit.speed_index)
        for name, (field, _, _) in VARIABLES.items():
            arrays[name][index] = getattr(r, field)
        failure[index] = list(r.failure)
        rule_failure[index] = r.rule_failure
        beta[index] = r.speed_ratio
    data: dict[str, Any] = {
        name: (dims, arrays[name], {"units": unit, "long_name": text}) for name, (_, unit, text) in VARIABLES.items()
    }
    data["sigma_over_F_m"] = (dims, arrays["sigma"] / arrays["F_m"], {"units": "1", "long_name": "sigma / F_m"})
    data["beta"] = (dims[:-1], beta, {"units": "1", "long_name": "speed ratio v / c_CW"})
    data["failed"] = (dims, failure != "", {"long_name": "the run did not finish"})
    data["failure"] = (dims, failure.astype(str), {"long_name": "why the run failed (empty if it finished)"})
    data["rule_failure"] = (dims[:-1], rule_failure.astype(str),
                            {"long_name": "why the quasi-static rules could not be evaluated"})
    nominal = np.add.outer(grid.aero_coefficient * np.asarray(grid.speeds) ** 2, np.asarray(grid.static_forces))
    data["F_m_nominal"] = (("speed", "static_force"), nominal,
                           {"units": "N", "long_name": "nominal mean contact force F_stat + alpha_ae v^2"})
    coords: dict[str, Any] = {
        "presag": ("presag", np.asarray(grid.presags), {"units": "m", "long_name": "mid-span pre-sag S"}),
        "speed": ("speed", np.asarray(grid.speeds), {"units": "m/s", "long_name": "train speed"}),
        "static_force": ("static_force", np.asarray(grid.static_forces),
                         {"units": "N", "long_name": "static uplift force"}),
    }
    for p in definition.parameters:
        coords[p.name] = (p.name, np.asarray(p.values), {"units": definition.parameter_unit(p.name), "long_name": f"swept parameter {p.name}"})
    attrs = {
        "study_name": definition.name,
        "study_definition": definition.to_json(),
        "study_hash": definition.digest(),
        "package_version": package_version(),
        "numerics": json.dumps(definition.to_dict()["settings"], sort_keys=True),
        "uplift_limit": definition.uplift_limit,
        "aero_coefficient": grid.aero_coefficient,
        "pantograph": "front (the only one)",
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


def write_store(dataset: xr.Dataset, store: Path) -> None:
    """Write the dataset atomically as netCDF (h5netcdf engine) at ``store``."""
    handle, temporary = tempfile.mkstemp(dir=store.parent, prefix=store.name + ".", suffix=TEMPORARY_SUFFIX)
    os.close(handle)
    try:
        dataset.to_netcdf(temporary, engine=ENGINE)
        with open(temporary, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(temporary, store)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    _fsync_directory(store.parent)


def open_store(store: str | Path) -> xr.Dataset:
    """Load a study store fully into memory (the file is closed on return).

    Raises
    ------
    ModelError
        If the file is missing or not a study store.
    """
    path = Path(store)
    if not path.is_file():
        raise ModelError(f"{path}: no such study store (run `presag sweep` first)")
    try:
        with xr.open_dataset(path, engine=ENGINE) as ds:
            dataset = ds.load()
    except (OSError, ValueError) as exc:
        raise ModelError(f"{path}: not a netCDF study store ({str(exc).splitlines()[0]})") from None
    if "study_hash" not in dataset.attrs:
        raise ModelError(f"{path}: not a study store (no study_hash attribute)")
    return dataset


def _store_digest(store: Path) -> str:
    return str(open_store(store).attrs["study_hash"])


def _fsync_directory(folder: Path) -> None:
    """Make a rename in ``folder`` durable."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
