"""Figures of a sensitivity analysis: the Morris μ*–σ plane and the Sobol bars (project style)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from presag_opt.sensitivity.methods import OutputIndices
from presag_opt.style import new_figure, save_figure, styled

LABELLED = 8
"""Inputs labelled in a Morris plot (the largest μ*). [-]"""


@styled
def plot_morris(table: OutputIndices, path: str | Path) -> Path:
    """μ* against σ of one output; the inputs with the largest μ* are labelled.

    Points on or above the line σ = μ* have effects that change sign or size across the input space
    (non-linear or interacting); points well below it act almost linearly.
    """
    fig, ax = new_figure(width=6.5, height=4.2)
    mu = np.array([e.mu_star for e in table.morris])
    sigma = np.array([e.sigma for e in table.morris])
    ax.errorbar(mu, sigma, xerr=[e.mu_star_conf for e in table.morris], fmt="o", ms=4, capsize=2)
    top = max(float(mu.max()), float(sigma.max()), 1e-12) * 1.1
    ax.plot([0, top], [0, top], color="0.6", lw=0.8, ls="--", label="σ = μ*")
    for e in table.morris[:LABELLED]:
        ax.annotate(e.name.split(".", 1)[-1], (e.mu_star, e.sigma), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel(f"μ* [{table.unit}]")
    ax.set_ylabel(f"σ [{table.unit}]")
    ax.set_title(f"Morris screening of {table.output}")
    ax.legend(loc="upper left")
    return save_figure(fig, path)


@styled
def plot_sobol(table: OutputIndices, path: str | Path) -> Path:
    """Bars of S1 and ST of one output with their confidence intervals, largest ST first."""
    rows = table.sobol
    fig, ax = new_figure(width=6.5, height=max(2.4, 0.32 * len(rows) + 1.0))
    y = np.arange(len(rows))[::-1]
    ax.barh(y + 0.18, [r.first for r in rows], height=0.36, xerr=[r.first_conf for r in rows], label="S1", capsize=2)
    ax.barh(y - 0.18, [r.total for r in rows], height=0.36, xerr=[r.total_conf for r in rows], label="ST", capsize=2)
    ax.set_yticks(y, [r.name.split(".", 1)[-1] for r in rows])
    ax.set_xlabel("index [-]")
    ax.set_title(f"Sobol indices of {table.output}")
    ax.legend(loc="lower right")
    return save_figure(fig, path)


def save_sensitivity_plots(result, folder: str | Path) -> list[Path]:
    """One figure per value of a :class:`~presag_opt.sensitivity.analysis.SensitivityResult` into ``folder``.

    Parameters
    ----------
    result : SensitivityResult
        The result to draw (its method picks the Morris or the Sobol figure).
    folder : str or Path
        Folder the figures are written into.

    Returns
    -------
    list of Path
        The figures written, one per value.
    """
    folder = Path(folder)
    draw = plot_morris if result.method == "morris" else plot_sobol
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", result.output)
    return [draw(t, folder / f"sensitivity_{stem}_{re.sub(r'[^A-Za-z0-9_.-]+', '_', t.output)}_{result.method}.png")
            for t in result.indices]
