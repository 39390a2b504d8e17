"""Recorded base motion and shock pulses (model/recorded_motion.py): the laws against their
closed forms and differences, the recorded law against the analytic law it samples, and
both through the time integrator against an independent scipy integration."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid, solve_ivp

from rotors import linear_rotor_toml, small_rotor_toml
from rotorsfd import api
from rotorsfd.errors import ConfigError
from rotorsfd.model.base_motion import BaseMotion, Harmonic
from rotorsfd.model.recorded_motion import PulseLaw, RecordedLaw


@pytest.mark.parametrize("shape", ["half_sine", "versine"])
def test_pulse_integrals_are_consistent(shape):
    """f'' = the pulse, f' and f its integrals: central differences of the closed forms and
    the cumulative quadrature of the pulse agree (1e-7 relative); the velocity change is
    2 A T / pi (half-sine) or A T / 2 (versine)."""
    A, T, t0 = 50.0, 0.011, 0.004
    law = PulseLaw(shape, A, T, t0, order=2)
    t = np.linspace(0.0, 0.03, 30001)
    a, v, x = law.d2(t), law.d1(t), law.value(t)
    assert a.max() == pytest.approx(A, rel=1e-6)
    np.testing.assert_allclose(v, cumulative_trapezoid(a, t, initial=0.0), atol=1e-7 * A * T)
    np.testing.assert_allclose(x, cumulative_trapezoid(v, t, initial=0.0),
                               atol=1e-7 * A * T * 0.03)
    dv = {"half_sine": 2 * A * T / np.pi, "versine": A * T / 2}[shape]
    assert v[-1] == pytest.approx(dv, rel=1e-12)
    assert x[-1] - x[-2] == pytest.approx(dv * (t[1] - t[0]), rel=1e-9)   # linear after it
    rate = PulseLaw(shape, A, T, t0, order=0)                 # a rate pulse: w and w'
    h = 1e-7
    tm = np.array([t0 + 0.3 * T, t0 + 0.7 * T])
    np.testing.assert_allclose(rate.d1(tm), (rate.value(tm + h) - rate.value(tm - h)) / (2 * h),
                               rtol=1e-6)


def test_recorded_acceleration_is_integrated_from_rest():
    """An accelerometer record a = A sin(w t) (sampled at 400 points): the law's velocity
    and displacement are A/w (1 - cos w t) and A/w (t - sin(w t)/w) (from rest, 1e-6
    relative to their scale); the spline passes through the samples."""
    A, w = 3.0, 40.0
    t = np.linspace(0.0, 0.5, 400)
    law = RecordedLaw(t, A * np.sin(w * t), order=2)
    tt = np.linspace(0.0, 0.5, 1777)
    v_ref = A / w * (1 - np.cos(w * tt))
    x_ref = A / w * (tt - np.sin(w * tt) / w)
    np.testing.assert_allclose(law.d2(t), A * np.sin(w * t), atol=1e-12)
    assert np.max(np.abs(law.d1(tt) - v_ref)) < 1e-6 * np.max(np.abs(v_ref))
    assert np.max(np.abs(law.value(tt) - x_ref)) < 1e-6 * np.max(np.abs(x_ref))
    # outside the record: held, derivatives zero
    assert law.d2(np.array([0.6]))[0] == 0.0 and law.d1(np.array([0.6]))[0] == 0.0


def test_recorded_angle_gives_the_rate():
    """An angle record theta = A0 sin(w t) gives the rate A0 w cos(w t) and its
    derivative (1e-5 relative to their scales)."""
    A0, w = 0.05, 6.0
    t = np.linspace(0.0, 2.0, 500)
    law = RecordedLaw(t, A0 * np.sin(w * t), order=-1)
    tt = np.linspace(0.01, 1.99, 999)
    assert np.max(np.abs(law.value(tt) - A0 * w * np.cos(w * tt))) < 1e-5 * A0 * w
    assert np.max(np.abs(law.d1(tt) + A0 * w**2 * np.sin(w * tt))) < 1e-3 * A0 * w**2


def test_filter_makes_a_noisy_displacement_differentiable():
    """A displacement record with 1e-4 relative noise: twice differentiated through the
    spline the acceleration is off by far more than its size; with a 4th-order zero-phase
    low-pass at 5 w the error is below 2 % of the acceleration amplitude."""
    rng = np.random.default_rng(4)
    X, w = 1e-3, 30.0
    t = np.linspace(0.0, 1.0, 4001)
    x = X * np.sin(w * t) + 1e-4 * X * rng.standard_normal(t.size)
    raw = RecordedLaw(t, x, order=0)
    smooth = RecordedLaw(t, x, order=0, cutoff=5 * w)
    tt = np.linspace(0.2, 0.8, 999)                     # away from the filter's ends
    a_ref = -X * w**2 * np.sin(w * tt)
    err_raw = np.max(np.abs(raw.d2(tt) - a_ref)) / (X * w**2)
    err_smooth = np.max(np.abs(smooth.d2(tt) - a_ref)) / (X * w**2)
    assert err_smooth < 0.02
    assert err_raw > 10 * err_smooth


def test_bad_records_are_refused():
    with pytest.raises(ConfigError, match="increasing"):
        RecordedLaw(np.array([0.0, 0.2, 0.1, 0.3]), np.zeros(4))
    with pytest.raises(ConfigError, match="at least 4"):
        RecordedLaw(np.array([0.0, 0.1]), np.zeros(2))
    with pytest.raises(ConfigError, match="Nyquist"):
        RecordedLaw(np.linspace(0, 1, 11), np.zeros(11), cutoff=1e6)
    with pytest.raises(ConfigError, match="duration"):
        PulseLaw("versine", 1.0, 0.0)


def _shock_config(tmp_path, base: str):
    return api.load_config(small_rotor_toml(tmp_path / "r.toml", unbalance="0 g*mm",
                                            base=base))


def test_config_table_and_pulse_laws(tmp_path):
    """[base] components with law = 'table' (CSV file, inline samples) and 'pulse' build
    the laws above; missing fields are one-line errors naming the field."""
    t = np.linspace(0.0, 1.0, 50)
    csv = tmp_path / "pitch.csv"
    np.savetxt(csv, np.c_[t, 0.2 * np.sin(3 * t)], delimiter=",", header="t [s], w [rad/s]")
    cfg = _shock_config(tmp_path, 'pitching = { law = "table", file = "pitch.csv", '
                                  'quantity = "rate" }\n'
                                  'z = { law = "pulse", shape = "half_sine", '
                                  'acceleration_amplitude = "20 g0", duration = "11 ms", '
                                  'start = "5 ms" }')
    motion = api.build_system(cfg, search_path=tmp_path).base
    st = motion.state(np.array([0.5, 0.0105]))
    assert st.w[1, 0] == pytest.approx(0.2 * np.sin(1.5), rel=1e-4)
    assert st.a0[2, 1] == pytest.approx(20 * 9.80665, rel=1e-9)      # the pulse's peak
    with pytest.raises(ConfigError, match="'20 g0'"):          # '20 g' is 20 grams
        _shock_config(tmp_path, 'z = { law = "pulse", shape = "versine", duration = "1 ms", '
                                'acceleration_amplitude = "20 g" }')
    for base, field in [('pitching = { law = "table", file = "pitch.csv" }', "quantity"),
                        ('z = { law = "pulse", shape = "versine", duration = "1 ms" }',
                         "acceleration_amplitude"),
                        ('z = { law = "table", times = [0, 1, 2, 3], quantity = "velocity" }',
                         "values")]:
        with pytest.raises(ConfigError, match=field):
            _shock_config(tmp_path, base)


@pytest.fixture(scope="module")
def linear_system(tmp_path_factory):
    """The small test rotor without its SFD (the reference below is solve_ivp of its own
    M, C, G, K)."""
    return linear_rotor_toml(tmp_path_factory.mktemp("shock") / "linear.toml")


def _run(cfg_path, base: str, speed: float, t_end: float, spp: int):
    from rotorsfd.analyses.runup import run_speed_law
    from rotorsfd.timedomain.speed_law import ConstantSpeed

    text = cfg_path.read_text().replace("[base]\n", f"[base]\n{base}\n")
    p = cfg_path.with_name("run.toml")
    p.write_text(text)
    system = api.build_system(api.load_config(p))
    return system, run_speed_law(system, ConstantSpeed(speed), t_end, steps_per_period=spp,
                                 record_dofs=range(system.n_dof))


def test_shock_response_matches_solve_ivp(linear_system):
    """A versine base shock (z, 30 g over 4 ms) on the linear rotor at 600 rad/s: Newmark
    against DOP853 of M q'' + (C + W G) q' + K q = -M r a_z(t) (r the rigid
    z-translation): second order in the step (error ratio ~4 from T/400 to T/800), within
    1e-3 of the peak at T/800."""
    speed, t_end = 600.0, 0.03
    base = ('z = { law = "pulse", shape = "versine", acceleration_amplitude = "30 g0", '
            'duration = "4 ms", start = "2 ms" }')
    system, coarse = _run(linear_system, base, speed, t_end, 400)
    _, fine = _run(linear_system, base, speed, t_end, 800)
    r = system.rotor
    M, C, K, G = (np.asarray(x, float) for x in (r.M, r.C, r.K, r.G))
    rz = np.zeros(r.n_dof)
    rz[1::4] = 1.0                                       # z of every node
    law = PulseLaw("versine", 30 * 9.80665, 0.004, 0.002, order=2)
    Minv = np.linalg.inv(M)

    def rhs(t, x):
        q, v = np.split(x, 2)
        a = Minv @ (-M @ rz * float(law.d2(t)) - (C + speed * G) @ v - K @ q)
        return np.concatenate([v, a])

    sol = solve_ivp(rhs, (0.0, fine.t[-1]), np.zeros(2 * r.n_dof), method="DOP853",
                    rtol=1e-10, atol=1e-14, t_eval=fine.t, max_step=2e-4)
    ref = sol.y[: r.n_dof].T
    peak = np.max(np.abs(ref))
    assert peak > 1e-6
    err_f = np.max(np.abs(fine.q - ref))
    err_c = np.max(np.abs(coarse.q - ref[::2]))
    assert err_f < 1e-3 * peak
    assert 3.0 < err_c / err_f < 5.0, (err_c, err_f)


def test_recorded_pitching_equals_the_harmonic_law(linear_system):
    """The paper's harmonic pitching given as a recorded rate table (2001 samples over the
    run) gives the same response as the harmonic law (1e-5 of the orbit)."""
    speed, t_end = 600.0, 0.2
    t = np.linspace(0.0, 0.25, 2001)
    rate = Harmonic(amplitude=0.5, frequency=30.0)
    table = ", ".join(f"{x:.17g}" for x in t)
    vals = ", ".join(f"{x:.17g}" for x in rate.value(t))
    _, a = _run(linear_system, 'pitching = { law = "harmonic", amplitude = "0.5 rad/s", '
                'frequency = "30 rad/s" }', speed, t_end, 200)
    _, b = _run(linear_system, f'pitching = {{ law = "table", quantity = "rate", '
                f'times = [{table}], values = [{vals}] }}', speed, t_end, 200)
    scale = np.max(np.abs(a.q))
    assert scale > 0
    assert np.max(np.abs(a.q - b.q)) < 1e-5 * scale
    assert isinstance(BaseMotion(wy=rate), BaseMotion)
