"""`rotorsfd fit-supports`: stiffness fields fitted to target critical speeds."""

import json

import pytest

from rotors import two_support_rotor_text
from rotorsfd import api, cli

SMALL = two_support_rotor_text()


def test_fit_recovers_known_stiffness(tmp_path, capsys):
    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    truth = api.run_modal(api.load_config(path, ["rotor.supports[1].stiffness=3e7"]))
    target = truth.critical_speeds[0].speed_rad_s
    argv = ["fit-supports", str(path), "--field", "rotor.supports[1].stiffness",
            "--target", f"{target!r}", "-o", str(tmp_path / "fit")]
    assert cli.main(argv) == 0
    out = capsys.readouterr().out
    assert "rotor.supports[1].stiffness = " in out and "reproduce: --set" in out
    data = json.loads((tmp_path / "fit" / "fit.json").read_text())
    assert data["stiffnesses_N_per_m"][0] == pytest.approx(3e7, rel=1e-5)
    assert data["exact"] is True


def test_fit_rejects_non_stiffness_field(tmp_path, capsys):
    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    argv = ["fit-supports", str(path), "--field", "rotor.shaft[0].outer_radius",
            "--target", "500"]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "must be a stiffness field" in err
