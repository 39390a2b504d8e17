"""StabilityOptions rejects a step-control tolerance that is not positive (the check sat
after a return and never ran), with the config path, the value and what is allowed."""

from __future__ import annotations

import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.stability.branch_options import StabilityOptions


@pytest.mark.parametrize("tol", [0.0, -1e-4])
def test_interval_tolerance_must_be_positive(tol):
    with pytest.raises(ConfigError) as err:
        StabilityOptions(interval_tol=tol)
    text = str(err.value)
    assert "analysis.stability.interval_tolerance" in text and "> 0" in text


def test_a_positive_or_no_interval_tolerance_is_accepted():
    assert StabilityOptions(interval_tol=1e-4).interval_tol == 1e-4
    assert StabilityOptions().interval_tol is None
