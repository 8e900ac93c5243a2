"""Dynamic check of pre-sag designs: simulated runs over a grid of static forces and speeds.

Holds :func:`dynamic_check` and its results (EN 50367 statistics per run, summarised per design and
speed regime). The simulation itself is :mod:`presag_opt.dynamics`; the designs come from
:mod:`presag_opt.robust.study`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.design.validity import QUASI_STATIC_BETA_LIMIT
from presag_opt.static.equilibrium import form_find


@dataclass(frozen=True, kw_only=True)
class DynamicRun:
    """One simulated run of a design: operating point and EN 50367 statistics.

    Attributes
    ----------
    design : str
        Design label.
    presag : float
        Mid-span pre-sag on the reference span. [m]
    static_force : float
        Static uplift force. [N]
    speed : float
        Train speed. [m/s]
    beta : float
        Speed over contact-wire wave speed. [-]
    mean_force : float
        Mean contact force F_m over the analysed section. [N]
    sigma_over_mean : float
        σ/F_m. [-]
    uplift_max : float
        Largest steady-arm uplift in the analysed section. [m]
    loss_of_contact : float
        Share of time without contact. [-]
    """

    design: str
    presag: float
    static_force: float
    speed: float
    beta: float
    mean_force: float
    sigma_over_mean: float
    uplift_max: float
    loss_of_contact: float


@dataclass(frozen=True, kw_only=True)
class DynamicCheck:
    """Dynamic runs of several designs over a grid of static forces and speeds.

    Attributes
    ----------
    runs : tuple of DynamicRun
        Every run.
    beta_limit : float
        Speed ratio separating the quasi-static regime (the paper's 0.4). [-]
    """

    runs: tuple[DynamicRun, ...]
    beta_limit: float = QUASI_STATIC_BETA_LIMIT

    def summary(self) -> list[dict]:
        """Per design and regime: worst and mean σ/F_m, largest uplift, runs counted."""
        rows = []
        for design in dict.fromkeys(r.design for r in self.runs):
            for regime, inside in (("beta < %.2g" % self.beta_limit, True), ("beta >= %.2g" % self.beta_limit, False)):
                runs = [r for r in self.runs if r.design == design and (r.beta < self.beta_limit) == inside]
                if not runs:
                    continue
                ratio = np.array([r.sigma_over_mean for r in runs])
                rows.append({
                    "design": design,
                    "presag_mm": runs[0].presag * 1e3,
                    "regime": regime,
                    "runs": len(runs),
                    "worst_sigma_over_Fm": float(ratio.max()),
                    "mean_sigma_over_Fm": float(ratio.mean()),
                    "uplift_max_mm": float(max(r.uplift_max for r in runs) * 1e3),
                    "loss_of_contact_max_pct": float(max(r.loss_of_contact for r in runs) * 100),
                })
        return rows


def dynamic_check(
    catenary,
    designs: dict[str, float],
    *,
    pantograph,
    static_forces,
    speeds,
    aero_coefficient: float,
    reference_span: float,
    settings=None,
    progress=None,
) -> DynamicCheck:
    """Simulate each parabolic design over a grid of static forces and speeds.

    Parameters
    ----------
    catenary : Catenary
        System model; each design is form-found with its own pre-sag.
    designs : dict
        Label -> relative pre-sag S_rel. [-]
    pantograph : Pantograph
        Pantograph model.
    static_forces : sequence of float
        Static uplift forces. [N]
    speeds : sequence of float
        Train speeds. [m/s]
    aero_coefficient : float
        α_ae. [N/(m/s)²]
    reference_span : float
        Span the pre-sag is quoted on. [m]
    settings : SimulationSettings, optional
        Numerical settings of the simulator; each design is form-found with its ``static`` settings.
    progress : callable, optional
        Called with a short message before each run.
    """
    # The simulator (scipy.signal) is imported only when a check runs, like in the command line.
    from presag_opt.dynamics.simulate import simulate

    runs = []
    for label, presag_rel in designs.items():
        state = form_find(catenary.with_presag(presag_rel), settings.static if settings is not None else None)
        for force in static_forces:
            for speed in speeds:
                if progress:
                    progress(f"{label}: F_stat {force:g} N, {speed * 3.6:g} km/h")
                result = simulate(state, pantograph, speed=speed, static_force=force,
                                  aero_coefficient=aero_coefficient, settings=settings)
                stats = result.statistics
                runs.append(DynamicRun(
                    design=label,
                    presag=presag_rel * reference_span,
                    static_force=float(force),
                    speed=float(speed),
                    beta=float(result.to_dict()["beta"]),
                    mean_force=stats.mean_force,
                    sigma_over_mean=stats.sigma_over_mean,
                    uplift_max=result.uplift_max,
                    loss_of_contact=stats.loss_of_contact,
                ))
    return DynamicCheck(runs=tuple(runs))
