"""Campbell diagram (tracking, CSV, plot) and static deflection."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from linear_helpers import STEEL, pinned_pinned

from rotorsfd.errors import ConvergenceError
from rotorsfd.linear import campbell, eigen, static_deflection
from rotorsfd.model import LinearSupport, Rotor, uniform_shaft


@pytest.fixture(scope="module")
def camp(paper):
    return campbell(paper, np.linspace(0.0, 4000.0, 21), n_modes=6)


def test_tracking_follows_branches(camp, paper):
    f = camp.frequencies
    assert f.shape == (21, 6)
    # each branch keeps its whirl over the range (isotropic rotor) and moves smoothly
    for j in range(6):
        assert len(set(camp.whirl[1:, j])) == 1
        assert np.all(np.abs(np.diff(f[:, j])) < 0.08 * f[:, j].max())
    # gyroscopic stiffening/softening: forward branch of pair 2 rises, backward falls
    fwd = [j for j in range(6) if camp.whirl[-1, j] == "forward"]
    bwd = [j for j in range(6) if camp.whirl[-1, j] == "backward"]
    assert f[-1, fwd[1]] > f[0, fwd[1]] * 1.1 and f[-1, bwd[1]] < f[0, bwd[1]] * 0.9
    # values equal the untracked eigen solution at each speed (as a set)
    res = eigen(paper, 4000.0, 6)
    np.testing.assert_allclose(np.sort(f[-1]), res.frequencies, rtol=1e-10)


def test_campbell_csv(tmp_path, camp):
    path = camp.to_csv(tmp_path / "campbell.csv")
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["speed_rad_s", "mode", "whirl", "frequency_rad_s",
                             "damping_ratio", "log_decrement"]
    assert len(rows) == 21 * 6
    last = rows[-1]
    assert float(last["speed_rad_s"]) == 4000.0 and int(last["mode"]) == 6
    assert float(last["frequency_rad_s"]) == pytest.approx(camp.frequencies[-1, 5], rel=1e-15)
    assert last["whirl"] in ("forward", "backward")


def test_campbell_plot(camp):
    """The figure lives in plots/ (the solver returns data): whirls styled apart, 1X."""
    import matplotlib

    matplotlib.use("Agg")
    from rotorsfd.plots.campbell import campbell_figure

    ax = campbell_figure(camp.speeds, camp.frequencies, camp.whirl).axes[0]
    labels = [line.get_label() for line in ax.get_lines()]
    assert "forward whirl" in labels and "backward whirl" in labels
    assert any(label.startswith("1X") for label in labels)
    styles = {line.get_label(): line.get_linestyle() for line in ax.get_lines()}
    assert styles["forward whirl"] != styles["backward whirl"]


def test_static_deflection_pinned_timoshenko_beam():
    """Central load F on a pinned-pinned Timoshenko beam:
    w(L/2) = F L^3 / (48 EI) + F L / (4 kappa G A); the element is nodally exact."""
    length, f = 1.0, 1000.0
    shaft = uniform_shaft(length, 10, 0.03, 0.05, STEEL)
    rotor = Rotor(shaft)
    sys_ = pinned_pinned(rotor)
    force = np.zeros(rotor.n_dof)
    force[rotor.dof_index(6, "z")] = f
    q = sys_.expand(static_deflection(sys_, force[sys_.free]))
    el = shaft[0]
    ei = STEEL.young_modulus * el.second_moment
    kga = el.kappa * STEEL.shear_modulus * el.area
    w = f * length**3 / (48 * ei) + f * length / (4 * kga)
    assert q[rotor.dof_index(6, "z")] == pytest.approx(w, rel=1e-10)
    assert abs(q[rotor.dof_index(6, "y")]) < 1e-14
    # section rotation at the left end: psi = F L^2 / (16 EI) (bending only, in the
    # direction of +dz/dx for a load along +z), and ty = -psi
    assert q[rotor.dof_index(1, "ty")] == pytest.approx(-f * length**2 / (16 * ei), rel=1e-10)


def test_static_deflection_on_springs_and_singular():
    rotor = Rotor(uniform_shaft(1.0, 4, 0.0, 0.05, STEEL),
                  supports=[LinearSupport.isotropic(1, 1e6), LinearSupport.isotropic(5, 1e6)])
    force = np.zeros(rotor.n_dof)
    force[rotor.dof_index(1, "y")::4] = 10.0           # uniform 10 N on each node's y
    q = static_deflection(rotor, force)
    # nearly rigid shaft: each spring carries half of 50 N
    assert q[rotor.dof_index(1, "y")] == pytest.approx(25.0 / 1e6, rel=1e-3)
    with pytest.raises(ConvergenceError):
        static_deflection(Rotor(uniform_shaft(1.0, 4, 0.0, 0.05, STEEL)), force)
