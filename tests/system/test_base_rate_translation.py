"""Continuation in a base rate on a base that translates with a constant velocity v0
while it rotates: the origin acceleration a0 = v0' + w x v0 (``model.base_motion`` eq. 1)
follows the rate, so the problem continued in the rate must be, at every rate, the problem
of a system copy with that rate set (its base state from ``BaseMotion.state``: the
independent check), in both assemblies and through ``two_parameter_problem``; its rate
derivatives must be those of central differences of the problem in the rate. A rate that
takes w off inertial gravity (or rotates a uniformly accelerating base) makes the model
time-varying: refused before any work."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import cli
from rotorsfd.elements.sfd import SFDConfig
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import FullHB
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.base_motion import BaseMotion, UniformAcceleration
from rotorsfd.model.gravity import Gravity
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance

STEEL = Material(7810.0, 211e9, 81.783e9)
CLEARANCE = 0.127e-3
H, N = 3, 32
SPEED = 700.0
RATES = ("base.rolling", "base.pitching", "base.yawing")
VALUES = (-4.0, 0.5, 7.0)         # the rates the problems are compared at [rad/s]


def translating(gravity: Gravity | None = None) -> BaseMotion:
    """Constant velocity along x, y and z with rotation about every axis."""
    return BaseMotion(x0=UniformAcceleration(0.0, velocity=1.5),
                      y0=UniformAcceleration(0.0, velocity=-0.8, offset=0.01),
                      z0=UniformAcceleration(0.0, velocity=2.0),
                      wx=3.0, wy=-2.0, wz=1.5, gravity=gravity)


def system(base: BaseMotion, n_elements: int = 12) -> RotorSystem:
    """An SFD rotor: 12 elements (52 DOFs, the banded linear part) or 6 (dense)."""
    shaft = uniform_shaft(0.6, n_elements, 0.02, 0.03, STEEL)
    rotor = Rotor(shaft, disks=[Disk.from_geometry(n_elements // 2, 7810.0, 0.03, 0.1, 0.05)],
                  supports=[LinearSupport.isotropic(1, 5e6),
                            LinearSupport.isotropic(n_elements + 1, 1e7)])
    sfd = SFDConfig.model_validate({"node": 1, "viscosity": 0.0051, "radius": 0.0262,
                                    "length": 0.017, "clearance": CLEARANCE}).build("sfd")
    return RotorSystem(rotor, [sfd],
                       [Unbalance(n_elements // 2, 5e-6, 0.3), Unbalance(2, 2e-6, -1.0)],
                       base)


def unknowns(s: RotorSystem) -> np.ndarray:
    rng = np.random.default_rng(11)
    return 0.05 * CLEARANCE * rng.standard_normal((2 * H + 1, s.n_dof))


def rel(a, b) -> float:
    a, b = np.asarray(a), np.asarray(b)
    return float(np.abs(a - b).max() / np.abs(b).max())


def in_rate(s: RotorSystem, rate: str, how: str) -> PeriodicProblem:
    if how == "second":
        return s.two_parameter_problem(rate).second(SPEED)
    return s.periodic_problem(rate, SPEED, assembly=how)


@pytest.fixture(scope="module")
def rotors() -> dict[str, RotorSystem]:
    return {"band": system(translating(Gravity(frame="base"))),
            "dense": system(translating(), n_elements=6)}


def test_rate_moves_the_origin_acceleration(rotors) -> None:
    """The base load of a copy at another rate differs (a0 = w x v0 changes): the case
    is not trivial; BaseState.with_rate gives the copy's state."""
    s = rotors["band"]
    st = s.constant_base_state()
    for rate in RATES:
        copy = s.with_parameter(rate, 7.0).constant_base_state()
        mine = st.with_rate({"base.rolling": 0, "base.pitching": 1, "base.yawing": 2}[rate],
                            7.0)
        np.testing.assert_allclose(mine.a0, copy.a0, rtol=1e-15, atol=1e-15)
        np.testing.assert_array_equal(mine.w, copy.w)
        np.testing.assert_array_equal(mine.g, copy.g)
        assert np.abs(copy.a0 - st.a0).max() > 1.0     # m/s^2


@pytest.mark.parametrize("how", ["polynomial", "direct", "second"])
@pytest.mark.parametrize("rate", RATES)
@pytest.mark.parametrize("which", ["band", "dense"])
def test_problem_in_rate_equals_copy_with_rate(rotors, which: str, rate: str, how: str
                                               ) -> None:
    """At each rate: the linear part, the forcing (base load, unbalance) and the HB
    residual and Jacobian equal those of the copy with that rate, to 1e-12 relative."""
    s = rotors[which]
    problem = in_rate(s, rate, how)
    x = unknowns(s)
    for value in VALUES:
        copy = s.with_parameter(rate, value).periodic_problem("speed")
        for a, b in zip(problem.matrices(value), copy.matrices(SPEED), strict=True):
            assert rel(a, b) <= 1e-12
        F, Fc = problem.forcing(value, H), copy.forcing(SPEED, H)
        assert rel(F[0], Fc[0]) <= 1e-12        # the base load
        assert rel(F, Fc) <= 1e-12
        R, J, _ = FullHB(problem, H, N).residual(x, value)
        Rc, Jc, _ = FullHB(copy, H, N).residual(x, SPEED)
        assert rel(R, Rc) <= 1e-12
        assert rel(J, Jc) <= 1e-12


@pytest.mark.parametrize("how", ["polynomial", "direct", "second"])
@pytest.mark.parametrize("rate", RATES)
def test_rate_derivatives_equal_central_differences(rotors, rate: str, how: str) -> None:
    """dmatrices, dforcing (the base load's slope with d a0/dw = e x v0) and dR/drate
    against central differences of the problem in the rate (1e-6 relative; the linear
    part is quadratic in the rate, so the differences are exact to round-off)."""
    s = rotors["band"]
    problem = in_rate(s, rate, how)
    hb = FullHB(problem, H, N)
    x = unknowns(s)
    h = 0.25     # the stiffness ~1e8 N/m: a smaller step loses digits to round-off
    for value in VALUES:
        lo, hi = value - h, value + h
        for d, a, b in zip(problem.dmatrices(value), problem.matrices(hi),
                           problem.matrices(lo), strict=True):
            fd = (np.asarray(a) - np.asarray(b)) / (2 * h)
            if np.abs(fd).max() == 0.0:
                assert np.abs(d).max() == 0.0
            else:
                assert rel(d, fd) <= 1e-6
        dF = problem.dforcing(value, H)
        fd = (problem.forcing(hi, H) - problem.forcing(lo, H)) / (2 * h)
        assert rel(dF[0], fd[0]) <= 1e-6
        assert rel(dF, fd) <= 1e-6
        dR = hb.residual(x, value)[2]
        fd = (hb.residual(x, hi, jac=False)[0] - hb.residual(x, lo, jac=False)[0]) / (2 * h)
        assert rel(dR, fd.ravel()) <= 1e-6


def test_without_translation_the_load_slope_is_the_partial_one() -> None:
    """A rotating base without translation (the paper's): the rate's load slope is the
    one with a0 held, bit for bit (the extra part only where v0 != 0)."""
    s = system(BaseMotion(wy=2.0, wz=-1.0, gravity=Gravity(frame="base")))
    for how in ("polynomial", "direct"):
        p = s.periodic_problem("base.pitching", SPEED, assembly=how)
        copy = s.with_parameter("base.pitching", 5.0).periodic_problem("speed")
        assert rel(p.forcing(5.0, H)[0], copy.forcing(SPEED, H)[0]) <= 1e-12


# ---- refusals ---------------------------------------------------------------------------
@pytest.mark.parametrize("rate", ["base.rolling", "base.pitching"])
def test_rate_off_inertial_gravity_is_refused(rate: str) -> None:
    """Inertial gravity along -z: a rate about x or y turns g in the base frame
    (dg/dt = -w x g, period 2 pi / |w|): refused, naming the parameter and what is
    allowed; about z (w parallel to g) or with gravity fixed to the base: allowed."""
    s = system(BaseMotion(wz=2.0, gravity=Gravity()))
    for build in (lambda: s.periodic_problem(rate, SPEED),
                  lambda: s.periodic_problem(rate, SPEED, assembly="direct"),
                  lambda: s.two_parameter_problem(rate)):
        with pytest.raises(ConfigError) as err:
            build()
        assert err.value.field == "parameter" and err.value.value == rate
        assert "base.yawing" in err.value.allowed and "gravity.frame" in err.value.allowed
    s.periodic_problem("base.yawing", SPEED)
    s.two_parameter_problem("base.yawing")
    system(BaseMotion(wz=2.0, gravity=Gravity(frame="base"))).periodic_problem(rate, SPEED)


def test_rate_of_uniformly_accelerating_base_is_refused() -> None:
    """a0 = v0' + w x v0 with v0 = v + a t grows in time once the base rotates."""
    s = system(BaseMotion(y0=UniformAcceleration(2.0)))
    with pytest.raises(ConfigError, match=r"uniform acceleration of base\.y"):
        s.periodic_problem("base.pitching", SPEED)


def test_cli_refuses_rate_off_gravity_before_any_work(tmp_path: Path, capsys,
                                                      monkeypatch) -> None:
    """``rotorsfd response --set``: exit status 2, one line naming the parameter field,
    the rate and what is allowed, the continuation never reached."""
    def reached(*args, **kwargs):
        raise AssertionError("the continuation was reached")

    monkeypatch.setattr("rotorsfd.analyses.response.continue_periodic", reached)
    monkeypatch.setattr("rotorsfd.api.announce_compilation", lambda *a, **k: None)
    cfg = small_rotor_toml(tmp_path / "r.toml")
    out = tmp_path / "out"
    status = cli.main(["response", str(cfg), "-o", str(out),
                       "--set", "gravity.enabled=true",
                       "--set", "analysis.response.parameter=base.pitching.value",
                       "--set", "analysis.response.speed_ratio=0.9",
                       "--set", "analysis.response.parameter_range=['0 rad/s', '6 rad/s']"])
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert status == 2, err
    assert len(lines) == 1 and "Traceback" not in err, err
    line = lines[0]
    assert line.startswith(cli.PREFIX)
    assert "parameter: got 'base.pitching'" in line
    assert "gravity.frame = 'base'" in line and "base.yawing" in line
