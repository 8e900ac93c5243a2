"""The outputs of a designed line: ``droppers.csv``, ``spans.csv``, ``index.html`` and an xlsx workbook.

Edge units (mm, m, N, mm/N, ‰) as the column names say. Spans count from 1 within each section,
droppers from 1 within each span, from ``from_mast``.
"""

from __future__ import annotations

import base64
import csv
import tempfile
from pathlib import Path

from presag_opt.design.band import KMH
from presag_opt.design.line_results import LineDesign
from presag_opt.errors import ModelError
from presag_opt.pipeline.line import (  # noqa: F401 (the tables' columns, read from here by tests)
    DROPPER_COLUMNS,
    SPAN_COLUMNS,
    STITCH_COLUMNS,
    LineAnswer,
    LineDynamicCheck,
    dropper_columns,
    dropper_rows,
    span_rows,
)
from presag_opt.report.html import CSS, _e, _table, decision_html
from presag_opt.style import new_figure, save_figure, styled

LINE_OPTIONS = {"validity_sweep": "--study STORE", "dynamic_check": "--dynamic-check",
                "dynamic_robust": "--dynamic-robust",
                "installation_monte_carlo": "not offered by presag design: presag recommend --dropper-error MM on "
                                            "the system model"}
"""The options of ``presag design`` that supply each kind of evidence it can miss."""


def _tolerance_text(span) -> str:
    if span.tolerance is None:
        return "— (end span)"
    low, high = span.margins()
    return (f"{span.tolerance[0] * 1e3:.1f}–{span.tolerance[1] * 1e3:.1f} "
            f"({low * 1e3:+.1f} / {high * 1e3:+.1f})")


def write_line_outputs(answer: LineAnswer, folder: str | Path, *, xlsx: bool = False) -> dict[str, Path]:
    """Write ``droppers.csv``, ``spans.csv``, ``index.html`` (and ``line_design.xlsx``) into ``folder``.

    Parameters
    ----------
    answer : LineAnswer
        The designed line and its decision.
    folder : str or Path
        Output folder (created if missing).
    xlsx : bool
        Also write the tables as one workbook (needs openpyxl).

    Returns
    -------
    dict
        Output name -> path.
    """
    design = answer.design
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    tables = {"droppers": (dropper_columns(design), dropper_rows(design)), "spans": (SPAN_COLUMNS, span_rows(answer))}
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
    out["html"] = folder / "index.html"
    out["html"].write_text(line_page(answer), encoding="utf-8")
    return out


def _write_workbook(answer: LineAnswer, tables: dict, path: Path) -> Path:
    try:
        import openpyxl
    except ImportError as exc:
        raise ModelError("--xlsx needs openpyxl: pip install 'presag-opt[xlsx]'") from exc
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
    book.save(path)
    return path


def line_page(answer: LineAnswer) -> str:
    """The line report as one self-contained HTML page (figures embedded)."""
    design = answer.design
    band = design.band
    low, high = band.mean_force_band()
    parts = ["<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Line design</title>"
             f"<style>{CSS}</style></head><body>",
             f"<h1>Line design: {_e(design.survey.source)} on {_e(design.base_name)}</h1>",
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
    if answer.check is not None:
        parts.append("<h2 id='dynamic'>Dynamic check</h2>" + _check_html(answer.check, answer.decision.evidence.uplift_limit))
    parts.append("<h2 id='rules'>Design rules</h2><p>Public examples from Bane NOR's technical regulations for "
                 "contact line systems; each is stated for a speed range.</p>" + _table(
        ["section", "rule", "applies at this band", "status", "worst"],
        [[r.section, r.rule, "yes" if r.applies else "no", r.status, r.worst] for r in design.rules]))
    for sec in design.sections:
        rec = sec.sizing.recommendation
        parts.append(f"<h2 id='section-{_e(sec.section)}'>Section {_e(sec.section)}</h2><p>S_rel range over the band "
                     f"(Δe rule, inner spans): {rec.presag_rel_range[0] * 1e3:.3f}–{rec.presag_rel_range[1] * 1e3:.3f} ‰; "
                     f"β_max {rec.speed.beta_max:.2f}.</p>" + _table(
            ["span", "masts", "l [m]", "S [mm]", "e_mid [mm/N]", "e_mast [mm/N]", "Δe [mm/N]", "steady arm [N]",
             "static uplift [mm]", "own tolerance [mm] (margins)", "flag"],
            [[s.span, f"{s.from_mast}–{s.to_mast}", f"{s.length:.1f}", f"{s.presag * 1e3:.1f}", f"{s.e_mid * 1e3:.3f}",
              f"{s.e_mast * 1e3:.3f}", f"{s.delta_e * 1e3:.3f}",
              "— (termination)" if s.steady_arm_force is None else f"{s.steady_arm_force:.0f}",
              "— (termination)" if s.static_uplift is None else f"{s.static_uplift * 1e3:.1f}",
              _tolerance_text(s), answer.flag(s) or s.note] for s in sec.spans],
            {0, 2, 3, 4, 5, 6}))
    parts.append("<p><small>Generated by presag_opt. Method: Schick, Liu &amp; Stichel, Railway Sciences (2025), "
                 "doi:10.1108/RS-05-2025-0016.</small></p></body></html>")
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
    for sec in design.sections[1:]:
        for ax in (top, bottom):
            ax.axvline(sec.spans[0].chainage, color="0.5", lw=0.8, ls="--")
    return save_figure(fig, path)


def _along_figure(design: LineDesign) -> str:
    """:func:`plot_along_line` as an embedded PNG."""
    with tempfile.TemporaryDirectory(prefix="presag-line-") as tmp:
        path = plot_along_line(design, Path(tmp) / "along.png")
        data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (f"<figure id='fig-along'><img class='report-figure' src='data:image/png;base64,{data}' "
            "alt='elasticity and pre-sag along the chainage'><figcaption>Elasticity at the band-centre F_m and the "
            "pre-sag built along the chainage; dashed: section boundaries (overlap spans not modelled).</figcaption>"
            "</figure>")
