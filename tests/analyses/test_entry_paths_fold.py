"""The fold and bifurcation curves' two entry paths are one resolution (issue 16 item 3):
``run_fold_curve(config, ...)`` builds the system once and goes through
:meth:`TwoParameterInputs.from_system`, so ``run_fold_curve(build(config), ...,
config.analysis.response)`` (the context an empty configuration's: Omega_ref the first
forward critical speed) gives the same curves, every array to 1e-12. The start
saddle-nodes are also checked against the paper rotor's known ones (Omega~ = 1.0527 and
1.0593 at U = 144.02 g mm, H = 3: tests/analyses/test_fold_curve.py), the period
doublings of the journal-bearing rotor against tests/analyses/test_bifurcation_curves.py
(1043.25 and 1076.74 rad/s)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.bifurcation_curves import run_bifurcation_curves
from rotorsfd.analyses.context import RunContext, build
from rotorsfd.analyses.fold_curve import run_fold_curve
from rotorsfd.analyses.response_inputs import TwoParameterInputs
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict, read_toml

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _same_tables(a: dict, b: dict) -> None:
    assert list(a) == list(b)
    for key in a:
        x, y = np.asarray(a[key]), np.asarray(b[key])
        if x.dtype == object:
            assert list(x) == list(y), key
        else:
            scale = float(np.abs(x).max()) if x.size else 0.0
            np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * scale, err_msg=key)


def test_fold_curve_system_with_its_section_is_the_config():
    cfg = api.load_config(EXAMPLES / "paper_rotor.toml",
                          ["unbalance[0].magnitude=144.02 g*mm",
                           "reference.speed=first_critical"])
    a = run_fold_curve(cfg, "base.pitching.value", 0.0, "1 rad/s", harmonics=3)
    b = run_fold_curve(build(cfg), "base.pitching.value", 0.0, "1 rad/s",
                       cfg.analysis.response, harmonics=3)
    assert a.success and b.success, (a.message, b.message)
    assert len(a.table["speed_rad_s"]) > 5
    _same_tables(a.table, b.table)
    assert (a.parameter, a.range2, a.H, a.n_samples, a.nodes) == \
        (b.parameter, b.range2, b.H, b.n_samples, b.nodes)
    assert a.reference_speed == b.reference_speed
    np.testing.assert_allclose(a.start_folds, b.start_folds, rtol=1e-12)
    np.testing.assert_allclose(sorted(np.array(a.start_folds) / a.reference_speed),
                               [1.0527, 1.0593], atol=1e-4)
    assert a.title == cfg.title and b.title == ""
    ds_a, ds_b = a.to_dataset(), b.to_dataset()
    _same_tables({k: ds_a[k].values for k in ds_a.variables},
                 {k: ds_b[k].values for k in ds_a.variables})
    assert not a.cusps and a.bistability_end is None   # the pair persists past 1 rad/s


def test_bifurcation_curves_system_with_its_section_is_the_config():
    raw = read_toml(EXAMPLES / "journal_bearing_rotor.toml")
    raw["analysis"]["response"]["speed_range"] = {"start": "1000 rad/s",
                                                  "stop": "1100 rad/s"}
    cfg = config_from_dict(raw)
    over = {"harmonics": 3}
    a = run_bifurcation_curves(cfg, "unbalance[0].magnitude", "5 g*mm", "4.5 g*mm", **over)
    system = build(cfg)
    ctx = RunContext(reference_speed=api.reference_speed(cfg))
    b = run_bifurcation_curves(system, "unbalance[0].magnitude", "5 g*mm", "4.5 g*mm",
                               cfg.analysis.response, context=ctx, **over)
    assert len(a.table["kind"]) > 5
    _same_tables(a.table, b.table)
    assert a.start_period_doublings == pytest.approx(b.start_period_doublings, rel=1e-12)
    assert a.start_period_doublings == pytest.approx([1043.25, 1076.74], abs=0.01)
    assert [c.type for c in a.codim2] == [c.type for c in b.codim2]
    assert (a.H, a.H2, a.n_samples_pd, a.range2) == (b.H, b.H2, b.n_samples_pd, b.range2)


def test_two_parameter_inputs_name_the_bad_field():
    cfg = api.load_config(EXAMPLES / "paper_rotor.toml")
    system = build(cfg)
    with pytest.raises(ConfigError, match=r"--parameter: got 'speed'"):
        TwoParameterInputs.from_system(system, "speed", 1.0, 2.0)
    with pytest.raises(ConfigError, match=r"--from/--to: got '2 m'"):
        TwoParameterInputs.from_system(system, "base.pitching.value", 0.0, "2 m",
                                       context=RunContext(reference_speed=811.3))
    ok = TwoParameterInputs.from_system(system, "base.pitching.value", 0.0, "60 rpm",
                                        context=RunContext(reference_speed=811.3))
    assert ok.range2 == pytest.approx((0.0, 2 * np.pi), rel=1e-12)   # 1 rev/s = 2 pi rad/s
    assert ok.speed_range == pytest.approx((0.5 * 811.3, 1.6 * 811.3), rel=1e-12)
