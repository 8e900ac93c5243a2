"""Figures. Plotting stays out of the physics modules; every function saves to a file."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from presag_opt.elasticity import ElasticityStudy  # noqa: E402


def plot_elasticity(study: ElasticityStudy, path: str | Path) -> Path:
    """Elasticity along the span for every curve of a study (like the paper's Fig. 3/4).

    Parameters
    ----------
    study : ElasticityStudy
        Curves to draw.
    path : str or Path
        Output file; the suffix selects the format (png, pdf, svg).
    """
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for curve in study.curves:
        label = "linear (tangent stiffness)" if curve.force is None else f"F = {curve.force:g} N"
        style = "k--" if curve.force is None else "-"
        ax.plot(curve.position, curve.elasticity * 1e3, style, label=label)
    ax.set_xlabel("position in span x [m]")
    ax.set_ylabel("elasticity e [mm/N]")
    ax.set_title(f"{study.catenary_name}: span {study.span + 1}")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path
