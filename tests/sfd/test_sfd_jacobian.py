"""Exact Jacobian against central finite differences (relative 1e-6)."""

from __future__ import annotations

import numpy as np
import pytest
from sfd_helpers import MODELS, C, paper_sfd, random_states


def fd_jacobian(sfd, y, z, vy, vz, hq, hv):
    """Central differences of the vectorised force, 4th order (Richardson)."""
    def deriv(k, h):
        out = []
        for step in (h, 2 * h):
            args_p = [y, z, vy, vz]
            args_m = [y, z, vy, vz]
            args_p[k] = args_p[k] + step
            args_m[k] = args_m[k] - step
            out.append((np.array(sfd.force(*args_p)) - np.array(sfd.force(*args_m)))
                       / (2 * step))
        return (4 * out[0] - out[1]) / 3  # (2,) + shape
    dq = np.stack([deriv(0, hq), deriv(1, hq)], axis=-1)  # (2, n, 2)
    dv = np.stack([deriv(2, hv), deriv(3, hv)], axis=-1)
    return np.moveaxis(dq, 0, -2), np.moveaxis(dv, 0, -2)


@pytest.mark.parametrize("eps_range", [(0.0, 0.5), (0.5, 0.95)])
@pytest.mark.parametrize("model", MODELS)
def test_jacobian_vs_finite_differences(model: str, eps_range) -> None:
    sfd = paper_sfd(model)
    lo = max(eps_range[0], 0.02) if model == "pi" else eps_range[0]  # pi: kink at eps = 0
    y, z, vy, vz = random_states(300, 21, lo, eps_range[1])
    dq, dv = sfd.jacobian(y, z, vy, vz)
    eps = np.hypot(y, z) / C
    hq = 1e-4 * C * np.minimum(1 - eps, np.maximum(eps, 0.02) if model == "pi" else 1.0)
    hv = 1e-4 * np.hypot(vy, vz)
    fq, fv = fd_jacobian(sfd, y, z, vy, vz, hq, hv)
    for exact, approx in ((dq, fq), (dv, fv)):
        scale = np.abs(exact).max(axis=(-2, -1), keepdims=True)
        np.testing.assert_allclose(exact / scale, approx / scale, atol=1e-6)


def test_pi_film_jacobian_is_not_symmetric() -> None:
    """The pi film's ends turn with psi: an edge term (6+2eps^2)/(1-eps^2)^3 v_r e_r e_t^T."""
    sfd = paper_sfd("pi")
    dq, _ = sfd.jacobian(0.3 * C, 0.0, 0.1, 0.0)  # psi = 0, pure radial squeeze
    K = sfd.coefficient
    edge = K / C * (6 + 2 * 0.09) / (1 - 0.09) ** 3 * 0.1
    sym = 0.5 * (dq[0, 1] + dq[1, 0])
    assert dq[0, 1] - sym == pytest.approx(0.5 * edge, rel=1e-12)
