"""The README's tutorial is code: its config validates, its commands parse, its example
files exist and its Python study runs and prints what the text says it prints."""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import shlex
import tomllib
from pathlib import Path

import pytest

from rotorsfd.cli import build_parser
from rotorsfd.io.config import config_from_dict
from rotorsfd.model.build import build_model

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", README, flags=re.DOTALL)


def _command_lines() -> list[str]:
    lines = []
    for block in _blocks("bash"):
        block = re.sub(r"\\\n\s*", " ", block)      # a command continued with "\"
        for line in block.splitlines():
            line = line.split(" #")[0].strip()
            if line.startswith("rotorsfd "):
                lines.append(line)
            elif "&& rotorsfd " in line:
                lines.append("rotorsfd " + line.split("&& rotorsfd ", 1)[1])
    return lines


def test_readme_has_the_tutorial_blocks():
    assert len(_blocks("toml")) >= 1
    assert len(_blocks("python")) >= 1
    assert len(_command_lines()) >= 10


@pytest.mark.parametrize("line", _command_lines())
def test_readme_command_parses(line, tmp_path, monkeypatch):
    # the CLI checks at parse time that the paths a command reads exist (--from-orbit,
    # --initial-state): in the README those are folders an earlier command wrote with
    # -o, so make every -o folder, as running the commands in order does
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    for other in _command_lines():
        args = shlex.split(other)
        for flag in ("-o", "--output"):
            if flag in args:
                (tmp_path / args[args.index(flag) + 1]).mkdir(parents=True, exist_ok=True)
    monkeypatch.chdir(tmp_path)
    argv = shlex.split(line)[1:]
    parser = build_parser()
    with contextlib.redirect_stderr(io.StringIO()) as err:
        try:
            parser.parse_args(argv)
        except SystemExit as exc:              # argparse rejects: show what it said
            pytest.fail(f"{line!r}: {err.getvalue().strip()} (exit {exc.code})")


def test_readme_example_files_exist():
    paths = set(re.findall(r"examples/[\w./-]+\.toml", README))
    assert paths
    missing = sorted(p for p in paths if not (ROOT / p).is_file())
    assert not missing


def test_readme_rotor_config_validates_and_builds():
    (block,) = [b for b in _blocks("toml") if b.startswith("title =")]
    config = config_from_dict(tomllib.loads(block))
    model = build_model(config)
    assert model.rotor.n_nodes == 17
    assert config.elements["sfd"].clearance == pytest.approx(0.15e-3)
    assert config.base.pitching.value == pytest.approx(2.0)


def test_readme_python_study_runs_and_finds_the_folds():
    (block,) = _blocks("python")
    out = io.StringIO()
    cwd = Path.cwd()
    try:
        os.chdir(ROOT)
        with contextlib.redirect_stdout(out):
            exec(compile(block, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    lines = out.getvalue().splitlines()
    assert len(lines) == 4
    # w_by = 0: Table 1's pair (our values 1.0593 / 1.0527); from w_by = 4.41 rad/s (the
    # cusp at this H = 3; 4.379 converged in H) on, no saddle-node: 6 rad/s prints [].
    folds0 = [float(v) for v in re.findall(r"\d\.\d+", lines[0].split("Omega~")[1])]
    assert sorted(folds0) == pytest.approx([1.0527, 1.0593], abs=2e-4)
    assert lines[3].endswith("[]")


def _coexisting_commands() -> list[str]:
    """The README's "Coexisting motions" commands, in order."""
    part = README.split("**Coexisting motions.**", 1)[1].split("### ", 1)[0]
    (block,) = re.findall(r"```bash\n(.*?)```", part, flags=re.DOTALL)
    return [line for line in block.splitlines() if line.startswith("rotorsfd ")]


#: The isola's period-1 orbit at Omega~ = 1.075: journal at the Poincare point [C] at
#: T/1600 (measured, docs/paper.md); the main branch's is (0.295, -0.817).
ISOLA_POINT = (-0.2242, -0.9022)


@pytest.mark.slow
@pytest.mark.parametrize("steps", [800, 1600])
def test_readme_coexisting_recipe_reaches_the_isola_at_converged_steps(tmp_path, steps):
    """The README's recipe finds the second orbit (at T/200), then integrates from there at
    a converged step (the file's T/800, and T/1600): it stays on the isola (300 periods
    instead of the file's 2000 here; the start is already close to it)."""
    import json

    from rotorsfd.cli import main

    find, _isola, second, _walk = _coexisting_commands()
    assert "--hb-phase 0.5" in find and "steps_per_period=200" in find
    assert "--initial-state out/find" in second and "steps_per_period" not in second
    with contextlib.redirect_stdout(io.StringIO()):
        cwd = Path.cwd()
        try:
            os.chdir(ROOT)
            argv = shlex.split(find.replace("out/", f"{tmp_path}/"))[1:]
            assert main([*argv, "-q"]) == 0
            argv = shlex.split(second.replace("out/", f"{tmp_path}/"))[1:]
            argv += ["--set", "analysis.simulate.periods=300", "--set",
                     f"analysis.simulate.steps_per_period={steps}", "-q"]
            assert main(argv) == 0
        finally:
            os.chdir(cwd)
    summary = json.loads((tmp_path / "second" / "summary.json").read_text())
    assert summary["motion"] == "period-1"
    head, *rows = (tmp_path / "second" / "poincare.csv").read_text().splitlines()
    sfd = [dict(zip(head.split(","), r.split(","), strict=True)) for r in rows]
    last = [r for r in sfd if r["node"] == "1"][-1]            # the journal (SFD node 1)
    C = summary["clearance_m"]
    y, z = float(last["y"]) / C, float(last["z"]) / C
    # T/800 is 2e-3 C from T/1600 here; the main branch is 0.5 C away
    assert math.hypot(y - ISOLA_POINT[0], z - ISOLA_POINT[1]) < 4e-3
