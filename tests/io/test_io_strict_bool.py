"""true/false fields take TOML booleans only (issue 24 item 5): pydantic alone reads
"yes", "off", 0 and 1 as booleans, so `gravity.enabled = "yes"` switched gravity on."""

from pathlib import Path

import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import load_config

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"


@pytest.mark.parametrize(("override", "message"), [
    ('gravity.enabled="yes"', "gravity.enabled: got 'yes'; expected true or false: "
     "include gravity (the paper neglects it)"),
    ("gravity.enabled=1", "gravity.enabled: got 1; expected true or false"),
    ('analysis.stability.enabled="no"', "analysis.stability.enabled: got 'no'; expected "
     "true or false: compute the stability of every point"),
    ("analysis.stability.enabled=0", "analysis.stability.enabled: got 0; expected true or "
     "false"),
    ('analysis.response.condensed="false"', "analysis.response.condensed: got 'false'; "
     "expected true or false"),
])
def test_non_boolean_rejected(override, message):
    with pytest.raises(ConfigError) as info:
        load_config(PAPER, [override])
    assert str(info.value).startswith(message)


@pytest.mark.parametrize("value", [True, False])
def test_booleans_accepted(value):
    text = str(value).lower()
    config = load_config(PAPER, [f"gravity.enabled={text}",
                                 f"analysis.stability.enabled={text}"])
    assert config.gravity.enabled is value and config.analysis.stability.enabled is value
