"""The coded base terms equal the sympy derivation (derivations/base_motion.py --check):
disk and Timoshenko element C_base, K_base, F_base, M, Omega G, assembly and unbalance,
entry by entry for random parameters and base states, relative tolerance 1e-10."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

pytest.importorskip("sympy")

SCRIPT = Path(__file__).resolve().parents[2] / "derivations" / "base_motion.py"


def _load():
    spec = importlib.util.spec_from_file_location("derivation_base_motion", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_coded_terms_match_derivation():
    failures = _load().check(n_trials=2, seed=7)
    assert failures == []

