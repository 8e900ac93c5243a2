"""Our numbers beside the paper's: Table 1, Table 2, the recommendation and Fig. 5b.

Holds the Table 2 rows of a section, the comparison rows and :func:`compare_with_paper`, which
computes what the comparison needs on the built-in models. The published numbers are in
:mod:`presag_opt.validation.paper`; the rules and the recommendation in :mod:`presag_opt.design`.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: Tables 1–2, Fig. 5b, section 5.2.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import presag_opt.validation.paper as published
from presag_opt.design.empirical import EmpiricalPresag
from presag_opt.design.recommendation import Recommendation
from presag_opt.design.section import SectionElasticity, section_elasticity, tension_label
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.loader import load_catenary
from presag_opt.validation.single_curve import SingleCurveError, single_curve_error


@dataclass(frozen=True, kw_only=True)
class Table2Row:
    """Quasi-static pre-sag of an ideal section at one F_m by both variants (the paper's Table 2).

    Attributes
    ----------
    tension_label : str
        System by its tensions in kN, e.g. ``"9.8/9.8"``.
    span_length : float
        Length of the analysed span. [m]
    mean_force : float
        F_m. [N]
    presag_mid_mast, presag_delta_e : float
        S by each variant. [m]
    """

    tension_label: str
    span_length: float
    mean_force: float
    presag_mid_mast: float
    presag_delta_e: float


def table2_row(section: SectionElasticity, mean_force: float = published.PAPER_TABLE2_FORCE) -> Table2Row:
    """Table 2 values of a section: S by both variants at ``mean_force`` (first analysed span).

    Parameters
    ----------
    section : SectionElasticity
        Elasticity study of the section.
    mean_force : float
        Mean contact force F_m. [N]

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, Table 2.
    """
    mid_mast = section.presag(mean_force, "mid-mast")
    delta_e = section.presag(mean_force, "delta-e")
    return Table2Row(
        tension_label=tension_label(section.catenary),
        span_length=float(section.span_lengths[0]),
        mean_force=float(mean_force),
        presag_mid_mast=float(mid_mast.presag[0]),
        presag_delta_e=float(delta_e.presag[0]),
    )


@dataclass(frozen=True, kw_only=True)
class ComparisonRow:
    """One of our numbers beside the paper's.

    Attributes
    ----------
    item : str
        What is compared.
    unit : str
        Unit of both values (edge units: mm, ‰, mm/N, %).
    ours, paper : float
        The two values. [``unit``]
    """

    item: str
    unit: str
    ours: float
    paper: float

    @property
    def difference(self) -> float:
        """ours − paper, in ``unit`` (the meaningful measure for values that are themselves errors in %)."""
        return self.ours - self.paper

    @property
    def relative_difference(self) -> float:
        """(ours − paper) / paper. [-]"""
        return (self.ours - self.paper) / self.paper


@dataclass(frozen=True, kw_only=True)
class PaperComparison:
    """Our values beside the paper's (Table 1, Table 2, recommendation, Fig. 5b).

    Attributes
    ----------
    rows : tuple of ComparisonRow
        The compared numbers.
    table2 : tuple of Table2Row
        Our Table 2 values the rows were made from.
    single_curve_errors : tuple of SingleCurveError
        Our Fig. 5b studies the rows were made from.
    """

    rows: tuple[ComparisonRow, ...]
    table2: tuple[Table2Row, ...] = ()
    single_curve_errors: tuple[SingleCurveError, ...] = ()

    def to_dict(self) -> list[dict]:
        """JSON-ready rows (relative difference as a fraction)."""
        return [
            {
                "item": r.item, "unit": r.unit, "ours": r.ours, "paper": r.paper,
                "difference": r.difference, "relative_difference": r.relative_difference,
            }
            for r in self.rows
        ]


def comparison_rows(
    *,
    recommendation: Recommendation | None = None,
    table2_rows: Sequence[Table2Row] = (),
    single_curve_errors: Sequence[SingleCurveError] = (),
) -> tuple[ComparisonRow, ...]:
    """Rows setting our numbers beside the paper's, from results already computed.

    Table 1 is always included (it needs no model); the other parts when given: Table 2 rows (S in
    mm at 140 N; systems the paper does not list are skipped), a recommendation (F_m band, S_rel
    range per layout kind, mean S_rel, S on the nominal span, β_max) and Fig. 5b errors at 179 N
    (geometries other than the paper's 30 and 70 mm are skipped).

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, Tables 1–2, Fig. 5b, section 5.2.
    """
    rows = []
    for label, paper in published.PAPER_TABLE1.items():
        cw, mw = (float(t) * 1e3 for t in label.split("/"))
        ours = EmpiricalPresag(
            span_length=published.PAPER_TABLE1_SPAN_LENGTH, contact_wire_tension=cw, messenger_wire_tension=mw,
            static_force=published.PAPER_TABLE1_STATIC_FORCE,
        ).printed()
        rows.append(ComparisonRow(
            item=f"Table 1 {label} e_mid", unit="mm/N", ours=ours["e_mid_mm_per_N"], paper=paper["e_mid_mm_per_N"],
        ))
        for end, i in (("low", 0), ("high", 1)):
            rows.append(ComparisonRow(
                item=f"Table 1 {label} S {end}", unit="mm", ours=ours["presag_mm"][i], paper=paper["presag_mm"][i],
            ))
            rows.append(ComparisonRow(
                item=f"Table 1 {label} S_rel {end}", unit="‰",
                ours=ours["presag_rel_permille"][i], paper=paper["presag_rel_permille"][i],
            ))
    for row in table2_rows:
        paper = published.PAPER_TABLE2_MM.get(row.tension_label)
        if paper is None:
            continue
        rows.append(ComparisonRow(
            item=f"Table 2 {row.tension_label} S mid-mast", unit="mm", ours=row.presag_mid_mast * 1e3, paper=paper["mid-mast"],
        ))
        rows.append(ComparisonRow(
            item=f"Table 2 {row.tension_label} S delta-e", unit="mm", ours=row.presag_delta_e * 1e3, paper=paper["delta-e"],
        ))
    if recommendation is not None:
        rec = recommendation
        for end, i in (("low", 0), ("high", 1)):
            rows.append(ComparisonRow(
                item=f"F_m band {end}", unit="N", ours=rec.mean_force_band[i],
                paper=published.PAPER_RECOMMENDATION["fm_band_N"][i],
            ))
        for lay in rec.layouts:
            paper = published.PAPER_RECOMMENDATION["presag_rel_range_permille"][lay.layout_kind]
            for end, i in (("low", 0), ("high", 1)):
                rows.append(ComparisonRow(
                    item=f"S_rel {lay.layout_kind} {end} ({rec.method})", unit="‰",
                    ours=lay.presag_rel_range[i] * 1e3, paper=paper[i],
                ))
        rows.append(ComparisonRow(
            item=f"S_rel recommended ({rec.method})", unit="‰", ours=rec.presag_rel * 1e3,
            paper=published.PAPER_RECOMMENDATION["presag_rel_permille"],
        ))
        rows.append(ComparisonRow(
            item=f"S recommended on {rec.nominal_span_length:g} m", unit="mm", ours=rec.presag * 1e3,
            paper=published.PAPER_RECOMMENDATION["presag_mm"],
        ))
        rows.append(ComparisonRow(
            item="beta_max", unit="-", ours=rec.beta_max, paper=published.PAPER_RECOMMENDATION["beta_max"],
        ))
    for study in single_curve_errors:
        paper = next(
            (v for s, v in published.PAPER_SINGLE_CURVE_ERROR.items()
             if math.isclose(s, study.geometry_presag, abs_tol=5e-4)),
            None,
        )
        if paper is None:
            continue
        rows.append(ComparisonRow(
            item=f"Fig. 5b error at {published.SINGLE_CURVE_MAX_FORCE:g} N, {study.geometry_presag * 1e3:.0f} mm geometry",
            unit="%", ours=study.error_at(published.SINGLE_CURVE_MAX_FORCE) * 100, paper=paper * 100,
        ))
    return tuple(rows)


def compare_with_paper(
    recommendation: Recommendation | None = None,
    *,
    step: float = 0.5,
    elasticity_method: str = "active-set",
    settings: StaticSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> PaperComparison:
    """Compute Table 2 and Fig. 5b on our models and set them (and Table 1) beside the paper.

    Table 2: ST 7,1/7,1 and ST 9,8/9,8 on ideal 60 m spans at their model pre-sag (the nominal 30 mm),
    S by both variants at F_m = 140 N. Fig. 5b: ST 9,8/9,8 ideal spans at 30 mm and 70 mm pre-sag,
    Δe rule, one 100 N curve against curves at 50, 100, 150 and 200 N, F_m up to 179 N. Three
    form-findings in all (the 30 mm ST 9,8/9,8 section serves both studies).

    Parameters
    ----------
    recommendation : Recommendation, optional
        Our case-study recommendation, compared with section 5.2.
    step : float
        Point spacing of the elasticity curves. [m]
    elasticity_method : {"active-set", "newton"}
        Method of the nonlinear elasticity.
    settings : StaticSettings, optional
        Numerical settings of the static model.
    progress : callable, optional
        Called with a short message before each expensive step.

    Returns
    -------
    PaperComparison
    """
    kwargs = dict(step=step, elasticity_method=elasticity_method, settings=settings, progress=progress)
    fig5b_levels = (50.0, 100.0, 150.0, 200.0)
    nominal = load_catenary(published.SINGLE_CURVE_MODEL)
    span_length = nominal.layout.span_lengths[nominal.layout.central_span]
    fig5b = [
        section_elasticity(nominal.with_presag(presag / span_length), force_levels=fig5b_levels, **kwargs)
        for presag in published.PAPER_SINGLE_CURVE_ERROR
    ]
    table2_sections = [
        fig5b[0] if name == published.SINGLE_CURVE_MODEL and math.isclose(nominal.presag_rel * span_length, 0.030)
        else section_elasticity(load_catenary(name), force_levels=(100.0, 150.0), **kwargs)
        for name in published.PAPER_TABLE2_MODELS
    ]
    table2 = tuple(table2_row(s) for s in table2_sections)
    errors = tuple(single_curve_error(s) for s in fig5b)
    return PaperComparison(
        rows=comparison_rows(recommendation=recommendation, table2_rows=table2, single_curve_errors=errors),
        table2=table2,
        single_curve_errors=errors,
    )

