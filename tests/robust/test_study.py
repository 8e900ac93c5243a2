"""robust/study.py: the robust pre-sag study of a section; its refusals before any work and of a
design outside the model's range (the full study is exercised by the CLI and LP tests)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from presag_opt.errors import ModelError
from presag_opt.robust.study import _within_model_range, robust_study
from presag_opt.system.loader import load_catenary


def test_a_bad_tolerance_loss_is_refused_before_the_form_finding():
    catenary = load_catenary("st_9.8_ideal")
    with pytest.raises(ModelError, match=r"within = 0 % is outside the valid range \(0, 200\] %"):
        robust_study(catenary, (70.0, 148.0), within=0.0)


def test_a_design_outside_the_models_range_is_refused_with_its_depth():
    catenary = load_catenary("st_9.8_ideal")
    inside = _within_model_range(catenary, SimpleNamespace(presag_rel=0.8e-3), (70.0, 148.0))
    assert inside.presag_rel == pytest.approx(0.8e-3, rel=1e-12)
    with pytest.raises(ModelError, match=r"S_rel = 6.00 ‰ \(360 mm on 60 m\), outside the model's valid range 0–5 ‰"):
        _within_model_range(catenary, SimpleNamespace(presag_rel=6e-3), (70.0, 148.0))
