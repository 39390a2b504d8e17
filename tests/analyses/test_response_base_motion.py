"""Responses and linear consequences under constant base rotation: pitching and yawing
related by a quarter turn about the shaft axis (paper 4.1.3), continuation in the base
rate, the static offset, and the Campbell shift of constant rolling (modal)."""

from __future__ import annotations

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.linear import eigen
from rotorsfd.model.base_terms import base_static_deflection
from rotorsfd.model.dofs import dof_index
from rotorsfd.model.system import RotorSystem

RATE = "6 rad/s"


def _constant(component: str, rate: str = RATE) -> str:
    return f'{component} = {{ law = "constant", value = "{rate}" }}'


@pytest.fixture(scope="module")
def pitch_yaw(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pitchyaw")
    out = {}
    for comp in ("pitching", "yawing"):
        cfg = api.load_config(small_rotor_toml(tmp / f"{comp}.toml", base=_constant(comp)))
        out[comp] = api.run_response(cfg, progress=False)
    return out


def test_pitching_and_yawing_same_deflection(pitch_yaw):
    p, y = pitch_yaw["pitching"], pitch_yaw["yawing"]
    assert p.success and y.success
    assert p.branch.n_points == y.branch.n_points
    np.testing.assert_allclose(y.branch.lam, p.branch.lam, rtol=1e-9)
    tp, ty = p.table(), y.table()
    for n in (1, 3):
        np.testing.assert_allclose(ty[f"defl_{n}"], tp[f"defl_{n}"], rtol=1e-6)
        # quarter turn about x, (y, z)_yaw(t) = (-z, y)_pitch(t - T/4): the rotated
        # unbalance is the same force a quarter period later, so X_k gains (-i)^k
        Xp, Xy = p.branch.X, y.branch.X
        shift = (-1j) ** np.arange(Xp.shape[1])
        scale = np.abs(Xp[:, :, dof_index(n, "y")]).max()
        np.testing.assert_allclose(Xy[:, :, dof_index(n, "y")],
                                   -Xp[:, :, dof_index(n, "z")] * shift, atol=1e-6 * scale)
        np.testing.assert_allclose(Xy[:, :, dof_index(n, "z")],
                                   Xp[:, :, dof_index(n, "y")] * shift, atol=1e-6 * scale)
    # the pitching offset is along y at the SFD journal (gyroscopic moment about z)
    assert np.all(np.abs(tp["static_1_y"]) > 10 * np.abs(tp["static_1_z"]))


def test_continuation_in_pitching_rate(tmp_path):
    """parameter = base.pitching.value at fixed speed: first column is the rate; the end
    point is the periodic solution of the system with that constant rate."""
    cfg = api.load_config(small_rotor_toml(tmp_path / "p.toml"), [
        "analysis.response.parameter=base.pitching.value",
        "analysis.response.speed_ratio=0.9",
        "analysis.response.parameter_range=['0 rad/s', '6 rad/s']"])
    result = api.run_response(cfg, progress=False)
    assert result.success
    table = result.table()
    assert list(table)[:3] == ["base_pitching_value_rad_s", "speed_rad_s", "speed_ratio"]
    np.testing.assert_allclose(table["speed_rad_s"], 720.0, rtol=1e-15)
    assert table["base_pitching_value_rad_s"][-1] == pytest.approx(6.0, rel=1e-9)
    pitched = result.system.with_base_rate("base.pitching", 6.0)
    ref = solve_periodic(pitched.periodic_problem(), 720.0, 3, result.branch.X[-1])
    np.testing.assert_allclose(result.branch.X[-1], ref.X, atol=1e-6 * np.abs(ref.X).max())
    paths = result.write(tmp_path / "out", plots=True)
    header = paths["branch.csv"].read_text().splitlines()[0].split(",")
    assert header[0] == "base_pitching_value_rad_s"


def test_static_offset_matches_zero_unbalance_response(tmp_path):
    """Without unbalance the periodic solution is the static offset of the linear rotor
    (the film has no static stiffness): run_static == X_0 == (K + K_base)^-1 F_base."""
    cfg = api.load_config(small_rotor_toml(tmp_path / "s.toml", unbalance="0 g*mm",
                                           base=_constant("pitching")))
    result = api.run_response(cfg, progress=False)
    static = api.run_static(cfg, speeds=result.speeds)
    q = static.q
    np.testing.assert_allclose(result.branch.X[:, 0, :].real, q, atol=1e-9 * np.abs(q).max())
    system = result.system
    direct = base_static_deflection(system.rotor, system.constant_base_state(), 700.0)
    np.testing.assert_allclose(api.run_static(system, speeds=[700.0]).q[0], direct,
                               rtol=1e-12, atol=1e-12 * np.abs(direct).max())
    path = static.write(tmp_path / "out", plots=False)["static_deflection.csv"]
    lines = path.read_text().splitlines()
    assert lines[0] == "speed_rad_s,speed_ratio,node,x_m,y_m,z_m,ty_rad,tz_rad"
    assert len(lines) == 1 + result.branch.n_points * system.rotor.n_nodes


def test_rolling_shifts_campbell(tmp_path):
    """Isotropic undamped rotor under constant rolling w_bx: seen from the base frame,
    forward whirl at w_f(Omega + w_bx) - w_bx, backward at w_b(Omega + w_bx) + w_bx (the
    base frame turns with w_bx; the spin relative to inertia is Omega + w_bx). Checked on
    the modal system of `rotorsfd modal` (api.linear_system)."""
    wx = 30.0
    fixed_cfg = api.load_config(small_rotor_toml(tmp_path / "f.toml"))
    roll_cfg = api.load_config(small_rotor_toml(tmp_path / "r.toml",
                                                base=_constant("rolling", f"{wx} rad/s")))
    fixed, rolling = api.linear_system(fixed_cfg), api.linear_system(roll_cfg)
    m = api.build_model(roll_cfg)
    system = RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)
    for speed in (0.0, 400.0, 900.0):
        for a, b in zip(rolling.matrices(speed), system.matrices(speed), strict=True):
            np.testing.assert_array_equal(a, b)
        ef, er = eigen(fixed, speed + wx, 8), eigen(rolling, speed, 8)
        for whirl, shift in (("forward", -wx), ("backward", wx)):
            f = np.sort(ef.frequencies[ef.whirl == whirl])
            r = np.sort(er.frequencies[er.whirl == whirl])
            n = min(f.size, r.size, 3)
            assert n >= 2
            np.testing.assert_allclose(r[:n], f[:n] + shift, rtol=1e-9)
    camp_fixed = api.run_modal(api.with_values(fixed_cfg, {"analysis.modal.speeds": [0.0]}))
    camp_roll = api.run_modal(api.with_values(roll_cfg, {"analysis.modal.speeds": [0.0]}))
    assert not np.allclose(camp_roll.campbell.frequencies, camp_fixed.campbell.frequencies)
