"""The interop entry points without ROSS: rotorsfd.from_ross / to_ross resolve lazily, and a
missing ROSS is one line naming the extra to install."""

from __future__ import annotations

import sys

import pytest

import rotorsfd
from rotorsfd.errors import ConfigError
from rotorsfd.interop import ross as rx


def test_top_level_names():
    assert rotorsfd.from_ross is rx.from_ross and rotorsfd.to_ross is rx.to_ross
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        _ = rotorsfd.nothing


def test_missing_ross_is_one_line(monkeypatch):
    monkeypatch.setitem(sys.modules, "ross", None)     # import ross -> ImportError
    with pytest.raises(ConfigError, match=r'pip install "rotorsfd\[ross\]"') as err:
        rx.from_ross(object())
    assert "\n" not in str(err.value)
