"""Contact-force statistics (EN 50367 / EN 50318 conventions) and wave-speed measures.

The contact force is low-pass filtered at 20 Hz without phase shift; over an analysis window (the
central spans, away from the ends of the model) the mean F_m, the standard deviation σ, σ/F_m, the
statistical extremes F_m ± 3σ and the actual extremes of the filtered force are reported. Loss of
contact is the share of time in the window with the raw (unfiltered) force at or below zero.

Filter: Butterworth of order :data:`FILTER_ORDER` (4) with its -3 dB point at the cut-off, applied
forward and backward (``scipy.signal.sosfiltfilt``): zero phase, magnitude response
1/(1 + (f/f_c)^8), i.e. -6 dB at the cut-off and an effective order of 8. The whole record is
filtered and the window cut out afterwards, so the filter's start-up lies outside the window when the
window keeps away from the record ends.

References
----------
EN 50367:2012+A1:2016, Railway applications - Current collection systems - Technical criteria for the
interaction between pantograph and overhead line (filtering at 20 Hz, F_m, σ).
EN 50318:2018, Railway applications - Current collection systems - Validation of simulation of the
dynamic interaction between pantograph and overhead contact line.
EN 50119:2020, Railway applications - Fixed installations - Electric traction overhead contact lines
(speed not above 70 % of the wave propagation speed).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError

CUTOFF_FREQUENCY = 20.0
"""Low-pass cut-off of the contact force. [Hz]"""

FILTER_ORDER = 4
"""Order of the Butterworth low-pass (applied twice: forward and backward). [-]"""

MIN_SAMPLES_PER_CUTOFF_PERIOD = 5
"""Sampling must give at least this many samples per cut-off period (100 Hz for 20 Hz). [-]"""

MIN_WINDOW_CUTOFF_PERIODS = 5
"""The analysis window must span at least this many cut-off periods (0.25 s for 20 Hz). [-]"""



@dataclass(frozen=True, kw_only=True)
class ContactForceStatistics:
    """Statistics of the filtered contact force over an analysis window.

    Attributes
    ----------
    mean_force : float
        Mean contact force F_m. [N]
    std_force : float
        Standard deviation σ (population, ddof = 0). [N]
    statistical_max : float
        F_m + 3σ. [N]
    statistical_min : float
        F_m - 3σ. [N]
    max_force : float
        Largest filtered force in the window. [N]
    min_force : float
        Smallest filtered force in the window. [N]
    loss_of_contact : float
        Share of the window's samples with raw force <= 0. [-]
    window_start, window_end : float
        The analysis window. [s]
    """

    mean_force: float
    std_force: float
    statistical_max: float
    statistical_min: float
    max_force: float
    min_force: float
    loss_of_contact: float
    window_start: float
    window_end: float

    @property
    def sigma_over_mean(self) -> float:
        """σ / F_m. [-]"""
        return self.std_force / self.mean_force

    def to_dict(self) -> dict[str, float]:
        """The statistics with units in the key names (forces in N, loss of contact in %)."""
        return {
            "Fm_N": self.mean_force,
            "sigma_N": self.std_force,
            "sigma_over_Fm": self.sigma_over_mean,
            "stat_max_N": self.statistical_max,
            "stat_min_N": self.statistical_min,
            "max_N": self.max_force,
            "min_N": self.min_force,
            "loss_of_contact_pct": 100.0 * self.loss_of_contact,
        }


def lowpass_filter(time: np.ndarray, force: np.ndarray, *, cutoff: float = CUTOFF_FREQUENCY) -> np.ndarray:
    """Zero-phase Butterworth low-pass of a uniformly sampled force signal.

    Parameters
    ----------
    time : numpy.ndarray
        Uniformly spaced sample times. [s]
    force : numpy.ndarray
        Force samples. [N]
    cutoff : float
        Cut-off frequency (-3 dB of the single pass). [Hz]

    Returns
    -------
    numpy.ndarray
        The filtered force. [N]

    Raises
    ------
    ModelError
        Mismatched lengths, non-uniform sampling, or sampling too coarse for the cut-off.
    """
    time, force = np.asarray(time, dtype=float), np.asarray(force, dtype=float)
    rate = _sampling_rate(time, force)
    if rate < MIN_SAMPLES_PER_CUTOFF_PERIOD * cutoff:
        lowest = MIN_SAMPLES_PER_CUTOFF_PERIOD * cutoff
        raise ModelError(
            f"sampling rate {rate:g} Hz is too coarse for a {cutoff:g} Hz low-pass: use at least "
            f"{lowest:g} Hz (time step <= {1e3 / lowest:g} ms)"
        )
    from scipy import signal  # imported here: it costs about a second, which every command would pay

    sos = signal.butter(FILTER_ORDER, cutoff, btype="low", fs=rate, output="sos")
    return signal.sosfiltfilt(sos, force)


def contact_force_statistics(
    time: np.ndarray,
    contact_force: np.ndarray,
    *,
    window_start: float,
    window_end: float,
    cutoff: float = CUTOFF_FREQUENCY,
) -> ContactForceStatistics:
    """EN 50367-style statistics of a contact-force record over an analysis window.

    Parameters
    ----------
    time : numpy.ndarray
        Uniformly spaced sample times of the whole record. [s]
    contact_force : numpy.ndarray
        Raw (unfiltered) contact force. [N]
    window_start, window_end : float
        Analysis window inside the record, e.g. the pantograph's passage over the central spans. [s]
    cutoff : float
        Low-pass cut-off frequency. [Hz]

    Returns
    -------
    ContactForceStatistics
        F_m, σ, F_m ± 3σ, filtered extremes and loss of contact.

    Raises
    ------
    ModelError
        A window outside the record or shorter than :data:`MIN_WINDOW_CUTOFF_PERIODS` cut-off
        periods, or a record the filter cannot handle (see :func:`lowpass_filter`).
    """
    time = np.asarray(time, dtype=float)
    raw = np.asarray(contact_force, dtype=float)
    filtered = lowpass_filter(time, raw, cutoff=cutoff)
    inside = window_mask(time, window_start, window_end, cutoff)
    window = filtered[inside]
    mean, std = float(np.mean(window)), float(np.std(window))
    return ContactForceStatistics(
        mean_force=mean,
        std_force=std,
        statistical_max=mean + 3.0 * std,
        statistical_min=mean - 3.0 * std,
        max_force=float(np.max(window)),
        min_force=float(np.min(window)),
        loss_of_contact=float(np.mean(raw[inside] <= 0.0)),
        window_start=window_start,
        window_end=window_end,
    )


def _sampling_rate(time: np.ndarray, force: np.ndarray) -> float:
    """Sampling rate of a uniformly sampled record. [Hz]"""
    if time.ndim != 1 or time.shape != force.shape:
        raise ModelError(f"time {time.shape} and force {force.shape} must be 1-D arrays of the same length")
    if len(time) < 2:
        raise ModelError("the record needs at least two samples")
    steps = np.diff(time)
    step = float(np.median(steps))
    if step <= 0.0 or np.max(np.abs(steps - step)) > 1e-6 * step:
        raise ModelError("time must be uniformly spaced and increasing (the filter assumes a constant sampling rate)")
    return 1.0 / step


def window_mask(time: np.ndarray, start: float, end: float, cutoff: float = CUTOFF_FREQUENCY) -> np.ndarray:
    """Boolean mask of the samples of a record in the analysis window [start, end], after checking the
    window: the samples :func:`contact_force_statistics` takes its statistics over. [-]

    Parameters
    ----------
    time : numpy.ndarray
        Sample times of the record. [s]
    start, end : float
        The analysis window. [s]
    cutoff : float
        Low-pass cut-off frequency (the window must span :data:`MIN_WINDOW_CUTOFF_PERIODS` of its periods). [Hz]

    Raises
    ------
    ModelError
        A window outside the record or too short.
    """
    shortest = MIN_WINDOW_CUTOFF_PERIODS / cutoff
    tol = 1e-9 * max(1.0, abs(time[-1]))
    if start < time[0] - tol or end > time[-1] + tol:
        raise ModelError(
            f"analysis window [{start:g}, {end:g}] s lies outside the record [{time[0]:g}, {time[-1]:g}] s"
        )
    if end - start < shortest:
        raise ModelError(
            f"analysis window [{start:g}, {end:g}] s is {end - start:g} s long; it must span at least "
            f"{MIN_WINDOW_CUTOFF_PERIODS} periods of the {cutoff:g} Hz filter ({shortest:g} s)"
        )
    return (time >= start - tol) & (time <= end + tol)
