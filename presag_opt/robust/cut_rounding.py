"""The cutting step as an installation error: rounded cut lengths by quasi-static Monte Carlo.

A crew cuts every dropper to a multiple of its step, so each dropper is built with an error in
±step/2; over a schedule the errors are spread evenly and independent of each other, so each is drawn
uniform in ±step/2 (:class:`~presag_opt.robust.installation.InstallationErrors`, dropper errors only)
and :class:`~presag_opt.robust.monte_carlo.QuasiStaticMonteCarlo` gives the P95 of the worst-case
path waviness of the rounded schedule beside the exact one, and
:func:`~presag_opt.robust.monte_carlo.installation_tolerance` the P95 of the mid-span pre-sag error
rounding alone causes (the floor of the crew tolerance a decision may use with that step).
"""

from __future__ import annotations

import numpy as np

from presag_opt.design.line_results import RoundingEffect
from presag_opt.robust.installation import InstallationErrors
from presag_opt.robust.monte_carlo import QuasiStaticMonteCarlo, installation_tolerance
from presag_opt.robust.path import PathModel
from presag_opt.robust.scenarios import ForceScenarios

ROUNDING_SAMPLES = 4000
"""Realisations of the rounding Monte Carlo per section (its P95 carries a 95 % interval). [-]"""


def rounding_effect(path: PathModel, depths: np.ndarray, scenarios: ForceScenarios, step: float, *,
                    samples: int = ROUNDING_SAMPLES, seed: int = 0) -> RoundingEffect:
    """The P95 waviness and pre-sag error of a design whose cut lengths are rounded to ``step``.

    Parameters
    ----------
    path : PathModel
        The section's path model.
    depths : ndarray
        The design's dropper depths (:attr:`PathModel.reference_depth` shape). [m]
    scenarios : ForceScenarios
        The F_m band. [N]
    step : float
        The cutting step (> 0). [m]
    samples : int
        Realisations. [-]
    seed : int
        Seed of the draws. [-]
    """
    mc = QuasiStaticMonteCarlo(path, depths, scenarios)
    errors = InstallationErrors(dropper_length=0.5 * step, contact_wire_height=0.0, messenger_height=0.0,
                                distribution="uniform")
    result = mc.run(errors, samples=samples, seed=seed)
    p95 = result.percentiles[95]
    presag = installation_tolerance(mc, errors, samples=samples, seed=seed)
    return RoundingEffect(step=step, waviness_exact=mc.nominal_worst_case, waviness_p95=p95.value,
                          waviness_p95_ci=(p95.low, p95.high), presag_error_p95=presag.half_width,
                          samples=samples, seed=seed)
