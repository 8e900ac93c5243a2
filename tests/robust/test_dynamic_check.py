"""The dynamic check of robust designs (presag_opt.robust.dynamic_check) on a small section, and the
catenary built to a per-dropper design."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.dynamics.simulate import simulate
from presag_opt.errors import ModelError
from presag_opt.robust import dynamic_check
from presag_opt.robust.dynamic_check import design_catenary
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

THREE_SPANS = SpanLayout(span_lengths=(60.0, 60.0, 60.0))


def test_dynamic_check_runs_each_design_and_sorts_runs_by_regime():
    catenary = load_catenary("st_9.8_ideal").with_layout(THREE_SPANS)
    pantograph = load_pantograph("case_study_2mass_friction")
    settings = SimulationSettings(analysed_spans=1, lead_in_spans=0)
    speeds = (90 / 3.6, 180 / 3.6)  # β = 0.26 and 0.52 on 9.8 kN: one run either side of 0.4
    check = dynamic_check(
        catenary, {"robust": 0.93e-3}, pantograph=pantograph, static_forces=(100.0,), speeds=speeds,
        aero_coefficient=0.0, reference_span=60.0, settings=settings,
    )
    assert [(r.design, r.speed) for r in check.runs] == [("robust", s) for s in speeds]
    # Each run is the simulation of the design's own geometry, in one batch: identical to a direct
    # batch (a run does not depend on the others of its batch), and close to the single-run path.
    state = form_find(catenary.with_presag(0.93e-3))
    direct = simulate_many(state, pantograph, [OperatingPoint(speed=v, static_force=100.0) for v in speeds],
                           settings=settings)
    assert [r.sigma_over_mean for r in check.runs] == [d.statistics[0].sigma_over_mean for d in direct.runs]
    single = simulate(state, pantograph, speed=speeds[0], static_force=100.0, settings=settings)
    assert check.runs[0].sigma_over_mean == pytest.approx(single.statistics.sigma_over_mean, rel=1e-3)
    assert check.runs[0].presag == pytest.approx(0.93e-3 * 60.0, rel=1e-15)
    summary = check.summary()
    assert [row["regime"] for row in summary] == ["beta < 0.4", "beta >= 0.4"]
    assert [row["runs"] for row in summary] == [1, 1]
    assert summary[1]["worst_sigma_over_Fm"] == check.runs[1].sigma_over_mean


class _Path:
    """The parts of a path model that design_catenary reads: analysed spans and their droppers."""

    def __init__(self, catenary, spans):
        lengths = catenary.layout.span_lengths
        self.spans = tuple(spans)
        drops = [catenary.droppers.positions_in_span(lengths[s]) for s in spans]
        self.dropper_span = np.concatenate([np.full(len(d), s) for s, d in zip(spans, drops)])
        self.dropper_fraction = np.concatenate([d / lengths[s] for s, d in zip(spans, drops)])


def test_an_ideal_section_gets_the_central_profile_in_every_span():
    catenary = load_catenary("st_9.8_ideal")
    path = _Path(catenary, [catenary.layout.central_span])
    depths = np.array([0.010, 0.030, 0.045, 0.052, 0.045, 0.030, 0.020, 0.010])[: len(path.dropper_span)]
    built = design_catenary(catenary, path, depths)
    assert built.presag_profile == (tuple(depths),) * catenary.layout.n_spans
    # its label: the mean mid-span depth over span length (the mid-span dropper here)
    middle = np.interp(0.5, path.dropper_fraction, depths)
    assert built.presag_rel == pytest.approx(middle / 60.0, rel=1e-12)


def test_a_mixed_section_scales_the_nearest_designed_span(short_mixed):
    lengths = short_mixed.layout.span_lengths  # 45.0, 58.4, 24.7, 40.7, 52.0
    path = _Path(short_mixed, [1, 2, 3])
    t = path.dropper_fraction
    depths = 1.1e-3 * np.asarray(lengths)[path.dropper_span] * 4.0 * t * (1.0 - t) * (1.0 + 0.1 * path.dropper_span)
    built = design_catenary(short_mixed, path, depths)
    for s in (1, 2, 3):
        np.testing.assert_array_equal(built.presag_profile[s], depths[path.dropper_span == s])
    # span 0 (45.0 m) takes the relative shape of span 3 (40.7 m, factor 1.3), span 4 (52.0 m) that of
    # span 1 (58.4 m, factor 1.1), straight between the source's droppers, scaled to their own length
    for s, source, factor in ((0, 3, 1.3), (4, 1, 1.1)):
        t_source = np.r_[0.0, t[path.dropper_span == source], 1.0]
        relative = 1.1e-3 * 4.0 * t_source * (1.0 - t_source) * factor
        drops = short_mixed.droppers.positions_in_span(lengths[s]) / lengths[s]
        expected = np.interp(drops, t_source, relative) * lengths[s]
        np.testing.assert_allclose(built.presag_profile[s], expected, rtol=1e-12)


def test_a_design_built_into_another_catenary_is_refused(path):
    """A per-dropper design belongs to the catenary it was designed for: a shorter section is refused
    with the reason, not an IndexError."""
    catenary = path.state.catenary
    short = catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 3))
    with pytest.raises(ModelError, match="build it into the catenary it was designed for"):
        design_catenary(short, path, path.parabola_depths(0.001))
