"""Per-orbit film quantities of a squeeze film damper, for the results: the peak film
pressure, the cavitated arc and the squeeze Reynolds number.

For the users' check against the supply pressure ``p_s`` (all pressures relative to the
cavity pressure, as the film models have them):

- ``p_max``: the largest film pressure of the model over the orbit [Pa] (pi film: on its
  arc; Guembel: clamped; 2 pi film: the uncavitated film).
- ``p_min``: the lowest pressure of the uncavitated film over the orbit [Pa]: a film
  supplied at ``p_s`` stays whole (no cavitation, the 2 pi model holds) if
  ``p_s + p_min > 0``.
- ``cavitated_arc``: the largest, over the orbit, circumferential arc at mid-land where
  the uncavitated film's pressure is below the cavity pressure [rad] (the arc the Guembel
  clamp removes; the pi film takes it as pi). For the short film it is exactly pi while
  the journal moves: ``p_full = -(3 mu L^2 / (2 C^3)) (w.m) / H^3`` at mid-land changes
  sign where ``w.m = 0``.
- ``squeeze_reynolds``: ``Re_s = rho omega C^2 / mu`` with the orbit's whirl frequency
  ``omega = rms(v - mean v) / rms(q - mean q)`` (exact for an orbit of one frequency,
  circular or elliptic); only with an oil density. Lubrication theory (all film models
  here) neglects fluid inertia, which is of order ``Re_s``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["MAX_ORBIT_SAMPLES", "film_diagnostics", "squeeze_reynolds"]

#: The finite film solves its grid per sample: its diagnostics use at most this many
#: samples of the orbit (evenly spaced in time).
MAX_ORBIT_SAMPLES = 64

_THETA = np.linspace(0.0, 2.0 * np.pi, 721)


def squeeze_reynolds(q: np.ndarray, v: np.ndarray, density: float, viscosity: float,
                     clearance: float) -> float:
    """``Re_s = rho omega C^2 / mu``, ``omega = rms(v - mean v) / rms(q - mean q)`` over the
    samples ``q, v (N, 2)`` (0 for a static orbit)."""
    dq = q - q.mean(axis=0)
    dv = v - v.mean(axis=0)
    amp = math.sqrt(float(np.mean(np.sum(dq * dq, axis=-1))))
    if amp <= 0.0:
        return 0.0
    omega = math.sqrt(float(np.mean(np.sum(dv * dv, axis=-1)))) / amp
    return density * omega * clearance**2 / viscosity


def _short_film(film: Any, d: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
    """Mid-land pressure of the short film on a fine theta grid, all samples at once."""
    e = np.hypot(d[:, 0], d[:, 1])
    eps = e / film.clearance
    psi = np.arctan2(d[:, 1], d[:, 0])
    cp, sp = np.cos(psi), np.sin(psi)
    wr = cp * v[:, 0] + sp * v[:, 1]
    wt = -sp * v[:, 0] + cp * v[:, 1]
    h = 1.0 + eps[:, None] * np.cos(_THETA)
    p_full = -1.5 * film.viscosity * film.length**2 / film.clearance**3 * (
        wr[:, None] * np.cos(_THETA) + wt[:, None] * np.sin(_THETA)) / h**3
    if film.cavitation == "pi":
        p_model = p_full[:, _THETA >= np.pi]
    elif film.cavitation == "guembel":
        p_model = np.maximum(p_full, 0.0)
    else:
        p_model = p_full
    moving = (wr != 0.0) | (wt != 0.0)
    arc = math.pi if np.any(moving) else 0.0
    return float(p_model.max(initial=0.0)), float(p_full.min(initial=0.0)), arc


def _finite_film(film: Any, d: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
    """The discrete film of each sample (``FiniteSFD.pressure``)."""
    step = max(1, math.ceil(d.shape[0] / MAX_ORBIT_SAMPLES))
    p_max, p_min, arc = 0.0, 0.0, 0.0
    for k in range(0, d.shape[0], step):
        _, _, p_full, p = film.pressure(float(d[k, 0]), float(d[k, 1]), float(v[k, 0]),
                                        float(v[k, 1]))
        p_max = max(p_max, float(p.max()))
        p_min = min(p_min, float(p_full.min()))
        arc = max(arc, 2.0 * math.pi * float(np.mean(p_full[:, 0] < 0.0)))
    return p_max, p_min, arc


def film_diagnostics(film: Any, d: np.ndarray, v: np.ndarray, density: float | None = None
                     ) -> dict[str, float]:
    """``p_max, p_min, cavitated_arc`` (and ``squeeze_reynolds`` with a ``density``) of
    the orbit ``d = q - o, v (N, 2)`` of ``film`` (a short ``SFD`` or a ``FiniteSFD``)."""
    d = np.atleast_2d(np.asarray(d, dtype=float))
    v = np.atleast_2d(np.asarray(v, dtype=float))
    finite = hasattr(film, "pressure")
    p_max, p_min, arc = (_finite_film if finite else _short_film)(film, d, v)
    out = {"p_max": p_max, "p_min": p_min, "cavitated_arc": arc}
    if density is not None:
        out["squeeze_reynolds"] = squeeze_reynolds(d, v, density, film.viscosity,
                                                   film.clearance)
    return out
