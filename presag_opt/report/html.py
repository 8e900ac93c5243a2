"""A design report as one self-contained HTML file: tables, and figures embedded as PNG.

:func:`write_report` writes ``index.html`` into a folder; nothing else is needed to open it (no
scripts, no files beside it, no network). The figures are the package's own
(:mod:`presag_opt.plotting`, :mod:`presag_opt.studies.plots`), in the one style of the command line
and the notebooks.
"""

from __future__ import annotations

import base64
import html
import math
import tempfile
from pathlib import Path

from presag_opt.design.band import KMH
from presag_opt.plotting import plot_elasticity, plot_presag_against_force, plot_waviness
from presag_opt.report.content import REPORT_OPTIONS, DesignReport
from presag_opt.studies.plots import save_validity_plots

CSS = """
body { font-family: system-ui, sans-serif; max-width: 62rem; margin: 2rem auto; padding: 0 1rem; color: #222; }
h1 { font-size: 1.5rem; } h2 { font-size: 1.2rem; margin-top: 2rem; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.5rem 0; font-size: 0.9rem; }
th, td { border: 1px solid #ddd; padding: 0.2rem 0.5rem; text-align: left; vertical-align: top; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
figure { margin: 1rem 0; } figure img { max-width: 100%; height: auto; }
figcaption { font-size: 0.85rem; color: #555; }
.summary { background: #f3f7fb; border: 1px solid #c9d9ea; padding: 0.5rem 1rem; }
.warn { background: #fff4e0; border: 1px solid #e8b86d; padding: 0.5rem 1rem; }
.assumed { color: #8a4b00; }
"""


def write_report(report: DesignReport, folder: str | Path) -> Path:
    """Write ``index.html`` for a report into ``folder`` (created if missing); return its path.

    Parameters
    ----------
    report : DesignReport
        The computed report.
    folder : str or Path
        Output folder.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="presag-report-") as tmp:
        figures = _figures(report, Path(tmp))
        page = _page(report, figures)
    path = folder / "index.html"
    path.write_text(page, encoding="utf-8")
    return path


def _figures(report: DesignReport, tmp: Path) -> dict[str, str]:
    """Every figure of the report as a data URL, by its id."""
    rec = report.answer.recommendation
    paths = {"fig-presag": plot_presag_against_force(rec, tmp / "presag.png"),
             "fig-waviness": plot_waviness(report.answer.robust, tmp / "waviness.png")}
    for i, lay in enumerate(rec.layouts):
        study = lay.section.studies[len(lay.section.studies) // 2]
        paths[f"fig-elasticity-{i}"] = plot_elasticity(study, tmp / f"elasticity_{i}.png")
    paths["fig-validity"], paths["fig-uplift"] = save_validity_plots(
        report.answer.validity.dataset, report.answer.validity.result, tmp / "validity", figures=("fig7_presag", "uplift"))
    return {key: "data:image/png;base64," + base64.b64encode(p.read_bytes()).decode("ascii") for key, p in paths.items()}


def _e(text: object) -> str:
    return html.escape(str(text))


def _table(headers: list[str], rows: list[list[object]], numeric: set[int] = frozenset()) -> str:
    head = "".join(f"<th>{_e(h)}</th>" for h in headers)
    body = "".join(
        "<tr>" + "".join(f'<td class="num">{_e(c)}</td>' if i in numeric else f"<td>{_e(c)}</td>"
                         for i, c in enumerate(row)) + "</tr>"
        for row in rows
    )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _figure(figures: dict[str, str], key: str, caption: str) -> str:
    return (f'<figure id="{key}"><img class="report-figure" src="{figures[key]}" alt="{_e(caption)}">'
            f"<figcaption>{_e(caption)}</figcaption></figure>")


def _kmh(speed: float | None) -> str:
    return "–" if speed is None or not math.isfinite(speed) else f"{speed / KMH:.0f} km/h"


def _page(report: DesignReport, figures: dict[str, str]) -> str:
    answer = report.answer
    rec, robust, validity, band, decision = (answer.recommendation, answer.robust, answer.validity, answer.band,
                                             answer.decision)
    l_ref = decision.reference_span
    low, high = rec.mean_force_band
    res = validity.result
    top = band.speed_high
    uplift_band = validity.uplift_up_to(top)
    limit = decision.evidence.uplift_limit
    parts = [f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Pre-sag design report</title>"
             f"<style>{CSS}</style></head><body>"]
    parts.append(f"<h1>Pre-sag design report: {_e(', '.join(lay.catenary_name for lay in rec.layouts))}</h1>")
    if validity.record.note:
        parts.append(f"<p class='warn'>Note: {_e(validity.record.note)}.</p>")
    if report.quick:
        parts.append("<p class='warn'>Draft (<code>--quick</code>): the validity sweep is two pre-sags × speeds × "
                     "static forces at coarse numerics. Run the report without <code>--quick</code>, or with "
                     "<code>--study</code>, for the validity range to quote.</p>")
    parts.append(decision_html(decision, REPORT_OPTIONS))
    parts.append(
        "<div class='summary' id='summary'>"
        f"<p><b>Steady-arm uplift</b> (dynamic, the sweep's runs up to {_kmh(top)}): "
        + ("no run at these speeds" if uplift_band is None else
           f"{uplift_band * 1e3:.1f} mm, {'within' if uplift_band <= limit else 'ABOVE'} the limit {limit * 1e3:g} mm")
        + ".</p></div>")
    parts.append("<h2>Operating band</h2>" + _table(
        ["static force F_stat", "speed", "α_ae", "mean contact force F_m"],
        [[f"{band.static_force_low:g}–{band.static_force_high:g} N",
          f"{band.speed_low / KMH:g}–{band.speed_high / KMH:g} km/h", f"{band.aero_coefficient * KMH**2:g} N/(km/h)²",
          f"{low:.1f}–{high:.1f} N"]]))
    parts.append("<h2 id='recommendation'>Quasi-static pre-sag over the band</h2><p>Quasi-static rule S = F_m·Δe over the "
                 "F_m band, per layout; the Δe rule's answer is the mean of the range ends, "
                 f"{rec.presag_rel * 1e3:.2f} ‰ = {rec.presag_rel * l_ref * 1e3:.0f} mm on {l_ref:g} m (the decision at "
                 "the top of the page weighs it against the robust designs).</p>" + _table(
        ["layout", "system", "spans sized", "S_rel [‰]", f"S on {l_ref:g} m [mm]", "β at top speed [-]"],
        [[lay.layout_kind, lay.catenary_name, len(lay.section.spans),
          f"{lay.presag_rel_range[0] * 1e3:.2f}–{lay.presag_rel_range[1] * 1e3:.2f}",
          f"{lay.presag_rel_range[0] * l_ref * 1e3:.0f}–{lay.presag_rel_range[1] * l_ref * 1e3:.0f}",
          f"{lay.speed.beta_max:.2f}"] for lay in rec.layouts], {2, 5}))
    parts.append(_figure(figures, "fig-presag", "Quasi-static pre-sag against the mean contact force, both variants "
                                                "of the rule, every layout; the operating band shaded."))
    weights = robust.scenarios.weights
    tol = robust.tolerance
    parts.append("<h2 id='robust'>Robust design and tolerance band</h2><p>The pre-sag that minimises the worst "
                 "waviness of the quasi-static pantograph path over the F_m band (minimax), beside the Δe rule; "
                 f"{_e(robust.catenary_name)}. Quasi-static tolerance (worst-case waviness within {tol.within * 100:g} % "
                 f"of the optimum): {tol.low * l_ref * 1e3:.1f}–{tol.high * l_ref * 1e3:.1f} mm on {l_ref:g} m.</p>"
                 + _table(
        ["design", f"S on {l_ref:g} m [mm]", "S_rel [‰]", "worst R [mm]", "mean R [mm]"],
        [[name, f"{d.presag_rel * l_ref * 1e3:.1f}", f"{d.presag_rel * 1e3:.3f}", f"{d.worst_case_waviness * 1e3:.1f}",
          f"{d.mean_waviness(weights) * 1e3:.1f}"]
         for name, d in (("robust (minimax)", robust.robust_parabola), ("Δe rule", robust.nominal))],
        {1, 2, 3, 4}))
    parts.append(_figure(figures, "fig-waviness", "Path waviness R against the parabolic pre-sag: worst case over the "
                                                  "band, single forces, the tolerance band shaded."))
    parts.append("<h2 id='elasticity'>Elasticity</h2>" + _table(
        ["layout", "F_m [N]", "e_mid [mm/N]", "e at supports [mm/N]", "Δe [mm/N]"],
        [[lay.layout_kind, f"{f:.0f}", f"{_mean(c.e_mid for c in curves):.3f}",
          f"{_mean(0.5 * (c.elasticity[0] + c.elasticity[-1]) for c in curves):.3f}",
          f"{_mean(c.delta_e for c in curves):.3f}"]
         for lay in rec.layouts for f in (low, high) for curves in [lay.section.curves_at(f)]], {1, 2, 3, 4}))
    for i, lay in enumerate(rec.layouts):
        parts.append(_figure(figures, f"fig-elasticity-{i}", f"Elasticity along a sized span of the {lay.layout_kind} "
                                                             "layout at the computed force levels."))
    if answer.dynamic is not None:
        parts.append(_dynamic_section(answer.dynamic, l_ref))
    parts.append("<h2 id='validity'>Validity range in speed</h2>"
                 f"<p>{_e(decision.validity.sentence())}.</p><p>Sweep: {_e(validity.source)}; it reads "
                 f"{_e(validity.record.limit.reading())}. Criterion: {_e(res.criterion)}.</p>" + _table(
        ["β [-]", "speed [km/h]", "Δe rule holds"],
        [[f"{v.beta:.3f}", f"{v.speed / KMH:.0f}", "yes" if v.holds else "no"] for v in res.per_beta], {0, 1}))
    parts.append(_figure(figures, "fig-validity", "Dynamically near-optimal pre-sag (σ within 5 % of its minimum) per "
                                                  "speed ratio, beside the quasi-static rules."))
    static_rows = [[f"static estimate F_m·e at the supports ({lay.layout_kind})", f"{high:.0f} N",
                    f"{lay.steady_arm_uplift.uplift * 1e3:.1f}"] for lay in rec.layouts]
    dynamic = [] if res.uplift is None else [[
        "dynamic, largest of the study", f"{res.uplift.speed / KMH:.0f} km/h, F_stat {res.uplift.static_force:g} N",
        f"{res.uplift.maximum * 1e3:.1f}"]]
    if uplift_band is not None:
        dynamic.append([f"dynamic, speeds up to {_kmh(top)}", "–", f"{uplift_band * 1e3:.1f}"])
    parts.append(f"<h2 id='uplift'>Steady-arm uplift</h2><p>Limit {limit * 1e3:g} mm.</p>" + _table(
        ["estimate", "where", "uplift [mm]"], static_rows + dynamic, {2}))
    parts.append(_figure(figures, "fig-uplift", "Largest steady-arm uplift over the static forces against the speed "
                                                "ratio, per pre-sag, and its limit."))
    parts.append(_dependence_section())
    parts.append("<h2 id='inputs'>Inputs and their provenance</h2>" + _table(
        ["file", "key", "value", "unit", "source", "note"],
        [[e.file, e.key, _value(e.value), e.unit, e.source, e.note] for e in report.inputs]))
    parts.append("<h2 id='assumed'>Every assumed value</h2><p>Model-file numbers tagged <i>assumed</i> (the paper's "
                 "appendix was not available) and the report's own choices.</p>" + _table(
        ["file", "key", "value", "unit", "note"],
        [[e.file, e.key, _value(e.value), e.unit, e.note] for e in report.assumed_inputs]) + _table(
        ["choice", "value", "why"], [[a.name, a.value, a.why] for a in report.assumptions]))
    parts.append("<p><small>Generated by presag_opt. Method: Schick, Liu &amp; Stichel, Railway Sciences (2025), "
                 "doi:10.1108/RS-05-2025-0016.</small></p></body></html>")
    return "\n".join(parts)


def decision_html(decision, options: dict[str, str], lines: list[str] | None = None) -> str:
    """The decision as the head of a page: what to build, why, margins, validity, what was not checked, the
    alternatives.

    Parameters
    ----------
    decision : Decision
        The decision (:mod:`presag_opt.design.decision`).
    options : dict of str to str
        Evidence name to the option that supplies it (see
        :meth:`~presag_opt.design.decision.Decision.not_checked`).
    lines : list of str, optional
        The decision's lines as rendered by the caller (a line's own headline); default
        ``decision.lines(options)``.
    """
    lines = lines or decision.lines(options)
    style = "summary" if decision.status == "decided" else "warn"
    items = "".join(f"<li>{_e(line.strip())}</li>" for line in lines[1:])
    return f"<div class='{style}' id='decision'><p><b>{_e(lines[0])}</b></p><ul>{items}</ul></div>"


def _dynamic_section(study, l_ref: float) -> str:
    """The dynamic robust design's comparison of the three methods by simulation."""
    data = study.to_dict()
    low, high = data["tolerance_mm"]
    return ("<h2 id='dynamic'>Dynamic robust design</h2>"
            f"<p>{_e(study.where())}; objective {_e(data['risk'])} of {_e(data['objective_name'])}; dynamic tolerance "
            f"(within {study.tolerance.within * 100:g} % of its optimum) {low:.1f}–{high:.1f} mm on "
            f"{data['reference_span_m']:g} m; {data['runs_used']} runs.</p>" + _table(
                ["method", f"S on {data['reference_span_m']:g} m [mm]", "objective", "worst case", "max uplift [mm]",
                 "inside the dynamic tolerance"],
                [[m["method"], f"{m['presag_mm']:.1f}", f"{m['objective']:.4f}", f"{m['worst_case_objective']:.4f}",
                  f"{m['uplift_max_mm']:.1f}", "yes" if m["within_tolerance"] else "no"] for m in data["methods"]],
                {1, 2, 3, 4}))


def _dependence_section() -> str:
    """"What this answer depends on": the top inputs of the recommended S_rel (shipped Morris screening)."""
    from presag_opt.sensitivity.screening import recommendation_dependence

    dep = recommendation_dependence()
    head = "<h2 id='dependence'>What this answer depends on</h2>"
    if dep is None:
        return head + "<p>No screening is shipped; run <code>presag sensitivity --quantity recommendation</code>.</p>"
    return head + f"<p>{_e(dep.note)}</p>" + _table(
        ["input", f"μ* [{dep.unit}]", "μ* / largest", "range varied"],
        [[name, f"{mu:.3f}", f"{rel:.2f}", rng] for name, mu, rel, rng in dep.rows], {1, 2})


def _mean(values) -> float:
    values = list(values)
    return sum(values) / len(values) * 1e3


def _value(value: object) -> str:
    return ", ".join(f"{v:g}" for v in value) if isinstance(value, tuple) else f"{value:g}" if isinstance(value, (int, float)) else str(value)
