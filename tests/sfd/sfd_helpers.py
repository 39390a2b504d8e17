"""Shared SFD test helpers: the paper's damper (C = 0.127 mm, C/R = 0.485 %, L/D = 0.325)."""

from __future__ import annotations

import numpy as np

from rotorsfd.sfd import SFD

MU, C, CR, LD = 0.0051, 1.27e-4, 0.00485, 0.325
MODELS = ("pi", "none", "guembel")


def paper_sfd(cavitation: str = "pi") -> SFD:
    return SFD.from_ratios(MU, C, CR, LD, cavitation=cavitation)


def random_states(n: int, seed: int, eps_lo: float = 0.0, eps_hi: float = 0.95,
                  speed: float = 300.0) -> tuple[np.ndarray, ...]:
    """(y, z, vy, vz) with eps uniform in [eps_lo, eps_hi] and velocities ~ speed * C."""
    rng = np.random.default_rng(seed)
    eps = rng.uniform(eps_lo, eps_hi, n)
    psi = rng.uniform(-np.pi, np.pi, n)
    v = rng.normal(size=(2, n)) * speed * C
    return eps * C * np.cos(psi), eps * C * np.sin(psi), v[0], v[1]
