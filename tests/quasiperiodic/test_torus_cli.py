"""`rotorsfd response` continuing a torus in another parameter than the speed (issue 19
item 2): the base frequency w_b, a base law's amplitude and the unbalance, at a fixed
speed, given as ``analysis.response.parameter`` (config paths, as for periodic branches).

Each branch's last point is checked against the torus solved alone (rotorsfd.quasiperiodic,
continued in the speed) for the config with that parameter value written into it: an
independent route (the branch's problem is the degree-4 interpolation of
torus_base_parameters, or the unbalance scaling; the reference is built directly).
Bad parameters exit 2 with one line naming the field."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd.cli import main
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_system

PITCHING = ('pitching = { law = "harmonic", frequency = "120 rad/s", '
            'angle_amplitude = "0.01 rad" }')
C = 1.27e-4
SPEED = 480.0            # speed_ratio 0.6 of the 800 rad/s reference


def run(tmp_path, *settings: str) -> tuple[int, str]:
    """Exit status of ``rotorsfd response`` on the small rotor under harmonic pitching at
    Omega~ 0.6 with ``settings``, and the config's path."""
    config = small_rotor_toml(tmp_path / "small.toml", base=PITCHING)
    args = ["response", str(config), "-o", str(tmp_path / "out"), "-q"]
    for s in ("analysis.response.speed_ratio=0.6", "analysis.response.harmonics=2",
              "analysis.response.tolerance=1e-10", "analysis.stability.enabled=false",
              "analysis.response.step_max=0.3", *settings):
        args += ["--set", s]
    return main(args), str(config)


@pytest.mark.parametrize(("parameter", "values", "column", "last", "direct"), [
    ("base.pitching.frequency", '["110 rad/s", "125 rad/s"]',
     "base_pitching_frequency_rad_s", 125.0, "base.pitching.frequency=125 rad/s"),
    ("base.pitching.angle_amplitude", '["0.005 rad", "0.012 rad"]',
     "base_pitching_angle_amplitude_rad", 0.012, "base.pitching.angle_amplitude=0.012 rad"),
    ("unbalance[0].magnitude", '["30 g*mm", "60 g*mm"]', "unbalance_0_magnitude_kg_m",
     60e-6, "unbalance[0].magnitude=60 g*mm"),
])
def test_torus_branch_in_a_parameter(tmp_path, capsys, parameter, values, column, last,
                                     direct):
    """The command continues the torus from the first to the last value (exit 0, the
    parameter's column in SI); the journal's 1X and 1 w_b lines at the last point equal
    the torus solved alone for the config at that value (1e-9 C)."""
    from rotorsfd.quasiperiodic import TorusLattice, solve_torus, torus_problem

    status, config = run(tmp_path, f"analysis.response.parameter={parameter}",
                            f"analysis.response.parameter_range={values}")
    err = capsys.readouterr().err
    assert status == 0, err
    with (tmp_path / "out" / "torus.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    lam = np.array([float(r[column]) for r in rows])
    assert lam[-1] == pytest.approx(last, rel=1e-12) and np.all(np.diff(lam) > 0)
    assert all(float(r["speed_rad_s"]) == pytest.approx(SPEED, rel=1e-12) for r in rows)
    wb = float(rows[-1]["base_frequency_rad_s"])
    assert wb == pytest.approx(last if parameter.endswith("frequency") else 120.0, rel=1e-12)

    system = build_system(load_config(config, [direct]))
    lat = TorusLattice(2, 2)
    alone = solve_torus(torus_problem(system), SPEED, lat, tol=1e-10)
    for k1, k2 in ((1, 0), (0, 1)):
        ref = abs(alone.X[lat.index(k1, k2), 0]) / C
        assert ref > 1e-3                                   # a real line
        assert abs(float(rows[-1][f"amp_1_y_{k1}_{k2}"]) - ref) < 1e-9


@pytest.mark.parametrize(("settings", "words"), [
    (["analysis.response.parameter=base.pitching.value",
      'analysis.response.parameter_range=["0 rad/s", "1 rad/s"]'],
     ["analysis.response.parameter", "base.pitching.value", "base.<law>.frequency"]),
    (["analysis.response.parameter=base.rolling.frequency",
      'analysis.response.parameter_range=["100 rad/s", "120 rad/s"]'],
     ["analysis.response.parameter", "base.rolling", "'off'"]),
    (["analysis.response.parameter=base.pitching.frequency",
      'analysis.response.parameter_range=["0 rad/s", "120 rad/s"]'],
     ["analysis.response.parameter_range", "> 0"]),
])
def test_bad_torus_parameter_is_one_line(tmp_path, capsys, settings, words):
    """A parameter the torus cannot be continued in, a law that is not harmonic, a base
    frequency range reaching 0: exit 2, one line naming the field and what is allowed,
    before any work (no output folder content)."""
    status, _ = run(tmp_path, *settings)
    err = capsys.readouterr().err.strip()
    assert status == 2, err
    assert len(err.splitlines()) == 1, err
    for w in words:
        assert w in err, err
    assert not (tmp_path / "out" / "torus.csv").exists()
