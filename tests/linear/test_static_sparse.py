"""Static deflection of a large model by sparse LU equals the dense LU solve (1e-10) and
an unsupported rotor is reported singular on both paths."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.errors import ConvergenceError
from rotorsfd.linear.static import static_deflection
from rotorsfd.model import LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.model.system import RotorSystem

STEEL = Material(7810.0, 211e9, 81.783e9)


class Dense:
    """The system seen through ``matrices`` only (the dense path)."""

    def __init__(self, system: RotorSystem) -> None:
        self.system, self.n_dof = system, system.n_dof

    def matrices(self, speed: float):
        return self.system.matrices(speed)


def system(n_elements: int, supported: bool = True) -> RotorSystem:
    supports = [LinearSupport.isotropic(1, 2e7), LinearSupport(n_elements + 1, 3e7, 1e7)]
    rotor = Rotor(uniform_shaft(1.2, n_elements, 0.0, 0.03, STEEL),
                  supports=supports if supported else [])
    return RotorSystem(rotor)


def test_sparse_static_deflection_equals_dense() -> None:
    s = system(120)
    assert s.n_dof > DENSE_MAX_DOF
    f = np.zeros(s.n_dof)
    f[4 * 60] = 1e3           # y at mid-span
    f[4 * 30 + 1] = -5e2      # z at a quarter
    q = static_deflection(s, f)
    ref = static_deflection(Dense(s), f)
    assert np.abs(q - ref).max() <= 1e-10 * np.abs(ref).max()
    # a simply supported beam under a mid-span load: the load point deflects most
    assert np.argmax(np.abs(q[0::4])) == 60


def test_unsupported_rotor_is_singular_on_both_paths() -> None:
    s = system(120, supported=False)
    f = np.ones(s.n_dof)
    for view in (s, Dense(s)):
        with pytest.raises(ConvergenceError, match=r"singular|not factorisable"):
            static_deflection(view, f)
