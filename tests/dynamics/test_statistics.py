"""Contact-force statistics on synthetic signals with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.statistics import contact_force_statistics, lowpass_filter
from presag_opt.errors import ModelError

RATE = 1000.0  # Hz, sampling of the synthetic records (2 ms simulations give 500 Hz)


def _time(duration: float, rate: float = RATE) -> np.ndarray:
    return np.arange(round(duration * rate) + 1) / rate


def _noise_above(t: np.ndarray, lowest: float, std: float, seed: int) -> np.ndarray:
    """Seeded white noise with every component below ``lowest`` Hz removed, scaled to ``std``. [N]"""
    spectrum = np.fft.rfft(np.random.default_rng(seed).standard_normal(len(t)))
    spectrum[np.fft.rfftfreq(len(t), t[1] - t[0]) < lowest] = 0.0
    noise = np.fft.irfft(spectrum, len(t))
    return std * noise / np.std(noise)


def test_filter_removes_content_above_20_hz_and_statistics_match_the_low_frequency_part():
    """F = 100 N + 20 N·sin(2π·2 Hz·t) + 15 N at 60 Hz + 5 N (std) of noise above 50 Hz.

    Over [1, 5] s (8 whole periods) the 2 Hz part has mean 100 N, σ = 20/√2 = 14.142 N,
    max 120 N and min 80 N (sampled exactly at 1 kHz). The filter's gain 1/(1 + (f/20)^8) leaves
    1.5e-4 of 60 Hz (2.3 mN) and at most 6.5e-4 of the noise (3 mN std), and passes 2 Hz to 1e-8:
    forces within 0.02 N and σ within 1e-3 relative. The raw signal's σ (19.0 N) would fail that.
    """
    t = _time(6.0)
    low = 100.0 + 20.0 * np.sin(2.0 * np.pi * 2.0 * t)
    raw = low + 15.0 * np.sin(2.0 * np.pi * 60.0 * t + 0.3) + _noise_above(t, 50.0, 5.0, seed=1)
    stats = contact_force_statistics(t, raw, window_start=1.0, window_end=5.0)
    sigma = 20.0 / np.sqrt(2.0)
    assert stats.mean_force == pytest.approx(100.0, abs=0.02)
    assert stats.std_force == pytest.approx(sigma, rel=1e-3)
    assert stats.sigma_over_mean == pytest.approx(sigma / 100.0, rel=1e-3)
    assert stats.statistical_max == pytest.approx(100.0 + 3.0 * sigma, abs=0.05)
    assert stats.statistical_min == pytest.approx(100.0 - 3.0 * sigma, abs=0.05)
    assert stats.max_force == pytest.approx(120.0, abs=0.02)
    assert stats.min_force == pytest.approx(80.0, abs=0.02)
    assert stats.loss_of_contact == 0.0
    assert np.std(raw[(t >= 1.0) & (t <= 5.0)]) > sigma * 1.2


def test_filter_has_the_stated_zero_phase_butterworth_gain():
    """Forward-backward 4th-order Butterworth: gain 1/(1 + (f/20)^8) and no phase shift, i.e. 0.5 at
    20 Hz and 0.99935 at 8 Hz. Amplitude and phase come from a least-squares fit of sin and cos over
    the middle 2 s (whole periods, away from the end transients); tolerance 1e-3 covers the
    bilinear transform's frequency warping at 20 Hz / 1 kHz (below 1e-4 with scipy's pre-warping)."""
    t = _time(4.0)
    middle = (t >= 1.0) & (t < 3.0)
    for frequency, gain in ((20.0, 0.5), (8.0, 1.0 / (1.0 + 0.4**8))):
        phase = 2.0 * np.pi * frequency * t[middle]
        filtered = lowpass_filter(t, np.sin(2.0 * np.pi * frequency * t))[middle]
        (sin_part, cos_part), *_ = np.linalg.lstsq(np.column_stack([np.sin(phase), np.cos(phase)]), filtered)
        assert sin_part == pytest.approx(gain, rel=1e-3)
        assert abs(cos_part) < 1e-3


def test_loss_of_contact_is_counted_on_the_raw_force():
    """F = 30 N + 60 N·sin(2π·97.3 Hz·t): the raw force is <= 0 a share 1/2 - arcsin(1/2)/π = 1/3 of
    the time, while the filtered force stays near 30 N. Tolerance 0.5 percentage points: 4 s at
    1 kHz hold 389 periods sampled at incommensurate phases, which equidistribute to about 1/389."""
    t = _time(5.0)
    raw = 30.0 + 60.0 * np.sin(2.0 * np.pi * 97.3 * t)
    stats = contact_force_statistics(t, raw, window_start=0.5, window_end=4.5)
    assert stats.to_dict()["loss_of_contact_pct"] == pytest.approx(100.0 / 3.0, abs=0.5)
    assert stats.min_force > 29.0


def test_to_dict_uses_the_documented_keys_and_units():
    t = _time(2.0)
    stats = contact_force_statistics(t, 120.0 + 10.0 * np.sin(2.0 * np.pi * 4.0 * t), window_start=0.5, window_end=1.5)
    result = stats.to_dict()
    assert list(result) == [
        "Fm_N",
        "sigma_N",
        "sigma_over_Fm",
        "stat_max_N",
        "stat_min_N",
        "max_N",
        "min_N",
        "loss_of_contact_pct",
    ]
    assert result["Fm_N"] == pytest.approx(120.0, abs=0.01)
    assert result["stat_max_N"] - result["Fm_N"] == pytest.approx(3.0 * result["sigma_N"], rel=1e-12)


@pytest.mark.parametrize(
    ("time", "window", "message"),
    [
        (_time(2.0), (0.5, 0.6), r"0.1 s long; it must span at least 5 periods of the 20 Hz filter \(0.25 s\)"),
        (_time(2.0, rate=50.0), (0.5, 1.5), "sampling rate 50 Hz is too coarse for a 20 Hz low-pass"),
        (_time(2.0), (1.0, 2.5), r"lies outside the record \[0, 2\] s"),
        (np.sort(np.random.default_rng(0).uniform(0.0, 2.0, 2001)), (0.5, 1.5), "uniformly spaced"),
    ],
)
def test_unusable_records_and_windows_are_model_errors(time, window, message):
    with pytest.raises(ModelError, match=message):
        contact_force_statistics(time, 100.0 + 0.0 * time, window_start=window[0], window_end=window[1])


def test_mismatched_lengths_are_a_model_error():
    with pytest.raises(ModelError, match="same length"):
        contact_force_statistics(_time(2.0), np.ones(10), window_start=0.5, window_end=1.5)
