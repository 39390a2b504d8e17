"""The intershaft SFD (issue 20 item 1): the single SFD's film on the relative state of two
nodes, +F on the journal and -F on the housing; kernel against numpy, Jacobians against
differences, and the HB residual Jacobian of a two-shaft system with it."""

from __future__ import annotations

import numpy as np
import pytest
from pydantic import ValidationError

from rotorsfd.elements.intershaft_sfd import IntershaftSFDConfig
from rotorsfd.elements.sfd import SFDConfig
from rotorsfd.harmonic.residual import FullHB
from rotorsfd.model import Disk, LinearSupport, Material, uniform_shaft
from rotorsfd.model.multishaft import MultiShaftRotor, Shaft
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance

FILM = dict(viscosity=0.02, clearance=2e-4, radius=0.04, length=0.015, offset_y=1e-5,
            offset_z=-2e-5)
C = FILM["clearance"]


def _states(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """n states (n, 4) whose relative eccentricity ratio is below 0.9."""
    d = rng.uniform(0.05, 0.9, n) * C
    th = rng.uniform(0, 2 * np.pi, n)
    qb = rng.normal(0.0, 3 * C, (n, 2))
    qa = qb + np.column_stack([d * np.cos(th), d * np.sin(th)]) + [FILM["offset_y"],
                                                                   FILM["offset_z"]]
    v = rng.normal(0.0, 0.05, (n, 4))
    return np.hstack([qa, qb]), v


@pytest.mark.parametrize("cavitation", ["pi", "none", "guembel"])
def test_force_is_the_single_sfd_on_the_relative_state(cavitation: str) -> None:
    e = IntershaftSFDConfig(node=3, outer_node=9, cavitation=cavitation, **FILM).build("i")
    single = SFDConfig(node=3, cavitation=cavitation, **FILM).build("s")
    assert e.dofs.tolist() == [8, 9, 32, 33] and e.nodes == (3, 9)
    q, v = _states(np.random.default_rng(1), 200)
    F, Jq, Jv = e.force_and_jacobian(q, v)
    f, jq, jv = single.force_and_jacobian(q[:, :2] - q[:, 2:], v[:, :2] - v[:, 2:])
    np.testing.assert_array_equal(F[:, :2], f)
    np.testing.assert_array_equal(F[:, 2:], -f)
    np.testing.assert_array_equal(Jq[:, :2, 2:], -jq)
    np.testing.assert_array_equal(Jv[:, 2:, 2:], jv)
    np.testing.assert_array_equal(e.force(q, v), F)
    assert e.limit(q) == pytest.approx(single.limit(q[:, :2] - q[:, 2:]), rel=1e-15)
    assert 0.8 < e.limit(q) < 0.9
    # the compiled kernel: the same numbers
    kernel, params = e.kernel, e.kernel_params
    for i in range(len(q)):
        Fk, Ak, Bk = np.zeros(4), np.zeros((4, 4)), np.zeros((4, 4))
        assert kernel(q[i].copy(), v[i].copy(), params, Fk, Ak, Bk) == 0
        np.testing.assert_allclose(Fk, F[i], rtol=1e-12, atol=1e-12 * np.abs(F[i]).max())
        np.testing.assert_allclose(Ak, Jq[i], rtol=1e-12, atol=1e-12 * np.abs(Jq[i]).max())
        np.testing.assert_allclose(Bk, Jv[i], rtol=1e-12, atol=1e-12 * np.abs(Jv[i]).max())
    # outside the film's domain: nonzero, outputs untouched
    bad = np.array([1.2 * C, 0.0, 0.0, 0.0])
    Fk = np.full(4, 7.0)
    assert kernel(bad, np.zeros(4), params, Fk, np.zeros((4, 4)), np.zeros((4, 4))) != 0
    assert np.all(Fk == 7.0)


def test_jacobians_against_central_differences() -> None:
    e = IntershaftSFDConfig(node=2, outer_node=6, **FILM).build("i")
    q, v = _states(np.random.default_rng(2), 20)
    _, Jq, Jv = e.force_and_jacobian(q, v)
    hq, hv = 1e-7 * C, 1e-6
    for k in range(4):
        dq = np.zeros(4)
        dq[k] = hq
        fd = (e.force(q + dq, v) - e.force(q - dq, v)) / (2 * hq)
        np.testing.assert_allclose(fd, Jq[:, :, k], rtol=1e-5, atol=1e-6 * np.abs(Jq).max())
        fd = (e.force(q, v + dq / hq * hv) - e.force(q, v - dq / hq * hv)) / (2 * hv)
        np.testing.assert_allclose(fd, Jv[:, :, k], rtol=1e-5, atol=1e-6 * np.abs(Jv).max())


def test_config_checks_and_centring_spring() -> None:
    with pytest.raises(ValidationError, match="another shaft"):
        IntershaftSFDConfig(node=3, outer_node=3, **FILM)
    with pytest.raises(ValidationError, match="short film only"):
        IntershaftSFDConfig(node=3, outer_node=8, film_length="finite", **FILM)
    t = IntershaftSFDConfig(node=3, outer_node=8, centring_stiffness="2e6 N/m", **FILM)
    assert t.linear_supports() == []
    (b,) = t.intershaft_bearings()
    assert (b.node, b.outer_node, b.kyy, b.kzz) == (3, 8, 2e6, 2e6)
    e = t.build("i").with_parameter("viscosity", 0.04)
    assert e.kind == "intershaft_sfd" and e.film.film.viscosity == 0.04


def _two_shaft_system() -> RotorSystem:
    steel = Material(7850.0, 2.1e11, 8.1e10)
    lp = Shaft("lp", uniform_shaft(1.0, 4, 0.0, 0.02, steel),
               disks=(Disk(2, 6.0, 0.05, 0.03),),
               supports=(LinearSupport.isotropic(1, 2e7, 200.0),
                         LinearSupport.isotropic(5, 2e7, 200.0)))
    hp = Shaft("hp", uniform_shaft(0.4, 3, 0.03, 0.045, steel), speed_ratio=1.6,
               x_start=0.4, disks=(Disk(7, 12.0, 0.2, 0.11),),
               supports=(LinearSupport.isotropic(6, 5e7, 400.0),))
    table = IntershaftSFDConfig(node=4, outer_node=9, centring_stiffness=3e6, **FILM)
    rotor = MultiShaftRotor([lp, hp], table.intershaft_bearings())
    return RotorSystem(rotor, [table.build("isfd")], [Unbalance(2, 1e-4, 0.0)])


def test_hb_residual_jacobian_of_a_two_shaft_system_against_differences() -> None:
    system = _two_shaft_system()
    p = system.periodic_problem("speed")
    H, N = 3, 32
    hb = FullHB(p, H, N)
    rng = np.random.default_rng(3)
    x = rng.normal(0.0, 0.15 * C, (2 * H + 1, p.n_dof))
    x[:, 2::4] = x[:, 3::4] = 0.0
    lam = 900.0
    _, J, dR = hb.residual(x.reshape(-1), lam)
    x = x.reshape(-1)
    scale = np.abs(J).max()
    cols = rng.choice(x.size, 25, replace=False)
    cols = np.union1d(cols, [k * p.n_dof + d for k in range(2 * H + 1)
                             for d in system.nl_dofs.tolist()])
    h = 1e-6 * C
    for c in cols:
        e = np.zeros_like(x)
        e[c] = h
        fd = (hb.residual(x + e, lam, jac=False)[0] - hb.residual(x - e, lam, jac=False)[0]
              ).reshape(-1) / (2 * h)
        np.testing.assert_allclose(fd, J[:, c], rtol=0, atol=1e-7 * scale)
    dl = 1e-3
    fd = (hb.residual(x, lam + dl, jac=False)[0] - hb.residual(x, lam - dl, jac=False)[0]
          ).reshape(-1) / (2 * dl)
    np.testing.assert_allclose(fd, dR, rtol=0, atol=1e-7 * np.abs(dR).max())
    assert np.abs(dR).max() > 0
