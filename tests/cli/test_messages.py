"""Messages in the user's terms (issue 24 item 1): where, which limit or field, what to
change; the solver's account (lam, ds, Newton, nl_limit) only with ``--verbose`` and in
the results files."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from rotors import tiny_rotor_text
from rotorsfd import cli
from rotorsfd.analyses.response_words import start_failure
from rotorsfd.cli import registry
from rotorsfd.cli.output import user_text
from rotorsfd.errors import ConvergenceError
from rotorsfd.studies.sweep import failure_text

JARGON = ("lam=", "nl_limit", "ds=", "Newton step damped", "[solver:")

#: a three-node rotor whose unbalance (2 kg m) drives the SFD journal to the housing at
#: the first speed of the range
TINY = tiny_rotor_text("front", "2 kg*m", "400 rad/s", "600 rad/s")


def test_user_text_drops_the_solver_account_unless_verbose():
    text = "branch ended at Omega~ = 1.4: raise x [solver: corrector [at lam=[1, 2]] failed]; ok"
    assert user_text(text) == "branch ended at Omega~ = 1.4: raise x; ok"
    assert user_text(text, verbose=True) == text
    assert user_text("a\nb [solver: c]\n") == "a b"
    assert user_text("no detail") == "no detail"


@pytest.mark.parametrize("where", ["before", "after", "none"])
def test_verbose_adds_the_solver_account(where, monkeypatch, capsys):
    monkeypatch.setattr(registry, "COMMANDS", dict(registry.COMMANDS))

    @cli.command("fail", "a failing command", config=False)
    def _fail(args, config):
        raise ConvergenceError("no periodic response at Omega~ = 0.8: raise "
                               "analysis.response.max_iterations [solver: lam=400 ds=1e-06]")

    argv = {"before": ["-v", "fail"], "after": ["fail", "--verbose"], "none": ["fail"]}[where]
    assert cli.main(argv) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("rotorsfd: error: no periodic response at Omega~ = 0.8: raise "
                          "analysis.response.max_iterations")
    assert ("[solver: lam=400 ds=1e-06]" in err) == (where != "none")


def test_response_start_failure_names_the_limit_and_what_to_change(tmp_path: Path, capsys):
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    argv = ["response", str(cfg), "-q", "-o", str(tmp_path / "out")]
    assert cli.main(argv) == 1
    line = capsys.readouterr().err.strip()
    assert line.startswith("rotorsfd: error: no periodic response at the start of the "
                           "range, Omega~ = 0.8 (400 rad/s): ")
    for words in ("SFD 'front' at node 1", "eps = 0.95", "analysis.response.max_eccentricity",
                  "analysis.response.speed_range.start", "up to 0.999"):
        assert words in line, words
    assert not any(j in line for j in JARGON), line
    assert cli.main([*argv, "--verbose"]) == 1
    verbose = capsys.readouterr().err.strip()
    assert verbose.startswith(line) and "[solver: " in verbose and "lam=400" in verbose


def _system(*limits: str | None) -> SimpleNamespace:
    elements = [SimpleNamespace(limit_label=lab, describe=lambda i=i: f"element {i}")
                for i, lab in enumerate(limits)]
    return SimpleNamespace(elements=elements)


@pytest.mark.parametrize(("solver", "words"), [
    ("Newton step damped 10 times: state limit reached", "past its validity measure = 0.9"),
    ("no convergence in 20 iterations (residual 3 > 1e-06)",
     "Newton did not converge in analysis.response.max_iterations"),
    ("singular extended Jacobian", "singular there"),
    ("at the initial guess: evaluation failed: overflow", "could not be evaluated")])
def test_start_failure_reasons(solver, words):
    text = start_failure(_system("eps", "delta"), "base.pitching.value", 2.0, 811.3, 0.9,
                         f"no periodic solution at lam=2: {solver}")
    assert text.startswith("no periodic response at the start of the range, "
                           "base.pitching.value = 2 rad/s: ")
    assert words in text
    assert "analysis.response.parameter_range" in text
    assert user_text(text) == text[:text.index(" [solver: ")]
    assert not any(j in user_text(text) for j in JARGON)


def test_a_failed_sweep_point_says_why_without_the_exception_type():
    assert failure_text(ConvergenceError("no periodic response at Omega~ = 0.8: ...")) == \
        "no periodic response at Omega~ = 0.8: ..."
    assert failure_text(ValueError("bad\nvalue")) == "internal error (ValueError): bad value"
