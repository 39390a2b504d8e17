"""Waterfall (spectrogram) of a whirl orbit: its short-time spectrum against time.

The orbit of a node is the complex whirl ``w(t) = y(t) + i z(t)``; a forward whirl of
radius r at frequency f is ``r exp(+2 pi i f t)`` and a backward one ``r exp(-2 pi i f t)``,
so the two-sided spectrum of w separates them (positive frequencies forward, negative
backward). The short-time Fourier transform on Hann windows of ``window`` seconds
(``scipy.signal.ShortTimeFFT``, hop ``window (1 - overlap)``) with the window's sum as
the scale,

    W(t_j, f) = sum_n w(t_n) h(t_n - t_j) exp(-2 pi i f t_n) / sum_n h(t_n - t_j),

gives the radius r at the whirl's frequency when it falls on a frequency bin (a Hann
window's scalloping loss is at most 15.1 % between bins; its resolution 2 / window).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import ShortTimeFFT
from scipy.signal.windows import hann


@dataclass(frozen=True)
class Waterfall:
    """``amplitude`` (n_windows, n_freq) [m] at window centres ``time`` [s] and two-sided
    ``frequency`` [Hz] (ascending: backward whirl < 0 < forward whirl)."""

    time: np.ndarray
    frequency: np.ndarray
    amplitude: np.ndarray

    def forward(self) -> tuple[np.ndarray, np.ndarray]:
        """(frequencies >= 0, amplitudes) of the forward whirl."""
        keep = self.frequency >= 0.0
        return self.frequency[keep], self.amplitude[:, keep]


def waterfall(t: np.ndarray, y: np.ndarray, z: np.ndarray, window: float,
              overlap: float = 0.75) -> Waterfall:
    """The waterfall of the orbit (y(t), z(t)) sampled uniformly at ``t`` (module
    docstring); ``window`` [s] is rounded to whole samples (at least 16)."""
    t = np.asarray(t, dtype=float)
    dt = float(t[1] - t[0])
    if not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0.0):
        raise ValueError("waterfall needs uniformly sampled times")
    n = max(16, round(window / dt))
    n = min(n, t.size)
    if not 0.0 <= overlap < 1.0:
        raise ValueError("overlap must be in [0, 1)")
    hop = max(1, round(n * (1.0 - overlap)))
    h = hann(n, sym=False)
    stft = ShortTimeFFT(h / h.sum(), hop=hop, fs=1.0 / dt, fft_mode="centered")
    w = np.asarray(y, dtype=float) + 1j * np.asarray(z, dtype=float)
    s = stft.stft(w)                                   # (n_freq, n_windows)
    # the windows wholly inside the record (slice p is column p - p_min)
    lo, hi = stft.lower_border_end[1], stft.upper_border_begin(w.size)[1]
    cols = np.arange(lo, hi) - stft.p_min
    if cols.size == 0:
        cols = np.arange(s.shape[1])
    centres = t[0] + stft.t(w.size)[cols]
    freq = stft.f
    return Waterfall(centres, freq, np.abs(s[:, cols]).T)


def default_window(omega_min: float, periods: float = 16.0) -> float:
    """``periods`` periods of the slowest speed [s]: a resolution of 1/8 of its 1X."""
    return periods * 2.0 * math.pi / float(omega_min)
