"""Timing of the SFD force + Jacobian: one sample through the compiled kernel (from a
compiled caller and from Python), one sample and 4096 samples through the vectorised API.

Run: ``python benchmarks/bench_sfd.py``.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
from numba import njit

from rotorsfd.sfd import SFD


def best_of(fn: Callable[[], object], repeat: int = 7, number: int = 200) -> float:
    """Best mean time per call [s] over ``repeat`` runs of ``number`` calls."""
    fn()
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best


def main() -> None:
    C = 1.27e-4
    rng = np.random.default_rng(0)
    n = 4096
    eps = rng.uniform(0.0, 0.9, n)
    psi = rng.uniform(-np.pi, np.pi, n)
    y, z = eps * C * np.cos(psi), eps * C * np.sin(psi)
    vy, vz = rng.normal(size=(2, n)) * 300 * C
    print(f"{'model':8s} {'kernel in njit loop':>20s} {'kernel from Python':>19s} "
          f"{'API 1 sample':>13s} {'API 4096 samples':>17s} {'per sample':>11s}")
    for model in ("pi", "none", "guembel"):
        bench_model(model, y, z, vy, vz)


@njit
def _kernel_loop(kernel, q, v, params, F, dq, dv):  # type: ignore[no-untyped-def]
    s = 0
    for i in range(q.shape[0]):
        s += kernel(q[i], v[i], params, F, dq, dv)
    return s


def bench_model(model: str, y: np.ndarray, z: np.ndarray, vy: np.ndarray, vz: np.ndarray
                ) -> None:
    n = y.size
    sfd = SFD.from_ratios(0.0051, 1.27e-4, 0.00485, 0.325, cavitation=model)
    kernel, params = sfd.numba_kernel, sfd.kernel_params
    q2 = np.ascontiguousarray(np.stack([y, z], 1))
    v2 = np.ascontiguousarray(np.stack([vy, vz], 1))
    F, dq, dv = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
    t_loop = best_of(lambda: _kernel_loop(kernel, q2, v2, params, F, dq, dv), number=20) / n
    q1, v1 = q2[0].copy(), v2[0].copy()
    t_kernel = best_of(lambda: kernel(q1, v1, params, F, dq, dv), number=2000)
    t_one = best_of(lambda: sfd.force_and_jacobian(y[0], z[0], vy[0], vz[0]), number=2000)
    t_many = best_of(lambda: sfd.force_and_jacobian(y, z, vy, vz), number=50)
    print(f"{model:8s} {t_loop * 1e9:17.0f} ns {t_kernel * 1e6:16.2f} us "
          f"{t_one * 1e6:10.1f} us {t_many * 1e6:14.0f} us {t_many / n * 1e9:8.0f} ns")


if __name__ == "__main__":
    main()
