"""Installation errors as a line crew makes them: per dropper, per registration, per messenger support.

A crew does not build a wrong pre-sag S; it cuts each dropper to within a few millimetres and sets
each registration (contact-wire height at the steady arm) and each messenger-wire support within a
few more, and these errors scatter independently along the line. :class:`InstallationErrors` states
their size (a standard deviation, or the half-width ±t of a uniform distribution, in metres inside
the code); :func:`draw_installation_errors` draws many realisations of a section at once.

Reproducibility: every sample is drawn in the calling process from one
:class:`numpy.random.Generator` seeded with ``seed``, in a fixed order (dropper errors of all samples,
then registration, then messenger supports), before any work is shared out, so a result does not
depend on how many worker processes evaluate the samples. The draws are *standard* (unit normal, or
uniform on [−1, 1]) and scaled by the tolerance: the samples of two tolerances are the same errors
at two scales (common random numbers), so a percentile compared across tolerances moves with the
tolerance, not with the sampling noise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError

DISTRIBUTIONS = ("normal", "uniform")
"""Distributions of one installation error: normal (size = standard deviation σ) or uniform within
±t (size = t)."""

MAX_ERROR = 0.1
"""Largest installation error size accepted: 100 mm (a dropper cut 10 cm wrong is not a tolerance). [m]"""

MAX_SAMPLES = 1_000_000
"""Most Monte Carlo samples of one draw. [-]"""


@dataclass(frozen=True, kw_only=True)
class InstallationErrors:
    """Sizes of the installation errors of a section, each independent per dropper or per mast.

    Attributes
    ----------
    dropper_length : float
        Error of each dropper's cut length (positive: longer, the contact wire lower). [m]
    contact_wire_height : float
        Error of the contact-wire height at each mast, the registration (positive: higher). [m]
    messenger_height : float
        Error of the messenger-wire support height at each mast (positive: higher). [m]
    distribution : {"normal", "uniform"}
        Each size is a standard deviation (normal) or the half-width ±t (uniform).
    """

    dropper_length: float = 0.0
    contact_wire_height: float = 0.0
    messenger_height: float = 0.0
    distribution: str = "normal"

    def __post_init__(self) -> None:
        for name in ("dropper_length", "contact_wire_height", "messenger_height"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not math.isfinite(value) or not 0.0 <= value <= MAX_ERROR:
                shown = f"{value * 1e3:g} mm" if isinstance(value, (int, float)) else repr(value)
                raise ModelError(f"{name} = {shown} is outside the valid range [0, {MAX_ERROR * 1e3:g}] mm")
            object.__setattr__(self, name, float(value))
        if self.distribution not in DISTRIBUTIONS:
            raise ModelError(f"distribution = {self.distribution!r} is not one of {', '.join(DISTRIBUTIONS)}")

    @property
    def standard_deviations(self) -> tuple[float, float, float]:
        """Standard deviation of each error (t/√3 for a uniform ±t). [m]"""
        scale = 1.0 if self.distribution == "normal" else 1.0 / math.sqrt(3.0)
        return (self.dropper_length * scale, self.contact_wire_height * scale, self.messenger_height * scale)


@dataclass(frozen=True, kw_only=True)
class StandardDraws:
    """Unit draws of every error of every sample, scaled by :meth:`scaled` (common random numbers).

    Attributes
    ----------
    distribution : str
        ``normal`` (unit normal) or ``uniform`` (uniform on [−1, 1]).
    seed : int
        Seed of the generator that drew them. [-]
    dropper : ndarray, shape (samples, droppers)
        Per dropper, in along-track order. [-]
    contact_wire : ndarray, shape (samples, masts)
        Per mast (registration). [-]
    messenger : ndarray, shape (samples, masts)
        Per mast (messenger-wire support). [-]
    """

    distribution: str
    seed: int
    dropper: np.ndarray
    contact_wire: np.ndarray
    messenger: np.ndarray

    @property
    def samples(self) -> int:
        """Number of samples. [-]"""
        return self.dropper.shape[0]

    def scaled(self, errors: InstallationErrors) -> InstallationSample:
        """The errors of every sample at the sizes of ``errors`` (same distribution). [m]"""
        if errors.distribution != self.distribution:
            raise ModelError(f"draws of a {self.distribution} distribution cannot be scaled to a "
                             f"{errors.distribution} one; draw again")
        return InstallationSample(dropper=self.dropper * errors.dropper_length,
                                  contact_wire=self.contact_wire * errors.contact_wire_height,
                                  messenger=self.messenger * errors.messenger_height)


@dataclass(frozen=True, kw_only=True)
class InstallationSample:
    """Installation errors of one or many realisations of a section.

    Attributes
    ----------
    dropper : ndarray, shape (samples, droppers)
        Dropper length errors (positive: longer). [m]
    contact_wire : ndarray, shape (samples, masts)
        Registration height errors (positive: higher). [m]
    messenger : ndarray, shape (samples, masts)
        Messenger-wire support height errors (positive: higher). [m]
    """

    dropper: np.ndarray
    contact_wire: np.ndarray
    messenger: np.ndarray

    @property
    def samples(self) -> int:
        """Number of realisations. [-]"""
        return self.dropper.shape[0]

    def stacked(self) -> np.ndarray:
        """All errors of each realisation in one row: droppers, then registrations, then messenger
        supports (the column order of :class:`~presag_opt.robust.realisation.InstallationResponse`). [m]"""
        return np.hstack([self.dropper, self.contact_wire, self.messenger])

    def row(self, i: int) -> InstallationSample:
        """Realisation ``i`` alone (arrays of one row).

        Parameters
        ----------
        i : int
            Index of the realisation. [-]
        """
        return InstallationSample(dropper=self.dropper[i : i + 1], contact_wire=self.contact_wire[i : i + 1],
                                  messenger=self.messenger[i : i + 1])


def draw_installation_errors(
    samples: int, droppers: int, masts: int, *, distribution: str = "normal", seed: int = 0
) -> StandardDraws:
    """Unit draws of every installation error of ``samples`` realisations, from one seeded generator.

    Parameters
    ----------
    samples : int
        Realisations, 1 to :data:`MAX_SAMPLES`. [-]
    droppers, masts : int
        Droppers and masts of the section. [-]
    distribution : {"normal", "uniform"}
        Unit normal, or uniform on [−1, 1].
    seed : int
        Seed of :func:`numpy.random.default_rng`, 0 to 2³²−1. [-]

    Returns
    -------
    StandardDraws
        Scale them with :meth:`StandardDraws.scaled`.
    """
    if samples != int(samples) or not 1 <= samples <= MAX_SAMPLES:
        raise ModelError(f"samples = {samples} is outside the valid range [1, {MAX_SAMPLES}]")
    if seed != int(seed) or not 0 <= seed < 2**32:
        raise ModelError(f"seed = {seed} is outside the valid range [0, {2**32 - 1}]")
    if distribution not in DISTRIBUTIONS:
        raise ModelError(f"distribution = {distribution!r} is not one of {', '.join(DISTRIBUTIONS)}")
    rng = np.random.default_rng(int(seed))
    if distribution == "normal":
        draw = rng.standard_normal
    else:
        def draw(shape):
            return rng.uniform(-1.0, 1.0, shape)
    samples = int(samples)
    return StandardDraws(distribution=distribution, seed=int(seed), dropper=draw((samples, droppers)),
                         contact_wire=draw((samples, masts)), messenger=draw((samples, masts)))
