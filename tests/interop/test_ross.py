"""ROSS import and export against ROSS itself (skipped without ``rotorsfd[ross]``).

ROSS's own example rotors are imported and their first 6 lateral natural frequencies at two
speeds compared with ROSS's ``run_modal``: ``rotor_example()`` (cylindrical elements, two
disks, two bearings) has the same element matrices as ROSS to rounding (ROSS's shear
coefficient is passed on), so its frequencies agree to 1e-9; the compressor shipped with
ROSS (91 elements, concentric mass-only layers, speed-dependent bearings and seals)
imports with its tables frozen at each speed and its layers merged, to 1e-3. Slow: ROSS
itself takes about 25 s to import.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import load_config, validate
from rotorsfd.linear.modal import eigen
from rotorsfd.model.build import build_rotor

pytestmark = pytest.mark.slow
PAPER = Path(__file__).resolve().parents[2] / "examples" / "paper_rotor.toml"


@pytest.fixture(scope="module")
def rs():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return pytest.importorskip("ross")


@pytest.fixture(scope="module")
def rx(rs):
    from rotorsfd.interop import ross as rx

    return rx


@pytest.fixture(scope="module")
def compressor(rs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rs.compressor_example()


def ross_lateral_wn(rx, rotor, speed: float, n: int = 6) -> np.ndarray:
    """|lambda| of ROSS's first n lateral modes (forward and backward) at ``speed``."""
    m = rotor.run_modal(speed=speed, num_modes=40, sparse=False)
    ev = np.asarray(m.evalues)
    keep = (rx.lateral_fraction(rotor, m.evectors) > 0.5) & (ev.imag > 0)
    ev = ev[keep]
    return np.abs(ev[np.argsort(ev.imag)][:n])


def rotorsfd_wn(rotor, speed: float, n: int = 6) -> np.ndarray:
    ev = eigen(rotor, speed, n + 4).eigenvalues
    ev = ev[ev.imag > 0]
    return np.abs(ev[np.argsort(ev.imag)][:n])


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


def test_rotor_example_same_matrices_and_frequencies(rs, rx):
    ross_rotor = rs.rotor_example()
    rotor = build_rotor(validate(rx.from_ross(ross_rotor)))
    assert rotor.n_nodes == 7 and len(rotor.disks) == 2 and len(rotor.supports) == 2
    for ours, theirs in zip((rotor.M, rotor.K, rotor.C, rotor.G),
                            rx.ross_matrices(ross_rotor, 0.0), strict=True):
        assert np.abs(ours - theirs).max() <= 1e-12 * max(np.abs(theirs).max(), 1.0)
    for speed in (0.0, 500.0):
        theirs, ours = ross_lateral_wn(rx, ross_rotor, speed), rotorsfd_wn(rotor, speed)
        assert theirs.size == 6
        np.testing.assert_allclose(ours, theirs, rtol=1e-9)
    # ROSS's doctest value of the first mode (rotor_example, speed 0): 91.79655318 rad/s
    assert rotorsfd_wn(rotor, 0.0)[0] == pytest.approx(91.79655318, rel=1e-9)


@pytest.mark.parametrize("speed", [500.0, 1000.0])
def test_compressor_frequencies(rx, compressor, speed):
    config = rx.from_ross(compressor, speed=speed, layers="merge")
    rotor = build_rotor(validate(config))
    assert rotor.n_nodes == 56 and len(rotor.supports) == 14 and len(rotor.disks) == 7
    theirs, ours = ross_lateral_wn(rx, compressor, speed), rotorsfd_wn(rotor, speed)
    np.testing.assert_allclose(ours, theirs, rtol=1e-3)
    # the merged layers keep E I, rho A and kappa G A: the stiffness is ROSS's to 1e-7
    _, K, C, _ = rx.ross_matrices(compressor, speed)
    assert _relative(rotor.K, K) < 1e-7
    assert _relative(rotor.C, C) < 1e-12    # the seal and bearing tables at this speed


def test_compressor_refusals_name_the_element(rx, compressor):
    with pytest.raises(ConfigError, match=r"ShaftElement 'ShaftElement 9'.*concentric layer"):
        rx.from_ross(compressor, speed=500.0)
    with pytest.raises(ConfigError, match=r"BearingElement 'Bearing 0' \(ROSS node 7\).*"
                                          r"speed-dependent kxx.*speed="):
        rx.from_ross(compressor, layers="merge")


def test_unsupported_elements_refused(rs, rx):
    steel = rs.materials.steel
    conical = [rs.ShaftElement(0.25, 0.0, 0.05, odr=0.06, material=steel),
               rs.ShaftElement(0.25, 0.0, 0.06, material=steel)]
    bearings = [rs.BearingElement(0, kxx=1e6, cxx=0), rs.BearingElement(2, kxx=1e6, cxx=0)]
    with pytest.raises(ConfigError, match=r"ShaftElement.*\(ROSS node 0\).*conical"):
        rx.from_ross(rs.Rotor(conical, [], bearings))
    euler = [rs.ShaftElement(0.25, 0.0, 0.05, material=steel, shear_effects=False)
             for _ in range(2)]
    with pytest.raises(ConfigError, match=r"shear_effects = False"):
        rx.from_ross(rs.Rotor(euler, [], bearings))
    shaft = [rs.ShaftElement(0.25, 0.0, 0.05, material=steel) for _ in range(2)]
    linked = [rs.BearingElement(0, kxx=1e6, cxx=0, n_link=3),
              rs.BearingElement(3, kxx=1e7, cxx=0), rs.BearingElement(2, kxx=1e6, cxx=0)]
    mass = [rs.PointMass(n=3, m=2.0)]
    with pytest.raises(ConfigError, match=r"n_link = 3"):
        rx.from_ross(rs.Rotor(shaft, [], linked, mass))


def test_round_trip_ross_rotorsfd_ross(rs, rx):
    ross_rotor = rs.rotor_example()
    back = rx.to_ross(build_rotor(validate(rx.from_ross(ross_rotor))))
    for a, b in zip(rx.ross_matrices(back, 0.0), rx.ross_matrices(ross_rotor, 0.0),
                    strict=True):
        assert np.abs(a - b).max() <= 1e-12 * max(np.abs(b).max(), 1.0)
    theirs, ours = ross_lateral_wn(rx, ross_rotor, 300.0), ross_lateral_wn(rx, back, 300.0)
    np.testing.assert_allclose(ours, theirs, rtol=1e-10)


def test_round_trip_paper_rotor_through_ross(rx):
    """The paper rotor (Hutchinson's shear coefficient, the SFD's centring spring as a
    support) to ROSS and back: the same linear rotor."""
    config = load_config(PAPER)
    rotor = build_rotor(config)
    ross_rotor = rx.to_ross(config)
    for a, b in zip(rx.ross_matrices(ross_rotor, 0.0), (rotor.M, rotor.K, rotor.C, rotor.G),
                    strict=True):
        assert np.abs(a - b).max() <= 1e-12 * max(np.abs(b).max(), 1.0)
    again = build_rotor(validate(rx.from_ross(ross_rotor)))
    for k in "MKCG":
        a, b = getattr(again, k), getattr(rotor, k)
        assert np.abs(a - b).max() <= 1e-12 * max(np.abs(b).max(), 1.0)
    np.testing.assert_allclose(ross_lateral_wn(rx, ross_rotor, 1000.0),
                               rotorsfd_wn(rotor, 1000.0), rtol=1e-9)


def test_import_ross_file(rs, rx, tmp_path):
    """ROSS's own TOML format (Rotor.save / Rotor.load) to a rotorsfd config file."""
    path = tmp_path / "rotor.toml"
    rs.rotor_example().save(path)
    out = tmp_path / "my_rotor.toml"
    text = rx.import_ross(path, out)
    assert out.read_text() == text and text.startswith("# Imported from the ROSS rotor")
    config = load_config(out)
    ref = build_rotor(validate(rx.from_ross(rs.rotor_example())))
    np.testing.assert_allclose(build_rotor(config).K, ref.K, rtol=1e-13)
    with pytest.raises(ConfigError, match=r"ROSS rotor file: got '.*missing\.toml'; no such"):
        rx.import_ross(tmp_path / "missing.toml")


def test_cli_import_ross(rs, tmp_path, capsys):
    from rotorsfd import cli

    path = tmp_path / "ross_rotor.toml"
    rs.rotor_example().save(path)
    assert cli.main(["import-ross", str(path), "-o", str(tmp_path / "my.toml")]) == 0
    assert "wrote" in capsys.readouterr().out
    assert load_config(tmp_path / "my.toml").rotor.n_nodes == 7
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rs.compressor_example().save(tmp_path / "compressor.toml")
    assert cli.main(["import-ross", str(tmp_path / "compressor.toml"), "-o",
                     str(tmp_path / "c.toml"), "--merge-layers"]) == 2
    assert "speed-dependent" in capsys.readouterr().err
    assert cli.main(["import-ross", str(tmp_path / "compressor.toml"), "-o",
                     str(tmp_path / "c.toml"), "--merge-layers", "--speed", "9000 rpm"]) == 0
    assert load_config(tmp_path / "c.toml").rotor.n_nodes == 56
