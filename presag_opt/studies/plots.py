"""Figures of a validity study (the paper's Fig. 6, 7 and 8, and the steady-arm uplift).

Every figure is saved as PNG with units on every axis; legends sit outside the axes so they never
cover data.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib
import numpy as np
import xarray as xr

from presag_opt.errors import ModelError
from presag_opt.studies.validity_results import ValidityResult
from presag_opt.style import legend_outside, new_figure, save_figure, styled
from presag_opt.units import KMH

MM = 1e3
"""Metres to millimetres, for axes. [mm/m]"""


VALIDITY_FIGURES = ("fig6_ratio", "fig7_presag", "fig8_optimal_force", "uplift")
"""The figures of a validity study, by file name without ``.png``: σ/F_m against F_m per pre-sag
(Fig. 6), the pre-sag against β (Fig. 7), the optimal F_m against β (Fig. 8), the steady-arm uplift."""


def save_validity_plots(dataset: xr.Dataset, result: ValidityResult, folder: str | Path,
                        selection: dict[str, float] | None = None,
                        figures: tuple[str, ...] = VALIDITY_FIGURES) -> list[Path]:
    """Save fig6_ratio.png, fig7_presag.png, fig8_optimal_force.png and uplift.png into ``folder``.

    Parameters
    ----------
    dataset : xarray.Dataset
        The study store's content.
    result : ValidityResult
        Its analysis.
    folder : str or pathlib.Path
        Output folder (created if missing).
    selection : dict, optional
        Values of the extra swept parameters, as given to the analysis. [SI]
    figures : tuple of str
        Which of :data:`VALIDITY_FIGURES` to draw (default all), in this order.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    unknown = [name for name in figures if name not in VALIDITY_FIGURES]
    if unknown:
        raise ModelError(f"figures = {unknown} are not validity figures ({', '.join(VALIDITY_FIGURES)})")
    out = Path(folder)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(f"--plot {folder}: cannot create the folder ({exc.strerror})") from None
    ds = dataset.sel(selection or {}, method="nearest").transpose("presag", "speed", "static_force")
    draw = {
        "fig6_ratio": lambda path: _fig6(ds, result, path),
        "fig7_presag": lambda path: _fig7(result, path),
        "fig8_optimal_force": lambda path: _fig8(result, path),
        "uplift": lambda path: _uplift(ds, path),
    }
    return [draw[name](out / f"{name}.png") for name in figures]


def _grid(count: int) -> tuple[matplotlib.figure.Figure, np.ndarray]:
    """Panels in rows of up to four, with room for a legend right of them."""
    cols = min(count, 4)
    rows = math.ceil(count / cols)
    fig, axes = new_figure(rows, cols, width=3.6 * cols, height=3.0 * rows, legend=True, squeeze=False, sharey=True)
    for ax in axes.flat[count:]:
        ax.set_visible(False)
    return fig, axes


@styled
def _fig6(ds: xr.Dataset, result: ValidityResult, path: Path) -> Path:
    presags = ds["presag"].values
    fig, axes = _grid(len(presags))
    betas = ds["beta"].isel(presag=0).values
    colours = matplotlib.colormaps["viridis"](np.linspace(0.0, 0.9, len(betas)))
    for i, (ax, s) in enumerate(zip(axes.flat, presags)):
        for j in np.argsort(betas):
            ax.plot(ds["F_m"].values[i, j], ds["sigma_over_F_m"].values[i, j], "o-", ms=3, color=colours[j],
                    label=f"β = {betas[j]:.2f}")
        for o in result.force_optima:
            if o.presag == s and o.ratio.distinct:
                ax.plot(o.ratio.location, o.ratio.value, "kx", ms=7)
        ax.set_title(f"S = {s * MM:g} mm")
        ax.set_xlabel("F_m [N]")
    for ax in axes[:, 0]:
        ax.set_ylabel("σ / F_m [-]")
    legend_outside(fig, axes.flat[0], title="× distinct minimum")
    return save_figure(fig, path)


@styled
def _fig7(result: ValidityResult, path: Path) -> Path:
    fig, axes = _grid(len(result.per_beta))
    for ax, verdict in zip(axes.flat, result.per_beta):
        fm = np.array([b.mean_force for b in verdict.bands])
        low = np.array([b.band_low for b in verdict.bands]) * MM
        high = np.array([b.band_high for b in verdict.bands]) * MM
        ax.fill_between(fm, low, high, color="tab:blue", alpha=0.2, label="near-optimal S (σ)")
        optimal = [(b.mean_force, b.optimal * MM) for b in verdict.bands if b.optimal is not None]
        if optimal:
            ax.plot(*zip(*optimal), "o", color="tab:blue", ms=4, label="optimal S (σ)")
        ax.plot(fm, [b.presag_delta_e * MM for b in verdict.bands], "k--", label="Δe rule")
        ax.plot(fm, [b.presag_mid_mast * MM for b in verdict.bands], "k:", label="mid/mast rule")
        ax.set_title(f"β = {verdict.beta:.2f} ({'holds' if verdict.holds else 'fails'})")
        ax.set_xlabel("F_m [N]")
    for ax in axes[:, 0]:
        ax.set_ylabel("pre-sag S [mm]")
    legend_outside(fig, axes.flat[0])
    return save_figure(fig, path)


@styled
def _fig8(result: ValidityResult, path: Path) -> Path:
    fig, axes = new_figure(1, 2, width=8.0, height=4.2, legend=True, sharey=True)
    presags = sorted({o.presag for o in result.force_optima})
    for s in presags:
        points = [o for o in result.force_optima if o.presag == s]
        for ax, which in zip(axes, ("sigma", "ratio")):
            found = [(o.beta, getattr(o, which).location) for o in points if getattr(o, which).distinct]
            xs, ys = zip(*found) if found else ((), ())
            ax.plot(xs, ys, "o-", label=f"S = {s * MM:g} mm")
    axes[0].set_title("(a) minima of σ")
    axes[1].set_title("(b) minima of σ / F_m")
    for ax in axes:
        ax.set_xlabel("β = v / c_CW [-]")
    axes[0].set_ylabel("optimal F_m [N]")
    legend_outside(fig, axes[0])
    return save_figure(fig, path)


@styled
def _uplift(ds: xr.Dataset, path: Path) -> Path:
    fig, ax = new_figure(width=7.0, height=4.2, legend=True)
    betas = ds["beta"].isel(presag=0).values
    order = np.argsort(betas)
    for i, s in enumerate(ds["presag"].values):
        worst = np.nanmax(ds["uplift_max"].values[i], axis=-1, initial=-np.inf)
        ax.plot(betas[order], worst[order] * MM, "o-", label=f"S = {s * MM:g} mm")
    limit = float(ds.attrs["uplift_limit"])
    ax.axhline(limit * MM, color="r", ls="--", label=f"limit {limit * MM:g} mm")
    ax.set_xlabel("β = v / c_CW [-]")
    ax.set_ylabel("max steady-arm uplift over F_stat [mm]")
    kmh_per_beta = float(ds["speed"].values[0] / betas[0]) / KMH
    top = ax.secondary_xaxis("top", functions=(lambda b: b * kmh_per_beta, lambda v: v / kmh_per_beta))
    top.set_xlabel("train speed v [km/h]")
    legend_outside(fig, ax)
    return save_figure(fig, path)
