"""Fresh starts of the bifurcation diagram's sweeps (the HB orbit, or the displaced state)
and sweeps that survive a failed speed.

Cases: the paper rotor with the smaller SFD (examples/paper_clearance.toml, C/R = 0.728 %,
U = 252 g mm, w_by = 10 rad/s, H = 8) over Omega~ 1.0 .. 1.11, where the 1 um displaced
start's transient reaches the clearance at the first speed (eps = 0.999 at period 12.5)
while the HB orbit's does not (eps 0.960); the small rotor of test_bifurcation_diagram
(U = 200 g mm) at Omega~ = 1.0, outside its fold interval, where both starts work.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses import bifurcation_diagram as bd
from rotorsfd.analyses import step_control
from rotorsfd.analyses.bifurcation_diagram import run_bifurcation_diagram
from rotorsfd.errors import ConfigError, ConvergenceError, JournalContactError

ROOT = Path(__file__).resolve().parents[2]
SWEEP = "analysis.bifurcation_diagram."
# these tests are about the starts: a fixed step T/200 (the step control has its own tests)
FIXED = "analysis.simulate.steps_per_period=200"
CLEARANCE = [FIXED, SWEEP + "speed_range.start_ratio=1.0", SWEEP + "speed_range.stop_ratio=1.11",
             SWEEP + "speed_range.n=3", SWEEP + "settle_periods=100",
             SWEEP + "record_periods=10", SWEEP + "direction=up"]
C_SMALL = 0.127e-3


@pytest.fixture(scope="module")
def clearance():
    return api.load_config(ROOT / "examples" / "paper_clearance.toml", CLEARANCE)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    path = small_rotor_toml(tmp_path_factory.mktemp("starts") / "small.toml",
                            unbalance="200 g*mm", reference="800 rad/s")
    return api.load_config(path, [FIXED, SWEEP + "speed_range.start_ratio=1.0",
                                  SWEEP + "speed_range.stop_ratio=1.3",
                                  SWEEP + "speed_range.n=3", SWEEP + "record_periods=20",
                                  SWEEP + "direction=up-down"])


def test_hb_start_avoids_the_contact_of_the_displaced_start(clearance, tmp_path):
    r = run_bifurcation_diagram(clearance, progress=False)
    assert r.success and not r.contacts, r.summary()
    assert [p.start for p in r.points] == ["hb", "previous", "previous"]
    assert r.points[0].max_eccentricity == pytest.approx(0.960, abs=0.01)
    assert "HB (H=8)" in r.settings["initial_state"]
    r.write(tmp_path, plots=False)
    with (tmp_path / "speeds.csv").open() as fh:
        assert [row["start"] for row in csv.DictReader(fh)] == ["hb", "previous",
                                                                "previous"]


def test_sweep_survives_a_contact_and_says_why(clearance, tmp_path):
    """Displaced start: contact at the first speed is recorded (where, eps, which start)
    and the sweep goes on from the HB orbit at the next speed instead of ending; the
    contact is a validity limit, a result (issue 22 item 3): ``ended = "limit"`` for that
    speed and the diagram, success (no numerical failure)."""
    r = run_bifurcation_diagram(clearance, progress=False, start_state="displaced")
    assert len(r.points) == 3 and r.success and r.ended == "limit"
    assert [p.ended for p in r.points] == ["limit", "range", "range"]
    first, second, third = r.points
    assert first.motion == "contact" and first.start == "displaced"
    assert "journal contact" in first.contact and "eps=0.999" in first.contact
    assert first.poincare_t.size == 0
    assert second.start == "hb" and second.contact is None and third.start == "previous"
    assert second.poincare_t.size == third.poincare_t.size == 10
    assert second.max_eccentricity < 0.999
    assert "the sweep goes on" in r.summary()
    r.write(tmp_path, plots=False)
    info = json.loads((tmp_path / "diagram.json").read_text())
    assert info["ended"] == "limit"
    assert info["contacts"] == [{"direction": "up", "speed_rad_s": first.speed,
                                 "start": "displaced", "ended": "limit",
                                 "message": first.contact}]
    with (tmp_path / "speeds.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [row["contact"] for row in rows] == ["1", "0", "0"]
    assert [row["ended"] for row in rows] == ["limit", "range", "range"]
    assert [row["start"] for row in rows] == ["displaced", "hb", "previous"]


def test_hb_start_gives_the_steady_state_of_a_long_displaced_run(small):
    """First speed Omega~ = 1.0 of the small rotor: 50 settling periods from the HB orbit
    land on the Poincare points of 1000 periods from the displaced start (measured
    2.6e-5 C; the displaced start after 50 periods is 2.2e-2 C away)."""
    def first(start: str, settle: int):
        r = run_bifurcation_diagram(small, progress=False, start_state=start,
                                    settle_periods=settle, direction="up", n=2)
        p = r.points[0]
        assert p.start == start and p.contact is None
        return p.poincare_q

    long = first("displaced", 1000)
    assert np.ptp(long[:, 0, 0]) < 1e-10 * C_SMALL             # settled
    assert np.max(np.abs(first("hb", 50) - long)) < 1e-4 * C_SMALL
    assert np.max(np.abs(first("displaced", 50) - long)) > 1e-2 * C_SMALL


def test_contact_in_the_middle_of_a_sweep(small, monkeypatch):
    """A failure at the middle speed of the up sweep: recorded, the next speed restarts
    from the HB orbit, the down sweep goes on from the up sweep's last state."""
    real = step_control.integrate_periods
    middle = 1.15 * 800.0
    calls = []

    def once(inputs, *args, **kwargs):
        # the speed's own run (settle + record periods), not its step check
        if abs(inputs.speed - middle) < 1e-9 * middle and kwargs.get("periods") == 120:
            calls.append(inputs.speed)
            if len(calls) == 1:
                raise JournalContactError(0.9991, 1e-4, 0.0, 0.0, 0.0, "t=0.01 s (test)")
        return real(inputs, *args, **kwargs)

    monkeypatch.setattr(step_control, "integrate_periods", once)
    r = run_bifurcation_diagram(small, progress=False, settle_periods=100)
    assert [(p.direction, p.start) for p in r.points] == [
        ("up", "hb"), ("up", "previous"), ("up", "hb"),
        ("down", "previous"), ("down", "previous"), ("down", "previous")]
    failed = r.points[1]
    assert failed.motion == "contact" and "eps=0.9991" in failed.contact
    assert [p.motion for p in r.points if p is not failed] == ["period-1"] * 5
    assert r.contacts == [failed] and len(calls) == 2


@pytest.mark.parametrize("error", [ConvergenceError("no HB solution (test)"),
                                   ConfigError("base", "harmonic", "constant base only")])
def test_falls_back_to_the_displaced_state_without_hb(small, monkeypatch, error):
    def no_hb(*args, **kwargs):
        raise error

    monkeypatch.setattr(bd, "hb_start", no_hb)
    r = run_bifurcation_diagram(small, progress=False, settle_periods=20, direction="up",
                                n=2)
    assert [p.start for p in r.points] == ["displaced", "previous"]
    assert any("no HB start" in n and "displaced 1e-06 m instead" in n for n in r.notes)


def test_unknown_start_rejected(small):
    with pytest.raises(ConfigError, match="start_state"):
        run_bifurcation_diagram(small, progress=False, start_state="orbit")


@pytest.mark.parametrize("error, status", [
    (JournalContactError(0.9991, 1e-4, 0.0, 0.0, 0.0, "t=0.01 s (test)"), 0),
    (ConvergenceError("time integration: Newton did not converge (test)"), 1)])
def test_cli_contact_is_a_result_a_numerical_failure_exit_1(tmp_path, monkeypatch, capsys,
                                                            error, status):
    """A speed that reaches the contact limit: a warning line naming the speed and the
    contact, exit 0, ``ended = limit`` in speeds.csv and diagram.json; a numerical failure
    of the time stepping: an error line and exit 1 (issue 22 item 3)."""
    from rotorsfd.cli import main

    real = step_control.integrate_periods

    def once(inputs, *args, **kwargs):
        if abs(inputs.speed - 800.0) < 1e-9 * 800.0 and kwargs.get("periods") == 30:
            raise error
        return real(inputs, *args, **kwargs)

    monkeypatch.setattr(step_control, "integrate_periods", once)
    path = small_rotor_toml(tmp_path / "small.toml", unbalance="200 g*mm",
                            reference="800 rad/s")
    out = tmp_path / "out"
    code = main(["bifurcation-diagram", str(path), "-o", str(out), "-q",
                 "--set", FIXED, "--set", SWEEP + "speed_range.start_ratio=1.0",
                 "--set", SWEEP + "speed_range.stop_ratio=1.1",
                 "--set", SWEEP + "speed_range.n=2", "--set", SWEEP + "direction=up",
                 "--set", SWEEP + "settle_periods=20", "--set", SWEEP + "record_periods=10"])
    err = [line for line in capsys.readouterr().err.splitlines()
           if line.startswith("rotorsfd:")]
    assert code == status
    ended = "limit" if status == 0 else "failed"
    head = "rotorsfd: warning: " if status == 0 else "rotorsfd: error: "
    assert len(err) == 1 and err[0].startswith(head) and "800 rad/s" in err[0], err
    with (out / "speeds.csv").open() as fh:
        assert [row["ended"] for row in csv.DictReader(fh)] == [ended, "range"]
    assert json.loads((out / "diagram.json").read_text())["ended"] == ended
