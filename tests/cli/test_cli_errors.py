"""Bad input on the command line: exit status 2 and ONE line on stderr naming the field;
other rotorsfd errors: exit status 1, one line; never a traceback without --debug."""

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from rotorsfd import cli
from rotorsfd.errors import ConvergenceError

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"
TEXT = PAPER.read_text()


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def _variant(tmp_path, old, new):
    assert old in TEXT
    path = tmp_path / "bad.toml"
    path.write_text(TEXT.replace(old, new, 1))
    return str(path)


@pytest.mark.parametrize(("old", "new", "field", "value"), [
    # wrong type
    ("n_elements = 20", 'n_elements = "twenty"', "rotor.shaft[0].n_elements", "'twenty'"),
    # wrong dimension
    ('viscosity = "0.0051 Pa*s"', 'viscosity = "0.0051 kg"', "elements.sfd.viscosity",
     "'0.0051 kg'"),
    # out of range
    ('clearance = "0.127 mm"', 'clearance = "-0.127 mm"', "elements.sfd.clearance", "'-0.127 mm'"),
    # unknown key
    ('thickness = "50.8 mm"', 'thicknes = "50.8 mm"', "rotor.disks[0].thicknes", "'50.8 mm'"),
    # missing required
    ('viscosity = "0.0051 Pa*s"', "", "elements.sfd.viscosity", "nothing"),
    # bad node
    ("node = 21", "node = 22", "rotor.supports[0].node", "22"),
    # bad choice
    ('cavitation = "pi"', 'cavitation = "half"', "elements.sfd.cavitation", "'half'"),
])
def test_bad_config_exits_2_with_one_line(tmp_path, capsys, old, new, field, value):
    path = _variant(tmp_path, old, new)
    assert cli.main(["config", "show", path]) == 2
    captured = capsys.readouterr()
    line = _one_line(captured.err)
    assert line.startswith(f"rotorsfd: error: {field}: got {value};")
    assert captured.out == ""


def test_bad_config_subprocess(tmp_path):
    """The real console entry: exit 2, one line, no traceback."""
    path = _variant(tmp_path, "node = 21", "node = 99")
    proc = subprocess.run([sys.executable, "-m", "rotorsfd", "modal", path, "-o",
                           str(tmp_path / "out")], capture_output=True, text=True,
                          env={**os.environ, "OPENBLAS_NUM_THREADS": "1"}, timeout=300)
    assert proc.returncode == 2
    assert "rotor.supports[0].node: got 99; must be a node of the rotor, 1..21" in \
        _one_line(proc.stderr)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(("argv", "words"), [
    (["modal"], "required: CONFIG"),
    (["modal", str(PAPER)], "-o/--output"),
    (["bogus"], "invalid choice: 'bogus'"),
    ([], "required: COMMAND"),
    (["config"], "required: SUBCOMMAND"),
    (["config", "show", str(PAPER), "--format", "yaml"], "invalid choice: 'yaml'"),
    (["config", "show", "no/such/file.toml"], "config file: got 'no/such/file.toml'; no such"),
    (["config", "show", str(PAPER), "--set", "oops"], "--set: got 'oops'; expected KEY=VALUE"),
    (["config", "show", str(PAPER), "--set", "elements.sfd.clearance_ratio=5 mm"],
     "elements.sfd.clearance_ratio: got '5 mm'; expected a dimensionless ratio"),
    (["config", "show", str(PAPER), "--set", "unbalance[4].node=3"], "index 4 out of range"),
])
def test_bad_arguments_exit_2(capsys, argv, words):
    assert cli.main(argv) == 2
    assert words in _one_line(capsys.readouterr().err)


def test_numerical_failure_exits_1(tmp_path, capsys, monkeypatch):
    from rotorsfd import api

    def fail(*args, **kwargs):
        raise ConvergenceError("Newton did not converge at Omega = 900 rad/s (step 12)")

    monkeypatch.setattr(api, "run_modal", fail)
    argv = ["modal", str(PAPER), "-o", str(tmp_path)]
    assert cli.main(argv) == 1
    line = _one_line(capsys.readouterr().err)
    assert line == "rotorsfd: error: Newton did not converge at Omega = 900 rad/s (step 12)"
    assert cli.main(["--debug", *argv]) == 1            # --debug shows the traceback
    assert "Traceback" in capsys.readouterr().err


def test_unexpected_error_one_line(tmp_path, capsys, monkeypatch):
    from rotorsfd import api

    monkeypatch.setattr(api, "run_modal", lambda *a, **k: 1 / 0)
    assert cli.main(["modal", str(PAPER), "-o", str(tmp_path)]) == 1
    assert "internal error (ZeroDivisionError)" in _one_line(capsys.readouterr().err)


def test_help_and_version(capsys):
    assert cli.main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "modal" in out and "config" in out
    assert cli.main(["--version"]) == 0
    assert "rotorsfd" in capsys.readouterr().out


def test_config_show_with_set(capsys):
    argv = ["config", "show", str(PAPER), "--set", "elements.sfd.clearance_ratio=0.61 %",
            "--set", "unbalance[0].magnitude=144.02 g*mm", "--format", "json"]
    assert cli.main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["elements"]["sfd"]["clearance_ratio"] == pytest.approx(0.0061)
    assert data["unbalance"][0]["magnitude"] == pytest.approx(144.02e-6)
    assert data["analysis"]["stability"]["intervals"] == 400          # default filled in


def test_config_show_round_trip_via_cli(tmp_path, capsys):
    assert cli.main(["config", "show", str(PAPER)]) == 0
    shown = capsys.readouterr().out
    again = tmp_path / "resolved.toml"
    again.write_text(shown)
    assert cli.main(["config", "show", str(again)]) == 0
    assert tomllib.loads(capsys.readouterr().out) == tomllib.loads(shown)


def test_config_check_and_schema(capsys):
    assert cli.main(["config", "check", str(PAPER)]) == 0
    assert "ok (rotor: 21 nodes" in capsys.readouterr().out
    assert cli.main(["config", "schema"]) == 0
    schema = json.loads(capsys.readouterr().out)
    assert "rotor" in schema["properties"]


def test_registry_adds_commands(monkeypatch, capsys, tmp_path):
    """A new command slots in through the registry, with CONFIG, --set, -o and --quiet."""
    from rotorsfd.cli import registry

    monkeypatch.chdir(tmp_path)   # "-o x" is relative: keep it out of the checkout

    monkeypatch.setattr(registry, "COMMANDS", dict(registry.COMMANDS))
    seen = {}

    @cli.command("demo", "a demo command", output=True, quiet=True,
                 arguments=[cli.arg("--speed-ratio", type=float, required=True)])
    def _demo(args, config):
        seen.update(ratio=args.speed_ratio, quiet=args.quiet, out=args.output,
                    h=config.analysis.response.harmonics)
        return 0

    argv = ["demo", str(PAPER), "-o", "x", "-q", "--speed-ratio", "1.05",
            "--set", "analysis.response.harmonics=8"]
    assert cli.main(argv) == 0
    assert seen == {"ratio": 1.05, "quiet": True, "out": Path("x"), "h": 8}
    assert cli.main(["demo", str(PAPER), "-o", "x"]) == 2
    assert "--speed-ratio" in _one_line(capsys.readouterr().err)


def test_unwritable_output_one_line(tmp_path, capsys, monkeypatch):
    from rotorsfd import api

    class Result:
        def write(self, directory):
            raise PermissionError(13, "Permission denied", str(directory))

    monkeypatch.setattr(api, "run_modal", lambda *a, **k: Result())
    assert cli.main(["modal", str(PAPER), "-o", str(tmp_path / "ro")]) == 1
    assert "Permission denied" in _one_line(capsys.readouterr().err)


def test_debug_after_subcommand(tmp_path, capsys):
    path = _variant(tmp_path, "node = 21", "node = 99")
    assert cli.main(["config", "show", path, "--debug"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" in err and err.strip().splitlines()[-1].startswith("rotorsfd: error:")
