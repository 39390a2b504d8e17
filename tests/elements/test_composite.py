"""The composite of nonlinear elements: the generated compiled kernel against the sum of the
elements' numpy laws, shared DOFs, contact attribution, and the config tables."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.elements import KINDS, ElementSet
from rotorsfd.elements.sfd import SFDElement
from rotorsfd.errors import ConfigError, JournalContactError
from rotorsfd.io.config import config_from_dict, read_toml
from rotorsfd.kernels import as_cfunc
from rotorsfd.model.sfd import SFD

FILM = SFD(0.0051, 0.0262, 0.017, 1.27e-4)
PAPER_TOML = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"
STIFF = SFD(0.02, 0.03, 0.01, 1.0e-4, cavitation="none")


def _kernel_values(es: ElementSet, q: np.ndarray, v: np.ndarray):
    """(code, F, dF/dq, dF/dv) of the compiled composite kernel at one sample."""
    m = es.m
    F, Jq, Jv = np.zeros(m), np.zeros((m, m)), np.zeros((m, m))
    kernel = as_cfunc(es.kernel)
    code = kernel(np.ascontiguousarray(q), np.ascontiguousarray(v), es.kernel_params, F, Jq,
                  Jv)
    return code, F, Jq, Jv


@pytest.mark.parametrize("layout", ["two nodes", "shared node", "offset housing"])
def test_composite_kernel_equals_the_numpy_sum(layout):
    """Generated kernel == sum of the elements' numpy laws at their DOF positions (1e-12)."""
    elements = {
        "two nodes": [SFDElement("front", 1, FILM), SFDElement("rear", 5, STIFF)],
        "shared node": [SFDElement("a", 2, FILM), SFDElement("b", 2, STIFF)],
        "offset housing": [SFDElement("off", 3, FILM, (2e-5, -3e-5)),
                           SFDElement("plain", 1, STIFF)],
    }[layout]
    es = ElementSet(elements)
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = rng.uniform(-4e-5, 4e-5, es.m)
        v = rng.uniform(-2e-2, 2e-2, es.m)
        code, F, Jq, Jv = _kernel_values(es, q, v)
        F_np, Jq_np, Jv_np = es.force_and_jacobian(q, v)
        assert code == 0
        for got, want in ((F, F_np), (Jq, Jq_np), (Jv, Jv_np)):
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    if layout == "shared node":
        assert es.m == 2                       # one node: the forces add on its two DOFs
        q, v = np.array([3e-5, -1e-5]), np.array([0.01, 0.02])
        F_sum = FILM.nl_force(q, v) + STIFF.nl_force(q, v)
        np.testing.assert_allclose(es.force(q, v), F_sum, rtol=1e-14)


def test_offset_housing_shifts_the_film():
    """F(q, v) of a housing centred at o is the centred film's F(q - o, v); eps from o."""
    o = np.array([4e-5, 1e-5])
    e = SFDElement("off", 1, FILM, o)
    q, v = np.array([6e-5, -2e-5]), np.array([0.03, -0.01])
    np.testing.assert_allclose(e.force(q, v), FILM.nl_force(q - o, v), rtol=1e-15)
    assert e.limit(o[None, :]) == 0.0
    assert e.limit(q[None, :]) == pytest.approx(np.hypot(*(q - o)) / FILM.clearance,
                                                rel=1e-14)


def test_single_element_passes_its_own_kernel_through():
    e = SFDElement("sfd", 1, FILM)
    assert ElementSet([e]).kernel is e.kernel


def test_contact_names_the_element():
    """The kernel returns e + 1 for element e outside its law; the numpy form names it."""
    es = ElementSet([SFDElement("front", 1, FILM), SFDElement("rear", 5, STIFF)])
    q = np.array([1e-6, 0.0, 0.9999 * STIFF.clearance, 0.0])
    v = np.zeros(4)
    code, *_ = _kernel_values(es, q, v)
    assert code == 2
    err = es.located_contact(q, v, "a test")
    assert isinstance(err, JournalContactError) and "'rear'" in str(err)


def test_limiting_element_and_diagnostics():
    es = ElementSet([SFDElement("front", 1, FILM), SFDElement("rear", 5, STIFF)])
    q = np.array([[0.2 * FILM.clearance, 0.0, 0.0, 0.5 * STIFF.clearance],
                  [0.0, 0.3 * FILM.clearance, 0.1 * STIFF.clearance, 0.0]])
    element, value = es.limiting(q)
    assert element.name == "rear" and value == pytest.approx(0.5)
    d = es.diagnostics(q, np.zeros_like(q))
    assert d == pytest.approx({"eps_max_front": 0.3, "eps_max_rear": 0.5})


def _raw_two_sfds(node_b: int = 17) -> dict:
    raw = read_toml(PAPER_TOML)
    front = dict(raw["elements"]["sfd"])
    raw["elements"] = {"front": front, "rear": {**front, "node": node_b}}
    return raw


def test_config_two_sfds_and_bad_tables():
    config = config_from_dict(_raw_two_sfds())
    assert list(config.elements) == ["front", "rear"]
    with pytest.raises(ConfigError, match=r"^elements\.rear\.node: got 2; elements\.front "
                       r"is an sfd at node 2 too"):
        config_from_dict(_raw_two_sfds(), ["elements.rear.node=2", "elements.front.node=2"])
    raw = _raw_two_sfds(node_b=99)
    with pytest.raises(ConfigError, match=r"^elements\.rear\.node: got 99; must be a node"):
        config_from_dict(raw)
    raw = read_toml(PAPER_TOML)
    raw["sfd"] = raw.pop("elements")["sfd"]
    with pytest.raises(ConfigError, match=r"^sfd: .*\[elements\.sfd\] with kind"):
        config_from_dict(raw)


ALLOWED = ", ".join(repr(k) for k in KINDS)   # every registered kind, in order


@pytest.mark.parametrize(("change", "message"), [
    ({"kind": "rubb"}, f"elements.sfd.kind: got 'rubb'; allowed: {ALLOWED}"),
    ({"kind": None}, f"elements.sfd.kind: got nothing; required, the element's kind: "
                     f"{ALLOWED}"),
])
def test_element_kind_errors_are_one_line(change, message):
    raw = read_toml(PAPER_TOML)
    table = raw["elements"]["sfd"]
    for key, value in change.items():
        if value is None:
            del table[key]
        else:
            table[key] = value
    with pytest.raises(ConfigError) as info:
        config_from_dict(raw)
    assert str(info.value) == message


def test_composite_module_is_written_to_the_cache_folder(tmp_path, monkeypatch):
    """The generated kernel's module lands in $ROTORSFD_CACHE_DIR, named by its text's
    hash (so numba caches its compiled code); the same layout reuses it in a process."""
    from rotorsfd.elements.composite import cache_folder

    monkeypatch.setenv("ROTORSFD_CACHE_DIR", str(tmp_path))
    assert cache_folder() == tmp_path
    layout = [SFDElement(f"e{n}", n, FILM) for n in (1, 4, 6)]   # a layout no other test uses
    kernel = ElementSet(layout).kernel
    files = list(tmp_path.glob("rotorsfd_composite_*.py"))
    assert len(files) == 1 and "cfunc(KERNEL_SIGNATURE, cache=True)" in files[0].read_text()
    assert ElementSet([SFDElement(f"x{n}", n, STIFF) for n in (2, 3, 5)]).kernel is kernel
