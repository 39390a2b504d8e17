"""The package's import structure (issue 16 item 2): no import cycle between modules and no
private name imported across modules, imports inside functions included (walked with ast,
so a cycle hidden in a function body counts)."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "src" / "rotorsfd"


def _module_name(path: Path) -> str:
    parts = ["rotorsfd", *path.relative_to(ROOT).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in ROOT.rglob("*.py")}


def _imports(path: Path) -> list[tuple[str, list[str], int]]:
    """(imported module, names taken from it, line) of every rotorsfd import in ``path``."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0 \
                and node.module.split(".")[0] == "rotorsfd":
            names = [a.name for a in node.names]
            sub = [f"{node.module}.{n}" for n in names if f"{node.module}.{n}" in MODULES]
            out.append((node.module, [n for n in names if f"{node.module}.{n}" not in sub],
                        node.lineno))
            out += [(m, [], node.lineno) for m in sub]
        elif isinstance(node, ast.Import):
            out += [(a.name, [], node.lineno) for a in node.names
                    if a.name.split(".")[0] == "rotorsfd"]
    return out


def _graph() -> dict[str, set[str]]:
    """module -> the rotorsfd modules it imports (a package's import of its own
    submodules excluded: ``rotorsfd.elements`` registering its kinds is no cycle)."""
    graph: dict[str, set[str]] = {m: set() for m in MODULES}
    for name, path in MODULES.items():
        for target, _, _ in _imports(path):
            while target not in MODULES and "." in target:
                target = target.rsplit(".", 1)[0]
            if target in MODULES and target != name and not target.startswith(name + "."):
                graph[name].add(target)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_walker_sees_function_level_imports():
    """The check could fail: a function-level import is an edge (api -> analyses)."""
    assert "rotorsfd.analyses.response" in _graph()["rotorsfd.api"]
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_import_cycle():
    assert _cycles(_graph()) == []


def test_no_private_name_imported_across_modules():
    found = [f"{path.relative_to(ROOT)}:{line} imports {name} from {module}"
             for path in MODULES.values() for module, names, line in _imports(path)
             for name in names if name.startswith("_") and not name.startswith("__")]
    assert found == []



def _uncommented_function_imports(source: str) -> list[int]:
    """Lines of the imports inside a function (at any depth) without a comment on their
    lines or within the 3 lines above (the reason an import is deferred: a heavy optional
    dependency, start-up time, ...)."""
    lines = source.splitlines()
    found = []
    for fn in ast.walk(ast.parse(source)):
        if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for node in ast.walk(fn):
                if isinstance(node, (ast.Import, ast.ImportFrom)) and "#" not in " ".join(
                        lines[max(0, node.lineno - 4):node.end_lineno]):
                    found.append(node.lineno)
    return sorted(set(found))


def test_the_comment_check_could_fail():
    """A bare import in a nested block is found; a commented one, or one at the top, not."""
    source = ("import os\n\n\ndef f():\n    x = 1\n    y = 2\n    if x:\n        for _ in ()"
              ":\n            import json\n    # deferred: heavy\n    import math\n"
              "    return y\n")
    assert _uncommented_function_imports(source) == [9]


def test_every_function_level_import_says_why():
    found = [f"{path.relative_to(ROOT)}:{line}" for path in sorted(MODULES.values())
             for line in _uncommented_function_imports(path.read_text())]
    assert found == []
