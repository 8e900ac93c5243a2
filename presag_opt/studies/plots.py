"""Figures of a validity study (the paper's Fig. 6, 7 and 8, and the steady-arm uplift).

Every figure is saved as PNG with units on every axis; legends sit outside the axes so they never
cover data.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from presag_opt.errors import ModelError  # noqa: E402
from presag_opt.studies.validity import ValidityResult  # noqa: E402

MM = 1e3
"""Metres to millimetres, for axes. [mm/m]"""


def save_validity_plots(dataset: xr.Dataset, result: ValidityResult, folder: str | Path,
                        selection: dict[str, float] | None = None) -> list[Path]:
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

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    out = Path(folder)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(f"--plot {folder}: cannot create the folder ({exc.strerror})") from None
    ds = dataset.sel(selection or {}, method="nearest").transpose("presag", "speed", "static_force")
    return [
        _fig6(ds, result, out / "fig6_ratio.png"),
        _fig7(result, out / "fig7_presag.png"),
        _fig8(result, out / "fig8_optimal_force.png"),
        _uplift(ds, out / "uplift.png"),
    ]


LEGEND_WIDTH = 2.8
"""Width kept free for a figure legend right of the axes. [inch]"""


def _grid(count: int) -> tuple[plt.Figure, np.ndarray]:
    """Panels in rows of up to four, with room for a legend right of them."""
    cols = min(count, 4)
    rows = math.ceil(count / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols + LEGEND_WIDTH, 3.0 * rows), squeeze=False,
                             sharey=True)
    for ax in axes.flat[count:]:
        ax.set_visible(False)
    return fig, axes


def _legend_right(fig: plt.Figure, ax: plt.Axes, title: str | None = None) -> None:
    """A figure legend in the free strip right of the axes, never over data."""
    room = LEGEND_WIDTH / fig.get_figwidth()
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="center left", bbox_to_anchor=(1.0 - room, 0.5), title=title)
    fig.tight_layout(rect=(0, 0, 1.0 - room, 1))


def _fig6(ds: xr.Dataset, result: ValidityResult, path: Path) -> Path:
    presags = ds["presag"].values
    fig, axes = _grid(len(presags))
    betas = ds["beta"].isel(presag=0).values
    colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(betas)))
    for i, (ax, s) in enumerate(zip(axes.flat, presags)):
        for j in np.argsort(betas):
            ax.plot(ds["F_m"].values[i, j], ds["sigma_over_F_m"].values[i, j], "o-", ms=3, color=colours[j],
                    label=f"β = {betas[j]:.2f}")
        for o in result.force_optima:
            if o.presag == s and o.ratio.distinct:
                ax.plot(o.ratio.location, o.ratio.value, "kx", ms=7)
        ax.set_title(f"S = {s * MM:g} mm")
        ax.set_xlabel("F_m [N]")
        ax.grid(True, alpha=0.3)
    for ax in axes[:, 0]:
        ax.set_ylabel("σ / F_m [-]")
    _legend_right(fig, axes.flat[0], title="× distinct minimum")
    return _save(fig, path)


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
        ax.grid(True, alpha=0.3)
    for ax in axes[:, 0]:
        ax.set_ylabel("pre-sag S [mm]")
    _legend_right(fig, axes.flat[0])
    return _save(fig, path)


def _fig8(result: ValidityResult, path: Path) -> Path:
    fig, axes = plt.subplots(1, 2, figsize=(8 + LEGEND_WIDTH, 4.2), sharey=True)
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
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("optimal F_m [N]")
    _legend_right(fig, axes[0])
    return _save(fig, path)


def _uplift(ds: xr.Dataset, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(8, 4.2))
    betas = ds["beta"].isel(presag=0).values
    order = np.argsort(betas)
    for i, s in enumerate(ds["presag"].values):
        worst = np.nanmax(ds["uplift_max"].values[i], axis=-1, initial=-np.inf)
        ax.plot(betas[order], worst[order] * MM, "o-", label=f"S = {s * MM:g} mm")
    limit = float(ds.attrs["uplift_limit"])
    ax.axhline(limit * MM, color="r", ls="--", label=f"limit {limit * MM:g} mm")
    ax.set_xlabel("β = v / c_CW [-]")
    ax.set_ylabel("max steady-arm uplift over F_stat [mm]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return _save(fig, path)


def _save(fig: plt.Figure, path: Path) -> Path:
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
