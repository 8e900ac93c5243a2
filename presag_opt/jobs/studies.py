"""The study jobs: ``sensitivity`` (global sensitivity of a result) and ``validity`` (a study store in,
β* out), in the designer's units."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from presag_opt.jobs.options import WORKERS

if TYPE_CHECKING:
    from presag_opt.sensitivity.analysis import SensitivityResult
    from presag_opt.studies.validity_results import ValidityResult

SENSITIVITY_CASE = "case_study_st98"
"""The case of ``sensitivity`` by default: the case study's ST 9,8/9,8 line."""


def sensitivity_study(
    case: str | Path = SENSITIVITY_CASE,
    *,
    quantity: str,
    method: str = "morris",
    inputs: Sequence[str] | None = None,
    ranges: Sequence[str] = (),
    samples: int | None = None,
    seed: int = 0,
    workers: int = WORKERS,
    scheduler: str | None = None,
    out: str | Path | None = None,
    announce: Callable[[str], None] | None = None,
    progress: Callable[[str], None] | None = None,
) -> SensitivityResult:
    """Global sensitivity of one result of a case to its assumed inputs: the job of ``presag sensitivity``.

    Parameters
    ----------
    case : str or Path
        Case file or built-in case name.
    quantity : str
        The result analysed: ``recommendation``, ``robust``, ``dynamic-robust``, ``dynamic:V1,V2``,
        ``minima:V`` or ``validity:V1,V2,...`` (speeds in km/h).
    method : {"morris", "sobol", "spread"}
        Morris screening, Sobol indices, or the result's mean and spread only.
    inputs : sequence of str, optional
        Dotted input names (default: every assumed input the result depends on).
    ranges : sequence of str
        ``NAME=LOW:HIGH`` in the model file's unit (adds the input).
    samples : int, optional
        Morris trajectories (default 10) or Sobol base sample, a power of two (default 64). [-]
    seed : int
        Seed of the design and of the bootstrap. [-]
    workers : int
        Local worker processes (not with ``scheduler``). [-]
    scheduler : str, optional
        A Dask scheduler address to run the evaluations on.
    out : str or Path, optional
        Folder of the resumable stores (a killed analysis computes only what it did not keep).
    announce : callable, optional
        Told what the analysis will cost before it starts.
    progress : callable, optional
        Called with a short message as the work goes on.

    Returns
    -------
    SensitivityResult
        The ranking of the inputs (``result.indices``); shows itself in a notebook.

    Examples
    --------
    >>> from presag_opt import sensitivity
    >>> result = sensitivity(quantity="recommendation", samples=4)  # doctest: +SKIP
    """
    from presag_opt.sensitivity import sensitivity_analysis

    return sensitivity_analysis(case, output=quantity, method=method, inputs=inputs, ranges=ranges, samples=samples,
                                seed=seed, workers=workers, scheduler=scheduler, out=out, announce=announce,
                                progress=progress)


def validity(store: str | Path, *, select: Mapping[str, float] | None = None,
             pantograph: str | None = None) -> ValidityResult:
    """The validity limit β* of the quasi-static pre-sag rule from a study store: the job of ``presag
    validity``.

    Parameters
    ----------
    store : str or Path
        A netCDF store written by ``presag sweep``.
    select : mapping of str to float, optional
        Value of each swept extra parameter of the study. [SI]
    pantograph : {"leading", "trailing"}, optional
        The pantograph of a two-pantograph study (default: the trailing one).

    Returns
    -------
    ValidityResult
        β*, the fit S_dyn = S_stat + k·β^a, the optimal pre-sag per speed ratio and the uplift.

    Examples
    --------
    >>> from presag_opt import validity
    >>> result = validity("paper_grid_st98.nc")  # doctest: +SKIP
    >>> result.beta_limit  # doctest: +SKIP
    """
    from presag_opt.studies.store import open_store
    from presag_opt.studies.validity_analysis import pantograph_view, validity_analysis

    dataset, view = pantograph_view(open_store(store), pantograph)
    return validity_analysis(dataset, dict(select or {}), view)
