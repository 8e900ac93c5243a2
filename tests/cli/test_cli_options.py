"""Command-line options no other default test reaches, run in-process:
``recommend --per-span / --recompute / --elasticity-method newton``, ``robust --asymmetric`` and the
``generic_3mass`` pantograph model in ``simulate``."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

SHORT_MODEL = Path(__file__).parents[1] / "studies" / "models" / "st_9.8_short.toml"


@pytest.fixture(scope="module")
def mixed_model(tmp_path_factory) -> Path:
    """The five-span test model with five different span lengths: a small mixed section."""
    text = SHORT_MODEL.read_text()
    text, count = re.subn(
        r"span_lengths = \{[^\n]*\}\nspan_count = \{[^\n]*\}",
        'span_lengths = { value = [45.0, 58.4, 24.7, 40.7, 52.0], unit = "m", source = "assumed" }',
        text,
    )
    assert count == 1
    path = tmp_path_factory.mktemp("models") / "mixed5.toml"
    path.write_text(text)
    return path


def test_recommend_newton_and_recompute_match_the_library(presag, mixed_model, tmp_path):
    """``--elasticity-method newton --recompute --step 10``: the JSON equals the library's result with the
    same arguments (same code, deterministic: 1e-12), and differs from the active-set result, so the
    option reached the computation (the methods differ by 0.3–1.4 % in Δe at 100–150 N)."""
    from presag_opt.design import recommend
    from presag_opt.system.loader import load_catenary

    run = presag("recommend", "--models", str(mixed_model), "--elasticity-method", "newton", "--recompute",
                 "--step", "10", "--json", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    newton = recommend(models=[load_catenary(mixed_model)], elasticity_method="newton", step=10.0)
    active = recommend(models=[load_catenary(mixed_model)], step=10.0)
    assert np.array(out["presag_rel_range_permille"]) == pytest.approx(np.array(newton.presag_rel_range) * 1e3, rel=1e-12)
    assert abs(newton.presag_rel / active.presag_rel - 1.0) > 1e-4
    again = out["recomputed_at_recommended_geometry"]
    assert again["layouts"][0]["geometry_presag_rel_permille"] == pytest.approx(out["presag_rel_permille"], rel=1e-12)


def test_recommend_per_span_table(presag, mixed_model, tmp_path):
    run = presag("recommend", "--models", str(mixed_model), "--per-span", "--step", "5", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    table = run.stdout.split("Per span,")[1]
    # the three inner spans (the two end spans are left out), with their lengths
    rows = [line.split() for line in table.splitlines() if re.match(r"\s+\d+\s+\d", line)]
    assert [(r[0], r[1]) for r in rows] == [("2", "58.4"), ("3", "24.7"), ("4", "40.7")]


def test_robust_asymmetric_per_dropper(presag, tmp_path):
    run = presag("robust", str(SHORT_MODEL), "--shape", "per-dropper", "--asymmetric", "--json", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    depths = np.array(out["dropper_depths_mm"])
    assert len(depths) == 7  # every dropper of the analysed span is a free depth
    np.testing.assert_allclose(depths / 5.0, np.round(depths / 5.0), atol=1e-9)  # 5 mm step, round-off only
    # The per-dropper profile relaxes the parabola: its continuous optimum is at most the worst case
    # of the nominal Δe parabola, a feasible profile (LP tolerance 1e-6).
    assert out["continuous_objective_mm"] <= out["nominal_worst_case_waviness_mm"] * (1 + 1e-6)
    assert out["objective_mm"] >= out["continuous_objective_mm"]  # rounding only loses


@pytest.mark.slow  # keeps the default run under 5 minutes; the batch tests cover the same path
def test_simulate_with_the_generic_three_mass_pantograph(presag, tmp_path):
    """The ``generic_3mass`` model runs; its mean contact force is the uplift force F_stat + α_ae v²
    within 2 % (as for the other pantographs in tests/dynamics/test_simulate.py)."""
    six_spans = tmp_path / "six.toml"  # the fewest spans for 2 analysed after 2 lead-in spans
    text, count = re.subn(r"span_count = \{ value = 5,", "span_count = { value = 6,", SHORT_MODEL.read_text())
    assert count == 1
    six_spans.write_text(text)
    run = presag("simulate", str(six_spans), "--pantograph", "generic_3mass", "--speed", "90",
                 "--static-force", "100", "--aero", "0.00097", "--json", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    assert out["pantograph"].startswith("Generic 3-mass")
    assert out["Fm_N"] == pytest.approx(100.0 + 0.00097 * 90.0**2, rel=0.02)  # measured 0.0 %
    assert out["sigma_N"] > 0.0
