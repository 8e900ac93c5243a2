"""Morris elementary effects and Sobol indices (SALib) over a model evaluated sample by sample.

The sample design (:func:`morris_design`, :func:`sobol_design`) depends on the inputs, the sample
size and the seed only; the evaluations (:func:`~presag_opt.sensitivity.evaluation.evaluate_rows`) run
in worker processes and are put back in sample order, so the indices do not depend on the worker
count. The analysis (:func:`morris_indices`, :func:`sobol_indices`) bootstraps confidence intervals
with the same seed, from the trajectories or base samples whose evaluations all finished.

References
----------
Morris, "Factorial sampling plans for preliminary computational experiments", Technometrics 33
(1991), doi:10.1080/00401706.1991.10484804; Campolongo, Cariboni, Saltelli, "An effective screening
design for sensitivity analysis of large models", Environ. Model. Softw. 22 (2007),
doi:10.1016/j.envsoft.2006.10.004 (μ*). Saltelli et al., "Variance based sensitivity analysis of model
output. Design and estimator for the total sensitivity index", Comput. Phys. Commun. 181 (2010),
doi:10.1016/j.cpc.2009.09.018. Herman, Usher, "SALib", J. Open Source Softw. 2(9) (2017),
doi:10.21105/joss.00097.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from SALib.analyze import morris as morris_analyze
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import morris as morris_sample
from SALib.sample import sobol as sobol_sample

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.sensitivity.inputs import SensitivityInput

CONFIDENCE = 0.95
"""Level of the bootstrap confidence intervals. [-]"""

RESAMPLES = 1000
"""Bootstrap resamples of the confidence intervals. [-]"""

MORRIS_LEVELS = 4
"""Grid levels of the Morris design (p = 4, step Δ = p / (2(p − 1)) = 2/3 of each range). [-]"""


@dataclass(frozen=True, kw_only=True)
class MorrisEffect:
    """Morris elementary-effect statistics of one input on one output.

    Attributes
    ----------
    name : str
        Input.
    mu_star : float
        Mean absolute elementary effect: the change of the output per change of the input over its
        whole range, from steps of 2/3 of the range (a linear f = c·x on [a, b] has μ* = |c|(b − a)).
        [output unit]
    mu_star_conf : float
        Half-width of its bootstrap confidence interval. [output unit]
    sigma : float
        Standard deviation of the elementary effects (non-linearity or interaction). [output unit]
    relative : float
        μ* over the largest μ* of the output (1 for the top input; 0 if no input has an effect). [-]
    """

    name: str
    mu_star: float
    mu_star_conf: float
    sigma: float
    relative: float


@dataclass(frozen=True, kw_only=True)
class SobolIndex:
    """Sobol first-order and total indices of one input on one output.

    Attributes
    ----------
    name : str
        Input.
    first, first_conf : float
        S1 and the half-width of its bootstrap confidence interval. [-]
    total, total_conf : float
        ST and the half-width of its bootstrap confidence interval. [-]
    """

    name: str
    first: float
    first_conf: float
    total: float
    total_conf: float

    @property
    def total_interval(self) -> tuple[float, float]:
        """Confidence interval of ST. [-]"""
        return (self.total - self.total_conf, self.total + self.total_conf)


@dataclass(frozen=True, kw_only=True)
class OutputIndices:
    """The indices of one output, ranked by importance (μ* or ST, largest first).

    Attributes
    ----------
    output : str
        Output name.
    unit : str
        Unit the output and μ*, σ are given in.
    method : str
        ``"morris"``, ``"sobol"`` or ``"spread"`` (mean and spread only).
    morris : tuple of MorrisEffect
        Ranked Morris table (empty for Sobol).
    sobol : tuple of SobolIndex
        Ranked Sobol table (empty for Morris).
    mean, std : float
        Mean and standard deviation of the output over the evaluations used. [unit]
    samples : int
        What the estimate rests on: Morris trajectories, Sobol base samples (the effective sample size
        N) or spread points, each with every one of its evaluations finished. [-]
    dropped : int
        Trajectories, base samples or points left out because one of their evaluations failed. [-]
    """

    output: str
    unit: str
    method: str
    morris: tuple[MorrisEffect, ...] = ()
    sobol: tuple[SobolIndex, ...] = ()
    mean: float = math.nan
    std: float = math.nan
    samples: int = 0
    dropped: int = 0

    def ranked_names(self) -> tuple[str, ...]:
        """Input names, most important first."""
        return tuple(e.name for e in (self.morris or self.sobol))

    def to_dict(self) -> dict:
        """JSON-ready table."""
        rows = ([{"input": e.name, "mu_star": e.mu_star, "mu_star_conf": e.mu_star_conf, "sigma": e.sigma,
                  "mu_star_relative": e.relative} for e in self.morris]
                or [{"input": s.name, "S1": s.first, "S1_conf": s.first_conf, "ST": s.total, "ST_conf": s.total_conf}
                    for s in self.sobol])
        return {"output": self.output, "unit": self.unit, "method": self.method, "mean": self.mean,
                "std": self.std, "samples": self.samples, "dropped": self.dropped, "ranked": rows}


def _problem(inputs: Sequence[SensitivityInput]) -> dict:
    if not inputs:
        raise ModelError("no inputs to vary: give --inputs or a model with assumed values")
    return {"num_vars": len(inputs), "names": [i.name for i in inputs],
            "bounds": [[i.low, i.high] for i in inputs]}


def morris_design(inputs: Sequence[SensitivityInput], trajectories: int, seed: int) -> np.ndarray:
    """Morris sample: ``trajectories`` one-at-a-time paths of k + 1 points over the inputs' ranges.

    Parameters
    ----------
    inputs : sequence of SensitivityInput
        The k inputs.
    trajectories : int
        r, at least 2. [-]
    seed : int
        Seed of the design. [-]

    Returns
    -------
    ndarray, shape (r (k + 1), k)
        Input values, SI. [SI units of the inputs]
    """
    if not 2 <= trajectories <= 1000:
        raise ModelError(f"samples = {trajectories} trajectories is outside the valid range [2, 1000] for Morris")
    return morris_sample.sample(_problem(inputs), trajectories, num_levels=MORRIS_LEVELS, seed=seed)


def sobol_design(inputs: Sequence[SensitivityInput], base_samples: int, seed: int) -> np.ndarray:
    """Saltelli sample (Sobol sequence, scrambled by the seed) for S1 and ST: N (k + 2) points.

    Parameters
    ----------
    inputs : sequence of SensitivityInput
        The k inputs.
    base_samples : int
        N, a power of two, at least 8. [-]
    seed : int
        Seed of the scrambling. [-]

    Returns
    -------
    ndarray, shape (N (k + 2), k)
        Input values, SI. [SI units of the inputs]
    """
    if base_samples < 8 or base_samples & (base_samples - 1):
        raise ModelError(f"samples = {base_samples} is not a valid Sobol base sample: a power of two, at least 8")
    return sobol_sample.sample(_problem(inputs), base_samples, calc_second_order=False, scramble=True, seed=seed)


def spread_design(inputs: Sequence[SensitivityInput], samples: int, seed: int) -> np.ndarray:
    """A scrambled Sobol sample of the inputs' box, for the spread of an output (no indices).

    Parameters
    ----------
    inputs : sequence of SensitivityInput
        The k inputs.
    samples : int
        Points, a power of two, at least 2. [-]
    seed : int
        Seed of the scrambling. [-]

    Returns
    -------
    ndarray, shape (samples, k)
        Input values, SI. [SI units of the inputs]
    """
    from scipy.stats import qmc

    if samples < 2 or samples & (samples - 1):
        raise ModelError(f"samples = {samples} is not a valid spread sample: a power of two, at least 2")
    problem = _problem(inputs)
    unit = qmc.Sobol(d=problem["num_vars"], scramble=True, seed=seed).random(samples)
    low, high = np.array(problem["bounds"]).T
    return low + unit * (high - low)


def spread_summary(values: np.ndarray, *, output: str, unit: str) -> OutputIndices:
    """Mean and standard deviation of an output over a spread sample (no indices).

    Parameters
    ----------
    values : ndarray, shape (n,)
        The output at each sample; non-finite values (failed evaluations) are left out and counted. [unit]
    output : str
        Output name (for the table).
    unit : str
        Output unit (for the table).
    """
    used = _used_groups(output, values, 1, "points", least=1)
    finite = values[used]
    return OutputIndices(output=output, unit=unit, method="spread", mean=float(np.mean(finite)),
                         std=float(np.std(finite)), samples=int(used.sum()), dropped=int((~used).sum()))


MIN_GROUPS = 2
"""Fewest Morris trajectories or Sobol base samples an estimate is made from. [-]"""


def _used_groups(output: str, values: np.ndarray, size: int, what: str, least: int = MIN_GROUPS) -> np.ndarray:
    """Which groups of ``size`` consecutive rows (a trajectory, a base sample) have every value finite.

    Raises
    ------
    ConvergenceError
        Fewer than ``least`` groups are left.
    """
    used = np.isfinite(values).reshape(-1, size).all(axis=1)
    if used.sum() < least:
        raise ConvergenceError(f"output {output}: {len(used) - used.sum()} of {len(used)} {what} hold a failed "
                               f"evaluation; fewer than {least} are left to estimate from")
    return used


def morris_indices(inputs: Sequence[SensitivityInput], rows: np.ndarray, values: np.ndarray, *, output: str,
                   unit: str, seed: int) -> OutputIndices:
    """Morris μ*, its confidence interval and σ of one output, ranked by μ*.

    A trajectory with a failed evaluation (a non-finite value) has lost an elementary effect of one
    input, two if the point is inside it: it is dropped whole, so that every input keeps the same
    number of effects, and counted (``dropped``).

    Parameters
    ----------
    inputs : sequence of SensitivityInput
        The inputs of the design.
    rows : ndarray, shape (n, k)
        The design (:func:`morris_design`). [SI units of the inputs]
    values : ndarray, shape (n,)
        The output at each row. [unit]
    output, unit : str
        Output name and unit (for the table).
    seed : int
        Seed of the bootstrap. [-]
    """
    groups = _used_groups(output, values, len(inputs) + 1, "trajectories")
    used = np.repeat(groups, len(inputs) + 1)
    rows, values = rows[used], values[used]
    res = morris_analyze.analyze(_problem(inputs), rows, values, num_resamples=RESAMPLES, conf_level=CONFIDENCE,
                                 num_levels=MORRIS_LEVELS, seed=seed)
    top = float(np.max(res["mu_star"]))
    effects = [MorrisEffect(name=str(n), mu_star=float(m), mu_star_conf=float(c), sigma=float(s),
                            relative=float(m) / top if top > 0.0 else 0.0)
               for n, m, c, s in zip(res["names"], res["mu_star"], res["mu_star_conf"], res["sigma"])]
    effects.sort(key=lambda e: -e.mu_star)
    return OutputIndices(output=output, unit=unit, method="morris", morris=tuple(effects),
                         mean=float(np.mean(values)), std=float(np.std(values)), samples=int(groups.sum()),
                         dropped=int((~groups).sum()))


def sobol_indices(inputs: Sequence[SensitivityInput], rows: np.ndarray, values: np.ndarray, *, output: str,
                  unit: str, seed: int) -> OutputIndices:
    """Sobol S1 and ST of one output with bootstrap confidence intervals, ranked by ST.

    An output that does not vary over the sample has no variance to share: all indices are 0. A base
    sample with a failed evaluation (a non-finite value among its k + 2 rows) is dropped whole: the
    estimators then run on the N' base samples left, the effective sample size (``samples``; the
    confidence intervals widen as 1/√N').

    Parameters
    ----------
    inputs : sequence of SensitivityInput
        The inputs of the design.
    rows : ndarray, shape (n, k)
        The design (:func:`sobol_design`). [SI units of the inputs]
    values : ndarray, shape (n,)
        The output at each row. [unit]
    output : str
        Output name (for the table).
    unit : str
        Output unit (for the table).
    seed : int
        Seed of the bootstrap. [-]
    """
    groups = _used_groups(output, values, len(inputs) + 2, "base samples")
    counts = {"samples": int(groups.sum()), "dropped": int((~groups).sum())}
    values = values[np.repeat(groups, len(inputs) + 2)]
    if np.ptp(values) == 0.0:
        zero = [SobolIndex(name=i.name, first=0.0, first_conf=0.0, total=0.0, total_conf=0.0) for i in inputs]
        return OutputIndices(output=output, unit=unit, method="sobol", sobol=tuple(zero),
                             mean=float(values[0]), std=0.0, **counts)
    res = sobol_analyze.analyze(_problem(inputs), values, calc_second_order=False, num_resamples=RESAMPLES,
                                conf_level=CONFIDENCE, seed=seed)
    rows_out = [SobolIndex(name=i.name, first=float(s1), first_conf=float(c1), total=float(st), total_conf=float(ct))
                for i, s1, c1, st, ct in zip(inputs, res["S1"], res["S1_conf"], res["ST"], res["ST_conf"])]
    rows_out.sort(key=lambda s: -s.total)
    return OutputIndices(output=output, unit=unit, method="sobol", sobol=tuple(rows_out),
                         mean=float(np.mean(values)), std=float(np.std(values)), **counts)

