"""SFD test fixtures: ``model`` runs a test for each film model."""

from __future__ import annotations

import pytest
from sfd_helpers import MODELS


@pytest.fixture(params=MODELS)
def model(request: pytest.FixtureRequest) -> str:
    return request.param
