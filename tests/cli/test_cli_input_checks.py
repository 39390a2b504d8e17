"""Bad input found before any work (issue 24, items 3 and 5): output folders, option
values, messages naming the field the user wrote, one error prefix, a closed pipe, and
the plausibility warnings of a valid config."""

from __future__ import annotations

import dataclasses
import errno
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from rotorsfd import cli
from rotorsfd.analyses.checks import config_warnings
from rotorsfd.io.config import load_config

ROOT = Path(__file__).parents[2]
PAPER = ROOT / "examples" / "paper_rotor.toml"
FOLDS = ROOT / "examples" / "paper" / "fig19_unstable_range.toml"

#: the arguments each command needs besides CONFIG and -o
EXTRA = {"fold-curve": ["--from", "0 rad/s", "--to", "6 rad/s"],
         "bifurcation-curves": ["--from", "0 rad/s", "--to", "6 rad/s"],
         "simulate": ["--speed-ratio", "1.0"],
         "fit-supports": ["--field", "elements.sfd.centring_stiffness", "--target", "811.3"],
         "calibrate": ["--fit", "elements.sfd.centring_stiffness",
                       "--target", "critical_speed[1]=811.3"]}
OUTPUT_COMMANDS = [*sorted(n for n, c in cli.COMMANDS.items() if c.output), "fit-supports"]


def _line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


class Reached(BaseException):
    """Raised by a handler that should not run (not caught by ``cli.main``)."""


def _no_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every command's handler raises :class:`Reached` if it is reached."""
    def boom(*args, **kwargs):
        raise Reached("the command started its work")

    for name, spec in list(cli.COMMANDS.items()):
        monkeypatch.setitem(cli.COMMANDS, name, dataclasses.replace(spec, handler=boom))


def _argv(name: str, output: str) -> list[str]:
    config = [] if not cli.COMMANDS[name].config else [str(PAPER)]
    return [*name.split(" "), *config, "-o", output, *EXTRA.get(name, [])]


def test_every_command_with_output_is_covered():
    assert {"modal", "response", "simulate", "sweep", "fold-curve", "paper", "static",
            "stability-chart", "bifurcation-diagram", "fit-supports"} <= set(OUTPUT_COMMANDS)


@pytest.mark.parametrize("name", OUTPUT_COMMANDS)
@pytest.mark.parametrize(("folder", "words"), [
    ("/proc/rotorsfd-no-such", "cannot write in /proc ("),
    ("FILE", "is a file, not a folder; give a folder (created if missing)"),
    ("FILE/sub", "is a file, so no folder can be created in it"),
])
def test_bad_output_folder_exits_2_before_work(tmp_path, monkeypatch, capsys, name, folder,
                                               words):
    (tmp_path / "FILE").write_text("not a folder")
    target = folder if folder.startswith("/") else str(tmp_path / folder)
    _no_work(monkeypatch)
    assert cli.main(_argv(name, target)) == 2
    line = _line(capsys.readouterr().err)
    assert line.startswith(f"rotorsfd: error: -o: got {target!r}; ")
    assert words in line


def test_read_only_file_system_named(tmp_path, monkeypatch, capsys):
    """EROFS (a read-only mount) or EACCES: the probe folder cannot be made."""
    def refuse(*args, **kwargs):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(tempfile, "mkdtemp", refuse)
    _no_work(monkeypatch)
    assert cli.main(_argv("modal", str(tmp_path / "out"))) == 2
    assert _line(capsys.readouterr().err) == (
        f"rotorsfd: error: -o: got '{tmp_path / 'out'}'; cannot write in {tmp_path} "
        f"(Read-only file system); give a folder you can write to")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_folder(tmp_path, monkeypatch, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    _no_work(monkeypatch)
    assert cli.main(_argv("modal", str(locked / "out"))) == 2
    assert "(Permission denied)" in _line(capsys.readouterr().err)


def test_good_output_folder_check_leaves_nothing(tmp_path, monkeypatch, capsys):
    target = tmp_path / "a" / "b"
    seen = []
    spec = cli.COMMANDS["modal"]
    monkeypatch.setitem(cli.COMMANDS, "modal", dataclasses.replace(
        spec, handler=lambda args, config: seen.append(sorted(
            p.name for p in tmp_path.rglob("*"))) or 0))
    assert cli.main(_argv("modal", str(target))) == 0
    assert seen == [["INCOMPLETE.txt", "a", "b"]]  # no probe folder, only the run's marker
    assert list(tmp_path.iterdir()) == []          # the run wrote nothing: folders removed


@pytest.mark.parametrize(("argv", "line"), [
    (["--from", "1 kg", "--to", "6 rad/s"],
     "rotorsfd: error: --from: got '1 kg'; expected an angular velocity in rad/s (a number "
     "in rad/s, or a string with units like '3000 rpm'); '1 kg' is a mass"),
    (["--from", "0", "--to", "abc"],
     "rotorsfd: error: --to: got 'abc'; expected an angular velocity in rad/s (a number in "
     "rad/s, or a string with units like '3000 rpm') for base.pitching.value; cannot read "
     "'abc' as a number with units ('abc' is not defined in the unit registry)"),
    (["--parameter", "unbalance[0].magnitude", "--from", "1 g*mm", "--to", "2 kg"],
     "rotorsfd: error: --to: got '2 kg'; expected an unbalance in kg*m (a number in kg*m, "
     "or a string with units like '360.04 g*mm'); '2 kg' is a mass"),
    (["--from", "2 rad/s", "--to", "2"],
     "rotorsfd: error: --to: got '2'; must differ from --from ('2 rad/s')"),
    (["--parameter", "speed", "--from", "0", "--to", "1"],
     "rotorsfd: error: --parameter: got 'speed'; must differ from the speed (the "
     "saddle-nodes are those of the speed response)"),
])
def test_fold_curve_range_checked_before_work(tmp_path, monkeypatch, capsys, argv, line):
    from rotorsfd import api

    monkeypatch.setattr(api, "run_fold_curve", lambda *a, **k: pytest.fail("work started"))
    assert cli.main(["fold-curve", str(FOLDS), "-o", str(tmp_path), *argv]) == 2
    assert _line(capsys.readouterr().err) == line


@pytest.mark.parametrize(("argv", "line"), [
    (["--speed-ratio", "-1"], "rotorsfd: error: simulate: argument --speed-ratio: must be "
     "> 0 (the rotor speed over the [reference] speed), got '-1' (see 'rotorsfd simulate "
     "--help')"),
    (["--speed-ratio", "inf"], "rotorsfd: error: simulate: argument --speed-ratio: expected "
     "a finite number, got 'inf' (see 'rotorsfd simulate --help')"),
    (["--speed", "-5 rpm"], "rotorsfd: error: simulate: argument --speed: must be > 0 "
     "rad/s, got '-5 rpm' (see 'rotorsfd simulate --help')"),
])
def test_simulate_speed_options_named(tmp_path, capsys, argv, line):
    assert cli.main(["simulate", str(PAPER), "-o", str(tmp_path), *argv]) == 2
    assert _line(capsys.readouterr().err) == line


@pytest.mark.parametrize(("argv", "words"), [
    (["fold-curve", str(FOLDS), "--from", "0", "--to", "1", "--harmonics", "0"],
     "fold-curve: argument --harmonics: must be >= 1, got '0'"),     # was silently ignored
    (["simulate", str(PAPER), "--speed-ratio", "1", "--lyapunov-periods", "-5"],
     "simulate: argument --lyapunov-periods: must be >= 0, got '-5'"),    # was accepted
    (["simulate", str(PAPER), "--speed-ratio", "1", "--record-periods", "0"],
     "simulate: argument --record-periods: must be >= 1, got '0'"),
    (["response", str(PAPER), "--multipliers-at", "nan"],
     "response: argument --multipliers-at: expected a finite number, got 'nan'"),
    (["sweep", str(PAPER), "--workers", "0"], "sweep: argument --workers: must be >= 1"),
    (["stability-chart", str(PAPER), "--workers", "x"],
     "stability-chart: argument --workers: expected an integer, got 'x'"),
])
def test_option_values_checked_before_work(tmp_path, monkeypatch, capsys, argv, words):
    _no_work(monkeypatch)
    assert cli.main([*argv, "-o", str(tmp_path / "out")]) == 2
    line = _line(capsys.readouterr().err)
    assert line.startswith("rotorsfd: error: ") and words in line
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(("argv", "line"), [
    (["simulate", str(PAPER), "--speed-ratio", "1", "--initial-state", "/no/such"],
     "rotorsfd: error: --initial-state: got '/no/such'; no such file or folder (give a "
     "simulate output folder or its timeseries.nc)"),
    (["response", str(PAPER), "--from-orbit", "/no/such"],     # was found after the start
     "rotorsfd: error: --from-orbit: got '/no/such'; no such file or folder (give a "
     "simulate output folder or its timeseries.nc)"),
])
def test_missing_input_files_named_before_work(tmp_path, monkeypatch, capsys, argv, line):
    from rotorsfd import api

    for name in ("run_response", "run_simulation"):
        monkeypatch.setattr(api, name, lambda *a, **k: pytest.fail("work started"))
    assert cli.main([*argv, "-o", str(tmp_path / "out")]) == 2
    assert _line(capsys.readouterr().err) == line
    assert not (tmp_path / "out").exists()


def test_unknown_paper_figure_named_alone(tmp_path, capsys):
    argv = ["paper", "--figure", "7", "--figure", "abc", "-o", str(tmp_path / "out")]
    assert cli.main(argv) == 2
    assert _line(capsys.readouterr().err).startswith(
        "rotorsfd: error: --figure: got 'abc'; no figure abc (known: ")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("argv", [["simulate", str(PAPER), "-o", "x", "--bogus"],
                                  ["config", "show"], ["nope"]])
def test_one_error_prefix(capsys, argv):
    assert cli.main(argv) == 2
    line = _line(capsys.readouterr().err)
    assert line.startswith("rotorsfd: error: ")
    assert "error: rotorsfd" not in line and line.count("error:") == 1


def test_time_varying_base_in_response_names_the_law(tmp_path, capsys):
    # a harmonic law gets the torus branch (tests/analyses/test_torus_response.py); a
    # law that is neither constant nor harmonic is refused, naming it
    argv = ["response", str(PAPER), "-o", str(tmp_path), "-q", "--set",
            "base.pitching.law=callable", "--set", "base.pitching.callable=numpy:sin"]
    assert cli.main(argv) == 2
    line = _line(capsys.readouterr().err)
    assert line.startswith("rotorsfd: error: base.pitching.law: got 'callable'; this "
                           "analysis needs a base motion constant in time")
    assert "BaseMotion(" not in line and "Harmonic(" not in line
    assert list(tmp_path.iterdir()) == []


def test_closed_pipe_is_quiet():
    """`rotorsfd config schema | head`: the reader goes away; no error, status 141."""
    proc = subprocess.Popen([sys.executable, "-m", "rotorsfd", "config", "schema"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()                           # before the command writes anything
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141
    assert err == ""


# ---- warnings ---------------------------------------------------------------------------------


def test_paper_rotor_has_no_warning():
    assert config_warnings(load_config(PAPER)) == []
    assert config_warnings(load_config(PAPER, ["gravity.enabled=true"])) == []


def test_stiff_support_at_the_sfd_node_warns():
    config = load_config(PAPER, ["rotor.supports[0].node=1"])
    (line,) = config_warnings(config)
    assert line.startswith("rotor.supports[0] (right support) is at node 1 of the damper "
                           "elements.sfd with stiffness 9.551e+06 N/m, in parallel with the "
                           "squeeze film")


def test_static_deflection_beyond_the_clearance_warns(capsys, tmp_path, monkeypatch):
    overrides = ["gravity.enabled=true", "elements.sfd.centring_stiffness=1e5 N/m"]
    (line,) = config_warnings(load_config(PAPER, overrides))
    # about 11 kg on the 1e5 N/m spring: 1.1 mm, 8.6 clearances
    assert "the static deflection at elements.sfd (node 1) under gravity, at rest, is " \
           "0.001096 m, eps = 8.63 > 1" in line
    sets = [a for o in overrides for a in ("--set", o)]
    assert cli.main(["config", "check", str(PAPER), *sets]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[1] == f"warning: {line}"
    _no_work(monkeypatch)                         # an analysis prints it before its work
    with pytest.raises(Reached):
        cli.main(["static", str(PAPER), "-o", str(tmp_path), *sets])
    assert capsys.readouterr().err == f"rotorsfd: warning: {line}\n"
