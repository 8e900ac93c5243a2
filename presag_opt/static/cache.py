"""On-disk cache of form-found states (and where long analyses keep their finished evaluations).

Form-finding (an IPOPT solve, and building the solver) is the largest fixed cost of the everyday
commands, and its result depends only on the catenary, the static settings and the code. The cache
keeps the numeric part of an :class:`~presag_opt.static.equilibrium.EquilibriumState` (coordinates
and element parameters) in one ``.npz`` file per key; the discretisation and the compiled functions
are rebuilt from the catenary, which is cheap.

The key is a SHA-256 over the catenary's ``repr`` (every value in SI, so editing a number in a model
file changes it; comments and provenance notes do not), the settings' ``repr``, the package and
CasADi versions and the source text of the modules the result depends on (``system`` and
``static``), so a code change invalidates every entry. A file that cannot be read, or whose arrays
do not fit the model, counts as a miss and is rewritten.

The folder is the runtime's (:attr:`presag_opt.runtime.Runtime.state_cache`): the library does not
cache unless a runtime with a cache folder is in force; the ``presag`` command line runs in one whose
folder is the user's cache directory (:func:`presag_opt.runtime.default_cache_directory`) unless
``--no-cache`` is given or ``PRESAG_NO_CACHE`` is set. Worker processes receive their parent's runtime,
so they read and write the same folder.

The same folder holds, in its ``evaluations`` subfolder, the finished evaluations of long
analyses (:func:`evaluation_folder`, :mod:`presag_opt.evaluation_store`): an analysis killed or
stopped by a failure resumes from them when run again.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import shutil
import tempfile
import zipfile
from dataclasses import fields
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from presag_opt import runtime
from presag_opt.version import VERSION

if TYPE_CHECKING:
    from presag_opt.static.equilibrium import EquilibriumState, StaticModel

_SOURCE_PARTS = ("system", "native", "static")
"""Parts of the package whose code determines a form-found state."""

MAX_ENTRIES = 32
"""Cached states kept; the least recently used beyond this are deleted (a code change or a new model
starts new entries, and a mixed section takes about 0.5 MB). [-]"""

def active_directory() -> Path | None:
    """The folder of the runtime in force (:attr:`presag_opt.runtime.Runtime.state_cache`), or None."""
    return runtime.current().state_cache


def clear(directory: str | Path) -> int:
    """Delete the cache files in ``directory``; return how many were deleted."""
    folder = Path(directory)
    removed = 0
    for path in folder.glob("state-*.npz") if folder.is_dir() else ():
        path.unlink(missing_ok=True)
        removed += 1
    return removed


EVALUATIONS = "evaluations"
"""Subfolder of the cache directory holding the finished evaluations of long analyses, one folder each
(:mod:`presag_opt.evaluation_store`)."""

MAX_EVALUATION_STORES = 16
"""Analyses whose evaluations are kept; the least recently used beyond this are deleted (a screening
keeps about 1 kB per evaluation). [-]"""


def evaluation_folder(label: str, key: str) -> Path | None:
    """The folder keeping the finished evaluations of one analysis, or None without a cache.

    ``<cache directory>/evaluations/<label>-<key>``; opening one deletes the least recently used
    folders beyond :data:`MAX_EVALUATION_STORES` (a folder is used when its store is opened).

    Parameters
    ----------
    label : str
        What the analysis is (letters, digits, ``-`` and ``_``), e.g. ``sensitivity-recommendation``.
    key : str
        The analysis' key (:func:`presag_opt.evaluation_store.analysis_key`).
    """
    active = active_directory()
    if active is None:
        return None
    root = active / EVALUATIONS
    folder = root / f"{label}-{key}"
    others = [p for p in root.iterdir() if p.is_dir() and p != folder] if root.is_dir() else []
    others.sort(key=lambda p: p.stat().st_mtime, reverse=True)
    for stale in others[MAX_EVALUATION_STORES - 1:]:
        shutil.rmtree(stale, ignore_errors=True)
    return folder


def clear_evaluations(directory: str | Path) -> int:
    """Delete the kept evaluations of every analysis in ``directory``; return how many analyses."""
    root = Path(directory) / EVALUATIONS
    folders = [p for p in root.iterdir() if p.is_dir()] if root.is_dir() else []
    for folder in folders:
        shutil.rmtree(folder, ignore_errors=True)
    return len(folders)


def _code_fingerprint() -> str:
    package = Path(__file__).resolve().parents[1]
    digest = hashlib.sha256()
    for part in _SOURCE_PARTS:
        for path in sorted((package / part).glob("*.py")):
            digest.update(path.name.encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()


def state_key(catenary: object, settings: object) -> str:
    """The key of a form-found state: a hex digest over everything the result depends on."""
    import casadi

    digest = hashlib.sha256()
    for text in (repr(catenary), repr(settings), VERSION, casadi.__version__, _code_fingerprint()):
        digest.update(text.encode())
        digest.update(b"\0")
    return digest.hexdigest()


def contains(key: str) -> bool:
    """Whether the active directory holds a file for ``key`` (it may still turn out unreadable)."""
    folder = active_directory()
    return folder is not None and (folder / f"state-{key}.npz").is_file()


def load(key: str) -> dict[str, np.ndarray] | None:
    """The arrays stored under ``key`` in the active directory, or None (no cache, a miss, or an
    unreadable file)."""
    folder = active_directory()
    if folder is None:
        return None
    path = folder / f"state-{key}.npz"
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
        os.utime(path)  # recently used: pruned last
        return arrays
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError):
        return None  # missing, or corrupt or truncated: the caller recomputes and store() rewrites it


def store(key: str, arrays: dict[str, np.ndarray]) -> None:
    """Write the arrays under ``key`` (atomically; a cache that cannot be written is skipped).

    Parameters
    ----------
    key : str
        Cache key (hash of the inputs).
    arrays : dict of str to ndarray
        Arrays to store, by name; each carries its own unit. [-]
    """
    folder = active_directory()
    if folder is None:
        return
    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=folder, suffix=".tmp")
    except OSError:
        return  # a read-only cache directory must not stop the computation
    try:
        with os.fdopen(handle, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(temporary, folder / f"state-{key}.npz")
        entries = sorted(folder.glob("state-*.npz"), key=lambda p: p.stat().st_mtime, reverse=True)
        for stale in entries[MAX_ENTRIES:]:
            stale.unlink(missing_ok=True)
    except OSError:
        Path(temporary).unlink(missing_ok=True)  # a full disk must not stop it either


def state_arrays(state: EquilibriumState) -> dict[str, np.ndarray]:
    """The numeric content of a state, as stored: coordinates [m], applied load [N], iterations [-],
    the form-finding's statistics (JSON text) and the element parameters (``params_<field>``, in their
    units)."""
    names = [f.name for f in fields(state.params)]
    solver = {} if state.form_finding is None else {"form_finding": np.array(json.dumps(state.form_finding.to_dict()))}
    return {"positions": state.positions, "applied_load": state.applied_load,
            "iterations": np.array(state.iterations), **solver,
            **{f"params_{n}": getattr(state.params, n) for n in names}}


def state_from_arrays(model: StaticModel, arrays: dict[str, np.ndarray] | None) -> EquilibriumState | None:
    """A state of ``model`` from stored arrays, or None when they are missing or do not fit the model.

    Parameters
    ----------
    model : StaticModel
        The model the state belongs to.
    arrays : dict of str to ndarray, or None
        Arrays as :func:`state_arrays` stores them (positions [m], applied load [N], iterations
        [-], the parameters in SI); None when nothing is stored.
    """
    from presag_opt.static.equilibrium import EquilibriumState  # the static model loads CasADi
    from presag_opt.static.potential import PhysicalParameters
    from presag_opt.static.solver_statistics import FormFindingStatistics

    if arrays is None:
        return None
    disc = model.discretisation
    try:
        params = PhysicalParameters(**{f.name: arrays[f"params_{f.name}"] for f in fields(PhysicalParameters)})
        solver = (dataclasses.replace(FormFindingStatistics.from_dict(json.loads(str(arrays["form_finding"]))),
                                      cached=True) if "form_finding" in arrays else None)
        state = EquilibriumState(model, arrays["positions"], params, arrays["applied_load"], int(arrays["iterations"]),
                                 solver)
    except (KeyError, TypeError, ValueError):
        return None
    expected = {"positions": (disc.n_nodes, 3), "applied_load": (disc.n_dofs,),
                "params_axial_stiffness": (len(disc.axial),), "params_unstretched_length": (len(disc.axial),),
                "params_nodal_force": (disc.n_dofs,)}
    if any(arrays[name].shape != shape for name, shape in expected.items()):
        return None
    return state
