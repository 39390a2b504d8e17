"""All matplotlib code is in rotorsfd/plots/ (issue 16 item 5): no module outside it imports
matplotlib, at module level or inside a function (walked with ast), except under
``if TYPE_CHECKING:`` (type hints); and plots/, the lower layer, imports neither the paper
nor the analyses (they resolve their data and call it)."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "src" / "rotorsfd"


def _type_checking_lines(tree: ast.AST) -> set[int]:
    """The line numbers inside ``if TYPE_CHECKING:`` blocks (``typing.TYPE_CHECKING`` too)."""
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and (
                (isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING")
                or (isinstance(node.test, ast.Attribute) and node.test.attr == "TYPE_CHECKING")):
            for child in node.body:
                lines.update(range(child.lineno, (child.end_lineno or child.lineno) + 1))
    return lines


def imports(source: str) -> list[tuple[str, int, bool]]:
    """(module, line, under TYPE_CHECKING) of every import in ``source``."""
    tree = ast.parse(source)
    hints = _type_checking_lines(tree)
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.append((node.module, node.lineno, node.lineno in hints))
        elif isinstance(node, ast.Import):
            out += [(a.name, node.lineno, node.lineno in hints) for a in node.names]
    return out


def _offenders(top: str, where) -> list[str]:
    return [f"{p.relative_to(ROOT)}:{line} imports {m}"
            for p in sorted(ROOT.rglob("*.py")) if where(p.relative_to(ROOT))
            for m, line, hint in imports(p.read_text())
            if m.split(".")[0] == top.split(".")[0] and m.startswith(top) and not hint]


def test_the_walker_tells_hints_from_imports():
    src = ("from typing import TYPE_CHECKING\nimport typing\n"
           "if TYPE_CHECKING:\n    from matplotlib.figure import Figure\n"
           "if typing.TYPE_CHECKING:\n    import matplotlib.axes\n"
           "def f():\n    from matplotlib.lines import Line2D\n    import matplotlib\n")
    found = sorted((m, hint) for m, _, hint in imports(src) if m.startswith("matplotlib"))
    assert found == [("matplotlib", False), ("matplotlib.axes", True),
                     ("matplotlib.figure", True), ("matplotlib.lines", False)]


def test_matplotlib_only_in_plots():
    bad = _offenders("matplotlib", lambda rel: rel.parts[0] != "plots")
    assert not bad, "matplotlib outside rotorsfd/plots/:\n" + "\n".join(bad)


def test_plots_import_neither_paper_nor_analyses():
    bad = [*_offenders("rotorsfd.paper", lambda rel: rel.parts[0] == "plots"),
           *_offenders("rotorsfd.analyses", lambda rel: rel.parts[0] == "plots")]
    assert not bad, "plots/ importing a higher layer:\n" + "\n".join(bad)
