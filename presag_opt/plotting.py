"""Figures of the command line, the notebooks and the HTML report, in the one style of
:mod:`presag_opt.style`. Plotting stays out of the physics modules; every function saves to a file
(the suffix selects the format) and returns its path. Every axis carries its unit; legends sit
right of the axes, never over data. The validity-study figures are in :mod:`presag_opt.studies.plots`.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from presag_opt.elasticity import ElasticityStudy
from presag_opt.style import legend_outside, new_figure, save_figure, styled
from presag_opt.units import KMH

if TYPE_CHECKING:
    from presag_opt.design import Recommendation
    from presag_opt.design.layouts import CurveEffect, MixedFinding
    from presag_opt.dynamics.results import BatchResult
    from presag_opt.dynamics.simulate import SimulationResult
    from presag_opt.robust import DynamicCheck, RobustDesign, RobustStudy
    from presag_opt.validation import SingleCurveError
    from presag_opt.validation.dynamic_model import ConvergenceStudy, CrawlingCheck, MovingForceCheck


@styled
def plot_elasticity(study: ElasticityStudy, path: str | Path) -> Path:
    """Elasticity along the span for every curve of a study (like the paper's Fig. 3/4).

    Parameters
    ----------
    study : ElasticityStudy
        Curves to draw.
    path : str or Path
        Output file; the suffix selects the format (png, pdf, svg).
    """
    fig, ax = new_figure(legend=True)
    for curve in study.curves:
        label = "linear (tangent stiffness)" if curve.force is None else f"F = {curve.force:g} N"
        style = "k--" if curve.force is None else "-"
        ax.plot(curve.position, curve.elasticity * 1e3, style, label=label)
    ax.set_xlabel("position in span x [m]")
    ax.set_ylabel("elasticity e [mm/N]")
    ax.set_title(f"{study.catenary_name}: span {study.span + 1}")
    legend_outside(fig, ax)
    return save_figure(fig, path)


@styled
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
    fig, ax = new_figure(legend=True)
    for i, lay in enumerate(recommendation.layouts):
        color = f"C{i}"
        label = lay.layout_kind
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
    systems = ", ".join(dict.fromkeys(lay.catenary_name for lay in recommendation.layouts))
    ax.set_title(f"Quasi-static pre-sag: {systems}\n(range and recommendation from the {recommendation.method} variant)")
    legend_outside(fig, ax)
    return save_figure(fig, path)


@styled
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
    fig, (top, bottom) = new_figure(2, 1, height=5.5, legend=True, sharex=True)
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
    bottom.set_xlabel("mean contact force F_m [N]")
    bottom.set_ylabel("relative error [%]")
    fig.suptitle(f"One elasticity curve instead of interpolation ({studies[0].catenary_name})" if studies else "")
    legend_outside(fig, top)
    return save_figure(fig, path)


@styled
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
    runs = list(results) if isinstance(results, (list, tuple)) else [results]
    fig, axes = new_figure(len(runs), 1, width=8.0, height=3.2 * len(runs), legend=True, squeeze=False)
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
            f"{run.catenary_name}: {run.operation.speed / KMH:g} km/h (β = {run.speed_ratio:.2f}), "
            f"F_m = {stats.mean_force:.1f} N, σ = {stats.std_force:.1f} N",
            fontsize=9,
        )
        ax.set_ylabel("contact force [N]")
    axes[-1, 0].set_xlabel("position along the section [m]")
    legend_outside(fig, axes[0, 0])
    return save_figure(fig, path)


@styled
def plot_batch_statistics(batch: BatchResult, path: str | Path) -> Path:
    """σ/F_m and σ against speed, one line per static force, for a batch of runs.

    Parameters
    ----------
    batch : presag_opt.dynamics.batch.BatchResult
        Runs on a grid of speeds × static forces (failed runs are left out).
    path : str or Path
        Output file; the suffix selects the format (png, pdf, svg).
    """
    fig, (top, bottom) = new_figure(2, 1, height=6.0, legend=True, sharex=True)
    forces = sorted({r.point.static_force for r in batch.runs})
    for i, force in enumerate(forces):
        runs = sorted((r for r in batch.runs if r.ok and r.point.static_force == force), key=lambda r: r.point.speed)
        speed = [r.point.speed / KMH for r in runs]
        top.plot(speed, [r.statistics[0].sigma_over_mean for r in runs], "o-", color=f"C{i}", label=f"{force:g} N")
        bottom.plot(speed, [r.statistics[0].std_force for r in runs], "o-", color=f"C{i}")
    top.set_ylabel("σ/F_m [-]")
    bottom.set_ylabel("σ [N]")
    bottom.set_xlabel("speed [km/h]")
    top.set_title(f"{batch.catenary_name}: contact-force statistics ({batch.pantograph_names[0]})", fontsize=9)
    legend_outside(fig, top, title="F_stat")
    return save_figure(fig, path)


@styled
def plot_waviness(study: RobustStudy, path: str | Path) -> Path:
    """Worst-case and per-force waviness R against the parabolic pre-sag S over the band.

    Parameters
    ----------
    study : presag_opt.robust.RobustStudy
        The study to draw.
    path : str or Path
        Output file.
    """
    model = study.path
    l_ref = study.reference_span
    rel = np.linspace(0.0, 2.0 * max(study.robust_parabola.presag_rel, study.nominal.presag_rel), 200)
    forces = study.scenarios.forces
    waviness = np.array([model.waviness(model.parabola_depths(s), forces).max(axis=1) for s in rel])  # (S, K)
    fig, ax = new_figure(legend=True)
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
    legend_outside(fig, ax)
    return save_figure(fig, path)


@styled
def plot_dropper_profile(study: RobustStudy, design: RobustDesign, path: str | Path) -> Path:
    """Dropper depths of a per-dropper design beside the robust and nominal parabolas, per analysed span.

    Parameters
    ----------
    study : RobustStudy
        The study (its path model, robust parabola and nominal design).
    design : RobustDesign
        A per-dropper design on the same path model.
    path : str or Path
        Output file.
    """
    model = study.path
    fig, ax = new_figure(legend=True)
    lengths = np.asarray(model.state.catenary.layout.span_lengths)
    for k, span in enumerate(model.spans):
        sel = model.dropper_span == span
        x = model.dropper_fraction[sel] * lengths[span]
        label = k == 0
        ax.plot(x, design.depths[sel] * 1e3, "o-", color="C0", label="per-dropper design" if label else None)
        ax.plot(x, model.parabola_depths(study.robust_parabola.presag_rel)[sel] * 1e3, "--", color="C2",
                label="robust parabola" if label else None)
        ax.plot(x, model.parabola_depths(study.nominal.presag_rel)[sel] * 1e3, ":", color="C1",
                label="nominal Δe parabola" if label else None)
    ax.invert_yaxis()
    ax.set_xlabel("dropper position from the span's first mast [m]")
    ax.set_ylabel("contact-wire depth below the supports [mm]")
    ax.set_title(f"{study.catenary_name}: worst-case R {design.worst_case_waviness * 1e3:.1f} mm (per-dropper), "
                 f"{study.robust_parabola.worst_case_waviness * 1e3:.1f} mm (parabola)")
    legend_outside(fig, ax)
    return save_figure(fig, path)


@styled
def plot_dynamic_check(check: DynamicCheck, path: str | Path) -> Path:
    """σ/F_m and the steady-arm uplift of every run of a dynamic check against β, one colour per design.

    Parameters
    ----------
    check : DynamicCheck
        The runs.
    path : str or Path
        Output file.
    """
    from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT

    fig, (top, bottom) = new_figure(2, 1, height=5.5, legend=True, sharex=True)
    for i, design in enumerate(dict.fromkeys(r.design for r in check.runs)):
        runs = sorted((r for r in check.runs if r.design == design), key=lambda r: (r.static_force, r.beta))
        label = f"{design} ({runs[0].presag * 1e3:.0f} mm)"
        top.plot([r.beta for r in runs], [r.sigma_over_mean for r in runs], "o", color=f"C{i}", label=label)
        bottom.plot([r.beta for r in runs], [r.uplift_max * 1e3 for r in runs], "o", color=f"C{i}")
    for ax in (top, bottom):
        ax.axvline(check.beta_limit, color="0.4", ls=":", label=f"β = {check.beta_limit:g}" if ax is top else None)
    bottom.axhline(STEADY_ARM_UPLIFT_LIMIT * 1e3, color="C6", ls="--")
    top.plot([], [], color="C6", ls="--", label=f"uplift limit {STEADY_ARM_UPLIFT_LIMIT * 1e3:g} mm (lower panel)")
    top.set_ylabel("σ/F_m [-]")
    bottom.set_ylabel("max steady-arm uplift [mm]")
    bottom.set_xlabel("speed ratio β = v/c_CW [-]")
    legend_outside(fig, top)
    return save_figure(fig, path)


@styled
def plot_crawling(check: CrawlingCheck, path: str | Path) -> Path:
    """Simulated contact-wire uplift at crawling speed beside contact force × static elasticity.

    Parameters
    ----------
    check : CrawlingCheck
        The run.
    path : str or Path
        Output file.
    """
    fig, (top, bottom) = new_figure(2, 1, height=5.0, legend=True, sharex=True)
    top.plot(check.position, check.uplift * 1e3, color="C0", label="simulated uplift")
    top.plot(check.position, check.expected * 1e3, "--", color="C1", label="contact force × static e(x)")
    bottom.plot(check.position, (check.uplift / check.expected - 1.0) * 100, color="C0")
    top.set_ylabel("contact-wire uplift [mm]")
    bottom.set_ylabel("difference [%]")
    bottom.set_xlabel("position in the span [m]")
    top.set_title(f"{check.speed / KMH:g} km/h (β = {check.beta:.3f}), {check.static_force:g} N")
    legend_outside(fig, top)
    return save_figure(fig, path)


@styled
def plot_moving_force(checks: Sequence[MovingForceCheck], path: str | Path) -> Path:
    """Mid-point deflection of a string under a moving force: integrator against the modal series.

    Parameters
    ----------
    checks : sequence of MovingForceCheck
        One per speed ratio.
    path : str or Path
        Output file.
    """
    fig, ax = new_figure(legend=True)
    for i, check in enumerate(checks):
        t = check.time / check.time[-1]
        ax.plot(t, check.analytic / check.static_mid, "-", color=f"C{i}", label=f"β = {check.beta:g}, modal series")
        ax.plot(t[::max(1, len(t) // 40)], (check.numerical / check.static_mid)[::max(1, len(t) // 40)], "o",
                ms=3, color=f"C{i}", label=f"β = {check.beta:g}, Newmark ({check.element_length:g} m, "
                f"{check.time_step * 1e3:g} ms)")
    ax.set_xlabel("position of the force along the string, x/l [-]")
    ax.set_ylabel("mid-point deflection / (P·l/4T) [-]")
    legend_outside(fig, ax)
    return save_figure(fig, path)


@styled
def plot_convergence(study: ConvergenceStudy, path: str | Path) -> Path:
    """σ against the element length and time step of each rung, one line per speed.

    Parameters
    ----------
    study : ConvergenceStudy
        The ladder.
    path : str or Path
        Output file.
    """
    fig, ax = new_figure(legend=True)
    labels = [f"{r.element_length:g} m / {r.time_step * 1e3:g} ms" for r in study.rungs]
    sigma = np.array([r.std_force for r in study.rungs])
    for j, speed in enumerate(study.rungs[0].speeds):
        ax.plot(range(len(labels)), sigma[:, j], "o-", color=f"C{j}",
                label=f"{speed / KMH:g} km/h (β = {study.rungs[0].betas[j]:.2f})")
    ax.set_xticks(range(len(labels)), labels)
    ax.set_xlabel("element length / time step [m / ms]")
    ax.set_ylabel("contact-force standard deviation σ [N]")
    ax.set_title(study.case_name)
    legend_outside(fig, ax)
    return save_figure(fig, path)


@styled
def plot_curve_effects(effects: Sequence[CurveEffect], path: str | Path) -> Path:
    """Steady-arm pull, support elasticity and quasi-static S_rel against the curve radius.

    Straight track (radius 0) is drawn at the right end, as the limit of a large radius.

    Parameters
    ----------
    effects : sequence of CurveEffect
        One per radius.
    path : str or Path
        Output file.
    """
    curved = sorted((e for e in effects if e.radius), key=lambda e: abs(e.radius))
    straight = [e for e in effects if not e.radius]
    fig, axes = new_figure(1, 3, width=9.0, height=3.2, legend=True)
    x = [abs(e.radius) for e in curved]
    for ax, values, label in (
        (axes[0], [e.steady_arm_pull / 1e3 for e in curved], "mean steady-arm pull [kN]"),
        (axes[1], [e.e_mast * 1e3 for e in curved], "e at the supports [mm/N]"),
        (axes[2], [e.presag_rel * 1e3 for e in curved], "quasi-static S_rel [‰]"),
    ):
        ax.plot(x, values, "o-", color="C0", label="curved track")
        ax.set_xlabel("curve radius R [m]")
        ax.set_ylabel(label)
    for e in straight:
        for ax, value in zip(axes, (e.steady_arm_pull / 1e3, e.e_mast * 1e3, e.presag_rel * 1e3)):
            ax.axhline(value, color="C1", ls="--", label="straight track")
    for e in curved:
        axes[0].plot([abs(e.radius)] * 2, np.array(e.steady_arm_pull_range) / 1e3, color="0.6", lw=3, alpha=0.5)
        axes[2].plot([abs(e.radius)] * 2, np.array(e.presag_rel_range) * 1e3, color="0.6", lw=3, alpha=0.5)
    axes[2].plot([], [], color="0.6", lw=3, alpha=0.5, label="range: arms (left), F_m band (right)")
    legend_outside(fig, axes[2])
    return save_figure(fig, path)


@styled
def plot_mixed_findings(findings: Sequence[MixedFinding], path: str | Path,
                        paper: dict[str, tuple[float, float]] | None = None) -> Path:
    """S_rel range on ideal and on mixed spans for each variant of the assumptions (and the paper's).

    Parameters
    ----------
    findings : sequence of MixedFinding
        One per variant.
    path : str or Path
        Output file.
    paper : dict, optional
        The paper's ranges by layout (``ideal``, ``mixed``) in ‰.
    """
    rows = [(f.label, f.ideal_range, f.mixed_range) for f in findings]
    if paper:
        rows.append(("paper (section 5.2)", tuple(v * 1e-3 for v in paper["ideal"]),
                     tuple(v * 1e-3 for v in paper["mixed"])))
    fig, ax = new_figure(height=0.5 * len(rows) + 1.2, legend=True)
    for i, (_, ideal, mixed) in enumerate(rows):
        ax.plot(np.array(ideal) * 1e3, [i + 0.12] * 2, color="C0", lw=5, label="ideal spans" if i == 0 else None)
        ax.plot(np.array(mixed) * 1e3, [i - 0.12] * 2, color="C1", lw=5, label="mixed spans" if i == 0 else None)
    ax.set_yticks(range(len(rows)), [r[0] for r in rows])
    ax.invert_yaxis()
    ax.set_xlabel("S_rel over the F_m band [‰]")
    legend_outside(fig, ax)
    return save_figure(fig, path)


@styled
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
    fig, ax = new_figure(legend=True)
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
                 f"{band.speed_low / KMH:g}–{band.speed_high / KMH:g} km/h (β {study.beta[0]:.2f}–{study.beta[1]:.2f})")
    legend_outside(fig, ax)
    return save_figure(fig, path)
