"""The EN 50318:2002 reference ranges of the reference case, and a verdict per statistic.

Holds the published ranges of the contact-force statistics and the steady-arm uplift at 250 and
300 km/h, and :func:`en50318_verdicts`, which sets a run's statistics against them. The runs
themselves come from :mod:`presag_opt.dynamics` (the built-in case ``en50318_2002``); the command
line, the benchmarks and the tests all judge them here.

References
----------
EN 50318:2002, Railway applications - Current collection systems - Validation of simulation of the
dynamic interaction between pantograph and overhead contact line, reference model and results, as
reproduced in secondary public sources.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from presag_opt.errors import ModelError

EN50318_RANGES = {
    250: {"Fm_N": (110, 120), "sigma_N": (26, 31), "stat_max_N": (190, 210), "stat_min_N": (20, 40),
          "max_N": (175, 210), "min_N": (50, 75), "uplift_max_mm": (48, 55), "loss_of_contact_pct": (0, 0)},
    300: {"Fm_N": (110, 120), "sigma_N": (32, 40), "stat_max_N": (210, 230), "stat_min_N": (-5, 20),
          "max_N": (190, 225), "min_N": (30, 55), "uplift_max_mm": (55, 65), "loss_of_contact_pct": (0, 0)},
}
"""Published ranges by speed [km/h], keyed like the run's ``to_dict()``: F_m, σ, F_m ± 3σ, the actual
extremes [N], the largest steady-arm uplift [mm] and the share of time without contact [%]."""


@dataclass(frozen=True, kw_only=True)
class Verdict:
    """One statistic of a run against its published range.

    Attributes
    ----------
    statistic : str
        Key of the statistic, e.g. ``"sigma_N"`` (unit in the name).
    value : float
        The run's value. [unit of the key]
    low, high : float
        The published range. [unit of the key]
    """

    statistic: str
    value: float
    low: float
    high: float

    @property
    def inside(self) -> bool:
        """Whether the value lies in the closed range [low, high]."""
        return self.low <= self.value <= self.high


def en50318_ranges(speed_kmh: float) -> dict[str, tuple[float, float]]:
    """The published ranges at one speed.

    Parameters
    ----------
    speed_kmh : float
        Train speed; must be one of the published speeds, 250 or 300. [km/h]

    Returns
    -------
    dict
        Statistic key -> (low, high), as in :data:`EN50318_RANGES`. [N, mm, %]

    Raises
    ------
    ModelError
        If the speed has no published ranges.
    """
    ranges = EN50318_RANGES.get(round(speed_kmh))
    if ranges is None or abs(speed_kmh - round(speed_kmh)) > 1e-6:
        raise ModelError(
            f"speed = {speed_kmh:g} km/h has no EN 50318 reference ranges; give one of "
            f"{', '.join(str(v) for v in EN50318_RANGES)} km/h"
        )
    return ranges


def en50318_verdicts(speed_kmh: float, statistics: Mapping[str, float]) -> tuple[Verdict, ...]:
    """A verdict for every published statistic of a run of the EN 50318 reference case.

    Parameters
    ----------
    speed_kmh : float
        Train speed of the run; must be one of the published speeds, 250 or 300. [km/h]
    statistics : mapping
        The run's statistics keyed like :data:`EN50318_RANGES` (a simulation result's ``to_dict()``).
        [N, mm, %]

    Returns
    -------
    tuple of Verdict
        In the order of :data:`EN50318_RANGES`.

    Raises
    ------
    ModelError
        If the speed has no published ranges.
    """
    return tuple(
        Verdict(statistic=key, value=float(statistics[key]), low=float(low), high=float(high))
        for key, (low, high) in en50318_ranges(speed_kmh).items()
    )
