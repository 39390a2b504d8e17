"""The response's outcome speaks the user's terms: a truncation warning of a fixed H names
the speed as Omega~ and rad/s, not the continuation's ``lam=`` (issue 24 item 1)."""

from __future__ import annotations

import re

import pytest

from rotors import small_rotor_toml
from rotorsfd import api


def test_truncation_warning_names_the_speed(tmp_path):
    path = small_rotor_toml(tmp_path / "r.toml",
                            base='pitching = { law = "constant", value = "6 rad/s" }')
    cfg = api.load_config(path,
                          ["analysis.response.harmonics=1",
                           "analysis.response.harmonics_tolerance=1e-9",
                           "analysis.stability.enabled=false"])
    res = api.run_response(cfg, progress=False)
    msg = res.message
    assert "warning: HB truncation error" in msg
    assert "lam=" not in msg and "(H=" not in msg
    m = re.search(r"at Omega~ = ([0-9.]+) \(([0-9.]+) rad/s\) \(H = 1\)", msg)
    assert m is not None, msg
    assert float(m.group(2)) / float(m.group(1)) == pytest.approx(res.reference_speed, rel=1e-4)

