"""Critical speeds against the speed of either spool (issue 20 item 2, first part): the
``SpoolSpeed`` view of a multi-shaft rotor. Independent check: two uncoupled shafts, whose
critical speeds are those of each shaft alone with its own excitation line."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.linear.critical import critical_speeds
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.multishaft import MultiShaftRotor, Shaft, SpoolSpeed

STEEL = Material(7850.0, 2.1e11, 8.1e10)
R = 1.7
RANGE = (0.0, 3000.0)


def _parts() -> tuple[dict, dict]:
    lp = dict(elements=uniform_shaft(1.2, 6, 0.0, 0.02, STEEL),
              disks=(Disk(4, 8.0, 0.09, 0.05),),
              supports=(LinearSupport.isotropic(1, 2e7), LinearSupport.isotropic(7, 2e7)))
    hp = dict(elements=uniform_shaft(0.5, 4, 0.03, 0.045, STEEL),
              disks=(Disk(10, 15.0, 0.25, 0.14),),
              supports=(LinearSupport.isotropic(8, 5e6), LinearSupport.isotropic(12, 4e6)))
    return lp, hp


def _alone(parts: dict, offset: int) -> Rotor:
    return Rotor(parts["elements"],
                 [Disk(d.node - offset, d.mass, d.polar_inertia, d.diametral_inertia)
                  for d in parts["disks"]],
                 supports=[LinearSupport(s.node - offset, s.kyy, s.kzz) for s in parts["supports"]])


def _speeds(system, harmonic: float, n: int = 3) -> np.ndarray:
    return np.array([c.speed_rad_s for c in critical_speeds(
        system, n=n, harmonic=harmonic, speed_range=RANGE, n_grid=25, xtol=1e-11)])


def test_critical_speeds_against_the_hp_speed_are_each_shafts_own() -> None:
    lp, hp = _parts()
    ms = MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", speed_ratio=R, **hp)])
    view = SpoolSpeed(ms, "hp")
    assert view.harmonic("hp") == 1.0 and view.harmonic("lp") == pytest.approx(1 / R)
    # HP unbalance line w = Omega_hp: the HP modes cross it at the HP shaft's own critical
    # speeds; the LP modes (at Omega_hp / R) cross it where the LP shaft alone meets
    # w = R Omega_lp
    found = _speeds(view, view.harmonic("hp"))
    hp_own = _speeds(_alone(hp, 7), 1.0)
    lp_own = R * _speeds(_alone(lp, 0), R)
    ref = np.sort(np.concatenate([hp_own, lp_own]))[:3]
    assert hp_own.size and lp_own.size
    np.testing.assert_allclose(found, ref, rtol=1e-8)
    # the LP unbalance line against the HP speed: w = Omega_hp / R
    found_lp = _speeds(view, view.harmonic("lp"), n=2)
    ref_lp = np.sort(np.concatenate([_speeds(_alone(hp, 7), 1 / R, 2),
                                     R * _speeds(_alone(lp, 0), 1.0, 2)]))[:2]
    np.testing.assert_allclose(found_lp, ref_lp, rtol=1e-8)


def test_either_spool_gives_the_same_criticals() -> None:
    lp, hp = _parts()
    ms = MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", speed_ratio=R, **hp)])
    on_hp = _speeds(SpoolSpeed(ms, "hp"), 1.0, 2)
    on_lp = _speeds(SpoolSpeed(ms, 0), R, 2)       # the same line, w = R Omega_lp
    np.testing.assert_allclose(on_hp, R * on_lp, rtol=1e-8)
    with pytest.raises(ConfigError, match="must name a shaft"):
        SpoolSpeed(ms, "ip")


def test_campbell_against_the_hp_speed_is_each_shafts_own() -> None:
    """The Campbell diagram of the view: at every HP speed the frequencies are the HP
    shaft's at that speed and the LP shaft's at HP speed / R."""
    from rotorsfd.linear.campbell import campbell

    lp, hp = _parts()
    ms = MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", speed_ratio=R, **hp)])
    speeds = np.array([0.0, 900.0, 2400.0])
    res = campbell(SpoolSpeed(ms, "hp"), speeds, n_modes=6)
    for k, s in enumerate(speeds):
        own = np.concatenate([np.asarray(campbell(_alone(hp, 7), [s], n_modes=6)
                                         .eigenvalues)[0],
                              np.asarray(campbell(_alone(lp, 0), [s / R], n_modes=6)
                                         .eigenvalues)[0]])
        lam = np.asarray(res.eigenvalues)[k]
        for x in lam:
            assert np.min(np.abs(own - x)) < 1e-9 * abs(x)
    assert res.frequencies[2].max() > res.frequencies[0].max()   # forward branches stiffen
