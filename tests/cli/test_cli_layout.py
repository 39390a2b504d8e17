"""The CLI's layout (issue 16 item 6): one module per command or group, registered by one
import line in ``rotorsfd/cli/__init__.py``; the parser built without numpy, pydantic or
the solvers, so that ``rotorsfd --help`` stays fast."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

from rotorsfd import cli

PACKAGE = Path(cli.__file__).parent
#: the modules that hold no command: registry and parser, main, option types, printing
INFRASTRUCTURE = {"__init__", "__main__", "app", "options", "output", "registry"}
HEAVY = ("numpy", "scipy", "pydantic", "xarray", "matplotlib", "numba", "tqdm")


def _registered_in(path: Path) -> set[str]:
    """Names of the ``@command(...)`` decorators in a module's source."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.FunctionDef):
            for d in node.decorator_list:
                if isinstance(d, ast.Call) and getattr(d.func, "id", "") == "command":
                    names.add(d.args[0].value)
    return names


def test_every_command_lives_in_its_own_module():
    modules = {p.stem: p for p in PACKAGE.glob("*.py")}
    by_module = {m: _registered_in(p) for m, p in modules.items() if m not in INFRASTRUCTURE}
    assert all(by_module.values()), f"command modules without a command: {by_module}"
    assert not any(_registered_in(modules[m]) for m in INFRASTRUCTURE if m in modules)
    assert set().union(*by_module.values()) == set(cli.COMMANDS)
    assert {n.split(" ")[0] for n in by_module["config"]} == {"config"}
    assert by_module["modal"] == {"modal", "fit-supports"}


def test_each_command_module_is_imported_by_one_line():
    tree = ast.parse((PACKAGE / "__init__.py").read_text())
    imported = [a.name for node in tree.body if isinstance(node, ast.ImportFrom)
                and node.module == "rotorsfd.cli" for a in node.names]
    commands = sorted(p.stem for p in PACKAGE.glob("*.py") if p.stem not in INFRASTRUCTURE)
    assert sorted(imported) == commands


def test_help_imports_no_heavy_module():
    """Building the parser (``rotorsfd --help``) imports no numerical library."""
    code = ("import sys; from rotorsfd.cli import build_parser; build_parser(); "
            f"print(sorted({{m.split('.')[0] for m in sys.modules}} & set({HEAVY!r})))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=60).stdout
    assert out.strip() == "[]"


def test_help_lists_the_commands_in_workflow_order(capsys):
    assert cli.main(["--help"]) == 0
    text = capsys.readouterr().out
    order = ["config", "modal", "fit-supports", "calibrate", "response", "static", "sweep",
             "simulate",
             "bifurcation-diagram", "stability-chart", "fold-curve", "bifurcation-curves",
             "attractors", "paper",
             "rerun", "import-ross",
             "export-matrices"]
    listed = re.findall(r"^ {4}(\S+)", text, flags=re.M)
    assert listed == order
