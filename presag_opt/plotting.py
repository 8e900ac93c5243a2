"""Figures. Plotting stays out of the physics modules; every function saves to a file."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from presag_opt.elasticity import ElasticityStudy  # noqa: E402

if TYPE_CHECKING:
    from presag_opt.design import Recommendation
    from presag_opt.validation import SingleCurveError


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
    return _save(fig, path)


def plot_presag_against_force(recommendation: Recommendation, path: str | Path) -> Path:
    """Quasi-static pre-sag against the mean contact force, both variants, every layout (like Fig. 5a).

    Solid lines use e_mid − e_mast, dashed lines Δe = e_max − e_min; the shaded band is the
    operating F_m band and the horizontal line the recommended S_rel. The right axis gives S on a
    span of the nominal length.

    Parameters
    ----------
    recommendation : Recommendation
        Result of :func:`presag_opt.design.recommend`.
    path : str or Path
        Output file; the suffix selects the format (png, pdf, svg).

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, Fig. 5a.
    """
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for i, lay in enumerate(recommendation.layouts):
        color = f"C{i}"
        label = f"{lay.layout_kind}: {lay.catenary_name}"
        ax.plot(lay.mean_forces, lay.presag_rel_mid_mast * 1e3, "-", color=color, label=f"{label}, e_mid − e_mast")
        ax.plot(lay.mean_forces, lay.presag_rel_delta_e * 1e3, "--", color=color, label=f"{label}, Δe")
    low, high = recommendation.mean_force_band
    ax.axvspan(low, high, color="0.9", zorder=0, label=f"F_m band {low:.0f}–{high:.0f} N")
    ax.axhline(recommendation.presag_rel * 1e3, color="k", lw=0.8, label=f"recommended {recommendation.presag_rel * 1e3:.2f} ‰")
    ax.set_xlabel("mean contact force F_m [N]")
    ax.set_ylabel("relative pre-sag S_rel [‰]")
    span = recommendation.nominal_span_length
    right = ax.secondary_yaxis("right", functions=(lambda r: r * span, lambda s: s / span))
    right.set_ylabel(f"pre-sag S on a {span:g} m span [mm]")
    ax.set_title(f"Quasi-static pre-sag (range and recommendation from the {recommendation.method} variant)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    return _save(fig, path)


def plot_single_curve_error(studies: Sequence[SingleCurveError], path: str | Path) -> Path:
    """Pre-sag from interpolated curves against one curve, and the relative error (like Fig. 5b).

    Parameters
    ----------
    studies : sequence of SingleCurveError
        One per geometry (e.g. 30 mm and 70 mm pre-sag).
    path : str or Path
        Output file; the suffix selects the format (png, pdf, svg).

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, Fig. 5b.
    """
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for i, study in enumerate(studies):
        color = f"C{i}"
        geometry = f"{study.geometry_presag * 1e3:.0f} mm geometry"
        top.plot(study.mean_forces, study.presag_interpolated * 1e3, "-", color=color, label=f"{geometry}, interpolated")
        top.plot(
            study.mean_forces, study.presag_single_curve * 1e3, ":", color=color,
            label=f"{geometry}, {study.reference_force:g} N curve only",
        )
        bottom.plot(study.mean_forces, study.relative_error * 100, "-", color=color, label=geometry)
    top.set_ylabel("pre-sag S [mm]")
    top.grid(True, alpha=0.3)
    top.legend(fontsize=7)
    bottom.set_xlabel("mean contact force F_m [N]")
    bottom.set_ylabel("relative error [%]")
    bottom.grid(True, alpha=0.3)
    bottom.legend(fontsize=7)
    fig.suptitle(f"One elasticity curve instead of interpolation ({studies[0].catenary_name})" if studies else "")
    return _save(fig, path)


from presag_opt.dynamics.simulate import SimulationResult  # noqa: E402


def plot_contact_force(results: SimulationResult | list[SimulationResult], path: str | Path) -> Path:
    """Contact force against position, raw and 20 Hz filtered, one panel per run.

    The analysed section is shaded; each pantograph of a train gets its own colour.

    Parameters
    ----------
    results : SimulationResult or list of SimulationResult
        Runs to draw (e.g. one per speed).
    path : str or Path
        Output file; the suffix selects the format (png, pdf, svg).
    """
    runs = [results] if isinstance(results, SimulationResult) else list(results)
    fig, axes = plt.subplots(len(runs), 1, figsize=(9, 3.2 * len(runs)), squeeze=False)
    for ax, run in zip(axes[:, 0], runs):
        ax.axvspan(*run.analysed_section, color="0.9", label="analysed section")
        for i, panto in enumerate(run.pantographs):
            colour = f"C{i}"
            label = panto.name if len(run.pantographs) == 1 else f"{panto.name} (+{panto.offset:g} m)"
            ax.plot(panto.position, panto.contact_force, color=colour, alpha=0.3, linewidth=0.6)
            ax.plot(panto.position, panto.contact_force_filtered, color=colour, linewidth=1.2, label=f"{label}, filtered")
        stats = run.statistics
        ax.axhline(stats.mean_force, color="k", linewidth=0.8, linestyle="--")
        ax.set_title(
            f"{run.catenary_name}: {run.operation.speed * 3.6:g} km/h (β = {run.speed_ratio:.2f}), "
            f"F_m = {stats.mean_force:.1f} N, σ = {stats.std_force:.1f} N",
            fontsize=9,
        )
        ax.set_ylabel("contact force [N]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel("position along the section [m]")
    return _save(fig, path)


def plot_batch_statistics(batch, path: str | Path) -> Path:
    """σ/F_m and σ against speed, one line per static force, for a batch of runs.

    Parameters
    ----------
    batch : presag_opt.dynamics.batch.BatchResult
        Runs on a grid of speeds × static forces (failed runs are left out).
    path : str or Path
        Output file; the suffix selects the format (png, pdf, svg).
    """
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    forces = sorted({r.point.static_force for r in batch.runs})
    for i, force in enumerate(forces):
        runs = sorted((r for r in batch.runs if r.ok and r.point.static_force == force), key=lambda r: r.point.speed)
        speed = [r.point.speed * 3.6 for r in runs]
        top.plot(speed, [r.statistics[0].sigma_over_mean for r in runs], "o-", color=f"C{i}", label=f"{force:g} N")
        bottom.plot(speed, [r.statistics[0].std_force for r in runs], "o-", color=f"C{i}")
    top.set_ylabel("σ/F_m [-]")
    bottom.set_ylabel("σ [N]")
    bottom.set_xlabel("speed [km/h]")
    top.set_title(f"{batch.catenary_name}: contact-force statistics ({batch.pantograph_names[0]})", fontsize=9)
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
    top.legend(title="F_stat", fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return _save(fig, path)


def plot_waviness(study, path: str | Path) -> Path:
    """Worst-case and per-force waviness R against the parabolic pre-sag S over the band.

    Parameters
    ----------
    study : presag_opt.robust.RobustStudy
        The study to draw.
    path : str or Path
        Output file.
    """
    import numpy as np

    model = study.path
    l_ref = study.reference_span
    rel = np.linspace(0.0, 2.0 * max(study.robust_parabola.presag_rel, study.nominal.presag_rel), 200)
    forces = study.scenarios.forces
    waviness = np.array([model.waviness(model.parabola_depths(s), forces).max(axis=1) for s in rel])  # (S, K)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    s_mm = rel * l_ref * 1e3
    for k in range(0, len(forces), max(1, len(forces) // 6)):
        ax.plot(s_mm, waviness[:, k] * 1e3, color="0.7", lw=0.8)
    ax.plot([], [], color="0.7", lw=0.8, label="R at single forces of the band")
    ax.plot(s_mm, waviness.max(axis=1) * 1e3, "k", lw=2, label="worst case over the band")
    tol = study.tolerance
    ax.axvspan(tol.low * l_ref * 1e3, tol.high * l_ref * 1e3, color="tab:green", alpha=0.2,
               label=f"tolerance (within {tol.within * 100:g} %)")
    ax.axvline(study.robust_parabola.presag_rel * l_ref * 1e3, color="tab:green", label="robust (minimax)")
    ax.axvline(study.nominal.presag_rel * l_ref * 1e3, color="tab:red", ls="--", label="nominal Δe at band centre")
    ax.set_xlabel(f"pre-sag S on a {l_ref:g} m span [mm]")
    ax.set_ylabel("path waviness R [mm]")
    ax.set_title(f"{study.catenary_name}: F_m {forces.min():g}–{forces.max():g} N")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def plot_dynamic_objective(study, path: str | Path) -> Path:
    """Objective and worst case against the parabolic pre-sag S over the band, by simulation.

    The lines are the history surrogate through the simulated pre-sags (markers); the shaded band
    is the installation tolerance, the vertical lines the three designs compared.

    Parameters
    ----------
    study : presag_opt.robust.dynamic_study.DynamicRobustStudy
        The study to draw.
    path : str or Path
        Output file.
    """
    import numpy as np

    design = study.design
    span_mm = design.reference_span * 1e3
    presags, objective, worst = study.curve
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(presags * span_mm, worst, "k", lw=2, label="worst case over the band")
    if design.risk != "minimax":
        ax.plot(presags * span_mm, objective, "tab:blue", lw=1.5, label=design.risk)
    simulated = np.array([s.presag_rel for s in study.simulated])
    ax.plot(simulated * span_mm, [s.losses(design.loss).max() for s in study.simulated], "ko", ms=5,
            label=f"simulated pre-sags ({study.runs_used} runs)")
    tolerance = study.tolerance
    ax.axvspan(tolerance.low * span_mm, tolerance.high * span_mm, color="tab:green", alpha=0.2,
               label=f"tolerance (within {tolerance.within * 100:g} %)")
    for method, colour, line in zip(study.methods, ("tab:red", "tab:orange", "tab:green"), ("--", "--", "-")):
        ax.axvline(method.presag_rel * span_mm, color=colour, ls=line,
                   label=f"{method.method}: {method.presag_rel * span_mm:.1f} mm")
    ax.set_xlabel(f"pre-sag S on a {design.reference_span:g} m span [mm]")
    ax.set_ylabel("σ/F_m" if design.loss == "sigma-over-fm" else "σ [N]")
    band = study.band
    ax.set_title(f"{study.catenary_name}: F_stat {band.static_force_low:g}–{band.static_force_high:g} N, "
                 f"{band.speed_low * 3.6:g}–{band.speed_high * 3.6:g} km/h (β {study.beta[0]:.2f}–{study.beta[1]:.2f})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def _save(fig: plt.Figure, path: str | Path) -> Path:
    """Lay out, save (150 dpi; the suffix selects the format) and close a figure; return its path."""
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path
