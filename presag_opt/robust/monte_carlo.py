"""Quasi-static Monte Carlo of the installation errors: the worst-case waviness of a built design.

For a pre-sag design (dropper depths d) on the path model of its section, each realisation of the
installation errors moves the contact wire by δz = B·ε (:class:`~presag_opt.robust.realisation.InstallationResponse`,
the installed line linearised on the nominal structure) and the quasi-static path becomes

    h(x; F) = z_CW(x; d) + δz(x) + F · e(x; F),

its worst case over the force band W = max_k max_span (max_x h − min_x h). The distribution of W over
the realisations is summarised by percentiles with distribution-free confidence intervals
(:func:`percentile_summary`). :func:`largest_dropper_tolerance` finds the largest per-dropper
tolerance whose P95 stays within a loss of the error-free design, on one set of standard draws
(common random numbers), so P95(t) is a function of t alone.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, section 6 (assembly and
maintenance tolerances within the width of the beneficial range of pre-sag).
W. J. Conover, Practical Nonparametric Statistics, 3rd ed., Wiley (1999), section 3.2 (confidence
interval of a quantile from order statistics).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from presag_opt.design.evidence import InstallationTolerance
from presag_opt.display import data_frame, html_summary
from presag_opt.errors import ModelError
from presag_opt.robust.installation import (
    InstallationErrors,
    StandardDraws,
    draw_installation_errors,
)
from presag_opt.robust.path import PathModel
from presag_opt.robust.realisation import InstallationResponse, installation_response
from presag_opt.robust.scenarios import ForceScenarios
from presag_opt.robust.tolerance import check_within

PERCENTILES = (50, 90, 95, 99)
"""Percentiles every Monte Carlo result reports. [%]"""

CHUNK = 512
"""Realisations evaluated together (the height array of a chunk is CHUNK × forces × points doubles). [-]"""


@dataclass(frozen=True, kw_only=True)
class Percentile:
    """One percentile of a sample with its confidence interval.

    Attributes
    ----------
    level : float
        Percentile. [%]
    value : float
        Sample percentile (linear interpolation between order statistics). [unit of the sample]
    low, high : float
        Distribution-free confidence interval: the order statistics whose ranks bracket the
        percentile with the stated confidence (binomial ranks). [unit of the sample]
    samples : int
        Size of the sample the percentile is taken from (the interval narrows as it grows). [-]
    """

    level: float
    value: float
    low: float
    high: float
    samples: int

    def to_dict(self, scale: float = 1.0) -> dict:
        """``{"value", "ci", "n"}``: the value and interval with every number multiplied by ``scale``, and
        the sample size.

        Parameters
        ----------
        scale : float
            Factor on every number, e.g. 1000 for m to mm. [-]
        """
        return {"value": self.value * scale, "ci": [self.low * scale, self.high * scale], "n": self.samples}


def percentile_summary(values: np.ndarray, levels=PERCENTILES, confidence: float = 0.95) -> dict[int, Percentile]:
    """Percentiles of a sample with distribution-free confidence intervals.

    The interval of the p-quantile is [x_(l), x_(u)] with l and u the α/2 and 1 − α/2 quantiles of a
    binomial(n, p) count (ranks clipped to 1…n; for small n the interval is then wider than stated).

    Parameters
    ----------
    values : ndarray
        The sample (e.g. worst-case waviness of each realisation). [any unit]
    levels : sequence of float
        Percentiles. [%]
    confidence : float
        Coverage of the intervals, in (0, 1). [-]
    """
    values = np.sort(np.asarray(values, dtype=float))
    n = len(values)
    if n == 0 or not np.all(np.isfinite(values)):
        raise ModelError("percentiles: the sample is empty or holds a non-finite value")
    if not 0.0 < confidence < 1.0:
        raise ModelError(f"confidence = {confidence:g} is outside the valid range (0, 1)")
    from scipy import stats  # imported here: it costs about a second, which every command would pay

    alpha = 1.0 - confidence
    out = {}
    for level in levels:
        p = level / 100.0
        lower = int(np.clip(stats.binom.ppf(alpha / 2, n, p), 1, n))
        upper = int(np.clip(stats.binom.ppf(1 - alpha / 2, n, p) + 1, 1, n))
        out[level] = Percentile(level=float(level), value=float(np.percentile(values, level)),
                                low=float(values[lower - 1]), high=float(values[upper - 1]), samples=n)
    return out


@dataclass(frozen=True, kw_only=True)
class MonteCarloResult:
    """Distribution of a design's worst case over the realisations of the installation errors.

    Attributes
    ----------
    errors : InstallationErrors
        Error sizes. [m]
    seed : int
        Seed of the draws. [-]
    nominal_worst_case : float
        Worst case of the error-free design. [unit of the loss]
    worst_case : ndarray
        Worst case of each realisation. [unit of the loss]
    percentiles : dict
        :class:`Percentile` by level (:data:`PERCENTILES`).
    confidence : float
        Coverage of the percentile intervals. [-]
    unit : str
        ``m`` (waviness) or a dynamic loss's unit.
    """

    errors: InstallationErrors
    seed: int
    nominal_worst_case: float
    worst_case: np.ndarray
    percentiles: dict
    confidence: float = 0.95
    unit: str = "m"

    @property
    def samples(self) -> int:
        """Realisations. [-]"""
        return len(self.worst_case)

    def table(self) -> list[dict]:
        """The error-free worst case and the percentiles with their confidence intervals as rows, in mm for
        the waviness (in the loss's unit otherwise)."""
        scale, unit = (1e3, "mm") if self.unit == "m" else (1.0, self.unit)
        rows = [{"": "error-free", f"value [{unit}]": self.nominal_worst_case * scale, "CI low": None, "CI high": None}]
        return rows + [{"": f"P{level:g}", f"value [{unit}]": p.value * scale, "CI low": p.low * scale,
                        "CI high": p.high * scale} for level, p in self.percentiles.items()]

    def to_frame(self):
        """:meth:`table` as a pandas DataFrame."""
        return data_frame(self.table())

    def _repr_html_(self) -> str:
        e = self.errors
        return html_summary(f"Installation errors by Monte Carlo: {self.samples} realisations, seed {self.seed}",
                            [f"per dropper {e.dropper_length * 1e3:.2f} mm, per mast height "
                             f"{e.contact_wire_height * 1e3:.2f} mm ({e.distribution}); confidence intervals "
                             f"{self.confidence:.0%}"], self.table())


def _chunked_worst(path: PathModel, depths: np.ndarray, scenarios: ForceScenarios, moves: np.ndarray) -> np.ndarray:
    """Worst-case waviness over forces and analysed spans of each realisation (rows of ``moves``). [m]"""
    base = path.heights(depths, scenarios.forces)  # forces × points, the error-free path
    spans = [path.node_span == s for s in path.spans]
    out = np.empty(moves.shape[0])
    for first in range(0, moves.shape[0], CHUNK):
        h = base[None, :, :] + moves[first : first + CHUNK, None, :]
        out[first : first + CHUNK] = np.max([np.ptp(h[:, :, sel], axis=2).max(axis=1) for sel in spans], axis=0)
    return out


class QuasiStaticMonteCarlo:
    """Monte Carlo of a design's worst-case waviness under installation errors, on one path model.

    The linearised response is computed once (at the path model's state) and the standard draws once
    per (samples, distribution, seed); each evaluation then costs one matrix product and the
    peak-to-peak values.

    Parameters
    ----------
    path : PathModel
        Path model of the section (its state is the nominal structure).
    depths : ndarray
        Dropper depths of the design over the analysed spans (e.g. :meth:`PathModel.parabola_depths`). [m]
    scenarios : ForceScenarios
        The F_m band. [N]
    response : InstallationResponse, optional
        Linearised response of the path nodes (computed here by default).
    """

    def __init__(self, path: PathModel, depths: np.ndarray, scenarios: ForceScenarios,
                 response: InstallationResponse | None = None):
        self.path = path
        self.depths = np.asarray(depths, dtype=float)
        if self.depths.shape != path.reference_depth.shape:
            raise ModelError(f"design: give {len(path.reference_depth)} dropper depths, got {self.depths.shape}")
        self.scenarios = scenarios
        self.response = response or installation_response(path.state, path.nodes)
        disc = path.state.discretisation
        self.dropper_count = len(disc.dropper_elements)
        self.mast_count = len(disc.mast_station)
        self.nominal_worst_case = float(_chunked_worst(path, self.depths, scenarios, np.zeros((1, len(path.nodes))))[0])
        self._draws: dict = {}

    def draws(self, samples: int, distribution: str, seed: int) -> StandardDraws:
        """The standard draws of this section (drawn once per samples, distribution and seed).

        Parameters
        ----------
        samples : int
            Realisations. [-]
        distribution : {"normal", "uniform"}
            Unit normal, or uniform on [−1, 1].
        seed : int
            Seed of the draws. [-]
        """
        key = (samples, distribution, seed)
        if key not in self._draws:
            self._draws[key] = draw_installation_errors(samples, self.dropper_count, self.mast_count,
                                                        distribution=distribution, seed=seed)
        return self._draws[key]

    def worst_cases(self, errors: InstallationErrors, draws: StandardDraws) -> np.ndarray:
        """Worst-case waviness of every realisation of ``draws`` at the sizes of ``errors``. [m]"""
        return _chunked_worst(self.path, self.depths, self.scenarios, self.response.heights(draws.scaled(errors)))

    def run(self, errors: InstallationErrors, *, samples: int = 10_000, seed: int = 0,
            confidence: float = 0.95) -> MonteCarloResult:
        """The distribution of the worst-case waviness for one set of error sizes.

        Parameters
        ----------
        errors : InstallationErrors
            Error sizes and distribution. [m]
        samples : int
            Realisations. [-]
        seed : int
            Seed of the draws. [-]
        confidence : float
            Coverage of the percentile intervals. [-]
        """
        worst = self.worst_cases(errors, self.draws(samples, errors.distribution, seed))
        return MonteCarloResult(errors=errors, seed=seed, nominal_worst_case=self.nominal_worst_case,
                                worst_case=worst, percentiles=percentile_summary(worst, confidence=confidence),
                                confidence=confidence)


@dataclass(frozen=True, kw_only=True)
class DropperTolerance:
    """Largest per-dropper tolerance whose percentile of the worst case stays within a loss.

    Attributes
    ----------
    tolerance : float
        Largest dropper-length error size (σ or ±t) that keeps the percentile within the loss, to
        ``resolution``. [m]
    within : float
        Allowed loss relative to the error-free worst case. [-]
    level : int
        The percentile held. [%]
    at_tolerance : MonteCarloResult
        The Monte Carlo at that size.
    resolution : float
        Bisection resolution. [m]
    """

    tolerance: float
    within: float
    level: int
    at_tolerance: MonteCarloResult
    resolution: float


def largest_dropper_tolerance(
    monte_carlo: QuasiStaticMonteCarlo, errors: InstallationErrors, *, within: float = 0.10, level: int = 95,
    samples: int = 10_000, seed: int = 0, upper: float = 0.05, resolution: float = 1e-4,
) -> DropperTolerance:
    """Largest dropper error size t with percentile ``level`` of the worst case ≤ (1 + within)·W₀.

    Bisection in t on one set of standard draws (common random numbers): the other error sizes of
    ``errors`` are held, the dropper size is varied. With the registration and messenger errors alone
    already beyond the loss, the answer is 0 and says so through ``at_tolerance``.

    Parameters
    ----------
    monte_carlo : QuasiStaticMonteCarlo
        The design and its section.
    errors : InstallationErrors
        Distribution and the held (height) error sizes; its dropper size is ignored. [m]
    within : float
        Allowed loss, in (0, 2]. [-]
    level : int
        Percentile held, one of :data:`PERCENTILES`. [%]
    samples, seed : int
        Realisations and seed. [-]
    upper : float
        Largest dropper error size searched. [m]
    resolution : float
        Bisection stops when the bracket is this narrow. [m]
    """
    check_within(within)
    if level not in PERCENTILES:
        raise ModelError(f"level = {level} % is not one of {', '.join(map(str, PERCENTILES))} %")
    draws = monte_carlo.draws(samples, errors.distribution, seed)
    bound = (1.0 + within) * monte_carlo.nominal_worst_case

    def at(t: float) -> float:
        worst = monte_carlo.worst_cases(dataclasses.replace(errors, dropper_length=t), draws)
        return float(np.percentile(worst, level))

    low, high = 0.0, upper
    if at(high) <= bound:
        low = high
    elif at(low) <= bound:
        while high - low > resolution:
            mid = 0.5 * (low + high)
            low, high = (mid, high) if at(mid) <= bound else (low, mid)
    found = dataclasses.replace(errors, dropper_length=low)
    return DropperTolerance(tolerance=low, within=within, level=level, resolution=resolution,
                            at_tolerance=monte_carlo.run(found, samples=samples, seed=seed))


def presag_errors(mc: QuasiStaticMonteCarlo, errors: InstallationErrors, draws: StandardDraws) -> np.ndarray:
    """Error of the built mid-span pre-sag of every analysed span in every realisation (samples × spans).

    δS = ½(δz at its two masts) − δz at mid-span: positive where the wire ends up lower at mid-span
    than designed relative to its supports (more pre-sag). [m]

    Parameters
    ----------
    mc : QuasiStaticMonteCarlo
        The Monte Carlo of the section (its path model and linearised response).
    errors : InstallationErrors
        Error sizes. [m]
    draws : StandardDraws
        The standard draws (:meth:`QuasiStaticMonteCarlo.draws`).
    """
    moves = mc.response.heights(draws.scaled(errors))  # samples × path points
    path = mc.path
    out = []
    for span in path.spans:
        points = np.flatnonzero(path.node_span == span)
        x = path.node_position[points]
        ends = points[[np.argmin(x), np.argmax(x)]]
        middle = points[np.argmin(np.abs(x - 0.5 * x.max()))]
        out.append(0.5 * (moves[:, ends[0]] + moves[:, ends[1]]) - moves[:, middle])
    return np.column_stack(out)


def installation_tolerance(mc: QuasiStaticMonteCarlo, errors: InstallationErrors, *, samples: int = 10_000,
                           seed: int = 0, level: int = 95) -> InstallationTolerance:
    """The crew's build tolerance of the mid-span pre-sag from per-dropper and per-mast errors.

    The percentile ``level`` of the largest |δS| over the analysed spans (:func:`presag_errors`) of
    each realisation: the ± tolerance within which the crew builds every span's pre-sag in that share
    of builds.

    Parameters
    ----------
    mc : QuasiStaticMonteCarlo
        The Monte Carlo of the section.
    errors : InstallationErrors
        Error sizes. [m]
    samples : int
        Realisations. [-]
    seed : int
        Seed of the draws. [-]
    level : int
        The percentile. [%]
    """
    worst = np.abs(presag_errors(mc, errors, mc.draws(samples, errors.distribution, seed))).max(axis=1)
    sizes = ", ".join(f"{name} {value * 1e3:g} mm" for name, value in (
        ("dropper", errors.dropper_length), ("registration", errors.contact_wire_height),
        ("messenger support", errors.messenger_height)) if value)
    return InstallationTolerance(
        half_width=float(np.percentile(worst, level)), kind="monte-carlo",
        source=f"P{level} of the mid-span pre-sag error over {samples} Monte Carlo builds "
               f"({errors.distribution} errors: {sizes or 'none'}; seed {seed})")
