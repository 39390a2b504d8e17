"""Generic pseudo arc-length continuation on algebraic curves."""

import numpy as np
import pytest

from rotorsfd.continuation import ArcLengthOptions, arclength, newton_extended, tangent
from rotorsfd.errors import JournalContactError


class SCurve:
    """x^3 - x + lam = 0: folds at x = +-1/sqrt(3) (lam = -+2/(3 sqrt 3))."""

    n = 1

    def __init__(self, x_min=-np.inf, contact_at=-np.inf):
        self.x_min, self.contact_at = x_min, contact_at

    def evaluate(self, z):
        x, lam = z
        if x <= self.contact_at:
            raise JournalContactError(abs(x), x, 0.0, 0.0, 0.0, "test")
        return np.array([x**3 - x + lam]), np.array([[3 * x**2 - 1, 1.0]])

    def admissible(self, z):
        return z[0] > self.x_min


def _start(system, lam):
    z0 = np.array([1.5, lam])
    e = np.array([0.0, 1.0])
    return newton_extended(system, z0, e, lam, tol=1e-12)


def _run(system, lam0=-2.0, lam1=2.0, **opts):
    res = _start(system, lam0)
    pts = []

    def on_point(z, t, J, it, ds):
        pts.append((z.copy(), t.copy(), it, ds))
        return False

    st = arclength(system, res.z, res.J, lam1, on_point, ArcLengthOptions(**opts))
    return st, pts


def test_both_folds_are_passed():
    st, pts = _run(SCurve(), max_angle=float(np.radians(15)), tol=1e-10)
    assert st.success, st.message
    z = np.array([p[0] for p in pts])
    t = np.array([p[1] for p in pts])
    assert np.abs(z[:, 0] ** 3 - z[:, 0] + z[:, 1]).max() < 1e-10
    sign = np.sign(t[:, 1])
    assert np.count_nonzero(sign[1:] != sign[:-1]) == 2          # two turning points
    assert z[-1, 1] == pytest.approx(2.0, abs=1e-12)
    assert z[-1, 0] == pytest.approx(-1.5213797068045676, abs=1e-9)  # other end
    ang = np.arccos(np.clip(np.sum(t[1:] * t[:-1], axis=1), -1, 1))
    assert ang.max() <= np.radians(15) + 1e-12
    ds = np.array([p[3] for p in pts[1:]])
    assert ds.max() <= 0.05 + 1e-15


def test_reverse_direction():
    res = newton_extended(SCurve(), np.array([-1.5, 2.0]), np.array([0.0, 1.0]), 2.0, 1e-12)
    pts = []
    st = arclength(SCurve(), res.z, res.J, -2.0,
                   lambda z, t, J, it, ds: pts.append(z) or False)
    assert st.success
    assert pts[-1][0] == pytest.approx(1.5213797068045676, abs=1e-9)


@pytest.mark.parametrize("system", [SCurve(x_min=-0.9), SCurve(contact_at=-0.9)])
def test_state_limit_stops_with_where_and_why(system):
    st, pts = _run(system)
    assert not st.success
    assert "lam=" in st.message
    assert ("limit" in st.message) or ("contact" in st.message)
    assert all(p[0][0] > -0.9 for p in pts)
    assert min(p[0][0] for p in pts) < -0.85


def test_callback_stop_and_max_points():
    res = _start(SCurve(), -2.0)
    st = arclength(SCurve(), res.z, res.J, 2.0, lambda z, t, J, it, ds: z[1] > -1.0)
    assert st.success and "callback" in st.message
    st = arclength(SCurve(), res.z, res.J, 2.0, lambda *a: False,
                   ArcLengthOptions(max_points=5))
    assert not st.success and "max_points" in st.message and st.n_points == 5


def test_tangent_orientation():
    J = np.array([[1.0, 1.0]])
    t = tangent(J, np.array([0.0, 1.0]))
    np.testing.assert_allclose(t, [-1 / np.sqrt(2), 1 / np.sqrt(2)])
    t = tangent(J, np.array([0.0, -1.0]))
    np.testing.assert_allclose(t, [1 / np.sqrt(2), -1 / np.sqrt(2)])


def test_newton_reports_divergence():
    r = newton_extended(SCurve(), np.array([0.0, 0.0]), np.array([0.0, 1.0]), 0.3,
                        tol=1e-14, max_iter=1)
    assert not r.converged and "iterations" in r.message


class CountingSCurve(SCurve):
    """SCurve counting its evaluations (the corrector's solves)."""

    def __init__(self):
        super().__init__()
        self.evaluations = 0

    def evaluate(self, z):
        self.evaluations += 1
        return super().evaluate(z)


def test_steps_aimed_below_the_angle_cap_take_fewer_solves_for_the_same_curve():
    # the cap rejects a converged step that turns the tangent by more than max_angle;
    # aiming the next step at 0.7 of the turn the last one took avoids most of those
    # (an option, off by default: ArcLengthOptions.angle_aim)
    runs = {}
    for aim in (0.7, np.inf):                       # inf: grow by 1.5 whatever the turn
        system = CountingSCurve()
        st, pts = _run(system, max_angle=float(np.radians(10)), tol=1e-10, ds_max=0.2,
                       angle_aim=aim)
        assert st.success, st.message
        z = np.array([p[0] for p in pts])
        assert np.abs(z[:, 0] ** 3 - z[:, 0] + z[:, 1]).max() < 1e-10   # on the curve
        assert z[-1, 0] == pytest.approx(-1.5213797068045676, abs=1e-9)
        runs[aim] = system.evaluations / len(pts)
    assert runs[0.7] < 0.9 * runs[np.inf]           # evaluations per accepted point
