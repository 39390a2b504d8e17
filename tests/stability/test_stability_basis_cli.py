"""``rotorsfd response --stability-basis full`` (issue 22 item 4): the unreduced monodromy;
its largest multiplier per point equals max(reduced, outside) of the default run, the
files say which basis they cover."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.cli import main
from rotorsfd.io.branch_files import read_branch

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from rotors import small_rotor_toml

pytestmark = pytest.mark.slow   # two branches with stability, ~20 s


def test_full_basis_matches_reduced_and_outside(tmp_path):
    config = small_rotor_toml(tmp_path / "small.toml")
    runs = {}
    for basis in ("reduced", "full"):
        out = tmp_path / basis
        args = ["response", str(config), "-o", str(out), "--quiet",
                "--set", "analysis.stability.adaptive_intervals=false"]
        if basis == "full":
            args += ["--stability-basis", "full"]
        assert main(args) == 0
        runs[basis] = read_branch(out / "branch.nc")
    red, full = runs["reduced"], runs["full"]
    assert red.attrs["floquet_basis"].startswith("craig-bampton")
    assert full.attrs["floquet_basis"].startswith("full")
    assert np.all(full["max_multiplier_outside"].values == 0.0)
    expect = np.maximum(red["max_multiplier"].values, red["max_multiplier_outside"].values)
    n = min(expect.size, full["max_multiplier"].size)
    # the same branch (the stability does not move the HB points); Newmark M = 400 on the
    # full model: its unresolved modes sit near |mu| = 1 only if undamped (trapezoid)
    assert np.abs(full["max_multiplier"].values[:n] - expect[:n]).max() <= 5e-3
