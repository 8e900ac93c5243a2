"""A designed line's tables as rows: the dropper schedule and the spans, in table units (mm, m, N, mm/N,
‰) as the column names say; ``droppers.csv`` and ``spans.csv`` are these rows, and
:meth:`~presag_opt.pipeline.line.LineAnswer.to_frame` gives them as data frames.

Spans count from 1 within each section, droppers from 1 within each span, from ``from_mast``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from presag_opt.design.line_results import LineDesign

if TYPE_CHECKING:
    from presag_opt.pipeline.line import LineAnswer

DROPPER_COLUMNS = ("section", "span", "from_mast", "to_mast", "dropper", "x_from_mast_m", "dropper_length_mm",
                   "contact_wire_height_mm", "presag_mm")
"""Columns of ``droppers.csv``."""

SPAN_COLUMNS = ("section", "span", "from_mast", "to_mast", "length_m", "presag_mm", "presag_rel_permille",
                "e_mid_mm_per_N", "e_mast_mm_per_N", "delta_e_mm_per_N", "steady_arm_pull_N", "static_uplift_mm",
                "robust_presag_mm", "presag_tolerance_low_mm", "presag_tolerance_high_mm", "margin_low_mm",
                "margin_high_mm", "flag", "note")
"""Columns of ``spans.csv``: steady-arm pull and static uplift at ``from_mast`` (empty where it is the
section's termination, which has no steady arm); the span's own quasi-static robust pre-sag and
tolerance interval on the built geometry, the built pre-sag's margin to each end (negative: outside)
and its flag (:data:`presag_opt.pipeline.line.SPAN_FLAGS`); why a span is not sized (empty for an end span's
tolerance columns)."""

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
    return [{"section": d.section, "span": d.span, "from_mast": d.from_mast, "to_mast": d.to_mast, "dropper": d.dropper,
             "x_from_mast_m": round(d.position, 3), "dropper_length_mm": round(d.length * 1e3, 1),
             "contact_wire_height_mm": round(d.contact_wire_height * 1e3, 1), "presag_mm": round(d.presag * 1e3, 1),
             **({"hangs_from": "stitch wire" if d.stitch else "messenger"} if stitched else {})}
            for d in design.droppers]


def _mm(value: float | None, digits: int = 1) -> object:
    return "" if value is None else round(value * 1e3, digits)


def span_rows(answer: LineAnswer) -> list[dict[str, object]]:
    """The span table as rows (mm, m, N, mm/N, ‰)."""
    rows = []
    for s in answer.design.spans:
        margins = s.margins() or (None, None)
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
            "note": s.note,
        })
    return rows
