"""The dynamic robust pre-sag as a sensitivity output: ``presag sensitivity --quantity dynamic-robust``.

Each sample runs the dynamic robust study of the case-study band — the job behind
``presag robust --dynamic`` (:func:`presag_opt.robust.dynamic_study.dynamic_robust_study`: the
quasi-static starts, the surrogate-guided search over S by batched simulation, the installation
tolerance by simulation) — on its own catenary, pantograph and α_ae, at the screening numerics of
:class:`ScreeningNumerics`. A sample is one task of :func:`presag_opt.sensitivity.evaluation.evaluate_rows`
(local worker processes or a Dask cluster, one file per finished sample in the resumable store): the
search is adaptive, so its simulations cannot be split into the study units of a fixed grid.

Band: F_stat 70–140 N × 50–90 km/h on a 4 × 3 grid, worst case of σ/F_m, steady-arm uplift ≤ 83.5 mm,
tolerance at 10 % loss — the defaults of ``presag robust --dynamic``; α_ae is the case's (an input).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import CASE_STUDY_BAND, KMH, OperatingBand
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.sensitivity.inputs import apply_inputs
from presag_opt.system.catenary import Catenary
from presag_opt.system.quantity import quantity, validate_fields

DYNAMIC_ROBUST_VALUES = (
    ("presag_rel", "‰"), ("tolerance_low", "‰"), ("tolerance_high", "‰"), ("tolerance_width", "‰"),
    ("worst_sigma_over_F_m", "-"),
)
"""Values of the dynamic robust output: the chosen S_rel, its installation tolerance interval
(worst case within 10 % of its minimum) and the worst σ/F_m over the band at the chosen S."""

DYNAMIC_ROBUST_BAND = dataclasses.replace(CASE_STUDY_BAND, speed_low=50.0 * KMH)
"""The band of ``presag robust --dynamic`` by default: F_stat 70–140 N, simulated at 50–90 km/h
(the paper's lowest grid speed up to the line speed). [N], [m/s]"""


@dataclass(frozen=True, kw_only=True)
class ScreeningNumerics:
    """Numerics of the dynamic robust design of each sample (screening resolution, no physics).

    Attributes
    ----------
    span_count : int
        Central spans of the section kept (one lead-in, one analysed span, the run-out). [-]
    element_length : float
        Longest element of the form-finding and the runs. [m]
    time_step : float
        Integration time step. [s] (shown in ms)
    presag_tolerance : float
        Resolution of the search and of the tolerance ends, on the reference span. [m] (shown in mm)
    static_points, speed_points : int
        Grid points of the band along each axis (those of ``presag robust --dynamic``). [-]
    """

    span_count: int = quantity("count", 4, 200, default=5)
    element_length: float = quantity("length", 0.05, 5.0, default=1.0)
    time_step: float = quantity("time", 0.1, 20.0, display="ms", default=2e-3)
    presag_tolerance: float = quantity("length", 0.01, 20.0, display="mm", default=1e-3)
    static_points: int = quantity("count", 2, 20, default=4)
    speed_points: int = quantity("count", 1, 20, default=3)

    def __post_init__(self) -> None:
        validate_fields(self)

    def text(self) -> str:
        """Short description, e.g. ``5 spans, 1 m elements, 2 ms, S to 1 mm, 4 x 3 points``."""
        return (f"{self.span_count} spans, {self.element_length:g} m elements, {self.time_step * 1e3:g} ms, "
                f"S to {self.presag_tolerance * 1e3:g} mm, {self.static_points} x {self.speed_points} points")


FULL_NUMERICS = None
"""Marker for :class:`DynamicRobustEvaluator`: the numerics of ``presag robust --dynamic`` itself
(the whole section, element length and time step from the speed, S to 0.5 mm)."""


@dataclass(frozen=True, kw_only=True)
class DynamicRobustEvaluator:
    """The dynamic robust pre-sag of the band and its tolerance at one row of inputs.

    Attributes
    ----------
    catenary : Catenary
        The case's catenary (its pre-sag is what the search replaces).
    pantograph : Pantograph
        The case's pantograph.
    operation : object
        The case's operation (``operation.aero_coefficient`` sets the band's α_ae).
    names : tuple of str
        Input names, in the order of a row.
    numerics : ScreeningNumerics or None
        Screening numerics; None runs the numerics of ``presag robust --dynamic`` (:data:`FULL_NUMERICS`).
    band : OperatingBand
        Static forces and speeds (its α_ae is replaced by the sample's). [N], [m/s]
    within : float
        Loss of the tolerance interval. [-]
    """

    catenary: Catenary
    pantograph: Pantograph
    operation: object
    names: tuple[str, ...]
    numerics: ScreeningNumerics | None = ScreeningNumerics()
    band: OperatingBand = DYNAMIC_ROBUST_BAND
    within: float = 0.10

    def study(self, row: np.ndarray):
        """The :class:`~presag_opt.robust.dynamic_study.DynamicRobustStudy` of one row.

        Parameters
        ----------
        row : ndarray, shape (k,)
            The sample's input values, in the order of :attr:`names`. [SI units of the inputs]
        """
        from presag_opt.robust.dynamic_design import SearchSettings
        from presag_opt.robust.dynamic_study import dynamic_robust_study
        from presag_opt.studies.reduced import central_spans

        roots = {"catenary": self.catenary, "pantograph": self.pantograph, "operation": self.operation}
        model = apply_inputs(roots, dict(zip(self.names, (float(v) for v in row))))
        band = dataclasses.replace(self.band, aero_coefficient=model["operation"].aero_coefficient)
        n = self.numerics
        if n is None:
            catenary, settings, search, points = model["catenary"], None, None, (4, 3)
        else:
            catenary = central_spans(model["catenary"], n.span_count)
            settings = dataclasses.replace(
                SimulationSettings().with_fixed_numerics(element_length=n.element_length, time_step=n.time_step),
                analysed_spans=1, lead_in_spans=1)
            search = SearchSettings(presag_tolerance=n.presag_tolerance)
            points = (n.static_points, n.speed_points)
        return dynamic_robust_study(catenary, model["pantograph"], band, within=self.within,
                                    static_points=points[0], speed_points=points[1], settings=settings,
                                    search=search, workers=1)

    def __call__(self, row: np.ndarray) -> np.ndarray:
        """S_rel, tolerance low, high, width [‰] and worst σ/F_m [-] (see :data:`DYNAMIC_ROBUST_VALUES`)."""
        study = self.study(row)
        low, high = study.tolerance.low, study.tolerance.high
        return np.array([study.design.presag_rel * 1e3, low * 1e3, high * 1e3, (high - low) * 1e3,
                         study.design.worst_case_objective])
