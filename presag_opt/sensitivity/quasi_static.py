"""Quasi-static outputs of a sensitivity analysis: the recommendation and the robust pre-sag.

Each evaluator is a picklable callable that takes one row of input values (SI, in the order of its
``names``) and returns the output values in edge units (‰, -); the methods run it in worker
processes (:func:`presag_opt.sensitivity.evaluation.evaluate_rows`).
"""

from __future__ import annotations

import dataclasses
import pickle
import warnings
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand, force_levels_for_band
from presag_opt.design.recommendation import layout_recommendation
from presag_opt.design.section import section_elasticity
from presag_opt.sensitivity.inputs import SPAN_LIST, apply_inputs
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary

RECOMMENDATION_VALUES = (
    ("presag_rel_ideal", "‰"), ("presag_rel_mixed", "‰"), ("presag_rel", "‰"), ("mixed_to_ideal", "-"),
)
"""Values of the recommendation output: the mean of each layout's S_rel range ends, the recommended
S_rel (mean of all range ends) and the ratio of the mixed to the ideal mean."""

ROBUST_VALUES = (("presag_rel", "‰"), ("tolerance_low", "‰"), ("tolerance_high", "‰"), ("tolerance_width", "‰"))
"""Values of the robust output: the minimax parabola's S_rel and its installation tolerance interval."""


def _band_with(band: OperatingBand, names: tuple[str, ...], row: np.ndarray) -> OperatingBand:
    for name, value in zip(names, row):
        if name == "operation.aero_coefficient":
            band = dataclasses.replace(band, aero_coefficient=float(value))
    return band


def _catenary_with(catenary: Catenary, names: tuple[str, ...], row: np.ndarray, *, span_list: bool) -> Catenary:
    values = {n: float(v) for n, v in zip(names, row)
              if n.startswith("catenary.") and (span_list or n != SPAN_LIST)}
    return apply_inputs({"catenary": catenary}, values)["catenary"]


class Reuse:
    """What one process keeps between consecutive samples: the last few form-found states (keyed by
    the catenary) and layout recommendations (keyed by catenary and band).

    Consecutive points of a Morris trajectory change one input each: a step in α_ae leaves both
    catenaries as they were (their form-finding is reused, only the elasticity at the band's new force
    levels is computed), a step in the span list leaves the ideal layout as it was (reused whole). A
    reused result is the very object computed before, so the outputs do not change at all.

    Parameters
    ----------
    size : int
        Entries kept of each kind (least recently used dropped first). [-]

    Attributes
    ----------
    hits, misses : int
        Form-findings reused and computed. [-]
    """

    def __init__(self, size: int = 4):
        self.size = size
        self.states: OrderedDict[bytes, object] = OrderedDict()
        self.layouts: OrderedDict[bytes, object] = OrderedDict()
        self.hits = 0
        self.misses = 0

    def _get(self, table: OrderedDict, key: bytes, make):
        if key in table:
            table.move_to_end(key)
            return table[key], True
        value = make()
        table[key] = value
        while len(table) > self.size:
            table.popitem(last=False)
        return value, False

    def layout(self, catenary: Catenary, band: OperatingBand, levels: tuple[float, ...], step: float):
        """The layout recommendation of ``catenary`` over ``band`` (computed, or the one kept).

        Parameters
        ----------
        catenary : Catenary
            The layout (form-found here at the default static settings unless kept).
        band : OperatingBand
            The operating band. [N], [m/s]
        levels : tuple of float
            Force levels of the elasticity curves. [N]
        step : float
            Point spacing of the elasticity curves. [m]
        """
        key = pickle.dumps(catenary)

        def state():
            return form_find(catenary)

        def make():
            found, reused = self._get(self.states, key, state)
            self.hits += reused
            self.misses += not reused
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the uplift and speed notes are not outputs here
                section = section_elasticity(found, force_levels=levels, step=step, elasticity_method="active-set")
                return layout_recommendation(section, band)

        return self._get(self.layouts, pickle.dumps((key, band, levels, step)), make)[0]

    def clear(self) -> None:
        """Forget everything kept (and the counts)."""
        self.states.clear()
        self.layouts.clear()
        self.hits = self.misses = 0

    def __getstate__(self) -> dict:
        """Pickled empty: an evaluator sent to a worker process starts its own memo there."""
        return {"size": self.size}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["size"])


@dataclass(frozen=True, kw_only=True)
class RecommendationEvaluator:
    """The case-study recommendation (ideal and mixed layouts over the band) at one row of inputs.

    Attributes
    ----------
    ideal, mixed : Catenary
        The two layouts (the span-list input applies to the mixed one only).
    band : OperatingBand
        The operating band (``operation.aero_coefficient`` replaces its α_ae).
    names : tuple of str
        Input names, in the order of a row.
    step : float
        Point spacing of the elasticity curves. [m]
    reuse : Reuse
        What this evaluator keeps between consecutive rows (its own; a copy sent to a worker process
        starts empty there).
    """

    ideal: Catenary
    mixed: Catenary
    names: tuple[str, ...]
    band: OperatingBand = CASE_STUDY_BAND
    step: float = 0.5
    reuse: Reuse = dataclasses.field(default_factory=Reuse, compare=False, repr=False)

    def __call__(self, row: np.ndarray) -> np.ndarray:
        """S_rel ideal, mixed, recommended [‰] and mixed/ideal [-] (see :data:`RECOMMENDATION_VALUES`)."""
        band = _band_with(self.band, self.names, row)
        low, high = band.mean_force_band()
        levels = force_levels_for_band(low, high)
        means = []
        ends = []
        for catenary, span_list in ((self.ideal, False), (self.mixed, True)):
            cat = _catenary_with(catenary, self.names, row, span_list=span_list)
            lay = self.reuse.layout(cat, band, tuple(levels), self.step)
            ends += list(lay.presag_rel_range)
            means.append(float(np.mean(lay.presag_rel_range)))
        return np.array([means[0] * 1e3, means[1] * 1e3, float(np.mean(ends)) * 1e3, means[1] / means[0]])


@dataclass(frozen=True, kw_only=True)
class RobustEvaluator:
    """The quasi-static robust (minimax) pre-sag and its tolerance interval at one row of inputs.

    Attributes
    ----------
    catenary : Catenary
        The section designed.
    names : tuple of str
        Input names, in the order of a row.
    band : OperatingBand
        The operating band whose F_m range is designed for.
    within : float
        Tolerance-band loss (share of the optimum). [-]
    """

    catenary: Catenary
    names: tuple[str, ...]
    band: OperatingBand = CASE_STUDY_BAND
    within: float = 0.10

    def __call__(self, row: np.ndarray) -> np.ndarray:
        """S_rel, tolerance low, high and width [‰] (see :data:`ROBUST_VALUES`)."""
        from presag_opt.robust.study import (
            robust_study,  # imports cvxpy: only where it is used
        )

        band = _band_with(self.band, self.names, row)
        cat = _catenary_with(self.catenary, self.names, row, span_list=True)
        study = robust_study(cat, band.mean_force_band(), within=self.within)
        low, high = study.tolerance.low, study.tolerance.high
        return np.array([study.robust.presag_rel, low, high, high - low]) * 1e3
