"""The case registry and the figure configs of examples/paper/: every case's config exists
and validates, a case's overrides only select one of its figure's [analysis.sweep]
variants, and the figure configs run the whole figure."""

from __future__ import annotations

import itertools
import math
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import rotorsfd
from rotorsfd.io.config import dump_config, load_config, parse_override, read_toml
from rotorsfd.io.schema import axis_values, parameter_values
from rotorsfd.paper.cases import (
    CASES,
    EXTRA_CASES,
    FIGURES,
    KINDS,
    calibration_overrides,
    examples_dir,
    literal_name,
    select,
)
from rotorsfd.paper.claims import CLAIMS

EXAMPLES = examples_dir()
REPO = Path(__file__).resolve().parents[2]
FIGURE_FILES = sorted(p.relative_to(EXAMPLES).as_posix()
                      for p in (EXAMPLES / "paper").glob("*.toml"))

#: Overrides that are not a variant of the figure (their values are not in the paper):
#: case-name prefix -> (keys, reason).
EXCEPTIONS = {
    "sens-": ({"elements.sfd.centring_stiffness", "rotor.supports[0].stiffness"},
              "sensitivity to the support stiffnesses the paper does not give (+/- 5 %)"),
    "fig23-t200-": ({"analysis.simulate.steps_per_period"},
                    "the paper's time step T/200 beside the file's converged T/800"),
}


def _exception(name: str) -> set[str]:
    return next((keys for prefix, (keys, _) in EXCEPTIONS.items()
                 if literal_name(name).startswith(prefix)), set())


def _axes(config) -> dict[str, list[float]]:
    return {a.parameter: axis_values(config, a) for a in config.analysis.sweep.axes}


def _variant(name: str, config) -> dict[str, float]:
    """The case's overrides that select a variant, as SI values by dotted path."""
    out = {}
    for item in CASES[name].overrides:
        key, value = parse_override(item)
        if key not in _exception(name):
            out[key] = parameter_values(config, key, [value])[0]
    return out


@pytest.mark.parametrize("name", sorted(CASES))
def test_case_config_exists_and_validates(name):
    case = CASES[name]
    assert case.kind in KINDS
    assert (EXAMPLES / case.config).is_file(), case.config
    if literal_name(name) != "modal":
        assert case.config in FIGURE_FILES, f"{name}: not a figure config: {case.config}"
    reading = calibration_overrides() if case.reading == "calibrated" else ()
    for quick in (False, True):
        load_config(EXAMPLES / case.config,
                    [*reading, *case.overrides, *(case.quick if quick else ())])


@pytest.mark.parametrize("name", sorted(CASES))
def test_case_overrides_select_a_sweep_variant(name):
    case = CASES[name]
    config = load_config(EXAMPLES / case.config)
    axes = _axes(config)
    keys = {parse_override(o)[0] for o in case.overrides}
    assert keys - _exception(name) <= set(axes), (
        f"{name}: overrides {sorted(keys - set(axes) - _exception(name))} are not "
        f"[analysis.sweep] axes of {case.config} ({sorted(axes)})")
    for key, value in _variant(name, config).items():
        assert any(math.isclose(value, v, rel_tol=1e-12) for v in axes[key]), (
            f"{name}: {key} = {value} is not one of the axis values {axes[key]}")
    if case.kind == "width-sweep":  # the rates it runs are the figure's rate axis
        rates = axes["base.pitching.value"]
        assert all(any(math.isclose(float(v), r) for r in rates)
                   for v in case.options["values"])


def test_the_exceptions_are_only_sensitivity_and_the_paper_step():
    assert {n for n in CASES if _exception(n)} == {
        n for n in CASES if n.startswith(("sens-", "fig23-t200-"))}
    for name in CASES:
        keys = {parse_override(o)[0] for o in CASES[name].overrides}
        if _exception(name):
            assert keys & _exception(name), name  # each exception case uses its exception


@pytest.mark.parametrize("path", FIGURE_FILES)
def test_figure_config_runs_the_whole_figure(path):
    """The response/simulate cases of a figure config are exactly its sweep's grid, so
    `rotorsfd sweep FILE` computes what `rotorsfd paper` draws (Figure 19's grid is finer:
    its cases are fold curves and width sweeps over the rate axis)."""
    config = load_config(EXAMPLES / path)
    cases = [n for n, c in CASES.items() if c.config == path and not _exception(n)
             and c.reading == "literal"]
    axes = _axes(config)
    if not axes:  # Figures 6 (the chart is the figure) and 9 (one branch)
        assert all(CASES[n].kind in ("chart",) for n in cases), cases
        return
    task = config.analysis.sweep.task
    grid = sorted(itertools.product(*axes.values()))
    runs = [n for n in cases if CASES[n].kind in ("response", "simulate")]
    for n in runs:
        assert CASES[n].kind == task, n
    if runs:
        got = sorted(tuple(_variant(n, config)[k] for k in axes) for n in runs)
        assert len(got) == len(grid)
        for a, b in zip(got, grid, strict=True):
            assert a == pytest.approx(b, rel=1e-12), path
    else:
        assert path == "paper/fig19_unstable_range.toml"


@pytest.mark.parametrize("path", FIGURE_FILES)
def test_figure_config_header(path):
    """Each figure config starts with a comment block: what the figure shows, what the
    paper reports, what we chose, and how to run it; and it extends a family file."""
    text = (EXAMPLES / path).read_text()
    header = text.split("\n\n")[0]
    assert all(line.startswith("#") for line in header.splitlines())
    for needed in ("Zhang et al. 2025", "The paper reports", "Chosen where the paper is "
                   "silent", "rotorsfd "):
        assert needed in text.replace("\n# ", " "), (path, needed)
    # every command named in the header uses this file's own path
    for cmd in re.findall(r"rotorsfd \S+ (examples/\S+\.toml)", text):
        assert cmd == f"examples/{path}", (path, cmd)
    raw = read_toml(EXAMPLES / path)
    assert raw["extends"].startswith("../") and (EXAMPLES / "paper" / raw["extends"]).is_file()


@pytest.mark.parametrize("name", sorted(n for n, c in CASES.items()
                                        if c.kind in ("response", "width-sweep")))
def test_response_cases_end_at_contact_not_at_the_limiter(name):
    case = CASES[name]
    config = load_config(EXAMPLES / case.config, case.overrides)
    assert config.analysis.response.max_eccentricity == pytest.approx(0.995)


def test_fixed_values_of_the_figures():
    """A few values the figures fix (the paper's), read from the resolved configs."""
    def cfg(path, *sets):
        return load_config(EXAMPLES / "paper" / path, sets)

    c = cfg("fig07_table1_fixed_base.toml")
    assert c.analysis.response.harmonics == 3 and c.base.pitching.law == "off"
    assert c.elements["sfd"].clearance_ratio == pytest.approx(0.00485)
    assert cfg("fig17_20_unbalance_h8.toml").analysis.response.harmonics == 8
    c = cfg("fig21_22_table3_clearance.toml")
    assert (c.analysis.response.harmonics, c.base.pitching.value,
            c.unbalance[0].magnitude) == (8, pytest.approx(10.0), pytest.approx(252e-6))
    c = cfg("fig23_time_domain.toml")
    s = c.analysis.simulate
    # T/800 (converged); the paper's T/200 is the fig23-t200-* cases
    assert (s.steps_per_period, s.periods, s.poincare_periods) == (800, 2000, 100)
    for name, case in CASES.items():
        if name.startswith("fig23-t200-"):
            steps = cfg("fig23_time_domain.toml", *case.overrides).analysis.simulate
            assert steps.steps_per_period == 200, name
        elif case.config == "paper/fig23_time_domain.toml":
            assert not any("steps_per_period" in o for o in case.overrides), name
    assert s.initial_displacement == pytest.approx(1e-6)
    assert c.elements["sfd"].clearance_ratio == pytest.approx(0.00728)
    # Figure 19's fold curves at H = 16 (converged), and at the paper's H
    assert CASES["fig19-u144"].options["harmonics"] == 16
    assert CASES["fig19-u252"].options["harmonics"] == 16
    assert CASES["fig19-u144-paper-h"].options["harmonics"] == 3   # Table 1's H
    assert "harmonics" not in CASES["fig19-u252-paper-h"].options  # the file's H = 8
    # Figure 9 is the U = 360.04 g mm branch of Figure 7
    a = dump_config(cfg("fig09_harmonics_fixed_base.toml"))
    b = dump_config(cfg("fig07_table1_fixed_base.toml", "unbalance[0].magnitude=360.04 g*mm"))
    for d in (a, b):
        d.pop("title")
        d["analysis"].pop("sweep")
    assert a == b


def test_figures_and_claims_name_known_cases():
    for spec in FIGURES.values():
        assert spec.cases and all(c in CASES for c in spec.cases), spec.number
    for claim in CLAIMS:
        assert claim.case in CASES, claim
    assert all(c in CASES for c in EXTRA_CASES)


def test_select():
    specs, cases = select(["7"])
    assert [s.number for s in specs] == ["7"]
    lit = {"modal", "fig7-u72", "fig7-u144", "fig7-u360"}
    assert {c.name for c in cases} == lit | {"cal-fig7-u144", "cal-fig7-u360"}
    assert {c.name for c in select(["7"], readings=("literal",))[1]} == lit
    specs, cases = select(None, quick=True)
    assert [s.number for s in specs] == ["7"]
    assert {c.name for c in cases} == lit | {"cal-fig7-u144", "cal-fig7-u360"}
    specs, cases = select(None)
    assert len(specs) == len(FIGURES) and len(cases) >= 40
    with pytest.raises(KeyError, match="no figure 99"):
        select(["99"])


def test_examples_ship_with_the_package_without_a_second_copy():
    """``rotorsfd/examples`` is the package's examples folder; in the repository it is a
    symbolic link to examples/ (one hand-edited copy), in a wheel its files."""
    packaged = Path(rotorsfd.__file__).resolve().parent / "examples"
    assert (packaged / "paper_rotor.toml").is_file()
    if (REPO / "src" / "rotorsfd") == Path(rotorsfd.__file__).resolve().parent:
        link = REPO / "src" / "rotorsfd" / "examples"
        assert link.is_symlink() and link.resolve() == (REPO / "examples").resolve()
        assert examples_dir() == (REPO / "examples").resolve()


@pytest.mark.slow
def test_wheel_holds_every_example_unchanged(tmp_path):
    """The wheel built from the repository carries examples/**.toml byte for byte (an
    isolated build: pyproject's setuptools>=68 is fetched like pip does for users)."""
    run = subprocess.run([sys.executable, "-m", "pip", "wheel", str(REPO), "--no-deps",
                          "-q", "-w", str(tmp_path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    wheel = next(tmp_path.glob("rotorsfd-*.whl"))
    with zipfile.ZipFile(wheel) as z:
        names = {n for n in z.namelist() if n.startswith("rotorsfd/examples/")}
        files = sorted((REPO / "examples").rglob("*.toml"))
        assert names == {f"rotorsfd/examples/{p.relative_to(REPO / 'examples').as_posix()}"
                         for p in files}
        for p in files:
            rel = p.relative_to(REPO / "examples").as_posix()
            assert z.read(f"rotorsfd/examples/{rel}") == p.read_bytes(), rel
