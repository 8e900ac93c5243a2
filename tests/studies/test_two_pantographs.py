"""Studies with a second raised pantograph: the definition, the store with both pantographs' statistics,
the analysis of either, and the physics of the spacing (issue 23, item 7)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.studies.definition import StudyGrid, StudyTrain, load_study, study_from_dict
from presag_opt.studies.reduced import run_in_process
from presag_opt.studies.store import TRAILING_VARIABLES
from presag_opt.studies.validity_analysis import pantograph_view, validity_analysis
from presag_opt.studies.work import UnitResult
from presag_opt.system.catenary import SpanLayout
from presag_opt.units import KMH

LEADING_TOLERANCE = 0.08
"""Leading pantograph of a far-apart pair against the single one, relative σ, at 480 m on 21 spans:
measured −1.9 % on a 2-core Xeon and +5.8 % on a 2-core AMD EPYC with the same code. The coarse
numerics (1 m, 4 ms) at 180 km/h make σ follow the processor's round-off (its BLAS kernels) by a few
per cent: on the EPYC the leading σ is +3.4 % and +0.9 % at 120 and 300 m, and the single
pantograph's own σ differs by 6 % between a 15- and a 21-span section. [-]"""

TRAILING_TOLERANCE = 0.08
"""Trailing pantograph 480 m behind against the single one, relative σ: measured −2.9 % (Xeon) and
−4.2 % (EPYC); a disturbed wire lies outside (+59 % and +66 % at 120 m, +18 % at 300 m). [-]"""

DISTURBED_EXCESS = 0.3
"""Least relative excess of the trailing pantograph's σ over the single one's at 120 m behind, where
it meets the leading one's waves: measured +59 % (Xeon) and +66 % (EPYC). [-]"""


def _one_point(small_study, spans: int, spacing: float | None):
    """The small study cut to one run (S 50 mm, 180 km/h, 100 N) on ``spans`` 60 m spans."""
    catenary = small_study.catenary.with_layout(SpanLayout(span_lengths=(60.0,) * spans))
    grid = StudyGrid(presags=(0.05,), speeds=(180 * KMH,), static_forces=(100.0,),
                     aero_coefficient=small_study.grid.aero_coefficient)
    return dataclasses.replace(small_study, catenary=catenary, grid=grid, train=StudyTrain(second_pantograph_at=spacing))


@pytest.fixture(scope="module")
def small_study(small_study_path):
    return load_study(small_study_path)


def test_the_spacing_is_validated_and_a_single_train_keeps_the_hash(small_study, small_study_path):
    with pytest.raises(ModelError, match=r"train.second_pantograph_at = 600 m is outside the valid range \[5, 500\] m"):
        StudyTrain(second_pantograph_at=600.0)
    with pytest.raises(ModelError, match=r"outside the valid range \[5, 500\] m"):
        StudyTrain(second_pantograph_at=1.0)
    assert StudyTrain().spacings is None and StudyTrain(second_pantograph_at=20.0).spacings == (20.0,)
    single = dataclasses.replace(small_study, train=StudyTrain())
    assert single.digest() == small_study.digest() and not single.two_pantographs
    pair = dataclasses.replace(small_study, train=StudyTrain(second_pantograph_at=20.0))
    assert pair.digest() != small_study.digest() and pair.two_pantographs
    # a train too long for the section is refused with the grid, before anything is form-found
    with pytest.raises(ModelError, match="rear pantograph would start"):
        dataclasses.replace(small_study, train=StudyTrain(second_pantograph_at=200.0))


def test_the_train_section_of_a_study_file(small_study_path):
    import tomllib

    data = tomllib.loads(small_study_path.read_text())
    data["study"]["catenary"] = str(small_study_path.parent / data["study"]["catenary"])
    data["train"] = {"second_pantograph_at": {"value": 20, "unit": "m", "source": "assumed"}}
    assert study_from_dict(data).train.second_pantograph_at == 20.0
    data["train"] = {"spacing": {"value": 20, "unit": "m", "source": "assumed"}}
    with pytest.raises(ModelError, match=r"\[train\]: unknown key 'spacing'; valid keys: second_pantograph_at"):
        study_from_dict(data)
    del data["train"]
    data["parameters"] = [{"name": "train.second_pantograph_at", "values": {"value": [10, 20], "unit": "m", "source": "assumed"}}]
    swept = study_from_dict(data)
    assert swept.two_pantographs and [v.train.second_pantograph_at for v in swept.variants()] == [10.0, 20.0]


def test_an_old_unit_file_without_trailing_statistics_still_loads(make_dataset):
    data = {"unit": {"parameter_indices": [], "presag_index": 0, "speed_index": 0}, "speed_ratio": 0.3,
            "rule_failure": "", "failure": [""]}
    for name in ("mean_force", "std_force", "statistical_max", "statistical_min", "max_force", "min_force",
                 "loss_of_contact", "uplift_max", "presag_delta_e", "presag_mid_mast"):
        data[name] = [1.0]
    assert UnitResult.from_dict(data).trailing is None
    data["trailing"] = {"std_force": [2.0]}
    assert UnitResult.from_dict(data).trailing == {"std_force": (2.0,)}


@pytest.fixture(scope="module")
def close_pair(small_study):
    """One run with the second pantograph 20 m behind, on the 5-span test section."""
    return run_in_process(_one_point(small_study, 5, 20.0))


def test_a_two_pantograph_store_has_both_pantographs(close_pair):
    ds = close_pair
    for name in (*TRAILING_VARIABLES, "sigma_over_F_m"):
        assert ds["trailing_" + name].dims == ds[name].dims
        assert ds["trailing_" + name].attrs["units"] == ds[name].attrs["units"]
        assert np.all(np.isfinite(ds["trailing_" + name].values))
    assert ds.attrs["second_pantograph_at"] == 20.0 and ds.attrs["second_pantograph_at_units"] == "m"
    # 20 m behind, the trailing pantograph runs into the swinging wire: a larger σ (measured +37 %)
    assert float(ds["trailing_sigma"].values.ravel()[0]) > 1.2 * float(ds["sigma"].values.ravel()[0])
    view, which = pantograph_view(ds)
    assert which == "trailing"
    assert float(view["sigma"].values.ravel()[0]) == float(ds["trailing_sigma"].values.ravel()[0])
    assert pantograph_view(ds, "leading")[0] is ds


def test_the_analysis_reads_the_chosen_pantograph(make_dataset):
    ds = make_dataset(sigma=lambda s, b, f, fm: 10.0 + 1e4 * (s - 0.05) ** 2 * (1 + b), presags_mm=[30, 40, 50, 60, 70],
                      betas=[0.2, 0.3], static_forces=[80, 120], rule_mm=lambda f: 50.0)
    assert validity_analysis(ds).settings["pantograph"] == "leading"
    with pytest.raises(ModelError, match="this study ran one pantograph"):
        validity_analysis(ds, pantograph="trailing")
    with pytest.raises(ModelError, match="pantograph = 'rear' is not one of leading, trailing"):
        pantograph_view(ds, "rear")
    # a trailing pantograph whose σ no longer depends on S: the pre-sag has no benefit for it
    pair = ds.assign({f"trailing_{n}": ds[n] for n in TRAILING_VARIABLES})
    pair["trailing_sigma"] = pair["sigma"] * 0 + 20.0
    pair["trailing_sigma_over_F_m"] = pair["trailing_sigma"] / pair["trailing_F_m"]
    trailing = validity_analysis(pair)
    assert trailing.settings["pantograph"] == "trailing"
    assert not any(b.benefit for v in trailing.per_beta for b in v.bands)
    leading = validity_analysis(pair, pantograph="leading")
    assert all(b.benefit for v in leading.per_beta for b in v.bands)


@pytest.mark.slow
def test_far_behind_the_pantographs_approach_the_single_one(small_study):
    """21 spans, the second pantograph 480 m behind (9.6 s at 180 km/h): the leading one sees
    the single pantograph's wire, and the trailing one a wire whose swinging has decayed; 120 m
    behind, the trailing one meets a swinging wire."""
    single = run_in_process(_one_point(small_study, 21, None))
    pair = run_in_process(_one_point(small_study, 21, 480.0))
    near = run_in_process(_one_point(small_study, 21, 120.0))
    one = float(single["sigma"].values.ravel()[0])
    lead = float(pair["sigma"].values.ravel()[0])
    trail = float(pair["trailing_sigma"].values.ravel()[0])
    assert math.isfinite(one) and one > 0
    assert lead == pytest.approx(one, rel=LEADING_TOLERANCE)
    assert trail == pytest.approx(one, rel=TRAILING_TOLERANCE)
    # the contrast: 120 m behind, the trailing pantograph still meets the leading one's waves
    assert float(near["trailing_sigma"].values.ravel()[0]) > (1.0 + DISTURBED_EXCESS) * one
    # F_m is set by the static and aerodynamic force: within 1 % (measured 0.8 %)
    assert float(pair["trailing_F_m"].values.ravel()[0]) == pytest.approx(float(single["F_m"].values.ravel()[0]),
                                                                        rel=0.02)


@pytest.mark.slow
def test_the_leading_pantograph_equals_the_single_one_with_the_trailing_one_behind(small_study):
    """15 spans, the second pantograph 120 m (two spans) behind, starting inside the section: the
    leading one's σ is close to the single one's, the trailing one's far above it.

    The leading pantograph is not untouched: the trailing one's waves run ahead at c − v (about 46 m/s
    here) and reach it within 3 s, inside the analysed section. How much they change its σ depends on
    the details of the static state at these coarse numerics (1 m, 4 ms): 0.05 % with the form-finding
    before its along-track anchor changed, 2.0 % after (σ 27.88 → 28.44 N), while the trailing one's
    rises by about 55 % in both. Hence 3 % for the leading one, and above 1.3 × for the trailing one."""
    single = run_in_process(_one_point(small_study, 15, None))
    pair = run_in_process(_one_point(small_study, 15, 120.0))
    one = float(single["sigma"].values.ravel()[0])
    assert float(pair["sigma"].values.ravel()[0]) == pytest.approx(one, rel=0.03)
    assert float(pair["trailing_sigma"].values.ravel()[0]) > 1.3 * one


def test_presag_validity_reads_the_chosen_pantograph(presag, close_pair, tmp_path):
    import json

    from presag_opt.studies.store import write_store

    store = tmp_path / "pair.nc"
    write_store(close_pair, store)
    for choice, expected in ((None, "trailing"), ("leading", "leading"), ("trailing", "trailing")):
        done = presag("validity", str(store), "--json", *([] if choice is None else ["--pantograph", choice]))
        assert done.returncode == 0, done.stderr
        assert json.loads(done.stdout)["settings"]["pantograph"] == expected
    done = presag("validity", str(store), "--pantograph", "rear")
    assert done.returncode != 0 and "invalid choice: 'rear'" in done.stderr
