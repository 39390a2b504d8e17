"""The tutorial notebooks (``docs/notebooks/*.py``, jupytext percent scripts) run as
notebooks: each is converted by jupytext and executed by nbclient in a fresh Python kernel
from the repository root, and fails on any cell error. Their cells assert the key numbers
(critical speeds, fold speeds, cusp, torus lines, fitted stiffnesses) against the README's
values and against a second method in the same notebook, so a silently wrong result fails
too. The kernel must import the rotorsfd under test (checked in an injected first cell).

Executing all seven takes about 40 s of CPU (slow); the fast checks below keep the folder,
the site's navigation and the notebook format in step. Needs the ``docs`` extra
(``pip install ".[docs]"``: jupytext, nbclient, ipykernel), skipped without it.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import rotorsfd

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "docs" / "notebooks").glob("[0-9][0-9]_*.py"))
MKDOCS = ROOT / "mkdocs.yml"


def _ids() -> list[str]:
    return [p.stem for p in NOTEBOOKS]


def test_there_is_a_notebook_per_main_analysis():
    names = {p.stem.split("_", 1)[1] for p in NOTEBOOKS}
    assert {"modal", "response", "simulate", "fold_curve", "sweep"} <= names, names
    assert len(NOTEBOOKS) >= 6


@pytest.mark.parametrize("path", NOTEBOOKS, ids=_ids())
def test_notebook_is_a_percent_script_that_asserts(path):
    text = path.read_text(encoding="utf-8")
    assert "# %% [markdown]" in text and "\n# %%\n" in text, "not a jupytext percent script"
    assert re.search(r"^assert ", text, flags=re.MULTILINE), "no asserted number"
    assert "from rotorsfd import api" in text


@pytest.mark.parametrize("path", NOTEBOOKS, ids=_ids())
def test_notebook_is_in_the_site_navigation(path):
    assert f"notebooks/{path.name}" in MKDOCS.read_text(encoding="utf-8")


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=_ids())
def test_notebook_executes(path):
    jupytext = pytest.importorskip("jupytext", reason="needs the docs extra")
    nbclient = pytest.importorskip("nbclient", reason="needs the docs extra")
    pytest.importorskip("ipykernel", reason="needs the docs extra")
    from nbformat import v4

    nb = jupytext.read(path)
    here = str(Path(rotorsfd.__file__).resolve())
    nb.cells.insert(0, v4.new_code_cell(   # the kernel runs the package under test
        f"import rotorsfd, pathlib\nassert str(pathlib.Path(rotorsfd.__file__).resolve()) "
        f"== {here!r}, rotorsfd.__file__"))
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(ROOT)}})
    client.execute()     # CellExecutionError (with the cell and its traceback) on failure
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors
