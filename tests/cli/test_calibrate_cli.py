"""`rotorsfd calibrate`: the command, its files, bad input (exit 2 before any work), and
fit-supports as a case of it."""

import json
import tomllib

import pytest

from rotors import two_support_rotor_text
from rotorsfd import api, cli
from rotorsfd.io.config import get_path

SMALL = two_support_rotor_text()
FIELD = "rotor.supports[1].stiffness"


@pytest.fixture()
def small(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    return path


def test_calibrate_writes_json_and_fitted_config(small, tmp_path, capsys):
    truth = api.run_modal(api.load_config(small, [f"{FIELD}=3e7"]))
    target = truth.critical_speeds[0].speed_rad_s
    out = tmp_path / "cal"
    argv = ["calibrate", str(small), "--fit", f"{FIELD}=1e6:1e9",
            "--target", f"critical_speed[1]={target!r}", "-o", str(out)]
    assert cli.main(argv) == 0
    printed = capsys.readouterr().out
    assert "critical_speed[1]" in printed and "exact (eigen-derivative)" in printed
    data = json.loads((out / "calibration.json").read_text())
    assert data["fields"][0]["value"] == pytest.approx(3e7, rel=1e-6)
    assert abs(data["targets"][0]["relative_residual"]) < 1e-9
    assert data["targets"][0]["sensitivities"][0] > 0
    assert data["covariance"] is None and data["success"] is True
    text = (out / "calibrated.toml").read_text()
    assert text.startswith("# rotorsfd calibrate, ") and FIELD in text.splitlines()[0]
    tomllib.loads(text)
    fitted = api.load_config(out / "calibrated.toml")
    assert get_path(fitted, FIELD) == pytest.approx(3e7, rel=1e-6)


def test_fit_supports_is_a_case_of_calibrate(small, tmp_path):
    """The same problem by `fit-supports` and by `calibrate`: the same stiffness."""
    crit = api.run_modal(api.load_config(small, [f"{FIELD}=2e7"])).critical_speeds
    target = repr(crit[0].speed_rad_s)
    assert cli.main(["fit-supports", str(small), "--field", FIELD, "--target", target,
                     "-o", str(tmp_path / "fs"), "--quiet"]) == 0
    assert cli.main(["calibrate", str(small), "--fit", FIELD, "--target",
                     f"critical_speed[1]={target}", "-o", str(tmp_path / "cal"),
                     "--quiet"]) == 0
    k_fs = json.loads((tmp_path / "fs" / "fit.json").read_text())["stiffnesses_N_per_m"][0]
    k_cal = json.loads((tmp_path / "cal" / "calibration.json").read_text())["fields"][0]
    assert k_cal["value"] == pytest.approx(k_fs, rel=1e-7)


@pytest.mark.parametrize("extra, words", [
    (["--fit", "rotor.supports[0].stiffness", "--fit", FIELD,
      "--target", "critical_speed[1]=700"], "more fields than targets"),
    (["--fit", "rotor.supports[9].stiffness", "--target", "critical_speed[1]=700"],
     "names no config field"),
    (["--fit", FIELD, "--target", "critical_speed[1]=7 mm"], "critical_speed[1]=7 mm"),
    (["--fit", FIELD, "--target", "speed[1]=700"], "kind must be one of"),
    (["--fit", f"{FIELD}=5:", "--target", "critical_speed[1]=700"], "--fit"),
])
def test_bad_input_exits_2_with_one_line(small, tmp_path, capsys, extra, words):
    out = tmp_path / "never"
    assert cli.main(["calibrate", str(small), *extra, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1
    assert not (out / "calibration.json").exists()
