"""A validity sweep as evidence (presag_opt.studies.validity_evidence), on a synthetic study whose β* is
known by construction (tests/studies/test_validity_analysis.py: the rule leaves its 10 mm band at
β = 0.447, between grid β 0.40 and 0.45)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.studies.validity_analysis import validity_analysis
from presag_opt.studies.validity_evidence import sweep_reference_span, sweep_wave_speed, validity_sweep
from presag_opt.system.loader import load_catenary
from presag_opt.units import KMH

BETAS = [0.1, 0.2, 0.3, 0.4, 0.45, 0.5]
PRESAGS_MM = [20, 60, 100]
FORCES = [50, 100, 150]


def uplift(s, beta, static_force):
    """Uplift rising with the speed ratio and the static force, falling with the pre-sag. [m]"""
    return 0.040 + 0.040 * beta + 0.0002 * static_force - 0.05 * s


@pytest.fixture(scope="module")
def study(make_dataset):
    from tests.studies.test_validity_analysis import relative_parabola, rule_mm

    return make_dataset(sigma=relative_parabola(0.010), presags_mm=PRESAGS_MM, betas=BETAS, static_forces=FORCES,
                        rule_mm=rule_mm, uplift=uplift)


def test_the_record_reads_beta_star_its_resolution_and_the_uplift_up_to_the_top_speed(study):
    wire = load_catenary("st_9.8_ideal").contact_wire
    result = validity_analysis(study)
    top = 0.3 * wire.wave_speed  # the band's top speed: β 0.3
    record = validity_sweep(study, result, kind="study", name="the test study", speed_high=top,
                            line_wave_speed=wire.wave_speed)
    assert record.limit.beta_star == pytest.approx(0.425, abs=1e-9)
    assert record.limit.resolution == pytest.approx(0.025, abs=1e-9)
    assert record.limit.grid_betas == pytest.approx(tuple(BETAS), rel=1e-9)
    assert sweep_reference_span(study) == 60.0 and sweep_wave_speed(study) == pytest.approx(wire.wave_speed, rel=1e-12)
    assert record.presag_rel == pytest.approx(tuple(s * 1e-3 / 60.0 for s in PRESAGS_MM), rel=1e-12)
    # the largest over the swept speeds up to β 0.3, exactly the formula there
    expected = np.array([[uplift(s * 1e-3, 0.3, f) for f in FORCES] for s in PRESAGS_MM])
    assert np.allclose(record.uplift, expected, rtol=1e-12, atol=0.0)
    assert record.note == ""


def test_a_study_of_another_contact_wire_is_noted(study):
    result = validity_analysis(study)
    record = validity_sweep(study, result, kind="reduced", name="the other sweep", speed_high=50 * KMH,
                            line_wave_speed=80.0)
    assert "wave speed 345 km/h, this line's is 288 km/h" in record.note and "ratios carry over" in record.note
