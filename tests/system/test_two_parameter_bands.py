"""The problems of a two-parameter family (``RotorSystem.two_parameter_problem``: its
``first(value)`` and ``second(speed)``, summed from terms stored once,
``model.base_polynomial.StoredTerms``) are the problems built from scratch at the same
(speed, value): the same band storage bit for bit, and the condensed residual and its
Jacobian equal to 1e-12; the independent check is the ``assembly="direct"`` problem (the
base terms recombined from the basis), equal to round-off."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from rotorsfd.elements.sfd import SFDConfig
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.base_motion import BaseMotion, BaseState, UniformAcceleration
from rotorsfd.model.base_polynomial import PolynomialTerms, StoredTerms
from rotorsfd.model.base_terms import BaseBasis
from rotorsfd.model.damping import ModalDamping
from rotorsfd.model.gravity import Gravity
from rotorsfd.model.sparse import BandedLinearPart, bandwidths, dense_bandwidths
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance

STEEL = Material(7810.0, 211e9, 81.783e9)
CLEARANCE = 0.127e-3
H, N = 3, 32

BASES = {
    "fixed": BaseMotion(),
    "pitching": BaseMotion(wy=6.0),
    "all rates, gravity": BaseMotion(wx=3.0, wy=-4.0, wz=2.5, gravity=Gravity(frame="base")),
    "acceleration, gravity": BaseMotion(y0=UniformAcceleration(2.0),
                                        z0=UniformAcceleration(-1.5), gravity=Gravity()),
}

#: (second parameter, two of its values)
SECOND = {
    "base.pitching": (0.0, -7.5),
    "base.rolling": (2.5, 9.0),
    "elements.sfd.clearance": (0.11e-3, 0.15e-3),
    "elements.sfd.viscosity": (0.004, 0.009),
    "unbalance.magnitude": (3e-6, 8e-6),
}
KINDS = list(SECOND)        # one of each kind (two base rates, two element fields)
SECOND |= {"base.yawing": (-3.0, 4.0), "elements.sfd.length": (0.012, 0.02)}
SPEEDS = (450.0, 1100.0)


def system(base: BaseMotion, n_elements: int = 12, damping=None) -> RotorSystem:
    """An SFD rotor: 12 elements (52 DOFs, the banded linear part) or fewer (dense)."""
    shaft = uniform_shaft(0.6, n_elements, 0.02, 0.03, STEEL)
    rotor = Rotor(shaft, disks=[Disk.from_geometry(n_elements // 2, 7810.0, 0.03, 0.1, 0.05)],
                  supports=[LinearSupport.isotropic(1, 5e6),
                            LinearSupport.isotropic(n_elements + 1, 1e7)], damping=damping)
    sfd = SFDConfig.model_validate({"node": 1, "viscosity": 0.0051, "radius": 0.0262,
                                    "length": 0.017, "clearance": CLEARANCE}).build("sfd")
    return RotorSystem(rotor, [sfd],
                       [Unbalance(n_elements // 2, 5e-6, 0.3), Unbalance(2, 2e-6, -1.0)],
                       base)


def condensed(problem: PeriodicProblem, lam: float, xs: np.ndarray,
              like: PeriodicProblem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(R, dR/dxs, dR/dlam) of ``problem`` at lam with the shift set on ``like`` at xs."""
    hb = CondensedHB(like, H, N)
    hb.set_shift(xs, lam)
    return hb.with_problem(problem).residual(xs, lam, jac=True)


def assert_close(a: tuple, b: tuple, rtol: float) -> None:
    for x, y in zip(a, b, strict=True):
        scale = float(np.abs(y).max())
        assert float(np.abs(x - y).max()) <= rtol * scale


def same_bands(a: PeriodicProblem, b: PeriodicProblem, lam: float) -> None:
    assert isinstance(a.matrices, BandedLinearPart) == isinstance(b.matrices, BandedLinearPart)
    if isinstance(b.matrices, BandedLinearPart):
        assert a.matrices.band == b.matrices.band
        for x, y in zip(a.matrices.banded(lam) + a.matrices.dbanded(lam),
                        b.matrices.banded(lam) + b.matrices.dbanded(lam), strict=True):
            assert np.array_equal(x, y)
    for x, y in zip(a.matrices(lam) + a.matrices.derivatives(lam),
                    b.matrices(lam) + b.matrices.derivatives(lam), strict=True):
        assert np.array_equal(x, y)
    assert np.array_equal(a.forcing(lam, H), b.forcing(lam, H))
    assert np.array_equal(a.dforcing(lam, H), b.dforcing(lam, H))


def unknowns(s: RotorSystem) -> np.ndarray:
    rng = np.random.default_rng(7)
    return 0.25 * CLEARANCE * rng.standard_normal((2 * H + 1, len(s.nl_dofs)))


def check_family(s: RotorSystem, second: str) -> None:
    family = s.two_parameter_problem(second)
    xs = unknowns(s)
    for value in SECOND[second]:
        copy = s.with_parameter(second, value)
        for speed in SPEEDS:
            fast, scratch = family.first(value), copy.periodic_problem("speed")
            direct = copy.periodic_problem("speed", assembly="direct")
            same_bands(fast, scratch, speed)
            ref = condensed(scratch, speed, xs, scratch)
            assert_close(condensed(fast, speed, xs, scratch), ref, 1e-12)
            assert_close(condensed(direct, speed, xs, scratch), ref, 1e-9)
            fast, scratch = family.second(speed), s.periodic_problem(second, speed)
            direct = s.periodic_problem(second, speed, assembly="direct")
            same_bands(fast, scratch, value)
            ref = condensed(scratch, value, xs, scratch)
            assert_close(condensed(fast, value, xs, scratch), ref, 1e-12)
            assert_close(condensed(direct, value, xs, scratch), ref, 1e-9)


@pytest.mark.parametrize("second", KINDS)
@pytest.mark.parametrize("base", ["fixed", "pitching", "all rates, gravity"])
def test_family_problems_equal_those_built_from_scratch(base: str, second: str) -> None:
    check_family(system(BASES[base]), second)


@pytest.mark.parametrize("second", ["elements.sfd.clearance", "unbalance.magnitude"])
def test_translating_base(second: str) -> None:
    """A uniformly accelerating base with gravity (a base rate would make it vary in
    time: only the other kinds)."""
    check_family(system(BASES["acceleration, gravity"]), second)


@pytest.mark.parametrize("second", ["base.pitching", "elements.sfd.length"])
def test_low_rank_modal_damping(second: str) -> None:
    """Modal damping of a few modes: the band beside the low-rank term."""
    s = system(BASES["pitching"], damping=ModalDamping(0.02, modes=4))
    assert s.rotor.damping_lowrank is not None
    check_family(s, second)


@pytest.mark.parametrize("second", ["base.yawing", "elements.sfd.viscosity"])
@pytest.mark.parametrize("case", ["small rotor", "full modal damping"])
def test_dense_linear_part(case: str, second: str) -> None:
    """A rotor too small for the band (28 DOFs) or with modal damping of every mode (C
    full): the terms stored dense, the problems' linear part dense."""
    s = (system(BASES["all rates, gravity"], n_elements=6) if case == "small rotor" else
         system(BASES["all rates, gravity"], damping=ModalDamping(0.02)))
    assert not isinstance(s.two_parameter_problem(second).first(1.0).matrices,
                          BandedLinearPart)
    check_family(s, second)


def test_terms_are_stored_once() -> None:
    """The problems of one family share the rotor's stored terms (M the same array in
    each: the band, or the dense matrix with modal damping of every mode)."""
    family = system(BASES["pitching"]).two_parameter_problem("base.pitching")
    a, b, c = family.first(1.0), family.first(2.0), family.second(700.0)
    assert a.matrices.M.terms[0] is b.matrices.M.terms[0] is c.matrices.M.terms[0]
    family = system(BASES["pitching"], damping=ModalDamping(0.02)).two_parameter_problem(
        "base.pitching")
    a, b, c = family.first(1.0), family.first(2.0), family.second(700.0)
    assert a.matrices.M is b.matrices.M is c.matrices.M


class _MatrixRotor:
    """A rotor given by its matrices alone (what StoredTerms reads): a lumped (diagonal)
    M, so that the band of a problem can be narrower than that of all the terms."""

    def __init__(self, n: int, rng: np.random.Generator) -> None:
        def banded(half: int) -> sp.csr_matrix:
            a = sp.diags([rng.standard_normal(n - abs(k)) for k in range(-half, half + 1)],
                         list(range(-half, half + 1)))
            return sp.csr_matrix(a + a.T)
        self.n_dof = n
        self.M_csr = sp.csr_matrix(sp.diags(1.0 + rng.random(n)))
        self.C_csr, self.G_csr, self.K_csr = banded(1), banded(2), banded(1)
        self.damping_lowrank = None


@pytest.mark.parametrize("variable", ["speed", "wx", "wy", "wz"])
@pytest.mark.parametrize("at", [None, 0.7])
@pytest.mark.parametrize("n", [60, 30])
def test_stored_terms_equal_polynomial_terms(n: int, variable: str, at: float | None
                                             ) -> None:
    """StoredTerms.linear_part against PolynomialTerms.of_base(...).plus(...)
    [.constant(at)].linear_part(M) bit for bit, the band read from the nonzeros of each
    case: narrower than that of all the terms on a fixed base (patterns up to 5 wide).
    60 DOFs: stored as bands; 30: stored dense (all the terms' band is too wide), the
    fixed base's problem banded all the same."""
    rng = np.random.default_rng(3)
    rotor = _MatrixRotor(n, rng)
    wide = sp.diags(rng.standard_normal(n - 5), 5)
    mats = [(k % 3 == 0) * (wide + wide.T) + (0.1 * k) * rotor.G_csr for k in range(12)]
    basis = BaseBasis(mats, rng.standard_normal((8, n)))
    stored = StoredTerms(rotor, basis)
    assert stored.storage == ("band" if n == 60 else "dense")
    state = BaseState.constant(w=(0.5, -1.5, 2.0), a0=(0.0, 0.3, -0.2), g=(0.0, 0.0, -9.81))
    speed = 0.0 if variable == "speed" else 400.0
    C = rotor.C_csr if variable == "speed" else rotor.C_csr + speed * rotor.G_csr
    for st in (state, None):
        if st is None and variable != "speed":
            continue
        if st is None:
            poly = PolynomialTerms(n, D=(rotor.C_csr, rotor.G_csr), K=(rotor.K_csr,))
        else:
            own = (C, rotor.G_csr) if variable == "speed" else (C,)
            poly = PolynomialTerms.of_base(basis, st, speed, variable).plus(
                D=own, K=(rotor.K_csr,))
        if at is not None:
            poly = poly.constant(at)
        ref = poly.linear_part(rotor.M_csr)
        got, load = stored.linear_part(variable, st, speed, at)
        assert type(got) is type(ref)
        assert isinstance(ref, BandedLinearPart) == (n == 60 or st is None)
        if isinstance(ref, BandedLinearPart):
            assert got.band == ref.band
            assert (got.band != stored.band) == (st is None)
        for lam in (-2.0, 3.5):
            if isinstance(ref, BandedLinearPart):
                for x, y in zip(got.banded(lam) + got.dbanded(lam),
                                ref.banded(lam) + ref.dbanded(lam), strict=True):
                    assert np.array_equal(x, y)
            for x, y in zip(got(lam) + got.derivatives(lam),
                            ref(lam) + ref.derivatives(lam), strict=True):
                assert np.array_equal(x, y)
            assert np.array_equal(load.load(lam), poly.load(lam))
            assert np.array_equal(load.dload(lam), poly.dload(lam))


def test_dense_bandwidths_equal_those_of_the_patterns() -> None:
    """dense_bandwidths (outermost diagonals first) against sparse.bandwidths."""
    rng = np.random.default_rng(5)
    for lower, upper in ((0, 0), (3, 0), (0, 4), (2, 7), (9, 9), (11, 3)):
        a = np.zeros((12, 12))
        for o in range(-lower, upper + 1):
            if o in (-lower, upper) or rng.random() < 0.5:
                a += np.diag(rng.standard_normal(12 - abs(o)), o)
        assert dense_bandwidths(a) == bandwidths((a,)) == (lower, upper)
    assert dense_bandwidths(np.zeros((5, 5))) == dense_bandwidths(None) == (0, 0)
