"""The README's tutorial is code: its config validates, its commands parse, its example
files exist and its Python study runs and prints what the text says it prints."""

from __future__ import annotations

import contextlib
import io
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
def test_readme_command_parses(line):
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
    assert config.sfd.clearance == pytest.approx(0.15e-3)
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
    # cusp) on, no saddle-node: 6 rad/s prints an empty list.
    folds0 = [float(v) for v in re.findall(r"\d\.\d+", lines[0].split("Omega~")[1])]
    assert sorted(folds0) == pytest.approx([1.0527, 1.0593], abs=2e-4)
    assert lines[3].endswith("[]")
