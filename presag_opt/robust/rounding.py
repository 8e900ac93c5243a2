"""Putting a continuous per-dropper profile on the construction step.

Holds the rounding that follows the linear program of :mod:`presag_opt.robust.lp`: with at most 12
free depths every combination of rounding down or up is evaluated exactly, with more a greedy
descent from the nearest rounding; both keep the limits of :mod:`presag_opt.robust.buildability`.
"""

from __future__ import annotations

import itertools

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.robust.buildability import Buildability, _violation


def _round_to_step(path, values, design_map, scenarios, risk, build: Buildability) -> tuple[np.ndarray, str]:
    """Put the design on the construction step: best (limit violation, objective) by enumeration
    (at most 12 free depths) or by a greedy descent from the nearest rounding."""
    if build.step == 0.0:
        return design_map @ values, "none"

    uplift = path.uplift(scenarios.forces)

    def score(v):
        d = design_map @ v
        return (_violation(path, d, build),
                risk.value(path.waviness(d, scenarios.forces, uplift).max(axis=1), scenarios.weights))

    if len(values) <= 12:
        low = np.floor(values / build.step + 1e-9) * build.step
        candidates = (low + np.asarray(ups) for ups in itertools.product((0.0, build.step), repeat=len(values)))
        best = min(candidates, key=score)
        how = "exhaustive"
    else:
        best = np.round(values / build.step) * build.step
        best_score = score(best)
        improved = True
        while improved:
            improved = False
            for i in range(len(best)):
                for delta in (-build.step, build.step):
                    trial = best.copy()
                    trial[i] += delta
                    trial_score = score(trial)
                    if trial_score < best_score and (trial_score[0] < best_score[0] or trial_score[1] < best_score[1] - 1e-12):
                        best, best_score, improved = trial, trial_score, True
        how = "greedy"
    if score(best)[0] > 0.0:
        raise ModelError(
            f"robust pre-sag: no rounding of the profile to the {build.step * 1e3:g} mm construction step meets the "
            "buildability limits (relax max_kink or the step)"
        )
    return design_map @ best, how
