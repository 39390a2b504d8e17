"""How a response branch ends (issue 22 item 3): at the end of its range, at an element's
validity limit (a result: a sweep point ``ok`` with its ending), on request, or by a
numerical failure; on a three-node rotor whose SFD journal reaches eps = 0.95."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from rotors import tiny_rotor_text
from rotorsfd.analyses.response import run_response
from rotorsfd.io.config import load_config
from rotorsfd.studies.tasks import response_output

TINY = tiny_rotor_text()


@pytest.fixture(scope="module")
def config(tmp_path_factory):
    path = tmp_path_factory.mktemp("tiny") / "tiny.toml"
    path.write_text(TINY)
    return lambda *sets: load_config(path, list(sets))


def test_a_branch_at_the_validity_limit_is_a_result(config):
    result = run_response(config(), progress=False)
    assert not result.success and result.ended == "limit"
    eps = result.element_columns()["eps_max_sfd"]
    assert eps[-1] == pytest.approx(0.95, abs=0.02) and np.all(eps < 0.951)
    assert result.summary().splitlines()[-1].startswith(
        "ended at a validity limit: response branch ended after ")
    out = response_output(result)
    assert out.status == "ok" and out.scalars["ended"] == "limit"
    assert "reached eps = 0.95" in out.message and "max_eccentricity" in out.message
    assert result.to_dataset().attrs["ended"] == "limit"


def test_range_and_stop_endings(config):
    full = run_response(config("unbalance[0].magnitude=0.02 kg*m"), progress=False)
    assert full.success and full.ended == "range"
    assert response_output(full).scalars["ended"] == "range"
    stopped = run_response(config("unbalance[0].magnitude=0.02 kg*m"), progress=False,
                           callback=lambda point: point.index >= 3)
    assert stopped.ended == "stopped" and stopped.branch.n_points == 4
    out = response_output(stopped)
    assert out.status == "incomplete" and out.scalars["ended"] == "stopped"


def test_a_result_without_an_ending_reads_its_success():
    """Duck-typed results (the documented fields only) keep working."""
    branch = SimpleNamespace(n_points=2, lam=np.array([1.0, 2.0]), folds=lambda: [])
    fake = SimpleNamespace(branch=branch, is_speed=False, parameter="p", stable=None,
                           max_multiplier=None, bifurcations=None, nodes=(),
                           deflection=lambda n: np.zeros(2), success=False,
                           message="no converged point beyond")
    out = response_output(fake)
    assert out.status == "incomplete" and out.scalars["ended"] == "failed"
