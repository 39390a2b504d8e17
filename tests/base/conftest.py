"""Fixtures of the base-motion tests (helpers in base_helpers.py)."""

from __future__ import annotations

import pytest
from base_helpers import make_rotor

from rotorsfd.model import Rotor


@pytest.fixture
def rotor() -> Rotor:
    return make_rotor()
