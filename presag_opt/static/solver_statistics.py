"""How the form-finding solver fared: counts and times per form-finding, as data.

:class:`FormFindingStatistics` is what one :func:`~presag_opt.static.form_finding.form_find` reports
(passes, IPOPT and Newton iterations, restarts, wall time); every state it returns carries one
(:attr:`~presag_opt.static.equilibrium.EquilibriumState.form_finding`). A long analysis counts the
form-findings of each of its evaluations with :func:`recording` (a context manager around the
evaluation: every form-finding inside it, at any depth, is added to the record) and summarises
them with :func:`statistics_summary` (quantiles), so that a loss of robustness shows in its results
and in the benchmarks before a user meets it.
"""

from __future__ import annotations

import contextvars
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass

import numpy as np

QUANTILES = (0.5, 0.9, 0.99, 1.0)
"""Quantiles of the summaries (the median, the tail and the largest). [-]"""


@dataclass(frozen=True, kw_only=True)
class FormFindingStatistics:
    """What one form-finding took.

    Attributes
    ----------
    passes : int
        Form-finding passes (an IPOPT solve of the form-finding equations and a Newton relaxation of
        the full model each); the first pass settles straight track, a curve takes one or two more. [-]
    ipopt_iterations : int
        IPOPT iterations over all passes and restarts. [-]
    newton_iterations : int
        Newton iterations of the relaxations. [-]
    restarts : int
        IPOPT solves begun again after one that did not converge (with the exact Hessian,
        :data:`~presag_opt.static.form_finding_solver.RESTART_OPTIONS`); 0 when every first solve
        converged. [-]
    seconds : float
        Wall time of the form-finding (of the original solve for a state read from the cache). [s]
    cached : bool
        Whether the state was read from the cache of form-found states instead of solved.
    """

    passes: int
    ipopt_iterations: int
    newton_iterations: int
    restarts: int
    seconds: float
    cached: bool = False

    @property
    def iterations(self) -> int:
        """IPOPT and Newton iterations together. [-]"""
        return self.ipopt_iterations + self.newton_iterations

    def to_dict(self) -> dict:
        """JSON-ready content (``seconds`` in s)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> FormFindingStatistics:
        """The statistics :meth:`to_dict` wrote."""
        return cls(**{name: data[name] for name in cls.__dataclass_fields__})


_RECORD: contextvars.ContextVar[list | None] = contextvars.ContextVar("form_finding_record", default=None)
"""The open record of :func:`recording` in this context (None outside one)."""


@contextmanager
def recording() -> Iterator[list[FormFindingStatistics]]:
    """Collect the statistics of every form-finding run inside the ``with`` block (in this thread).

    Yields
    ------
    list of FormFindingStatistics
        Filled as form-findings finish (those read from the cache too, flagged ``cached``).
    """
    found: list[FormFindingStatistics] = []
    token = _RECORD.set(found)
    try:
        yield found
    finally:
        _RECORD.reset(token)


def record(statistics: FormFindingStatistics) -> None:
    """Add one form-finding to the open :func:`recording` (nothing outside one).

    Parameters
    ----------
    statistics : FormFindingStatistics
        The form-finding's counts and time.
    """
    found = _RECORD.get()
    if found is not None:
        found.append(statistics)


def statistics_summary(statistics: Sequence[FormFindingStatistics]) -> dict:
    """Counts and quantiles (:data:`QUANTILES`) of iterations and wall time per solved form-finding.

    States read from the cache are counted but left out of the quantiles (their counts are those of
    an earlier solve).

    Parameters
    ----------
    statistics : sequence of FormFindingStatistics
        The form-findings.

    Returns
    -------
    dict
        ``form_findings`` (solved), ``cached``, ``restarts`` (total), ``passes_above_one`` (solves that
        took a second pass or more), and per quantile q ``iterations`` and ``seconds`` as
        ``{"q50": …, "q90": …, "q99": …, "q100": …}``. [-], [s]
    """
    solved = [s for s in statistics if not s.cached]
    out = {"form_findings": len(solved), "cached": len(statistics) - len(solved),
           "restarts": sum(s.restarts for s in solved), "passes_above_one": sum(s.passes > 1 for s in solved)}
    for name, values in (("iterations", [s.iterations for s in solved]), ("seconds", [s.seconds for s in solved])):
        out[name] = ({f"q{round(q * 100)}": float(np.quantile(values, q)) for q in QUANTILES} if values else {})
    return out


__all__ = ["QUANTILES", "FormFindingStatistics", "record", "recording", "statistics_summary"]
