"""Bad input as a new user types it (issue 24): every case exits 2 with one line on
stderr, ``rotorsfd: error: ``, that names the field (or option), the value given and what
is allowed, before any work starts (the solvers are replaced by a function that fails the
test if it is reached), and prints no traceback.

A case is a command line (``{cfg}`` is the config file, ``{out}`` the output folder) and,
for mistakes in the file, an edit of the README's rotor (:data:`BASE`): a line replaced
or a block appended.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from rotorsfd import cli

ROOT = Path(__file__).parents[2]
PAPER = ROOT / "examples" / "paper_rotor.toml"

#: the README's "your own rotor" (section 4 of the tutorial), short
BASE = """\
title = "My rotor"

[materials.steel]
density = "7850 kg/m^3"
young_modulus = "210 GPa"
poisson_ratio = 0.3

[[rotor.shaft]]
length = "0.8 m"
n_elements = 16
outer_radius = "25 mm"
material = "steel"

[[rotor.disks]]
node = 6
material = "steel"
inner_radius = "25 mm"
outer_radius = "120 mm"
thickness = "30 mm"

[[rotor.disks]]
node = 12
mass = "8 kg"
polar_inertia = "0.05 kg*m^2"
diametral_inertia = "0.026 kg*m^2"

[[rotor.supports]]
node = 17
stiffness = "5e7 N/m"

[elements.sfd]
kind = "sfd"
node = 1
viscosity = "0.01 Pa*s"
clearance = "0.15 mm"
radius = "40 mm"
length = "20 mm"
cavitation = "pi"
centring_stiffness = "4e6 N/m"

[[unbalance]]
node = 6
magnitude = "300 g*mm"

[base]
pitching = { law = "constant", value = "2 rad/s" }

[analysis.response]
harmonics = "auto"
speed_range = { start = "1000 rpm", stop = "8000 rpm" }
"""

RESPONSE = ("response", "{cfg}", "-o", "{out}")
SIMULATE = ("simulate", "{cfg}", "-o", "{out}", "--speed-ratio", "1.0")
SWEEP = ("sweep", "{cfg}", "-o", "{out}", "--workers", "1")
AXIS = ("--axis", "elements.sfd.viscosity=0.01,0.02")
FOLD = ("fold-curve", "{cfg}", "-o", "{out}", "--from", "0 rad/s", "--to", "6 rad/s")
CHECK = ("config", "check", "{cfg}")
#: words that say what is allowed
ALLOWED = re.compile(r"must|expected|allowed|one of|choose from|give |needs|need |not |"
                     r"no such|cannot|unknown|invalid|at most|at least|only|>=|<=|> |< |"
                     r"extra|required|missing|use |valid|differ|refused|already|range|"
                     r"known|did you mean|takes|is a file|no folder")


@dataclass(frozen=True)
class Case:
    """A bad input: the command line, the edit of :data:`BASE` (``replace`` old -> new,
    or ``append``), and what the line must name."""

    id: str
    argv: tuple[str, ...]
    field: str
    value: str
    replace: tuple[str, str] | None = None
    append: str = ""


def case(id: str, argv: tuple[str, ...] | list[str], field: str, value: str, *,
         replace: tuple[str, str] | None = None, append: str = "") -> Case:
    return Case(id, tuple(argv), field, value, replace, append)


CASES = [
    # ---- command-line options ----------------------------------------------------------
    case("speed-ratio-negative", (*SIMULATE[:4], "--speed-ratio", "-1"), "--speed-ratio", "-1"),
    case("speed-ratio-text", (*SIMULATE[:4], "--speed-ratio", "abc"), "--speed-ratio", "abc"),
    case("speed-bad-unit", (*SIMULATE[:4], "--speed", "8000 furlongs"), "--speed", "furlongs"),
    case("speed-wrong-kind", (*SIMULATE[:4], "--speed", "10 kg"), "--speed", "10 kg"),
    case("speed-zero", (*SIMULATE[:4], "--speed", "0"), "--speed", "0"),
    case("speed-and-ratio", (*SIMULATE, "--speed", "800"), "--speed/--speed-ratio", "800"),
    case("hb-phase-without-hb", (*SIMULATE, "--hb-phase", "0.5"), "--hb-phase", "0.5"),
    case("hb-phase-nan", (*SIMULATE, "--from-hb", "--hb-phase", "nan"), "--hb-phase", "nan"),
    case("record-periods-zero", (*SIMULATE, "--record-periods", "0"), "--record-periods", "0"),
    case("lyapunov-negative", (*SIMULATE, "--lyapunov-periods", "-1"), "--lyapunov-periods",
         "-1"),
    case("lyapunov-float", (*SIMULATE, "--lyapunov-periods", "2.5"), "--lyapunov-periods",
         "2.5"),
    case("initial-state-missing", (*SIMULATE, "--initial-state", "/nonexistent/run"),
         "--initial-state", "/nonexistent/run"),
    case("from-orbit-missing", (*RESPONSE, "--from-orbit", "/nonexistent/ts.nc"),
         "--from-orbit", "/nonexistent/ts.nc"),
    case("multipliers-at-text", (*RESPONSE, "--multipliers-at", "high"), "--multipliers-at",
         "high"),
    case("bifurcation-start", ("bifurcation-diagram", "{cfg}", "-o", "{out}", "--start",
                               "cold"), "--start", "cold"),
    case("config-show-format", ("config", "show", "{cfg}", "--format", "yaml"), "--format",
         "yaml"),
    case("fields-format", ("config", "fields", "--format", "html"), "--format", "html"),
    case("unknown-command", ("respond", "{cfg}"), "COMMAND", "respond"),
    case("unknown-option", (*RESPONSE, "--harmonic", "5"), "--harmonic", "--harmonic"),
    case("stray-argument", (*RESPONSE, "extra.toml"), "response", "extra.toml"),
    case("missing-output", ("modal", "{cfg}"), "-o", "-o/--output"),
    case("stability-workers", ("stability-chart", "{cfg}", "-o", "{out}", "--workers", "0"),
         "--workers", "0"),
    case("sweep-workers", (*SWEEP[:4], "--workers", "0"), "--workers", "0"),
    case("paper-workers", ("paper", "-o", "{out}", "--workers", "none"), "--workers", "none"),
    case("paper-figure", ("paper", "-o", "{out}", "--figure", "99"), "--figure", "99"),
    case("fit-target-text", ("fit-supports", "{cfg}", "--field",
                             "elements.sfd.centring_stiffness", "--target", "fast"),
         "--target", "fast"),
    case("fit-field-unknown", ("fit-supports", "{cfg}", "--field", "rotor.bogus",
                               "--target", "800"), "rotor.bogus", "rotor.bogus"),
    case("fit-field-not-stiffness", ("fit-supports", "{cfg}", "--field",
                                     "elements.sfd.viscosity", "--target", "800"),
         "elements.sfd.viscosity", "elements.sfd.viscosity"),
    # ---- files and folders ---------------------------------------------------------------
    case("config-missing", ("response", "/nonexistent/rotor.toml", "-o", "{out}"),
         "rotor.toml", "/nonexistent/rotor.toml"),
    case("config-is-folder", ("response", "/tmp", "-o", "{out}"), "/tmp", "/tmp"),
    case("output-is-file", ("response", "{cfg}", "-o", "{cfg}"), "-o", "rotor.toml"),
    case("output-in-proc", ("response", "{cfg}", "-o", "/proc/rotorsfd/out"), "-o",
         "/proc/rotorsfd/out"),
    case("output-under-file", ("modal", "{cfg}", "-o", "{cfg}/out"), "-o", "rotor.toml/out"),
    case("toml-syntax", CHECK, "rotor.toml", "line", append="[analysis.modal\n"),
    case("empty-file", CHECK, "rotor", "rotor", replace=(BASE, "")),
    case("extends-missing", CHECK, "extends", "missing.toml",
         replace=('title = "My rotor"', 'extends = "missing.toml"')),
    # ---- --set ---------------------------------------------------------------------------
    case("set-no-equals", (*CHECK, "--set", "elements.sfd.viscosity"), "--set",
         "elements.sfd.viscosity"),
    case("set-unknown-field", (*CHECK, "--set", "elements.sfd.viscocity=0.02"),
         "elements.sfd.viscocity", "viscocity"),
    case("set-unknown-section", (*CHECK, "--set", "analysis.respones.harmonics=5"),
         "analysis.respones", "respones"),
    case("set-bad-number", (*CHECK, "--set", "elements.sfd.viscosity=thick"),
         "elements.sfd.viscosity", "thick"),
    case("set-wrong-unit", (*CHECK, "--set", "elements.sfd.viscosity=0.01 Pa"),
         "elements.sfd.viscosity", "0.01 Pa"),
    case("set-harmonics-zero", (*CHECK, "--set", "analysis.response.harmonics=0"),
         "analysis.response.harmonics", "0"),
    case("set-harmonics-word", (*CHECK, "--set", "analysis.response.harmonics=many"),
         "analysis.response.harmonics", "many"),
    case("set-index-out-of-range", (*CHECK, "--set", "unbalance[3].magnitude=1 g*mm"),
         "unbalance[3]", "3"),
    case("set-eccentricity-range", (*CHECK, "--set",
                                    "analysis.response.max_eccentricity=1.5"),
         "analysis.response.max_eccentricity", "1.5"),
    case("set-bool-word", (*CHECK, "--set", "gravity.enabled=yes"), "gravity.enabled", "yes"),
    case("set-periods-negative", (*CHECK, "--set", "analysis.simulate.periods=-3"),
         "analysis.simulate.periods", "-3"),
    case("set-element-kind", (*CHECK, "--set", "elements.sfd.kind=damper"),
         "elements.sfd.kind", "damper"),
    case("set-cavitation", (*CHECK, "--set", "elements.sfd.cavitation=half"),
         "elements.sfd.cavitation", "half"),
    case("set-law", (*CHECK, "--set", "base.pitching.law=sine"), "base.pitching.law", "sine"),
    case("set-node-range", (*CHECK, "--set", "elements.sfd.node=40"), "elements.sfd.node",
         "40"),
    # ---- wrong types, units and ranges in the file ---------------------------------------
    case("length-furlongs", CHECK, "elements.sfd.length", "furlongs",
         replace=('length = "20 mm"', 'length = "3 furlongs"')),
    case("length-wrong-kind", CHECK, "elements.sfd.length", "3 kg",
         replace=('length = "20 mm"', 'length = "3 kg"')),
    case("length-list", CHECK, "rotor.shaft[0].length", "[1, 2]",
         replace=('length = "0.8 m"', "length = [1, 2]")),
    case("n-elements-float", CHECK, "rotor.shaft[0].n_elements", "2.5",
         replace=("n_elements = 16", "n_elements = 2.5")),
    case("n-elements-zero", CHECK, "rotor.shaft[0].n_elements", "0",
         replace=("n_elements = 16", "n_elements = 0")),
    case("negative-viscosity", CHECK, "elements.sfd.viscosity", "-0.01 Pa*s",
         replace=('viscosity = "0.01 Pa*s"', 'viscosity = "-0.01 Pa*s"')),
    case("clearance-negative", CHECK, "elements.sfd.clearance", "-1 mm",
         replace=('clearance = "0.15 mm"', 'clearance = "-1 mm"')),
    case("clearance-radius-and-ratio", CHECK, "elements.sfd", "clearance_ratio",
         replace=('radius = "40 mm"', 'radius = "40 mm"\nclearance_ratio = "0.4 %"')),
    case("length-to-diameter-range", CHECK, "elements.sfd.length_to_diameter", "50",
         replace=('length = "20 mm"', "length_to_diameter = 50")),
    case("derived-length-to-diameter", CHECK, "elements.sfd", "12.5",
         replace=('length = "20 mm"', 'length = "1 m"')),
    case("cavitation-bogus", CHECK, "elements.sfd.cavitation", "half",
         replace=('cavitation = "pi"', 'cavitation = "half"')),
    case("unknown-material", CHECK, "rotor.shaft[0].material", "stainless",
         replace=('n_elements = 16\nouter_radius = "25 mm"\nmaterial = "steel"',
                  'n_elements = 16\nouter_radius = "25 mm"\nmaterial = "stainless"')),
    case("inner-above-outer", CHECK, "rotor.shaft[0]", "30 mm",
         replace=('outer_radius = "25 mm"\nmaterial', 'outer_radius = "25 mm"\n'
                  'inner_radius = "30 mm"\nmaterial')),
    case("density-negative", CHECK, "materials.steel.density", "-7850",
         replace=('density = "7850 kg/m^3"', 'density = "-7850 kg/m^3"')),
    case("poisson-range", CHECK, "materials.steel.poisson_ratio", "0.7",
         replace=("poisson_ratio = 0.3", "poisson_ratio = 0.7")),
    case("unbalance-wrong-kind", CHECK, "unbalance[0].magnitude", "300 g",
         replace=('magnitude = "300 g*mm"', 'magnitude = "300 g"')),
    case("gravity-yes", CHECK, "gravity.enabled", "yes", append="[gravity]\nenabled = \"yes\"\n"),
    case("law-bogus", CHECK, "base.pitching.law", "sine",
         replace=('law = "constant"', 'law = "sine"')),
    case("harmonic-law-no-frequency", CHECK, "base.pitching", "harmonic",
         replace=('law = "constant", value = "2 rad/s"', 'law = "harmonic", value = "2 rad/s"')),
    case("callable-base-in-response", RESPONSE, "base.pitching.law", "callable",
         replace=('law = "constant", value = "2 rad/s"',
                  'law = "callable", callable = "numpy:sin"')),
    case("speed-range-empty", RESPONSE, "analysis.response.speed_range", "1000 rpm",
         replace=('start = "1000 rpm", stop = "8000 rpm"',
                  'start = "1000 rpm", stop = "1000 rpm"')),
    case("speed-range-zero-stop", CHECK, "analysis.response.speed_range.stop", "0 rpm",
         replace=('stop = "8000 rpm"', 'stop = "0 rpm"')),
    case("harmonics-too-many", CHECK, "analysis.response.harmonics", "500",
         replace=('harmonics = "auto"', "harmonics = 500")),
    case("response-node-range", RESPONSE, "analysis.response.nodes", "99",
         append="nodes = [1, 99]\n"),
    case("response-direction", CHECK, "analysis.response.directions", "x",
         append='directions = ["x"]\n'),
    # ---- unknown fields ------------------------------------------------------------------
    case("unknown-top-level", CHECK, "rotors", "rotors", append="[rotors]\nx = 1\n"),
    case("unknown-element-field", CHECK, "elements.sfd.viscocity", "viscocity",
         replace=('viscosity = "0.01 Pa*s"', 'viscocity = "0.01 Pa*s"')),
    case("unknown-disk-field", CHECK, "rotor.disks[1].weight", "weight",
         replace=('mass = "8 kg"', 'weight = "8 kg"')),
    case("unknown-analysis", CHECK, "analysis.responce", "responce",
         replace=("[analysis.response]", "[analysis.responce]")),
    # ---- element tables ------------------------------------------------------------------
    case("element-no-kind", CHECK, "elements.sfd.kind", "kind",
         replace=('kind = "sfd"\n', "")),
    case("element-unknown-kind", CHECK, "elements.sfd.kind", "squeeze",
         replace=('kind = "sfd"', 'kind = "squeeze"')),
    case("element-missing-viscosity", CHECK, "elements.sfd.viscosity", "viscosity",
         replace=('viscosity = "0.01 Pa*s"\n', "")),
    case("element-missing-node", CHECK, "elements.sfd.node", "node",
         replace=('kind = "sfd"\nnode = 1\n', 'kind = "sfd"\n')),
    case("element-node-range", CHECK, "elements.sfd.node", "99",
         replace=('kind = "sfd"\nnode = 1', 'kind = "sfd"\nnode = 99')),
    case("element-node-zero", CHECK, "elements.sfd.node", "0",
         replace=('kind = "sfd"\nnode = 1', 'kind = "sfd"\nnode = 0')),
    case("element-node-text", CHECK, "elements.sfd.node", "front",
         replace=('kind = "sfd"\nnode = 1', 'kind = "sfd"\nnode = "front"')),
    case("element-not-a-table", CHECK, "elements.damper", "0.01",
         append='[elements]\ndamper = 0.01\n'),
    case("two-sfds-one-node", CHECK, "elements.rear", "1",
         append='[elements.rear]\nkind = "sfd"\nnode = 1\nviscosity = "0.01 Pa*s"\n'
                'clearance = "0.15 mm"\nradius = "40 mm"\nlength = "20 mm"\n'),
    case("rub-missing-clearance", CHECK, "elements.seal.clearance", "nothing",
         append='[elements.seal]\nkind = "rub"\nnode = 6\ncontact_stiffness = "1e7 N/m"\n'),
    case("disk-node-range", CHECK, "rotor.disks[0].node", "60",
         replace=("node = 6\nmaterial", "node = 60\nmaterial")),
    case("support-node-zero", CHECK, "rotor.supports[0].node", "0",
         replace=("node = 17", "node = 0")),
    case("unbalance-node-range", CHECK, "unbalance[0].node", "18",
         replace=('node = 6\nmagnitude', 'node = 18\nmagnitude')),
    # ---- sweeps --------------------------------------------------------------------------
    case("axis-no-equals", (*SWEEP, "--axis", "elements.sfd.viscosity"), "--axis",
         "elements.sfd.viscosity"),
    case("axis-unknown-field", (*SWEEP, "--axis", "elements.sfd.viscocity=0.01,0.02"),
         "elements.sfd.viscocity", "viscocity"),
    case("axis-bad-value", (*SWEEP, "--axis", "elements.sfd.viscosity=0.01,thick"),
         "elements.sfd.viscosity", "thick"),
    case("axis-wrong-unit", (*SWEEP, "--axis", "unbalance[0].magnitude=1 g*mm,2 m"),
         "unbalance[0].magnitude", "2 m"),
    case("axis-empty", (*SWEEP, "--axis", "elements.sfd.viscosity="), "--axis",
         "elements.sfd.viscosity="),
    case("axis-every-point-invalid", (*SWEEP, "--axis", "elements.sfd.viscosity=-1,-2"),
         "elements.sfd.viscosity", "-1"),
    case("sweep-task-unknown", (*SWEEP, *AXIS, "--task", "transient"), "task", "transient"),
    case("sweep-task-option", (*SWEEP, *AXIS, "--task", "response:bogus=1"), "--task",
         "bogus"),
    case("sweep-task-no-value", (*SWEEP, *AXIS, "--task", "response:fast"), "--task", "fast"),
    case("sweep-no-axes", SWEEP, "analysis.sweep.axes", "[]"),
    case("sweep-axis-n-zero", SWEEP, "analysis.sweep.axes[0].n", "0",
         append='[analysis.sweep]\naxes = [{parameter = "elements.sfd.viscosity", '
                'start = 0.01, stop = 0.02, n = 0}]\n'),
    case("sweep-axis-no-stop", SWEEP, "analysis.sweep.axes[0]", "stop",
         append='[analysis.sweep]\naxes = [{parameter = "elements.sfd.viscosity", '
                'start = 0.01}]\n'),
    case("sweep-axis-parameter", SWEEP, "analysis.sweep.axes[0].parameter", "rotor.bogus",
         append='[analysis.sweep]\naxes = [{parameter = "rotor.bogus", values = [1, 2]}]\n'),
    # ---- fold curve ----------------------------------------------------------------------
    case("fold-from-mass", (*FOLD[:4], "--from", "1 kg", "--to", "6 rad/s"), "--from",
         "1 kg"),
    case("fold-to-text", (*FOLD[:4], "--from", "0 rad/s", "--to", "abc"), "--to", "abc"),
    case("fold-equal", (*FOLD[:4], "--from", "2 rad/s", "--to", "2 rad/s"), "--to", "2 rad/s"),
    case("fold-parameter-speed", (*FOLD, "--parameter", "speed"), "--parameter", "speed"),
    case("fold-parameter-unknown", (*FOLD, "--parameter", "base.bogus.value"), "--parameter",
         "base.bogus.value"),
    case("fold-harmonics-zero", (*FOLD, "--harmonics", "0"), "--harmonics", "0"),
]


class Reached(BaseException):
    """Raised by a solver entry point that a bad input must not reach."""


#: the solvers' entry points, by the module that calls them
SOLVERS = [("rotorsfd.analyses.response", "continue_periodic"),
           ("rotorsfd.analyses.fold_curve", "continue_periodic"),
           ("rotorsfd.analyses.orbit_branch", "continue_periodic"),
           ("rotorsfd.analyses.orbit_branch", "solve_periodic"),
           ("rotorsfd.analyses.modal", "campbell"),
           ("rotorsfd.analyses.static", "run_static"),
           ("rotorsfd.analyses.stability_chart", "stability_chart"),
           ("rotorsfd.analyses.td_integration", "run"),
           ("rotorsfd.studies.sweep", "execute_point"),
           ("rotorsfd.paper.run", "run_cases")]


@pytest.fixture
def no_work(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib

    def reached(*args, **kwargs):
        raise Reached("a solver was reached")

    # a first run on a cold numba cache says it compiles before the analysis' own checks
    # (a late config error then follows that progress line): not what these cases test
    monkeypatch.setattr("rotorsfd.api.announce_compilation", lambda *a, **k: None)

    for module, name in SOLVERS:
        try:
            mod = importlib.import_module(module)
        except ImportError:
            continue
        monkeypatch.setattr(mod, name, reached, raising=False)


def test_at_least_75_kinds():
    assert len(CASES) >= 75
    assert len({c.id for c in CASES}) == len(CASES)


@pytest.mark.parametrize("bad", CASES, ids=[c.id for c in CASES])
def test_bad_input_is_one_line_naming_field_value_and_what_is_allowed(
        bad: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None):
    text = BASE
    if bad.replace is not None:
        assert bad.replace[0] in text, bad.replace[0]
        text = text.replace(*bad.replace)
    text += bad.append
    cfg = tmp_path / "rotor.toml"
    cfg.write_text(text)
    out = tmp_path / "out"
    argv = [a.format(cfg=cfg, out=out) for a in bad.argv]
    try:
        status = cli.main(argv)
    except Reached:
        pytest.fail(f"{bad.id}: the work started before the bad input was found")
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    line = lines[0]
    assert status == 2, line
    assert line.startswith(cli.PREFIX), line
    assert "internal error" not in line, line
    assert bad.field in line, line
    assert bad.value in line, line
    assert ALLOWED.search(line.split(bad.value, 1)[-1] + line), line
    assert not out.exists() or not any(p.name != "INCOMPLETE.txt" for p in out.iterdir())


def test_root_cannot_hide_read_only_check(tmp_path, capsys, no_work):
    """A read-only output folder (skipped as root, who writes anyway)."""
    if os.geteuid() == 0:
        pytest.skip("root writes into read-only folders")
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        assert cli.main(["modal", str(PAPER), "-o", str(locked / "out")]) == 2
    finally:
        locked.chmod(0o700)
    assert "-o" in capsys.readouterr().err
