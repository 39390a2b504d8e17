"""Amplitude spectra, spectral lines and their ratios to the forcing frequency.

One-sided amplitude spectrum with a window ``w``::

    A(w_k) = 2 |sum_j w_j x_j exp(-i w_k t_j)| / sum_j w_j      (A(0) without the 2)

so a line ``a cos(w t + phi)`` on a bin shows amplitude ``a`` (half peak-to-peak, the
project's convention). Frequencies are angular [rad/s]. Line frequencies and amplitudes
are refined by a parabola through the logarithm of the three bins around each peak.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

#: Main-lobe half width in bins of the supported windows.
_HALF_LOBE = {"boxcar": 1, "hann": 2, "hamming": 2, "blackman": 3, "blackmanharris": 4}


@dataclass(frozen=True)
class SpectralLine:
    """A peak: angular ``frequency`` [rad/s], ``amplitude``, ``ratio`` to the reference
    frequency, the nearest fraction ``p/q`` (``q <= max_denominator``) and whether the
    ratio is within the resolution of it (``rational``)."""

    frequency: float
    amplitude: float
    ratio: float
    fraction: Fraction
    rational: bool


@dataclass(frozen=True)
class SpectrumAnalysis:
    """Spectrum, its lines and ``broadband_fraction``: the share of the (non-static)
    spectral power outside the main lobes of the lines (0 for a few clean lines)."""

    frequencies: np.ndarray
    amplitudes: np.ndarray
    lines: tuple[SpectralLine, ...]
    broadband_fraction: float
    resolution: float

    @property
    def incommensurate(self) -> tuple[SpectralLine, ...]:
        """Lines whose ratio to the reference is not a small-denominator fraction."""
        return tuple(ln for ln in self.lines if not ln.rational)


def amplitude_spectrum(x: np.ndarray, dt: float, window: str = "blackmanharris",
                       detrend: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Angular frequencies ``2 pi k/(N dt)`` and one-sided amplitudes of ``x`` (module
    docstring); ``detrend`` removes the mean first."""
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 8:
        raise ValueError(f"need a 1-D signal of at least 8 samples, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("signal has non-finite samples")
    if detrend:
        x = x - x.mean()
    import scipy.signal  # 0.8 s CPU of import: only where a spectrum is taken

    w = scipy.signal.get_window(window, x.size, fftbins=True)
    X = np.fft.rfft(w * x)
    amp = np.abs(X) / w.sum()
    amp[1:] *= 2.0
    if x.size % 2 == 0:
        amp[-1] *= 0.5
    freq = 2.0 * math.pi * np.fft.rfftfreq(x.size, dt)
    return freq, amp


def _refine(freq: np.ndarray, amp: np.ndarray, k: int) -> tuple[float, float]:
    """Log-parabolic interpolation of the peak at bin ``k``."""
    if k <= 0 or k >= amp.size - 1:
        return float(freq[k]), float(amp[k])
    a, b, c = (math.log(max(v, 1e-300)) for v in amp[k - 1:k + 2])
    den = a - 2.0 * b + c
    p = 0.5 * (a - c) / den if den < 0.0 else 0.0
    p = max(-0.5, min(0.5, p))
    df = freq[1] - freq[0]
    return float(freq[k] + p * df), float(math.exp(b - 0.25 * (a - c) * p))


def spectral_lines(x: np.ndarray, dt: float, omega_ref: float, *,
                   window: str = "blackmanharris", rel_threshold: float = 1e-3,
                   max_lines: int = 30, max_denominator: int = 8,
                   ratio_tol_bins: float = 0.25, detrend: bool = True) -> SpectrumAnalysis:
    """Peaks of the amplitude spectrum above ``rel_threshold`` times the largest, with
    their ratios to ``omega_ref`` and the broadband fraction.

    A ratio counts as rational when its refined frequency lies within
    ``ratio_tol_bins`` frequency bins of ``(p/q) omega_ref`` with
    ``q <= max_denominator``; a line that is not is *incommensurate* (two independent
    frequencies: quasi-periodic or broadband motion).
    """
    freq, amp = amplitude_spectrum(x, dt, window=window, detrend=detrend)
    half = _HALF_LOBE.get(window, 4)
    df = float(freq[1] - freq[0])
    top = float(amp[1:].max()) if amp.size > 1 else 0.0
    lines: list[SpectralLine] = []
    power = amp[1:] ** 2
    total = float(power.sum())
    if top <= 0.0:
        return SpectrumAnalysis(freq, amp, (), 0.0, df)
    # deferred: scipy.signal costs 0.8 s CPU to import (only where a spectrum is taken)
    import scipy.signal

    peaks, props = scipy.signal.find_peaks(amp, height=rel_threshold * top,
                                           prominence=0.5 * rel_threshold * top,
                                           distance=half)
    order = np.argsort(props["peak_heights"])[::-1][:max_lines]
    in_lobe = np.zeros(amp.size, dtype=bool)
    tol = ratio_tol_bins * df / omega_ref
    for k in sorted(peaks[order]):
        if k == 0:
            continue
        f, a = _refine(freq, amp, int(k))
        ratio = f / omega_ref
        frac = Fraction(ratio).limit_denominator(max_denominator)
        lines.append(SpectralLine(f, a, ratio, frac, abs(ratio - float(frac)) <= tol))
        in_lobe[max(0, k - half):k + half + 1] = True
    outside = float(power[~in_lobe[1:]].sum())
    return SpectrumAnalysis(freq, amp, tuple(lines), outside / total if total else 0.0, df)


def two_frequency_fraction(analysis: SpectrumAnalysis, omega_ref: float, *,
                           rel_amplitude: float = 0.01, max_order: int = 8,
                           tol_bins: float = 0.5) -> tuple[float, float | None]:
    """Share of the power of the strong lines (amplitude >= ``rel_amplitude`` times the
    largest) at combinations ``p omega_ref + r omega_2`` (``|p|, |r| <= max_order``),
    ``omega_2`` the strongest incommensurate line. Near 1 for a two-frequency
    (quasi-periodic) response; lower for a broadband one. Returns
    ``(fraction, omega_2)``; ``(0, None)`` without an incommensurate strong line."""
    if not analysis.lines:
        return 0.0, None
    top = max(ln.amplitude for ln in analysis.lines)
    strong = [ln for ln in analysis.lines if ln.amplitude >= rel_amplitude * top]
    inc = [ln for ln in strong if not ln.rational]
    if not inc:
        return 0.0, None
    w2 = max(inc, key=lambda ln: ln.amplitude).frequency
    orders = np.arange(-max_order, max_order + 1)
    combos = (orders[:, None] * omega_ref + orders[None, :] * w2).ravel()
    tol = tol_bins * analysis.resolution
    power = np.array([ln.amplitude**2 for ln in strong])
    ok = np.array([np.min(np.abs(combos - ln.frequency)) <= tol for ln in strong])
    return float(power[ok].sum() / power.sum()), float(w2)
