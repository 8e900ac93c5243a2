"""The finished evaluations of a long analysis, kept one file each: a rerun computes only the rest.

A long analysis (a sensitivity screening, a dynamic Monte Carlo) is many independent evaluations.
:class:`EvaluationStore` keeps each finished one in its own small JSON file, written atomically
(:func:`~presag_opt.atomic_files.write_atomic`: absent or complete, whenever the process is killed),
in a folder whose manifest (``store.json``) holds the analysis' key, a digest over everything that
decides its evaluations (:func:`analysis_key`). The same analysis started again reads them back and
computes only the missing ones; a folder of another analysis is refused before any work.

A failed evaluation is kept too (:class:`Evaluation` with ``failure``, its inputs and the one-line
reason): the same inputs with the same code fail the same way, so a rerun does not repeat it.

Where: a folder the user gives (``--out``), or by default one folder per analysis under the user's
cache (:func:`presag_opt.static.cache.evaluation_folder`), so that an analysis interrupted without
``--out`` loses nothing either.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

from presag_opt.atomic_files import storage_errors, write_atomic
from presag_opt.errors import ModelError
from presag_opt.version import VERSION

MANIFEST = "store.json"
"""File name of a store's manifest (its key and what it holds)."""


def analysis_key(*inputs: object) -> str:
    """A digest over everything that decides an analysis' evaluations, and the package version.

    Parameters
    ----------
    *inputs : object
        The inputs; their ``repr`` is hashed (the models are dataclasses whose repr holds every value
        in SI, so a changed number changes the key).

    Returns
    -------
    str
        20 hex digits. [-]
    """
    return hashlib.sha256(repr((VERSION, *inputs)).encode()).hexdigest()[:20]


@dataclass(frozen=True, kw_only=True)
class Evaluation:
    """One evaluation of an analysis: its values, or why it failed.

    Attributes
    ----------
    index : int
        Position in the analysis' design (-1 for a reference evaluation such as the error-free run). [-]
    inputs : dict
        Input name -> value, in the display units of the analysis (what a reader needs to repeat it).
    values : dict
        Output name -> value (empty when the evaluation failed). [units of the analysis]
    failure : str
        One line: why the evaluation failed ("" when it finished).
    solver : dict
        Solver statistics of the evaluation (e.g. its form-findings, see
        :mod:`presag_opt.static.solver_statistics`).
    seconds : float
        Wall time of the evaluation. [s]
    """

    index: int
    inputs: dict = field(default_factory=dict)
    values: dict = field(default_factory=dict)
    failure: str = ""
    solver: dict = field(default_factory=dict)
    seconds: float = math.nan

    @property
    def ok(self) -> bool:
        """Whether the evaluation finished."""
        return not self.failure

    def to_dict(self) -> dict:
        """JSON-ready content."""
        return {"index": self.index, "inputs": self.inputs, "values": self.values, "failure": self.failure,
                "solver": self.solver, "seconds": self.seconds}

    @classmethod
    def from_dict(cls, data: dict) -> Evaluation:
        """The evaluation :meth:`to_dict` wrote."""
        return cls(index=int(data["index"]), inputs=dict(data["inputs"]), values=dict(data["values"]),
                   failure=str(data["failure"]), solver=dict(data["solver"]), seconds=float(data["seconds"]))


@dataclass(frozen=True)
class EvaluationStore:
    """A folder of finished evaluations of one analysis (see the module notes).

    Attributes
    ----------
    folder : pathlib.Path
        The folder.
    key : str
        The analysis' key (:func:`analysis_key`).
    """

    folder: Path
    key: str

    @classmethod
    def open(cls, folder: str | Path, key: str, label: str = "") -> EvaluationStore:
        """The store of the analysis ``key`` in ``folder`` (created if missing).

        Parameters
        ----------
        folder : str or pathlib.Path
            Folder of the store.
        key : str
            The analysis' key.
        label : str
            What the analysis is, written to the manifest for a reader.

        Raises
        ------
        ModelError
            The folder holds another analysis' evaluations.
        StorageError
            The folder or its manifest cannot be written.
        """
        folder = Path(folder)
        manifest = folder / MANIFEST
        with storage_errors(folder):
            folder.mkdir(parents=True, exist_ok=True)
            if manifest.exists():
                saved = json.loads(manifest.read_text()).get("key")
                if saved != key:
                    raise ModelError(f"{folder}: holds the evaluations of another analysis (other inputs); "
                                     "give another folder or remove it")
            write_atomic(manifest, json.dumps({"key": key, "label": label}).encode())  # also marks it recently used
        return cls(folder, key)

    def _path(self, index: int) -> Path:
        return self.folder / ("reference.json" if index < 0 else f"evaluation_{index:05d}.json")

    def read(self, indices) -> dict[int, Evaluation]:
        """The evaluations kept among ``indices``, by index.

        Parameters
        ----------
        indices : iterable of int
            The evaluations asked for. [-]

        Raises
        ------
        ModelError
            A file of another analysis (its key differs).
        """
        out = {}
        for index in indices:
            path = self._path(index)
            if not path.exists():
                continue
            with storage_errors(path):
                saved = json.loads(path.read_text())
            if saved.get("key") != self.key:
                raise ModelError(f"{path}: holds an evaluation of another analysis; give another folder")
            out[index] = Evaluation.from_dict(saved["evaluation"])
        return out

    def write(self, evaluation: Evaluation) -> None:
        """Keep one evaluation (atomically).

        Parameters
        ----------
        evaluation : Evaluation
            The finished or failed evaluation.
        """
        content = {"key": self.key, "evaluation": evaluation.to_dict()}
        write_atomic(self._path(evaluation.index), json.dumps(content).encode())


__all__ = ["MANIFEST", "Evaluation", "EvaluationStore", "analysis_key"]
