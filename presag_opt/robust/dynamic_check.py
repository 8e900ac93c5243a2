"""Dynamic check of pre-sag designs: simulated runs over a grid of static forces and speeds.

Holds :func:`dynamic_check` and its results (EN 50367 statistics per run, summarised per design and
speed regime), and :func:`design_catenary`, the catenary built to a per-dropper design of the linear
program, so that any design — a parabola or a per-dropper profile — is form-found to its own
geometry and simulated the same way. The runs of a design are one
:func:`~presag_opt.dynamics.batch.simulate_many` batch on one form-found state. The designs come
from :mod:`presag_opt.robust.study`; the dynamic design itself is
:mod:`presag_opt.robust.dynamic_design`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import KMH
from presag_opt.design.speed_range import QUASI_STATIC_BETA_LIMIT
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.robust.operating_grid import band_static_settings
from presag_opt.robust.path import PathModel
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary


def window_settings(catenary: Catenary) -> SimulationSettings:
    """Numerics of a check of a section: automatic, two lead-in and two analysed spans where the section
    has them, fewer on a short one (lead-in spans on both sides of the analysed ones).

    Parameters
    ----------
    catenary : Catenary
        The section to be simulated.
    """
    spans = catenary.layout.n_spans
    lead_in = min(2, (spans - 1) // 2)
    return SimulationSettings(numerics="auto", lead_in_spans=lead_in, analysed_spans=min(2, spans - 2 * lead_in))


@dataclass(frozen=True, kw_only=True)
class DynamicRun:
    """One simulated run of a design: operating point and EN 50367 statistics.

    Attributes
    ----------
    design : str
        Design label.
    presag : float
        Mid-span pre-sag on the reference span (for a profile: its mean mid-span depth over span
        length times the reference span). [m]
    static_force : float
        Static uplift force. [N]
    speed : float
        Train speed. [m/s]
    beta : float
        Speed over contact-wire wave speed. [-]
    mean_force : float
        Mean contact force F_m over the analysed section. [N]
    std_force : float
        σ of the filtered contact force. [N]
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
    std_force: float
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


def design_catenary(catenary: Catenary, path: PathModel, depths: np.ndarray) -> Catenary:
    """The catenary built to a design of the path model's droppers (e.g. a per-dropper profile).

    The designed spans get the design's depths. Every other span gets the relative profile (depth
    over span length against x/l) of the designed span nearest to it in length, interpolated at its
    own droppers; in an ideal section, whose central span is designed, every span gets the same
    profile. On a stitched catenary the stitch droppers are design droppers but the profile is per
    ordinary dropper: a designed span gets the design's relative profile at its ordinary droppers
    (the stitch droppers' targets then follow the profile between them, as in any stitched span).

    Parameters
    ----------
    catenary : Catenary
        System model the design was made for.
    path : PathModel
        Path model of the design (its droppers, spans and relative positions).
    depths : ndarray
        Depth below the support level of every design dropper, as in
        :attr:`~presag_opt.robust.lp.RobustDesign.depths`. [m]
    """
    lengths = catenary.layout.span_lengths
    if max(int(s) for s in path.spans) >= len(lengths):
        raise ModelError(
            f"the design is of spans up to {max(int(s) for s in path.spans) + 1} but {catenary.name!r} has "
            f"{len(lengths)}: build it into the catenary it was designed for"
        )
    designed = {int(s): np.flatnonzero(path.dropper_span == s) for s in path.spans}
    profile = []
    for s, length in enumerate(lengths):
        drops = catenary.droppers.positions_in_span(length)
        if s in designed and len(designed[s]) == len(drops):
            profile.append(tuple(depths[designed[s]]))
            continue
        # another span, or a stitched span (its stitch droppers are design droppers but not in the
        # profile, which is per ordinary dropper): the relative profile at the span's own droppers
        source = s if s in designed else min(designed, key=lambda d: (abs(lengths[d] - length), d))
        idx = designed[source]
        t = np.concatenate([[0.0], path.dropper_fraction[idx], [1.0]])
        relative = np.concatenate([[0.0], depths[idx] / lengths[source], [0.0]])
        profile.append(tuple(np.interp(drops / length, t, relative) * length))
    return catenary.with_presag_profile(profile)


def dynamic_check(
    catenary: Catenary,
    designs: Mapping[str, float | Catenary],
    *,
    pantograph,
    static_forces,
    speeds,
    aero_coefficient: float,
    reference_span: float,
    settings: SimulationSettings | None = None,
    progress=None,
) -> DynamicCheck:
    """Simulate each design over a grid of static forces and speeds.

    Each design is form-found once, with the element length the fastest speed needs
    (:func:`~presag_opt.robust.operating_grid.band_static_settings`), and all its runs are one batch.

    Parameters
    ----------
    catenary : Catenary
        System model.
    designs : mapping
        Label -> relative pre-sag S_rel of a parabola [-], or a catenary built to any profile (see
        :func:`design_catenary`).
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
        Numerical settings of the simulator; default automatic numerics.
    progress : callable, optional
        Called with a short message before each design's runs.

    Raises
    ------
    ConvergenceError
        A run failed (the message names the design and the point).
    """
    settings = settings or SimulationSettings(numerics="auto")
    static = band_static_settings(catenary, speeds, settings)
    points = [OperatingPoint(speed=v, static_force=f, aero_coefficient=aero_coefficient)
              for f in static_forces for v in speeds]
    runs = []
    for label, design in designs.items():
        built = design if isinstance(design, Catenary) else catenary.with_presag(design)
        if progress:
            progress(f"{label}: {len(points)} runs")
        batch = simulate_many(form_find(built, static), pantograph, points, settings=settings)
        for run in batch.runs:
            if not run.ok:
                raise ConvergenceError(f"dynamic check of {label}: the run at {run.point.speed / KMH:g} km/h, F_stat "
                                       f"{run.point.static_force:g} N failed: {run.error}")
            stats = run.statistics[0]
            runs.append(DynamicRun(
                design=label,
                presag=built.presag_rel * reference_span,
                static_force=run.point.static_force,
                speed=run.point.speed,
                beta=run.speed_ratio,
                mean_force=stats.mean_force,
                std_force=stats.std_force,
                sigma_over_mean=stats.sigma_over_mean,
                uplift_max=run.uplift_max,
                loss_of_contact=stats.loss_of_contact,
            ))
    return DynamicCheck(runs=tuple(runs))
