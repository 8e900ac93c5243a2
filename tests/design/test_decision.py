"""The one decision (presag_opt.design.decision): a table over every branch of ``decide``, with hand-made
evidence whose answer is known by construction (intervals in mm on a 60 m span, the crew's ±2.5 mm)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design.decision import (
    DELTA_E_RULE,
    DYNAMIC_ROBUST,
    LARGEST_MARGIN,
    QUASI_STATIC_ROBUST,
    decide,
)
from presag_opt.design.evidence import (
    DeltaERule,
    DynamicRobust,
    Evidence,
    InstallationTolerance,
    QuasiStaticRobust,
    ValiditySweep,
    crew_tolerance,
)
from presag_opt.design.validity_limit import SweepLimit
from presag_opt.units import KMH

SPAN = 60.0
C_KMH = 344.5  # the case study's contact-wire wave speed, in km/h


def rel(mm: float) -> float:
    """mm on the 60 m span -> S_rel."""
    return mm * 1e-3 / SPAN


def evidence(*, beta: float = 0.26, qs: tuple | None = (55.8, 50.9, 58.3), delta_e_mm: float = 56.0,
             static_uplift_mm: float = 53.9, dyn: tuple | None = None, sweep: ValiditySweep | None = None,
             crew_mm: float | None = None, scope: str = "band") -> Evidence:
    """Evidence of a band at speed ratio ``beta``; ``qs`` and ``dyn`` are (S, low, high) in mm (``dyn`` may
    carry a fourth item, its uplift in mm, and a fifth, its simulated (S mm, uplift mm) points)."""
    dynamic = None
    if dyn is not None:
        s, low, high, *rest = dyn
        uplift = rest[0] if rest else 60.0
        points = rest[1] if len(rest) > 1 else ((low, uplift), (s, uplift), (high, uplift))
        dynamic = DynamicRobust(presag_rel=rel(s), tolerance=(rel(low), rel(high)), within=0.1, uplift=uplift * 1e-3,
                                simulated=tuple((rel(a), b * 1e-3) for a, b in points), where="test grid")
    return Evidence(
        wave_speed=C_KMH * KMH, speed_high=beta * C_KMH * KMH, uplift_limit=0.0835, reference_span=SPAN,
        static_force_floor=70.0, static_force_estimate=150.0,
        delta_e=DeltaERule(presag_rel=rel(delta_e_mm), presag_rel_range=(rel(41.0), rel(80.0)),
                           static_uplift=static_uplift_mm * 1e-3, support_elasticity=static_uplift_mm * 1e-3 / 147.9),
        quasi_static_robust=None if qs is None else QuasiStaticRobust(presag_rel=rel(qs[0]),
                                                                      tolerance=(rel(qs[1]), rel(qs[2])), within=0.1),
        dynamic_robust=dynamic, validity_sweep=sweep, installation=crew_tolerance(None if crew_mm is None else crew_mm * 1e-3),
        scope=scope,
    )


def mm(value: float) -> float:
    return value * SPAN * 1e3


# (name, evidence, status, basis, S to build [mm], tolerance [mm])
CASES = [
    ("trusted, the robust design keeps the crew's margin: built as it is, provisional without the dynamic tolerance",
     evidence(qs=(55.0, 50.9, 58.3)), "provisional", QUASI_STATIC_ROBUST, 55.0, 1e-9),
    ("trusted, the robust design 1.0 mm from an end: moved to the largest margin",
     evidence(qs=(57.3, 50.9, 58.3)), "provisional", LARGEST_MARGIN, 54.6, 0.01),
    ("trusted, an interval narrower than twice the crew's tolerance: tolerance-bound at its centre",
     evidence(qs=(55.8, 54.0, 58.0)), "tolerance-bound", LARGEST_MARGIN, 56.0, 0.01),
    ("trusted and inside the dynamic tolerance with margin: the quasi-static robust design is decided",
     evidence(qs=(52.0, 48.0, 58.0), dyn=(45.0, 28.0, 56.1)), "decided", QUASI_STATIC_ROBUST, 52.0, 1e-9),
    ("the case study: 55.8 mm lies 0.3 mm inside the dynamic tolerance's end: the intersection's centre",
     evidence(dyn=(45.1, 28.0, 56.1)), "decided", LARGEST_MARGIN, 53.5, 0.01),
    ("the case study with a crew of ±3 mm: the 5.2 mm intersection cannot hold it",
     evidence(dyn=(45.1, 28.0, 56.1), crew_mm=3.0), "tolerance-bound", LARGEST_MARGIN, 53.5, 0.01),
    ("beyond the limit with the dynamic design: it decides, the quasi-static interval not in force",
     evidence(beta=0.45, dyn=(40.0, 30.0, 50.0)), "decided", DYNAMIC_ROBUST, 40.0, 1e-9),
    ("beyond the limit without the dynamic design: provisional, the quasi-static answer shown",
     evidence(beta=0.45), "provisional", QUASI_STATIC_ROBUST, 55.8, 1e-9),
    ("at the paper's limit (0.35 < β ≤ 0.40): not trusted, as beyond",
     evidence(beta=0.37), "provisional", QUASI_STATIC_ROBUST, 55.8, 1e-9),
    ("no robust design: the Δe rule, no interval in force",
     evidence(qs=None, delta_e_mm=61.0), "provisional", DELTA_E_RULE, 61.0, 1e-9),
]


@pytest.mark.parametrize(("name", "ev", "status", "basis", "built_mm", "tol"), CASES, ids=[c[0][:40] for c in CASES])
def test_every_branch_of_decide(name, ev, status, basis, built_mm, tol):
    d = decide(ev)
    assert (d.status, d.basis) == (status, basis), name
    assert mm(d.presag_rel) == pytest.approx(built_mm, abs=tol), name


def test_non_overlapping_intervals_put_the_quasi_static_one_out_of_force():
    d = decide(evidence(qs=(62.0, 60.0, 64.0), dyn=(45.0, 38.0, 52.0)))
    intervals = {i.name: i for i in d.intervals}
    assert intervals["quasi-static tolerance"].in_force is False
    assert "does not overlap" in intervals["quasi-static tolerance"].why_not
    assert intervals["dynamic tolerance"].in_force
    assert mm(d.presag_rel) == pytest.approx(45.0, abs=0.01)  # the centre of 38–52 mm, its largest margin
    assert d.basis == LARGEST_MARGIN


def test_margin_is_the_smallest_distance_to_an_end_in_force_and_reaches_the_crew():
    d = decide(evidence(dyn=(45.1, 28.0, 56.1)))
    assert mm(d.margin()) == pytest.approx((56.1 - 50.9) / 2, abs=0.01)  # the intersection 50.9–56.1 mm, halved
    assert mm(d.margin()) >= 2.5
    row = d.to_dict()
    assert row["margin_mm"] == pytest.approx(2.6, abs=0.01)
    assert [i["name"] for i in row["intervals"]] == ["dynamic tolerance", "quasi-static tolerance"]
    for interval in row["intervals"]:
        below, above = interval["margins_mm"]
        assert below == pytest.approx(row["presag_mm"] - interval["low_mm"], abs=1e-9)
        assert above == pytest.approx(interval["high_mm"] - row["presag_mm"], abs=1e-9)


def test_the_moved_pre_sag_keeps_the_uplift_limit_where_the_simulation_knows_it():
    """The dynamic design's simulated uplift is over the limit above 53 mm: the largest margin is sought
    where it is kept (the feasible part 50.9–53 mm of the intersection), on the safe side of each bracket."""
    points = ((28.0, 60.0), (45.1, 62.0), (53.0, 80.0), (54.0, 90.0), (56.1, 95.0))
    d = decide(evidence(dyn=(45.1, 28.0, 56.1, 62.0, points)))
    assert d.basis == LARGEST_MARGIN
    assert mm(d.presag_rel) == pytest.approx((50.9 + 53.0) / 2, abs=0.01)  # the centre of 50.9–53 mm
    assert d.uplift <= 0.0835
    assert mm(d.margin()) == pytest.approx(1.05, abs=0.01)  # to 50.9 mm; the uplift limit is as far above
    assert d.status == "tolerance-bound"  # 50.9–53 mm holds at most 1.05 mm of margin
    assert "at most 1.1 mm of margin" in d.reason


def sweep(uplift_mm: np.ndarray, presags_mm=(30.0, 55.0, 80.0), forces=(70.0, 105.0, 140.0), betas=(0.2, 0.3)):
    limit = SweepLimit(kind="study", name="the test study", beta_star=None, resolution=0.0,
                       grid_betas=betas, holds_at=(True,) * len(betas))
    return ValiditySweep(limit=limit, presag_rel=tuple(rel(s) for s in presags_mm), static_forces=forces,
                         uplift=np.asarray(uplift_mm) * 1e-3)


def test_uplift_bound_names_the_highest_static_force_the_sweep_allows():
    uplift = np.array([[70.0, 82.0, 90.0], [72.0, 84.0, 91.0], [75.0, 88.0, 95.0]])  # presag × static force
    d = decide(evidence(sweep=sweep(uplift)))
    assert d.status == "uplift-bound"
    assert d.highest_static_force == 105.0  # the 30 mm pre-sag keeps 83.5 mm up to 105 N
    assert "105 N" in d.reason and "uplift compatibility" in d.reason


def test_uplift_bound_not_even_at_the_lowest_force():
    d = decide(evidence(sweep=sweep(np.full((3, 3), 90.0))))
    assert d.status == "uplift-bound" and d.highest_static_force is None
    assert "lowest static force, 70 N" in d.reason


def test_uplift_bound_from_the_static_estimate_alone():
    d = decide(evidence(static_uplift_mm=90.0))
    assert d.status == "uplift-bound"
    assert d.highest_static_force == 150.0  # the evidence's static estimate
    assert d.uplift_kind == "static estimate"


def test_a_dynamic_design_within_the_limit_proves_the_band_buildable():
    """The dynamic search keeps the uplift limit as a constraint: its design within the limit means some S
    keeps it, whatever the static estimate says."""
    d = decide(evidence(static_uplift_mm=90.0, dyn=(45.1, 28.0, 56.1, 70.0)))
    assert d.status != "uplift-bound"


def test_no_verdict_on_round_off_an_indicative_sweep_leaves_the_paper_s_limit():
    """The report's quick sweep has its lowest speed at the band's top (β 0.261226 against the band's
    0.261227): it cannot place the limit below the band and the paper's limit stays in force, on either
    side of the 1e-6."""
    for beta in (0.261226479, 0.261227479, 0.261225479):
        limit = SweepLimit(kind="reduced", name="the reduced sweep", beta_star=None, resolution=0.0,
                           grid_betas=(0.261226479, 0.6), holds_at=(False, False))
        swept = ValiditySweep(limit=limit, presag_rel=(rel(28.0), rel(84.0)), static_forces=(70.0, 140.0),
                              uplift=np.full((2, 2), 0.05))
        d = decide(evidence(beta=beta, sweep=swept))
        assert d.validity.verdict == "holds" and d.status == "provisional", beta
        assert "indicative" in d.validity.note


def test_not_checked_is_the_missing_records_named_by_the_command_s_options():
    d = decide(evidence())
    assert d.missing == ("validity_sweep", "dynamic_robust", "installation_monte_carlo")
    text = d.not_checked({"dynamic_robust": "--dynamic-robust"})
    assert any("--dynamic-robust" in t for t in text)
    assert any("not offered by this command" in t for t in text)
    line = decide(evidence(scope="line"))
    assert "dynamic_check" in line.missing  # only a line's built pre-sag has a dynamic check of its own
    mc = InstallationTolerance(half_width=0.002, kind="monte-carlo", source="P95 of a test Monte Carlo")
    d = decide(Evidence(**{**evidence().__dict__, "installation": mc}))
    assert "installation_monte_carlo" not in d.missing


def test_lines_show_every_interval_s_margins_the_validity_sentence_and_the_alternatives():
    d = decide(evidence(dyn=(45.1, 28.0, 56.1)))
    text = "\n".join(d.lines({}))
    assert text.splitlines()[0].startswith("Pre-sag to build: 0.89 ‰ = ")
    assert "dynamic tolerance 28.0–56.1 mm: inside, +25.5 / +2.6 mm" in text
    assert "quasi-static tolerance 50.9–58.3 mm: inside, +2.6 / +4.8 mm" in text
    assert "crew tolerance ±2.5 mm (assumed" in text
    assert d.validity.sentence() in text
    assert "alternative: quasi-static robust design 0.93 ‰ = 55.8 mm" in text
    assert "alternative: dynamic robust design 0.75 ‰ = 45.1 mm" in text
    line = d.headline(span_lengths=[51.0, 66.0])
    assert "0.89 ‰ × span length (45–59 mm on 51–66 m spans)" in line


@pytest.mark.parametrize(("status", "start"), [
    ("tolerance-bound", "The band cannot be met with a crew tolerance of ±3.0 mm"),
    ("uplift-bound", "No pre-sag keeps the steady-arm uplift limit"),
    ("provisional", "Pre-sag to build (provisional)"),
])
def test_headline_of_each_status(status, start):
    ev = {"tolerance-bound": evidence(dyn=(45.1, 28.0, 56.1), crew_mm=3.0),
          "uplift-bound": evidence(static_uplift_mm=90.0), "provisional": evidence()}[status]
    d = decide(ev)
    assert d.status == status and d.headline().startswith(start)
