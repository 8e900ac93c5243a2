"""Settings of a dynamic run (numerics and analysis window) and its operating point.

:class:`SimulationSettings` holds the numerics (time integration, element length, damping band,
friction regularisation; fixed, or following the speed with ``numerics = "auto"``, see
:mod:`presag_opt.dynamics.numerics`) and the analysis window (analysed and lead-in spans, run-out,
cut-off frequency) of :func:`~presag_opt.dynamics.simulate.simulate` and of the batch engine;
:class:`OperatingPoint` an operating point (speed, static force, α_ae), shared by the batch engine
and the studies, and :class:`Operation` one run's point with its pantograph spacings.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from presag_opt.contact_force import mean_force
from presag_opt.dynamics.integrator import IntegratorSettings
from presag_opt.dynamics.numerics import numerics_for_speed
from presag_opt.dynamics.pantograph import FrictionRegularisation
from presag_opt.dynamics.structure import StructureSettings
from presag_opt.errors import ModelError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.quantity import quantity, validate_fields

DROPPER_RECORDS = ("analysed", "all")
NUMERICS = ("fixed", "auto")


@dataclass(frozen=True, kw_only=True)
class SimulationSettings:
    """Numerical settings and the analysis window of a dynamic simulation (no physics).

    Attributes
    ----------
    integrator : IntegratorSettings
        Time step, scheme and solution method; default HHT-α, α = −0.005, 2 ms (see
        :mod:`presag_opt.dynamics.simulate`).
    static : StaticSettings
        Settings of the static model (element length) used when a catenary has to be form-found.
    structure : StructureSettings
        Damping band of the structural model.
    friction : FrictionRegularisation
        Regularisation of the pantographs' dry friction.
    analysed_spans : int
        Number of central spans analysed. [-]
    lead_in_spans : int
        Spans the leading pantograph runs before the analysed section. [-]
    run_out : float
        Time the rear pantograph runs past the analysed section: data for the zero-phase filter,
        whose 20 Hz Butterworth impulse response falls below 1e-4 of its peak within 0.2 s. [s]
    cutoff_frequency : float
        Low-pass cut-off of the contact force. [Hz]
    droppers : {"analysed", "all"}
        Droppers whose forces are recorded: those of the analysed section, or all.
    numerics : {"fixed", "auto"}
        ``"fixed"``: ``static.element_length`` and ``integrator.time_step`` as given; ``"auto"``: both
        from the speed (:func:`~presag_opt.dynamics.numerics.numerics_for_speed`).
    """

    integrator: IntegratorSettings = field(
        default_factory=lambda: IntegratorSettings(scheme="hht", hht_alpha=-0.005)
    )
    static: StaticSettings = field(default_factory=StaticSettings)
    structure: StructureSettings = field(default_factory=StructureSettings)
    friction: FrictionRegularisation = field(default_factory=FrictionRegularisation)
    analysed_spans: int = quantity("count", 1, 200, default=2)
    lead_in_spans: int = quantity("count", 0, 200, default=2)
    run_out: float = quantity("time", 0.0, 10.0, default=0.25)
    cutoff_frequency: float = quantity("frequency", 1.0, 200.0, display="Hz", default=20.0)
    droppers: Literal["analysed", "all"] = "analysed"
    numerics: Literal["fixed", "auto"] = "fixed"

    def __post_init__(self) -> None:
        validate_fields(self)
        for name in ("analysed_spans", "lead_in_spans"):
            value = getattr(self, name)
            if value != int(value):
                raise ModelError(f"{name} = {value!r} is not a whole number")
            object.__setattr__(self, name, int(value))
        if self.droppers not in DROPPER_RECORDS:
            raise ModelError(f"droppers = {self.droppers!r} is not one of {', '.join(map(repr, DROPPER_RECORDS))}")
        if self.numerics not in NUMERICS:
            raise ModelError(f"numerics = {self.numerics!r} is not one of {', '.join(map(repr, NUMERICS))}")

    def with_fixed_numerics(
        self, *, element_length: float | None = None, time_step: float | None = None
    ) -> SimulationSettings:
        """These settings with ``numerics = "fixed"`` at the given element length [m] and time step [s]
        (each None: the paper's 0.5 m and 2 ms).

        Parameters
        ----------
        element_length : float, optional
            Element length (None: 0.5 m). [m]
        time_step : float, optional
            Time step (None: 2 ms). [s]
        """
        return dataclasses.replace(
            self,
            numerics="fixed",
            static=dataclasses.replace(self.static, element_length=element_length or 0.5),
            integrator=dataclasses.replace(self.integrator, time_step=time_step or 2e-3),
        )

    def for_speed(self, speed: float, wave_speed: float) -> SimulationSettings:
        """The settings of a run at ``speed`` [m/s] on a wire of ``wave_speed`` [m/s]: with
        ``numerics = "auto"`` the element length and time step from the speed, otherwise ``self``.

        Parameters
        ----------
        speed : float
            Train speed. [m/s]
        wave_speed : float
            Wave speed of the contact wire. [m/s]
        """
        if self.numerics != "auto":
            return self
        chosen = numerics_for_speed(speed, wave_speed, self.cutoff_frequency)
        return dataclasses.replace(
            self,
            static=dataclasses.replace(self.static, element_length=chosen.element_length),
            integrator=dataclasses.replace(self.integrator, time_step=chosen.time_step),
        )


@dataclass(frozen=True, kw_only=True)
class OperatingPoint:
    """One operating point: train speed, static force and aerodynamic uplift.

    Attributes
    ----------
    speed : float
        Train speed. [m/s]
    static_force : float
        Static uplift force of each pantograph. [N]
    aero_coefficient : float
        Aerodynamic uplift coefficient α_ae of F_m = F_stat + α_ae v². [N/(m/s)²]
    """

    speed: float = quantity("speed", 0.0, 600.0, display="km/h", low_open=True)
    static_force: float = quantity("force", 0.0, 500.0, low_open=True)
    aero_coefficient: float = quantity("aero_coefficient", 0.0, 0.01, display="N/(km/h)^2", default=0.0)

    def __post_init__(self) -> None:
        validate_fields(self)

    @property
    def uplift_force(self) -> float:
        """Mean uplift force F_stat + α_ae v² of each pantograph (:func:`~presag_opt.contact_force.mean_force`). [N]"""
        return mean_force(self.static_force, self.speed, self.aero_coefficient)

    @property
    def aero_force(self) -> float:
        """Aerodynamic part α_ae v² of the mean uplift force. [N]"""
        return mean_force(0.0, self.speed, self.aero_coefficient)


@dataclass(frozen=True, kw_only=True)
class Operation(OperatingPoint):
    """Operating point of a run with its train: the point and the pantograph spacings.

    Attributes
    ----------
    spacings : tuple of float or None
        Distances between consecutive pantographs, front to rear; None for a single pantograph. [m]
    """

    spacings: tuple[float, ...] | None = quantity("length", 1.0, 2000.0, default=None, allow_none=True)

    def __post_init__(self) -> None:
        if self.spacings is not None:
            spacings = tuple(float(s) for s in self.spacings)
            object.__setattr__(self, "spacings", spacings or None)
        super().__post_init__()

    @property
    def offsets(self) -> np.ndarray:
        """Distance of each pantograph behind the leading one. [m]"""
        return np.concatenate([[0.0], np.cumsum(self.spacings or ())])
