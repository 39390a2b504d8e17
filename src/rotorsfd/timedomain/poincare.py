"""Poincare sections: periodicity, clusters, closed curves, correlation dimension.

Points are rows of ``P (N, d)`` sampled once per forcing period, in coordinates
normalised by the spread of the orbit (``normalise``), so every tolerance below is
relative: a period-n orbit has ``|P[k+n] - P[k]| <= rtol`` for all ``k``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.distance import pdist


def normalise(points: np.ndarray, scale: np.ndarray | float | None = None) -> np.ndarray:
    """``(P - mean P) / scale`` per coordinate; ``scale`` defaults to the peak-to-peak
    of the points (use the spread of the whole orbit, not of the section, for periodic
    motion); zero scales are replaced by 1."""
    P = np.asarray(points, dtype=float)
    if P.ndim == 1:
        P = P[:, None]
    s = np.ptp(P, axis=0) if scale is None else np.broadcast_to(
        np.asarray(scale, dtype=float), (P.shape[1],)).copy()
    s = np.where(s > 0.0, s, 1.0)
    return (P - P.mean(axis=0)) / s


def poincare_period(P: np.ndarray, rtol: float = 1e-3, n_max: int = 16) -> int | None:
    """Smallest ``n <= n_max`` with ``max_k |P[k+n] - P[k]|_inf <= rtol`` (normalised
    points), or ``None`` (not periodic within the data). Needs ``N >= 2 n + 1``."""
    P = np.asarray(P, dtype=float)
    N = P.shape[0]
    for n in range(1, n_max + 1):
        if N < 2 * n + 1:
            return None
        if np.max(np.abs(P[n:] - P[:-n])) <= rtol:
            return n
    return None


def distinct_points(P: np.ndarray, tol: float = 1e-3) -> np.ndarray:
    """Greedy clustering: representatives of the groups of points closer than ``tol``
    (inf-norm) to their first member; returns their coordinates ``(n_clusters, d)``."""
    P = np.asarray(P, dtype=float)
    centers: list[np.ndarray] = []
    for p in P:
        if not any(np.max(np.abs(p - c)) <= tol for c in centers):
            centers.append(p)
            if len(centers) > 1000:
                break
    return np.array(centers).reshape(-1, P.shape[1])


def closed_curve_test(P: np.ndarray, max_roughness: float = 0.1,
                      max_gap_fraction: float = 0.25) -> dict[str, float | bool]:
    """Do the points lie on a smooth closed curve around their centroid?

    Projects on the two principal axes, orders the points by angle about the centroid
    and measures the radial ``roughness = median |r_{i+1} - r_i| / median r`` (small on
    a smooth curve, O(0.3) for a cloud) and the largest angular gap over ``2 pi`` (a
    closed curve is visited all round). Assumes the curve winds once around its
    centroid, as an invariant circle born at a secondary Hopf (Neimark-Sacker) does.
    """
    P = np.asarray(P, dtype=float)
    if P.shape[0] < 12:
        return {"roughness": math.nan, "max_gap_fraction": math.nan, "passed": False}
    X = P - P.mean(axis=0)
    _, s, vt = np.linalg.svd(X, full_matrices=False)
    if s[0] == 0.0:
        return {"roughness": 0.0, "max_gap_fraction": 1.0, "passed": False}
    Y = X @ vt[:2].T if vt.shape[0] >= 2 else np.column_stack([X @ vt[0], np.zeros(len(X))])
    Y = Y / np.where(Y.std(axis=0) > 0, Y.std(axis=0), 1.0)
    ang = np.arctan2(Y[:, 1], Y[:, 0])
    order = np.argsort(ang)
    r = np.hypot(Y[order, 0], Y[order, 1])
    dr = np.abs(np.diff(np.append(r, r[0])))
    rough = float(np.median(dr) / max(np.median(r), 1e-300))
    a = np.sort(ang)
    gaps = np.diff(np.append(a, a[0] + 2.0 * math.pi))
    gap = float(gaps.max() / (2.0 * math.pi))
    return {"roughness": rough, "max_gap_fraction": gap,
            "passed": bool(rough <= max_roughness and gap <= max_gap_fraction)}


def correlation_dimension(P: np.ndarray, quantiles: tuple[float, float] = (0.02, 0.2),
                          ) -> float:
    """Grassberger-Procaccia estimate: slope of ``log C(r)`` against ``log r`` between
    the given quantiles of the pair distances (``C`` the fraction of pairs closer than
    ``r``). About 1 for points on a curve, 0 for a finite set, larger for a cloud."""
    P = np.asarray(P, dtype=float)
    if P.shape[0] < 10:
        return math.nan
    d = np.sort(pdist(P))
    d = d[d > 0.0]
    if d.size < 10:
        return 0.0
    r = np.quantile(d, np.linspace(quantiles[0], quantiles[1], 12))
    C = np.searchsorted(d, r, side="right") / d.size
    ok = (r > 0) & (C > 0)
    if ok.sum() < 3 or np.ptp(np.log(r[ok])) == 0.0:
        return 0.0
    return float(np.polyfit(np.log(r[ok]), np.log(C[ok]), 1)[0])


def converging_period(P: np.ndarray, n: int, rtol: float = 1e-3,
                      decay: float = 0.7) -> tuple[int, float] | None:
    """A divisor ``m < n`` of a period-n section that the points are still *converging*
    to, with the shrink factor per period: the differences ``d_k = max |P[k+m] - P[k]|``
    (normalised points; the largest in the first and in the last quarter of the window)
    fall by more than ``decay`` and start above ``rtol``. A period-1 orbit whose slowest
    multiplier is complex, ``|mu| ~ 1`` at an angle near ``2 pi / n``, spirals in and passes
    the period-n
    test (``d`` over n periods is ``|mu^n - 1|`` times the spiral's size); a true
    period-n orbit keeps ``d`` constant. None: no such divisor."""
    P = np.asarray(P, dtype=float)
    N = P.shape[0]
    for m in range(1, n):
        if n % m or N < 4 * m + 8:
            continue
        d = np.max(np.abs(P[m:] - P[:-m]), axis=1)
        q = max(2, d.size // 4)
        first, last = float(np.max(d[:q])), float(np.max(d[-q:]))
        if first > rtol and last < decay * first:
            per = (last / first) ** (1.0 / (d.size - q)) if last > 0.0 else 0.0
            return m, float(per)
    return None


def steady_drift(P: np.ndarray, n: int, n_distinct: int, decay: float = 0.7
                 ) -> float | None:
    """``max |P[k+n] - P[k]|`` of a section that passes the period-n test but has more
    than n distinct points while that difference does not shrink through the window
    (largest in the last quarter at least ``decay`` times that in the first): the points
    move on steadily (a torus near a 1/n resonance), not settling. None otherwise (settled,
    or settling: a transient into the period-n orbit)."""
    P = np.asarray(P, dtype=float)
    if n_distinct <= n or P.shape[0] < 4 * n + 8:
        return None
    d = np.max(np.abs(P[n:] - P[:-n]), axis=1)
    q = max(2, d.size // 4)
    first, last = float(np.max(d[:q])), float(np.max(d[-q:]))
    if last > 0.0 and last >= decay * first:
        return float(np.max(d))
    return None
