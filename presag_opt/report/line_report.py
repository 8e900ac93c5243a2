"""The outputs of a designed line: ``droppers.csv``, ``spans.csv``, ``index.html``, an xlsx workbook and a DXF.

Edge units (mm, m, N, mm/N, ‰) as the column names say. Spans count from 1 within each section,
droppers from 1 within each span, from ``from_mast``.
"""

from __future__ import annotations

import csv
from pathlib import Path

from presag_opt.design.band import KMH
from presag_opt.design.line_results import LineDesign
from presag_opt.design.line_rules import gradient_limits, gradient_status
from presag_opt.pipeline.line import LineAnswer, LineDynamicCheck
from presag_opt.report.html import CSS, _e, _table, decision_html
from presag_opt.report.line_dxf import write_dxf
from presag_opt.report.line_figures import embedded, mark_sections, plot_elasticity_along, plot_profile
from presag_opt.report.line_sheets import PRINT_CSS, add_sheets, sheets_html
from presag_opt.style import new_figure, save_figure, styled

DROPPER_COLUMNS = ("dropper_id", "section", "span", "from_mast", "to_mast", "dropper", "chainage_m", "x_from_mast_m",
                   "dropper_length_mm", "cut_length_mm", "messenger_height_mm", "contact_wire_height_mm", "lateral_mm",
                   "presag_mm")
"""Columns of ``droppers.csv``: the id (section/from–to/number), the absolute chainage, the distance from
``from_mast``, the clamp-to-clamp length, the cut length (with the dropper type's terminal and loop
allowances, rounded to ``--round``), the heights of the wire it hangs from and of the contact wire above
the rail, the contact wire's lateral position (+ to the left of the track centre line) and its depth below
the line between its supports."""

ROUNDING_COLUMNS = ("section", "step_mm", "waviness_exact_mm", "waviness_p95_rounded_mm", "p95_ci_low_mm",
                    "p95_ci_high_mm", "presag_error_p95_mm", "samples")
"""Columns of the rounding table (``rounding.csv``, the workbook's sheet and the page)."""

SPAN_COLUMNS = ("section", "span", "from_mast", "to_mast", "length_m", "presag_mm", "presag_rel_permille",
                "e_mid_mm_per_N", "e_mast_mm_per_N", "delta_e_mm_per_N", "steady_arm_pull_N", "static_uplift_mm",
                "robust_presag_mm", "presag_tolerance_low_mm", "presag_tolerance_high_mm", "margin_low_mm",
                "margin_high_mm", "flag", "note", "uniformity", "gradient_permille", "gradient_change_permille",
                "gradient_flag")
"""Columns of ``spans.csv``: steady-arm pull and static uplift at ``from_mast`` (empty where it is the
section's termination, which has no steady arm); the span's own quasi-static robust pre-sag and
tolerance interval on the built geometry, the built pre-sag's margin to each end (negative: outside)
and its flag (:data:`presag_opt.pipeline.line.SPAN_FLAGS`); why a span is not sized (empty for an end span's
tolerance columns); the uniformity (e_max − e_min)/(e_max + e_min) of e(x) as built; the contact-wire
gradient between its masts (+ rising) and its change from the section's previous span, with the limits of
:data:`presag_opt.design.line_rules.GRADIENT_LIMITS` at the band's top speed (``gradient_flag``)."""

LINE_OPTIONS = {"validity_sweep": "--study STORE", "dynamic_check": "--dynamic-check",
                "dynamic_robust": "--dynamic-robust",
                "installation_monte_carlo": "not offered by presag design: presag recommend --dropper-error MM on "
                                            "the system model"}
"""The options of ``presag design`` that supply each kind of evidence it can miss."""


STITCH_COLUMNS = ("hangs_from",)
"""Column ``droppers.csv`` adds on a line with stitched supports: ``messenger`` or ``stitch wire`` (a stitch
dropper's cut length is between the stitch-wire and contact-wire clamp points)."""


def dropper_columns(design: LineDesign) -> tuple[str, ...]:
    """Columns of ``droppers.csv`` for this design (:data:`DROPPER_COLUMNS`, and where a dropper hangs from on
    a line with stitch droppers)."""
    return DROPPER_COLUMNS + (STITCH_COLUMNS if _stitched(design) else ())


def _stitched(design: LineDesign) -> bool:
    return any(getattr(d, "stitch", False) for d in design.droppers)


def dropper_rows(design: LineDesign) -> list[dict[str, object]]:
    """The dropper schedule as table rows (lengths and heights rounded to 0.1 mm)."""
    stitched = _stitched(design)
    return [{"dropper_id": d.id, "section": d.section, "span": d.span, "from_mast": d.from_mast, "to_mast": d.to_mast,
             "dropper": d.dropper, "chainage_m": round(d.chainage, 3), "x_from_mast_m": round(d.position, 3),
             "dropper_length_mm": round(d.length * 1e3, 1), "cut_length_mm": round(d.cut_length * 1e3, 1),
             "messenger_height_mm": round(d.messenger_height * 1e3, 1),
             "contact_wire_height_mm": round(d.contact_wire_height * 1e3, 1), "lateral_mm": round(d.lateral * 1e3, 1),
             "presag_mm": round(d.presag * 1e3, 1),
             **({"hangs_from": "stitch wire" if d.stitch else "messenger"} if stitched else {})}
            for d in design.droppers]


def rounding_rows(design: LineDesign) -> list[dict[str, object]]:
    """The rounding Monte Carlo of every section as table rows (mm; empty where the lengths are exact)."""
    return [{"section": section, "step_mm": round(r.step * 1e3, 3), "waviness_exact_mm": round(r.waviness_exact * 1e3, 2),
             "waviness_p95_rounded_mm": round(r.waviness_p95 * 1e3, 2),
             "p95_ci_low_mm": round(r.waviness_p95_ci[0] * 1e3, 2), "p95_ci_high_mm": round(r.waviness_p95_ci[1] * 1e3, 2),
             "presag_error_p95_mm": round(r.presag_error_p95 * 1e3, 2), "samples": r.samples}
            for section, r in design.rounding()]


def _mm(value: float | None, digits: int = 1) -> object:
    return "" if value is None else round(value * 1e3, digits)


def span_rows(answer: LineAnswer) -> list[dict[str, object]]:
    """The span table as rows (mm, m, N, mm/N, ‰)."""
    rows = []
    gradient_limit, change_limit, _ = gradient_limits(answer.design.band.speed_high / KMH)
    for s in answer.design.spans:
        margins = s.margins() or (None, None)
        steep = [f"gradient {g}" for g in [gradient_status(s.gradient, gradient_limit)] if g]
        steep += [f"change {c}" for c in [gradient_status(s.gradient_change, change_limit)] if c]
        rows.append({
            "section": s.section, "span": s.span, "from_mast": s.from_mast, "to_mast": s.to_mast,
            "length_m": round(s.length, 3), "presag_mm": round(s.presag * 1e3, 1),
            "presag_rel_permille": round(s.presag / s.length * 1e3, 4), "e_mid_mm_per_N": round(s.e_mid * 1e3, 4),
            "e_mast_mm_per_N": round(s.e_mast * 1e3, 4), "delta_e_mm_per_N": round(s.delta_e * 1e3, 4),
            "steady_arm_pull_N": "" if s.steady_arm_force is None else round(s.steady_arm_force, 1),
            "static_uplift_mm": _mm(s.static_uplift), "robust_presag_mm": _mm(s.robust_presag),
            "presag_tolerance_low_mm": _mm(None if s.tolerance is None else s.tolerance[0]),
            "presag_tolerance_high_mm": _mm(None if s.tolerance is None else s.tolerance[1]),
            "margin_low_mm": _mm(margins[0]), "margin_high_mm": _mm(margins[1]), "flag": answer.flag(s),
            "note": s.note, "uniformity": round(s.uniformity, 4), "gradient_permille": round(s.gradient * 1e3, 3),
            "gradient_change_permille": "" if s.gradient_change is None else round(s.gradient_change * 1e3, 3),
            "gradient_flag": "; ".join(steep),
        })
    return rows


def _tolerance_text(span) -> str:
    if span.tolerance is None:
        return "— (end span)"
    low, high = span.margins()
    return (f"{span.tolerance[0] * 1e3:.1f}–{span.tolerance[1] * 1e3:.1f} "
            f"({low * 1e3:+.1f} / {high * 1e3:+.1f})")


def write_line_outputs(answer: LineAnswer, folder: str | Path, *, xlsx: bool = False,
                       dxf: bool = False) -> dict[str, Path]:
    """Write ``droppers.csv``, ``spans.csv``, ``index.html`` (and ``line_design.xlsx``) into ``folder``.

    Parameters
    ----------
    answer : LineAnswer
        The designed line and its decision.
    folder : str or Path
        Output folder (created if missing).
    xlsx : bool
        Also write the tables and the crew's sheets as one workbook.
    dxf : bool
        Also write the profile and the plan as ``line_design.dxf`` (:mod:`presag_opt.report.line_dxf`).

    Returns
    -------
    dict
        Output name -> path.
    """
    design = answer.design
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    tables = {"droppers": (dropper_columns(design), dropper_rows(design)), "spans": (SPAN_COLUMNS, span_rows(answer))}
    if design.rounding():
        tables["rounding"] = (ROUNDING_COLUMNS, rounding_rows(design))
    out = {}
    for name, (columns, rows) in tables.items():
        path = folder / f"{name}.csv"
        with path.open("w", newline="", encoding="utf-8") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(columns))
            writer.writeheader()
            writer.writerows(rows)
        out[name] = path
    if xlsx:
        out["xlsx"] = _write_workbook(answer, tables, folder / "line_design.xlsx")
    if dxf:
        out["dxf"] = write_dxf(design, folder / "line_design.dxf")
    out["html"] = folder / "index.html"
    out["html"].write_text(line_page(answer), encoding="utf-8")
    return out


def _write_workbook(answer: LineAnswer, tables: dict, path: Path) -> Path:
    import openpyxl  # imported here: only --xlsx pays for it

    book = openpyxl.Workbook()
    book.remove(book.active)
    sheet = book.create_sheet("decision")
    for line in answer.lines(LINE_OPTIONS):
        sheet.append([line.strip()])
    for name, (columns, rows) in tables.items():
        sheet = book.create_sheet(name)
        sheet.append(list(columns))
        for row in rows:
            sheet.append([row[c] for c in columns])
    sheet = book.create_sheet("rules")
    sheet.append(["section", "rule", "applies", "status", "worst"])
    for r in answer.design.rules:
        sheet.append([r.section, r.rule, r.applies, r.status, r.worst])
    add_sheets(book, answer.design)
    book.save(path)
    return path


def line_page(answer: LineAnswer) -> str:
    """The line report as one self-contained HTML page (figures embedded)."""
    design = answer.design
    band = design.band
    low, high = band.mean_force_band()
    parts = ["<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Line design</title>"
             f"<style>{CSS}{PRINT_CSS}</style></head><body><div class='screen-only'>",
             f"<h1>Line design: {_e(design.survey.source)} on {_e(design.base_name)}</h1>",
             "<p><small>Printing this page prints the crew's dropper sheets only (one section per page, the "
             "headers repeated); they follow the report below.</small></p>",
             decision_html(answer.decision, LINE_OPTIONS, answer.lines(LINE_OPTIONS))]
    failing = [r for r in design.rules if not r.passed]
    if failing:
        parts.append("<div class='warn' id='rules-failing'><p><b>Design rules not met</b></p><ul>"
                     + "".join(f"<li>section {_e(r.section)}: {_e(r.rule)} — {_e(r.worst)} ({_e(r.status)})</li>"
                               for r in failing) + "</ul></div>")
    parts.append("<div class='summary'><p>" + "</p><p>".join(_e(n) for n in design.notes) + "</p></div>")
    parts.append("<h2>Line and band</h2>" + _table(
        ["masts", "sections", "length", "band", "F_m", "pre-sag rule", "line S_rel"],
        [[len(design.survey.masts), len(design.sections), f"{design.survey.length:.0f} m",
          f"F_stat {band.static_force_low:g}–{band.static_force_high:g} N, {band.speed_low / KMH:g}–"
          f"{band.speed_high / KMH:g} km/h", f"{low:.0f}–{high:.0f} N", design.options.rule,
          f"{design.presag_rel * 1e3:.3f} ‰"]]))
    parts.append("<h2 id='along'>Elasticity and pre-sag along the line</h2>" + _along_figure(design))
    parts.append("<h2 id='profile'>Height profile</h2>" + embedded(
        plot_profile, design, "fig-profile", "Heights above the rail of the contact wire and of the wire the droppers "
        "hang from, at every mast and dropper as built; dashed: section boundaries; shaded: curves; red: masts "
        "where the contact-wire height changes."))
    parts.append("<h2 id='as-built'>Elasticity as built</h2>" + embedded(
        plot_elasticity_along, design, "fig-elasticity", "The elasticity e(x) along every span at the pre-sag "
        "built, at the band-centre F_m (top), and each span's uniformity (e_max − e_min)/(e_max + e_min) (bottom)."))
    if answer.check is not None:
        parts.append("<h2 id='dynamic'>Dynamic check</h2>" + _check_html(answer.check, answer.decision.evidence.uplift_limit))
    parts.append("<h2 id='rules'>Design rules</h2><p>Public examples from Bane NOR's technical regulations for "
                 "contact line systems; each is stated for a speed range.</p>" + _table(
        ["section", "rule", "applies at this band", "status", "worst"],
        [[r.section, r.rule, "yes" if r.applies else "no", r.status, r.worst] for r in design.rules]))
    rows = {(r["section"], r["span"]): r["gradient_flag"] for r in span_rows(answer)}
    for sec in design.sections:
        rec = sec.sizing.recommendation
        parts.append(f"<h2 id='section-{_e(sec.section)}'>Section {_e(sec.section)}</h2><p>S_rel range over the band "
                     f"(Δe rule, inner spans): {rec.presag_rel_range[0] * 1e3:.3f}–{rec.presag_rel_range[1] * 1e3:.3f} ‰; "
                     f"β_max {rec.speed.beta_max:.2f}.</p>" + _table(
            ["span", "masts", "l [m]", "S [mm]", "e_mid [mm/N]", "e_mast [mm/N]", "Δe [mm/N]", "steady arm [N]",
             "static uplift [mm]", "own tolerance [mm] (margins)", "uniformity", "gradient [‰]", "flag"],
            [[s.span, f"{s.from_mast}–{s.to_mast}", f"{s.length:.1f}", f"{s.presag * 1e3:.1f}", f"{s.e_mid * 1e3:.3f}",
              f"{s.e_mast * 1e3:.3f}", f"{s.delta_e * 1e3:.3f}",
              "— (termination)" if s.steady_arm_force is None else f"{s.steady_arm_force:.0f}",
              "— (termination)" if s.static_uplift is None else f"{s.static_uplift * 1e3:.1f}",
              _tolerance_text(s), f"{s.uniformity:.3f}", f"{s.gradient * 1e3:+.2f}",
              "; ".join(f for f in (answer.flag(s) or s.note, rows[(sec.section, s.span)]) if f)] for s in sec.spans],
            {0, 2, 3, 4, 5, 6, 10, 11}))
    if design.rounding():
        parts.append("<h2 id='rounding'>Rounding of the cut lengths</h2><p>Every cut length rounded to the crew's step "
                     "is built with an error in ±step/2: a quasi-static Monte Carlo with that error, uniform and "
                     "independent on every dropper, on each section's quasi-static robust design. The crew tolerance "
                     "of the decision is never below the P95 pre-sag error rounding alone causes.</p>"
                     + _table(list(ROUNDING_COLUMNS), [[row[c] for c in ROUNDING_COLUMNS] for row in rounding_rows(design)],
                              set(range(1, 8))))
    parts.append("<p><small>Generated by presag_opt. Method: Schick, Liu &amp; Stichel, Railway Sciences (2025), "
                 "doi:10.1108/RS-05-2025-0016.</small></p></div>")
    parts.append("<h2 class='screen-only' id='sheets'>Dropper sheets</h2>" + sheets_html(design) + "</body></html>")
    return "\n".join(parts)


def _check_html(check: LineDynamicCheck, limit: float) -> str:
    """The dynamic check's runs as an HTML table with a sentence (uplift limit in m)."""
    rows = [[r.design, f"{r.speed / KMH:.0f}", f"{r.static_force:g}", f"{r.mean_force:.1f}", f"{r.sigma_over_mean:.3f}",
             f"{r.uplift_max * 1e3:.1f}", f"{r.loss_of_contact * 100:.2f}"] for r in check.runs.runs]
    return (f"<p>Section {_e(check.section)} (largest static uplift estimate) at the pre-sags the decision may build "
            f"(S on its {check.reference_span:g} m span), at the band's top speed and its lowest and highest static "
            f"force; steady-arm uplift limit {limit * 1e3:g} mm.</p>"
            + _table(["pre-sag", "speed [km/h]", "F_stat [N]", "F_m [N]", "σ/F_m [-]", "uplift [mm]",
                      "loss of contact [%]"], rows, {1, 2, 3, 4, 5, 6}))


@styled
def plot_along_line(design: LineDesign, path: str | Path) -> Path:
    """Save e_mid, e at the masts and Δe (top) and the pre-sag built (bottom) against chainage.

    Parameters
    ----------
    design : LineDesign
        The designed line.
    path : str or Path
        Output file; the suffix sets the format.
    """
    spans = design.spans
    mid = [s.chainage + 0.5 * s.length for s in spans]
    fig, (top, bottom) = new_figure(2, 1, width=9.0, height=5.5, sharex=True)
    top.plot(mid, [s.e_mid * 1e3 for s in spans], "o-", label="e_mid")
    top.plot([s.chainage for s in spans], [s.e_mast * 1e3 for s in spans], "s", label="e at the mast (from_mast)")
    top.plot(mid, [s.delta_e * 1e3 for s in spans], "^-", label="Δe")
    top.set_ylabel("elasticity [mm/N]")
    top.legend()
    bottom.bar(mid, [s.presag * 1e3 for s in spans], width=[0.8 * s.length for s in spans], label="pre-sag built")
    bottom.set_ylabel("pre-sag [mm]")
    bottom.set_xlabel("chainage [m]")
    mark_sections(design, (top, bottom))
    return save_figure(fig, path)


def _along_figure(design: LineDesign) -> str:
    """:func:`plot_along_line` as an embedded PNG."""
    return embedded(plot_along_line, design, "fig-along", "Elasticity at the band-centre F_m and the pre-sag built "
                    "along the chainage; dashed: section boundaries (overlap spans not modelled).")
