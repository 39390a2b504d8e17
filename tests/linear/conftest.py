"""Fixtures of the linear-analysis tests (helpers in linear_helpers.py)."""

from __future__ import annotations

import pytest
from linear_helpers import paper_rotor

from rotorsfd.model import Rotor


@pytest.fixture(scope="session")
def paper() -> Rotor:
    return paper_rotor()
