"""The Fig. 5b study (presag_opt.validation.single_curve): one elasticity curve against interpolation."""

from __future__ import annotations

import pytest

from presag_opt.validation import single_curve_error

# Regression values: relative error of sizing S (Δe rule) from the 100 N curve alone, at F_m = 179 N,
# on the nominal 30 mm and the 70 mm geometry; computed once with this code (active-set, 0.5 m). The
# paper reads 16 % and 2 %. Tolerance 0.002 (absolute, i.e. 0.2 percentage points): solver noise is
# ~1e-6, and the paper's own values are read off a figure.
FIG5B_REGRESSION = {0.030: 0.2046, 0.070: 0.0853}


def test_single_curve_error_study(ideal98, ideal98_70mm):
    nominal, large = single_curve_error(ideal98), single_curve_error(ideal98_70mm)
    for study in (nominal, large):
        assert study.mean_forces[-1] == pytest.approx(179.0, abs=1e-12)
        # At the reference force the single curve is the interpolated curve (same object).
        assert study.error_at(100.0) == 0.0
        assert study.error_at(179.0) == pytest.approx(FIG5B_REGRESSION[round(study.geometry_presag, 3)], abs=2e-3)
    # The paper's finding: the single curve is much better on the near-optimal (70 mm) geometry.
    assert large.error_at(179.0) < 0.5 * nominal.error_at(179.0)


@pytest.mark.slow
def test_single_curve_error_against_direct_newton_curves(ideal98, ideal98_70mm):
    """Fig. 5b recomputed without the study's two approximations: Δe from full Newton re-solves
    at 100 N and directly at 179 N (no active-set method, no interpolation between 150 and 200 N).

    Measured: Newton gives 23.0 % (30 mm) and 13.6 % (70 mm) against the study's 20.5 % and 8.5 %;
    the paper reads 16 % and 2 %. The gap is the active-set method's Δe error near 179 N (it grows to
    5.9 % at 200 N, tests/elasticity/test_methods.py) times the 1/(1 − error) leverage of a ratio, so
    the tolerance is 0.06 (absolute), just above the larger measured gap; the paper's finding (the
    70 mm geometry is the better one for a single curve) holds in both.
    """
    from presag_opt.elasticity import nonlinear_elasticity
    from presag_opt.static.form_finding import form_find

    direct = {}
    for section in (ideal98, ideal98_70mm):
        state = form_find(section.catenary)
        at_100, at_179 = (nonlinear_elasticity(state, f, step=0.5) for f in (100.0, 179.0))
        error = at_100.delta_e / at_179.delta_e - 1.0
        study = single_curve_error(section)
        assert error == pytest.approx(study.error_at(179.0), abs=0.06)
        direct[round(study.geometry_presag, 3)] = error
    assert direct[0.070] < direct[0.030]
