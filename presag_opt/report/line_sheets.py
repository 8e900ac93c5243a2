"""The crew's dropper sheets: one per tension section, a table per span, on the page and in the workbook.

Each sheet names the section, its masts, the dropper type and the cutting step; each span's table gives
every dropper's id, chainage, distance from the mast, cut length, clamp-to-clamp length, both wires'
heights and the contact wire's lateral position. On paper (:data:`PRINT_CSS`) only the sheets print,
one section per page, with every table's header repeated on each page it runs onto.
"""

from __future__ import annotations

from itertools import groupby

from presag_opt.design.line_results import DropperDesign, LineDesign
from presag_opt.report.html import _e, _table

SHEET_HEADERS = ("dropper", "chainage [m]", "from mast [m]", "cut length [mm]", "clamp to clamp [mm]",
                 "messenger [mm]", "contact wire [mm]", "lateral [mm]")
"""Columns of a span's table on a sheet (heights above the rail, lateral + to the left)."""

PRINT_CSS = """
.sheet h3 { font-size: 1rem; margin: 0.8rem 0 0.2rem; }
.sheet td { white-space: nowrap; }
@media print {
  @page { size: A4; margin: 12mm; }
  body { max-width: none; margin: 0; padding: 0; font-size: 9pt; }
  .screen-only { display: none; }
  .sheet { break-before: page; }
  .sheet:first-of-type { break-before: auto; }
  .sheet h2 { font-size: 12pt; margin-top: 0; }
  .sheet h3 { font-size: 10pt; margin: 6pt 0 2pt; }
  .sheet table { width: 100%; font-size: 8pt; }
  .sheet th, .sheet td { padding: 1pt 3pt; }
  thead { display: table-header-group; }
  tr, h3 { break-inside: avoid; } h3 { break-after: avoid; }
}
"""
"""The sheets' print stylesheet (the rest of the page is marked ``screen-only``)."""


def sheet_row(d: DropperDesign) -> list[object]:
    """One dropper on a sheet, in :data:`SHEET_HEADERS` order (m to 3 decimals, mm to 1)."""
    return [d.id, f"{d.chainage:.3f}", f"{d.position:.3f}", f"{d.cut_length * 1e3:.1f}", f"{d.length * 1e3:.1f}",
            f"{d.messenger_height * 1e3:.1f}", f"{d.contact_wire_height * 1e3:.1f}", f"{d.lateral * 1e3:+.1f}"]


def sheet_title(design: LineDesign, section: str) -> str:
    """The heading of a section's sheet: the line, the section and its masts."""
    sec = next(s for s in design.sections if s.section == section)
    return (f"Dropper sheet — {design.survey.source}, section {section}: masts {sec.spans[0].from_mast}–"
            f"{sec.spans[-1].to_mast}, {len(sec.droppers)} droppers")


def cutting_note(design: LineDesign) -> str:
    """How the cut lengths were made: the dropper type's allowances and the step."""
    step = design.options.round_step
    kind = design.options.dropper_type
    allowances = "" if kind is None else f"{kind.describe()}; "
    return (f"Cut length = clamp-to-clamp length + terminal and loop allowances ({allowances}"
            + (f"rounded to {step * 1e3:g} mm)" if step else "not rounded)")
            + ". Heights above the rail; lateral + to the left of the track centre line looking towards "
              "increasing chainage.")


def sheets_html(design: LineDesign) -> str:
    """Every section's sheet as HTML (a ``<section class='sheet'>`` each)."""
    parts = []
    note = cutting_note(design)
    for sec in design.sections:
        spans = {s.span: s for s in sec.spans}
        body = [f"<section class='sheet' id='sheet-{_e(sec.section)}'><h2>{_e(sheet_title(design, sec.section))}</h2>"
                f"<p><small>{_e(note)}</small></p>"]
        for span, droppers in groupby(sec.droppers, key=lambda d: d.span):
            s = spans[span]
            body.append(f"<h3>Span {span}: {_e(s.from_mast)}–{_e(s.to_mast)}, l = {s.length:.2f} m, pre-sag "
                        f"{s.presag * 1e3:.1f} mm</h3>"
                        + _table(list(SHEET_HEADERS), [sheet_row(d) for d in droppers], set(range(1, 8))))
        body.append("</section>")
        parts.append("".join(body))
    return "".join(parts)


def add_sheets(book, design: LineDesign) -> None:
    """Add a sheet per section to an openpyxl workbook: the title, the cutting note, then per span a
    heading row and its droppers (the header row repeats on every printed page).

    Parameters
    ----------
    book : openpyxl.Workbook
        The workbook.
    design : LineDesign
        The line as built.
    """
    note = cutting_note(design)
    for sec in design.sections:
        sheet = book.create_sheet(f"sheet {sec.section}"[:31])
        sheet.append(list(SHEET_HEADERS))
        sheet.print_title_rows = "1:1"
        sheet.append([sheet_title(design, sec.section)])
        sheet.append([note])
        spans = {s.span: s for s in sec.spans}
        for span, droppers in groupby(sec.droppers, key=lambda d: d.span):
            s = spans[span]
            sheet.append([f"span {span}: {s.from_mast}–{s.to_mast}, l = {s.length:.2f} m, pre-sag "
                          f"{s.presag * 1e3:.1f} mm"])
            for d in droppers:
                sheet.append([d.id, round(d.chainage, 3), round(d.position, 3), round(d.cut_length * 1e3, 1),
                              round(d.length * 1e3, 1), round(d.messenger_height * 1e3, 1),
                              round(d.contact_wire_height * 1e3, 1), round(d.lateral * 1e3, 1)])
