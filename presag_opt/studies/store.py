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

One study runs on one store at a time: :func:`hold_store` takes the lock file ``PATH.units/lock``
(holding the pid and host of its holder) before anything in the units directory is touched, and a
second command on the same store is refused with the holder's pid; a lock left by a killed command
(its pid no longer running on this host) is taken over. A file that cannot be written (no space
left, no permission, a read-only folder, a file where a folder should be) raises
:class:`~presag_opt.errors.StorageError` with one line naming the path and what to do; the
temporary is removed, so the units directory holds only complete files and the study resumes when
the cause is fixed.
"""

from __future__ import annotations

import json
import os
import socket
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from presag_opt.atomic_files import TEMPORARY_SUFFIX, storage_errors, write_atomic
from presag_opt.contact_force import mean_force
from presag_opt.errors import ModelError
from presag_opt.studies.definition import StudyDefinition
from presag_opt.studies.work import UnitResult, WorkUnit
from presag_opt.version import VERSION

ENGINE = "h5netcdf"
MANIFEST = "study.json"
LOCK = "lock"

VARIABLES = {
    "F_m": ("mean_force", "N", "mean contact force (leading pantograph)"),
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

TRAILING_PREFIX = "trailing_"
"""Prefix of the trailing pantograph's variables in the store of a two-pantograph study."""

TRAILING_VARIABLES = ("F_m", "sigma", "stat_max", "stat_min", "max_force", "min_force", "loss_of_contact")
"""Variables of :data:`VARIABLES` that are per pantograph (the uplift and the rules are per run)."""


def units_directory(store: Path) -> Path:
    """The units directory beside a store: ``PATH.units``."""
    return store.with_name(store.name + ".units")


def package_version() -> str:
    """The version of presag_opt (:data:`presag_opt.version.VERSION`)."""
    return VERSION


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
    directory, and those of the store beside it. Call after :func:`check_store`, inside
    :func:`hold_store` (another command's temporaries are not strays). Returns the units directory.

    Raises
    ------
    StorageError
        The directory or the manifest cannot be written.
    """
    folder = units_directory(store)
    with storage_errors(folder):
        folder.mkdir(parents=True, exist_ok=True)
        for stray in [*folder.glob(f"*{TEMPORARY_SUFFIX}"), *store.parent.glob(f"{store.name}.*{TEMPORARY_SUFFIX}")]:
            stray.unlink()
    manifest = folder / MANIFEST
    if not manifest.exists():
        content = {"study_hash": definition.digest(), "study_definition": definition.to_dict()}
        write_atomic(manifest, json.dumps(content, sort_keys=True).encode())
    return folder


@contextmanager
def hold_store(store: Path) -> Iterator[Path]:
    """Hold the lock of a store's units directory for the ``with`` block (created if missing).

    The lock file ``PATH.units/lock`` is created exclusively and holds ``pid@host`` of its holder;
    it is removed at the end of the block. A lock whose holder no longer runs on this host is stale
    and taken over.

    Parameters
    ----------
    store : pathlib.Path
        The netCDF store.

    Raises
    ------
    ModelError
        Another command holds the lock (one line with its pid and the lock's path).
    StorageError
        The units directory or the lock cannot be written.
    """
    folder = units_directory(store)
    lock = folder / LOCK
    me = f"{os.getpid()}@{socket.gethostname()}"
    with storage_errors(folder):
        folder.mkdir(parents=True, exist_ok=True)
        for _ in range(3):
            try:
                handle = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                holder = _lock_holder(lock)
                if holder is not None:
                    raise ModelError(
                        f"{store}: another presag sweep (pid {holder}) is running this study; wait for it to "
                        f"finish (or stop it) and run again — finished units are kept (lock {lock})"
                    ) from None
                lock.unlink(missing_ok=True)  # stale: its holder is gone
                continue
            try:
                with os.fdopen(handle, "w") as fh:
                    fh.write(me)
                    fh.flush()
                    os.fsync(fh.fileno())
            except BaseException:
                lock.unlink(missing_ok=True)
                raise
            break
        else:
            raise ModelError(f"{lock}: cannot take the study lock; another command keeps taking it")
    try:
        yield folder
    finally:
        try:
            if lock.read_text() == me:
                lock.unlink()
        except OSError:
            pass


def _lock_holder(lock: Path) -> str | None:
    """The holder ``pid`` (or ``pid@host``) of a lock, or None if the lock is stale."""
    try:
        pid_text, _, host = lock.read_text().strip().partition("@")
        pid = int(pid_text)
    except (OSError, ValueError):
        return None  # unreadable or half-written: left by a command killed while taking it
    if host and host != socket.gethostname():
        return f"{pid} on {host}"  # cannot be checked from here: assume it runs
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return None
    except PermissionError:
        pass  # runs, as another user
    return str(pid)


def finished_units(folder: Path) -> set[str]:
    """Keys of the units whose result file exists."""
    return {p.stem for p in folder.glob("*.json") if p.name != MANIFEST}


def save_unit(folder: Path, result: UnitResult) -> None:
    """Write one unit's result atomically."""
    write_atomic(folder / f"{result.unit.key}.json", json.dumps(result.to_dict(), sort_keys=True).encode())


def load_unit(folder: Path, unit: WorkUnit) -> UnitResult:
    """Read one unit's result."""
    return UnitResult.from_dict(json.loads((folder / f"{unit.key}.json").read_text()))


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
        ``F_m_nominal`` [N]; the attributes described in ``docs/studies.md``. The statistics are
        the leading pantograph's; a study with two pantographs adds the trailing one's as
        ``trailing_<name>`` (:data:`TRAILING_VARIABLES`, and ``trailing_sigma_over_F_m``).
    """
    grid = definition.grid
    dims = (*(p.name for p in definition.parameters), "presag", "speed", "static_force")
    shape = definition.shape
    arrays = {name: np.full(shape, np.nan) for name in VARIABLES}
    two = definition.two_pantographs
    if two:
        arrays.update({TRAILING_PREFIX + name: np.full(shape, np.nan) for name in TRAILING_VARIABLES})
    failure = np.full(shape, "", dtype=object)
    rule_failure = np.full(shape[:-1], "", dtype=object)
    beta = np.full(shape[:-1], np.nan)
    for r in results:
        index = (*r.unit.parameter_indices, r.unit.presag_index, r.unit.speed_index)
        for name, (field, _, _) in VARIABLES.items():
            arrays[name][index] = getattr(r, field)
        if two:
            for name in TRAILING_VARIABLES:
                arrays[TRAILING_PREFIX + name][index] = r.trailing[VARIABLES[name][0]]
        failure[index] = list(r.failure)
        rule_failure[index] = r.rule_failure
        beta[index] = r.speed_ratio
    data: dict[str, Any] = {
        name: (dims, arrays[name], {"units": unit, "long_name": text}) for name, (_, unit, text) in VARIABLES.items()
    }
    data["sigma_over_F_m"] = (dims, arrays["sigma"] / arrays["F_m"], {"units": "1", "long_name": "sigma / F_m"})
    if two:
        for name in TRAILING_VARIABLES:
            _, unit, text = VARIABLES[name]
            data[TRAILING_PREFIX + name] = (dims, arrays[TRAILING_PREFIX + name],
                                            {"units": unit, "long_name": f"{text} (trailing pantograph)"})
        data["trailing_sigma_over_F_m"] = (dims, arrays["trailing_sigma"] / arrays["trailing_F_m"],
                                           {"units": "1", "long_name": "sigma / F_m (trailing pantograph)"})
    data["beta"] = (dims[:-1], beta, {"units": "1", "long_name": "speed ratio v / c_CW"})
    data["failed"] = (dims, failure != "", {"long_name": "the run did not finish"})
    data["failure"] = (dims, failure.astype(str), {"long_name": "why the run failed (empty if it finished)"})
    data["rule_failure"] = (dims[:-1], rule_failure.astype(str),
                            {"long_name": "why the quasi-static rules could not be evaluated"})
    nominal = mean_force(np.asarray(grid.static_forces)[None, :], np.asarray(grid.speeds)[:, None],
                                 grid.aero_coefficient)
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
    if two:
        spacing = definition.train.second_pantograph_at
        attrs["pantograph"] = ("leading (F_m, sigma, ...) and trailing (trailing_F_m, trailing_sigma, ...); "
                               "uplift_max over the whole run")
        attrs["second_pantograph_at"] = spacing if spacing is not None else "swept"
        attrs["second_pantograph_at_units"] = "m"
    return xr.Dataset(data, coords=coords, attrs=attrs)


def write_store(dataset: xr.Dataset, store: Path) -> None:
    """Write the dataset atomically as netCDF (h5netcdf engine) at ``store``.

    The file is built in memory and written with :func:`write_atomic`: HDF5 writing into a full disk
    itself reports the failure only on standard error and can crash the process as it closes the
    file, so the file system sees one plain write.

    Raises
    ------
    StorageError
        The store cannot be written (the temporary is removed; the units stay).
    """
    with _no_distributed_lock():
        content = bytes(dataset.to_netcdf(engine=ENGINE))
    write_atomic(store, content)


@contextmanager
def _no_distributed_lock() -> Iterator[None]:
    """Keep xarray from taking a Dask distributed lock for the in-memory write: with a Dask client
    active in the process it would ask the scheduler for a lock named after the memory buffer, which
    the scheduler does not know. The dataset is in memory; nothing is computed by Dask."""
    if "dask" not in sys.modules:
        yield
        return
    import dask

    with dask.config.set(scheduler="synchronous"):
        yield


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


