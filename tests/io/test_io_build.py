"""Config -> model objects (rotor with the SFD centring spring, SFD, unbalance, base)."""

import math
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict, read_toml
from rotorsfd.model.build import build_base_motion, build_elements, build_model, build_rotor

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"


@pytest.fixture
def raw():
    return read_toml(PAPER)


def test_paper_rotor(raw):
    model = build_model(config_from_dict(raw))
    rotor = model.rotor
    assert rotor.n_nodes == 21 and rotor.n_dof == 84
    assert rotor.node_x[-1] == pytest.approx(0.5994)
    disk = rotor.disks[0]
    ro, ri, h = 0.1016, 0.03015, 0.0508
    assert disk.node == 8
    assert disk.mass == pytest.approx(7810 * math.pi * (ro**2 - ri**2) * h)
    # right support + the SFD centring spring at node 1; the film is not in the rotor
    assert sorted(s.node for s in rotor.supports) == [1, 21]
    assert model.elements[0].node == 1
    assert model.elements[0].film.clearance == pytest.approx(0.127e-3)
    assert model.elements[0].film.radius == pytest.approx(0.127e-3 / 0.00485)
    assert model.elements[0].film.length == pytest.approx(0.325 * 2 * model.elements[0].film.radius)
    assert model.unbalances[0].magnitude == pytest.approx(360.04e-6)
    assert model.base_motion.is_fixed


def test_no_sfd_no_centring_spring(raw):
    del raw["elements"]["sfd"]
    raw["rotor"]["supports"].append({"node": 1, "kyy": 2e7, "kzz": 3e7, "cyy": 10, "czz": 20})
    cfg = config_from_dict(raw)
    rotor = build_rotor(cfg)
    assert build_elements(cfg) == []
    left = next(s for s in rotor.supports if s.node == 1)
    assert (left.kyy, left.kzz, left.cyy, left.czz) == (2e7, 3e7, 10, 20)


def test_inertia_disk_and_damping(raw):
    raw["rotor"]["disks"][0] = {"node": 8, "mass": "12 kg", "polar_inertia": 0.06,
                                "diametral_inertia": 0.035}
    raw["rotor"]["damping"] = {"kind": "rayleigh", "beta": "2e-5 s"}
    rotor = build_rotor(config_from_dict(raw))
    assert rotor.disks[0].mass == 12.0
    assert rotor.damping.beta == 2e-5 and rotor.damping.alpha == 0.0
    assert np.any(rotor.C != 0)


def test_base_motion_laws(raw):
    cfg = config_from_dict(raw, [
        "base.pitching.law=harmonic", "base.pitching.frequency=20 rad/s",
        "base.pitching.angle_amplitude=0.01", "base.rolling.law=constant",
        "base.rolling.value=10 rad/s", "gravity.enabled=true"])
    base = build_base_motion(cfg)
    w = base.rates(0.1)
    assert w[0] == pytest.approx(10.0)
    assert w[1] == pytest.approx(0.01 * 20 * math.sin(2.0))     # A0 w sin(w t)
    assert base.gravity is not None and base.gravity.enabled


def test_callable_law_from_config_folder(raw, tmp_path):
    (tmp_path / "mybase.py").write_text("import numpy as np\n"
                                        "def rate(t):\n    return 2.0 + 0 * np.asarray(t)\n")
    cfg = config_from_dict(raw, ["base.yawing.law=callable", "base.yawing.callable=mybase:rate"])
    assert build_base_motion(cfg, search_path=tmp_path).rates(0.3)[2] == pytest.approx(2.0)
    bad = config_from_dict(raw, ["base.yawing.law=callable",
                                 "base.yawing.callable=no_such_module_xyz:rate"])
    with pytest.raises(ConfigError) as info:
        build_base_motion(bad, search_path=tmp_path)
    assert info.value.field == "base.yawing.callable"
