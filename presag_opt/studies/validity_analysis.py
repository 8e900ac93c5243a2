"""Validity analysis of a study: where does the quasi-static pre-sag rule stop matching dynamics?

The criteria below fill the named results of :mod:`presag_opt.studies.validity_results`.

The analysis reads a study store (one combination of any extra parameters) and reproduces the
paper's figures as numbers (Schick, Liu, Stichel 2025, doi:10.1108/RS-05-2025-0016, sections
5.2–5.3):

- **Fig. 6** – σ/F_m against the measured F_m, per pre-sag S and speed ratio β. A cubic spline
  (not-a-knot) through the static-force grid gives the minimum. The minimum is *distinct* if it lies
  strictly inside the F_m band and the spline rises by at least :data:`DISTINCT_RISE` (5 %) from it
  to both ends of the band. 5 % is several times the numerical scatter of σ (the case file's
  lead-in check: < 0.5 %; the simulator's time-step and mesh convergence: about 1 %), so a distinct
  minimum is not noise, yet small enough to keep the shallow minima the paper still reads near
  β = 0.35.
- **Fig. 8** – the F_m of those minima per S against β, from σ (8a) and from σ/F_m (8b); a
  minimum that is not distinct is reported as missing, never invented.
- **Fig. 7** – per β and static force (nominal F_m = F_stat + α_ae v²): σ against S through a
  cubic spline; the *dynamically optimal S* is its minimum if that lies strictly inside the S grid;
  the *near-optimal band* is the connected range of S around the minimum where σ stays within
  :data:`NEAR_OPTIMAL_MARGIN` (5 %) of it (a band reaching an end of the grid is open on that
  side). The pre-sag has a *benefit* at that point if σ somewhere on the grid exceeds the minimum
  by more than the margin; otherwise every S is near-optimal and S does not matter. Beside it the
  quasi-static Δe and mid/mast rules, from the elasticity of the study's catenary at the nominal
  F_m. Elasticity depends on the pre-sag built, so each rule is evaluated on every S of the grid
  and its value is the self-consistent one, S_rule(S) = S, found by linear interpolation between
  the grid's S (or from the least-squares line through them when the crossing lies outside).
- **Validity limit β\\*** – the Δe rule *holds* at a β if the pre-sag has a benefit at more than
  half of the static forces (:data:`HOLD_SHARE`) and, among those, the rule lies inside the
  near-optimal band at more than half. β\\* is the lowest β, above the lowest β at which the rule
  holds, at which it no longer holds (the rule left the band, or the pre-sag's benefit vanished),
  placed midway between it and the β below, with half that interval as its uncertainty. Failures
  below the first holding β (e.g. S hardly mattering at the lowest speeds) are named in the
  ``criterion`` text but do not set β\\*. This reads the limit from σ and the optimal-S band, so it
  exists even where σ/F_m has no distinct minimum at all (on a pantograph whose σ keeps a floor
  that hardly depends on S); the ``criterion`` string says which case applies.
- **Fit** – S_dyn = S_stat + k·β^a (paper eq. 7) by least squares through every interior optimal
  S at a β with benefit, with S_stat the Δe rule; r² is that of the correction S_dyn − S_stat.
  Optima that cannot support the law give *no fit* with the reason: fewer than three at two β, an
  optimum that does not move from the rule, an exponent on its bound, or r² below
  :data:`FIT_MIN_R2`.
- **Uplift** – the largest steady-arm uplift of the grid against the study's limit.
- **Pantograph** – a study with two raised pantographs stores both pantographs' statistics; the
  analysis reads one of them (:func:`pantograph_view`). The default is the *trailing* one: it runs
  into the wire the leading one has set swinging, so its σ is the larger and it is the pantograph
  that limits the line (the uplift is the run's, the same for both).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from scipy.interpolate import make_interp_spline
from scipy.optimize import curve_fit

from presag_opt.errors import ModelError
from presag_opt.studies.validity_results import (
    BetaVerdict,
    ForceOptimum,
    Minimum,
    PowerFit,
    PresagBand,
    UpliftCheck,
    ValidityResult,
)

DISTINCT_RISE = 0.05
"""Relative rise from a σ/F_m (or σ) minimum to both band ends that makes it distinct. [-]"""

NEAR_OPTIMAL_MARGIN = 0.05
"""σ within this share of its minimum over S counts as near-optimal. [-]"""

HOLD_SHARE = 0.5
"""Share of static forces (exceeded) at which the pre-sag must have a benefit and the rule lie in the band. [-]"""

FIT_MIN_R2 = 0.8
"""Smallest r² of the eq. 7 correction reported as a fit: below it k·β^a explains less than 80 % of
the spread of S_opt − S_Δe, and k and a describe the noise of the optima, not a law. [-]"""

FIT_EXPONENT_BOUNDS = (0.05, 20.0)
"""Range of the fitted exponent a; a fit whose a ends on either bound is no fit. [-]"""

FIT_MIN_SHIFT = 1e-4
"""Largest |S_opt − S_Δe| below which the optimum has not moved and there is nothing to fit
(0.1 mm, below any pre-sag grid's resolution). [m]"""

PANTOGRAPHS = ("leading", "trailing")
"""Pantographs of a two-pantograph study the analysis can read. [-]"""

DENSE_POINTS = 2001
"""Points at which splines are evaluated to find minima and band edges. [-]"""


def pantograph_view(dataset: xr.Dataset, pantograph: str | None = None) -> tuple[xr.Dataset, str]:
    """The dataset with one pantograph's statistics under the standard names (``F_m``, ``sigma``, ...).

    Parameters
    ----------
    dataset : xarray.Dataset
        A study store's content.
    pantograph : {"leading", "trailing"}, optional
        Which pantograph; default the trailing one of a two-pantograph study (see the module notes),
        the only one otherwise.

    Returns
    -------
    (xarray.Dataset, str)
        The dataset to analyse and plot, and the pantograph read.

    Raises
    ------
    ModelError
        An unknown name, or the trailing pantograph of a single-pantograph study.
    """
    from presag_opt.studies.store import TRAILING_PREFIX, TRAILING_VARIABLES

    two = TRAILING_PREFIX + "F_m" in dataset
    if pantograph is None:
        pantograph = "trailing" if two else "leading"
    if pantograph not in PANTOGRAPHS:
        raise ModelError(f"pantograph = {pantograph!r} is not one of {', '.join(PANTOGRAPHS)}")
    if pantograph == "leading":
        return dataset, pantograph
    if not two:
        raise ModelError("pantograph = 'trailing': this study ran one pantograph (no [train] second_pantograph_at); "
                         "analyse the leading one")
    names = (*TRAILING_VARIABLES, "sigma_over_F_m")
    view = dataset.assign({name: dataset[TRAILING_PREFIX + name] for name in names})
    return view, pantograph


def validity_analysis(dataset: xr.Dataset, selection: dict[str, float] | None = None,
                      pantograph: str | None = None) -> ValidityResult:
    """Analyse a study dataset (see the module notes for every criterion).

    Parameters
    ----------
    dataset : xarray.Dataset
        A study store's content (:func:`presag_opt.studies.store.open_store`).
    selection : dict, optional
        Value of each extra swept parameter (dotted name -> SI value), required if there are any.
    pantograph : {"leading", "trailing"}, optional
        The pantograph of a two-pantograph study to read (default trailing, see
        :func:`pantograph_view`); ``settings["pantograph"]`` of the result names it.

    Returns
    -------
    ValidityResult
    """
    dataset, pantograph = pantograph_view(dataset, pantograph)
    ds = _select(dataset, selection or {})
    presags = ds["presag"].values
    speeds = ds["speed"].values
    forces = ds["static_force"].values
    betas = ds["beta"].isel(presag=0).values
    order = np.argsort(betas)
    optima = tuple(
        ForceOptimum(presag=float(s), speed=float(speeds[j]), beta=float(betas[j]),
                     ratio=_minimum(ds["F_m"].values[i, j], ds["sigma_over_F_m"].values[i, j]),
                     sigma=_minimum(ds["F_m"].values[i, j], ds["sigma"].values[i, j]))
        for i, s in enumerate(presags) for j in order
    )
    verdicts = []
    for j in order:
        bands = tuple(
            _band(presags, ds["sigma"].values[:, j, f], float(forces[f]), float(ds["F_m_nominal"].values[j, f]),
                  ds["presag_delta_e"].values[:, j, f], ds["presag_mid_mast"].values[:, j, f])
            for f in range(len(forces))
        )
        with_benefit = [b for b in bands if b.benefit]
        holds = (len(with_benefit) > HOLD_SHARE * len(bands)
                 and sum(b.rule_inside for b in with_benefit) > HOLD_SHARE * len(with_benefit))
        verdicts.append(BetaVerdict(speed=float(speeds[j]), beta=float(betas[j]), bands=bands, holds=holds))
    limit, uncertainty, reading = _limit(verdicts)
    distinct = sum(o.ratio.distinct for o in optima)
    if distinct:
        ratio_text = f"sigma/F_m has a distinct minimum in {distinct} of {len(optima)} (S, beta) curves"
    else:
        ratio_text = ("sigma/F_m has no distinct minimum on this grid, so the limit is read from sigma and the "
                      "optimal-S band only")
    criterion = (f"{reading}; the Delta-e rule holds at a beta if S matters (sigma varies by more than "
                 f"{NEAR_OPTIMAL_MARGIN:.0%} over S) at more than {HOLD_SHARE:.0%} of the static forces and the "
                 f"rule lies within the near-optimal S band (sigma within {NEAR_OPTIMAL_MARGIN:.0%} of its minimum) "
                 f"at more than {HOLD_SHARE:.0%} of those; {ratio_text}")
    fit, no_fit_reason = _fit(verdicts)
    return ValidityResult(
        beta_limit=limit, beta_limit_uncertainty=uncertainty, criterion=criterion, fit=fit,
        per_beta=tuple(verdicts), force_optima=optima, uplift=_uplift(ds), no_fit_reason=no_fit_reason,
        settings={"distinct_rise": DISTINCT_RISE, "near_optimal_margin": NEAR_OPTIMAL_MARGIN,
                  "hold_share": HOLD_SHARE, "fit_min_r2": FIT_MIN_R2,
                  "fit_exponent_bounds": list(FIT_EXPONENT_BOUNDS), "pantograph": pantograph},
    )


def _select(dataset: xr.Dataset, selection: dict[str, float]) -> xr.Dataset:
    """The dataset at one combination of the extra parameters, dims (presag, speed, static_force)."""
    extra = [d for d in dataset["F_m"].dims if d not in ("presag", "speed", "static_force")]
    unknown = sorted(set(selection) - set(extra))
    if unknown:
        raise ModelError(f"selection: {unknown[0]!r} is not a swept parameter of this study "
                         f"(swept: {', '.join(extra) or 'none'})")
    missing = [d for d in extra if d not in selection]
    if missing:
        values = ", ".join(f"{v:g}" for v in dataset[missing[0]].values)
        raise ModelError(f"selection: give a value of the swept parameter {missing[0]} (one of {values})")
    for name, value in selection.items():
        if not np.any(np.isclose(dataset[name].values, value, rtol=1e-12, atol=0.0)):
            values = ", ".join(f"{v:g}" for v in dataset[name].values)
            raise ModelError(f"selection: {name} = {value:g} is not a grid value (one of {values})")
    return dataset.sel(selection, method="nearest").transpose("presag", "speed", "static_force")


def _spline(x: np.ndarray, y: np.ndarray):
    """Interpolating spline (cubic, not-a-knot; lower degree with fewer points) through finite points."""
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    order = np.argsort(x)
    x, y = x[order], y[order]
    if len(x) < 2 or np.any(np.diff(x) <= 0.0):
        return None, x
    return make_interp_spline(x, y, k=min(3, len(x) - 1)), x


def _minimum(x: np.ndarray, y: np.ndarray) -> Minimum:
    """Minimum of the spline of y over x and whether it is distinct (see :data:`DISTINCT_RISE`)."""
    spline, xs = _spline(x, y)
    if spline is None:
        return Minimum(location=None, value=math.nan, distinct=False)
    dense = np.linspace(xs[0], xs[-1], DENSE_POINTS)
    values = spline(dense)
    i = int(np.argmin(values))
    low = values[i]
    interior = 0 < i < len(dense) - 1
    distinct = interior and low > 0.0 and min(values[0], values[-1]) >= (1.0 + DISTINCT_RISE) * low
    return Minimum(location=float(dense[i]) if distinct else None, value=float(low), distinct=bool(distinct))


def _band(presags: np.ndarray, sigma: np.ndarray, static_force: float, mean_force: float,
          rule_delta_e: np.ndarray, rule_mid_mast: np.ndarray) -> PresagBand:
    """Fig. 7 at one β and static force (see the module notes)."""
    rules = {"presag_delta_e": _self_consistent(presags, rule_delta_e),
             "presag_mid_mast": _self_consistent(presags, rule_mid_mast)}
    spline, xs = _spline(presags, sigma)
    if spline is None:
        return PresagBand(static_force=static_force, mean_force=mean_force, optimal=None, band_low=math.nan,
                          band_high=math.nan, open_low=False, open_high=False, benefit=False, **rules)
    dense = np.linspace(xs[0], xs[-1], DENSE_POINTS)
    values = spline(dense)
    i = int(np.argmin(values))
    near = values <= (1.0 + NEAR_OPTIMAL_MARGIN) * values[i]
    lo = i
    while lo > 0 and near[lo - 1]:
        lo -= 1
    hi = i
    while hi < len(dense) - 1 and near[hi + 1]:
        hi += 1
    return PresagBand(
        static_force=static_force, mean_force=mean_force,
        optimal=float(dense[i]) if 0 < i < len(dense) - 1 else None,
        band_low=float(dense[lo]), band_high=float(dense[hi]),
        open_low=lo == 0, open_high=hi == len(dense) - 1,
        benefit=bool(not near.all()), **rules,
    )


def _self_consistent(presags: np.ndarray, rule: np.ndarray) -> float:
    """S with S_rule(S) = S, from the rule evaluated on every S of the grid. [m]"""
    keep = np.isfinite(rule)
    s, gap = presags[keep], rule[keep] - presags[keep]
    if len(s) == 0:
        return math.nan
    if len(s) == 1:
        return float(rule[keep][0])
    crossings = np.nonzero(np.sign(gap[:-1]) * np.sign(gap[1:]) <= 0.0)[0]
    if len(crossings):
        i = crossings[0]
        if gap[i] == gap[i + 1]:
            return float(s[i])
        return float(s[i] - gap[i] * (s[i + 1] - s[i]) / (gap[i + 1] - gap[i]))
    slope, intercept = np.polyfit(s, gap, 1)
    return float(-intercept / slope) if slope != 0.0 else float(np.mean(rule[keep]))


def _limit(verdicts: list[BetaVerdict]) -> tuple[float | None, float | None, str]:
    """β*, its uncertainty and how it was found (verdicts sorted by β).

    β* is where the rule *leaves* the band: the first failing β above the lowest β at which it
    holds. Failures below that (e.g. S not mattering at the lowest speeds) are named in the text.
    """
    holding = [i for i, v in enumerate(verdicts) if v.holds]
    if not holding:
        return None, None, "the rule holds at no beta of the grid (" + (
            _failure_cause(verdicts[0]) if verdicts else "no speeds") + " at the lowest): no limit can be read"
    start = holding[0]
    before = "" if start == 0 else f"the rule does not hold below beta {verdicts[start].beta:.3f} ({_failure_cause(verdicts[0])}); "
    failing = [i for i in range(start, len(verdicts)) if not verdicts[i].holds]
    if not failing:
        return None, None, before + (f"the rule holds from beta {verdicts[start].beta:.3f} up to the highest beta of the "
                                     f"grid ({verdicts[-1].beta:.3f}): beta* is above the grid")
    first = failing[0]
    low, high = verdicts[first - 1].beta, verdicts[first].beta
    return (low + high) / 2.0, (high - low) / 2.0, before + (
        f"beta* lies between the last holding beta {low:.3f} and the first failing beta {high:.3f} "
        f"({_failure_cause(verdicts[first])})")


def _failure_cause(verdict: BetaVerdict) -> str:
    with_benefit = [b for b in verdict.bands if b.benefit]
    if len(with_benefit) <= HOLD_SHARE * len(verdict.bands):
        return "the pre-sag's benefit on sigma vanished"
    return "the Delta-e rule left the near-optimal band"


def _fit(verdicts: list[BetaVerdict]) -> tuple[PowerFit | None, str]:
    """Least-squares fit of S_opt − S_Δe = k·β^a (paper eq. 7), or None and why the optima cannot
    support one (see :data:`FIT_MIN_R2`, :data:`FIT_EXPONENT_BOUNDS`, :data:`FIT_MIN_SHIFT`)."""
    points = [(v.beta, b.optimal - b.presag_delta_e) for v in verdicts if v.beta > 0.0 for b in v.bands
              if b.benefit and b.optimal is not None and math.isfinite(b.presag_delta_e)]
    if len(points) < 3 or len({p[0] for p in points}) < 2:
        return None, (f"{len(points)} interior optima at {len({p[0] for p in points})} speed ratios; the fit needs "
                      "at least three at two")
    beta, shift = np.array(points).T
    if float(np.max(np.abs(shift))) <= FIT_MIN_SHIFT:
        return None, (f"the optimum does not move from the Delta-e rule (|S_opt - S_Delta-e| <= {FIT_MIN_SHIFT * 1e3:g} mm "
                      "at every point): no dynamic correction to fit")

    def model(b, k, a):
        return k * b**a

    low, high = FIT_EXPONENT_BOUNDS
    try:
        (k, a), _ = curve_fit(model, beta, shift, p0=(float(np.mean(shift)) or 1e-3, 1.0),
                              bounds=([-np.inf, low], [np.inf, high]), maxfev=20000)
    except (RuntimeError, ValueError):
        return None, "the least-squares fit of k*beta^a did not converge"
    residual = float(np.sum((shift - model(beta, k, a)) ** 2))
    total = float(np.sum((shift - shift.mean()) ** 2))
    r2 = 1.0 - residual / total if total > 0.0 else math.nan
    if min(a - low, high - a) <= 1e-3 * (high - low):  # the solver stops just short of an active bound
        return None, (f"the exponent ran to its bound a = {a:.3g} (bounds {low:g}-{high:g}; r² {r2:.2f}, "
                      f"{len(points)} optima): the optima do not follow k*beta^a")
    if not r2 >= FIT_MIN_R2:
        return None, (f"r² = {r2:.2f} is below {FIT_MIN_R2:g} (k = {k * 1e3:.1f} mm, a = {a:.2f}, {len(points)} optima): "
                      "the optima do not follow k*beta^a")
    return PowerFit(k=float(k), a=float(a), r2=r2, points=len(points)), ""


def _uplift(ds: xr.Dataset) -> UpliftCheck | None:
    uplift = ds["uplift_max"].values
    if not np.any(np.isfinite(uplift)):
        return None
    i, j, f = np.unravel_index(int(np.nanargmax(uplift)), uplift.shape)
    return UpliftCheck(maximum=float(uplift[i, j, f]), limit=float(ds.attrs["uplift_limit"]),
                       presag=float(ds["presag"][i]), speed=float(ds["speed"][j]),
                       static_force=float(ds["static_force"][f]))
