"""The one shape of every analysis result.

Each ``run_x`` returns an object with

- ``summary() -> str``: what the command prints (lines in the user's terms);
- ``plot() -> dict[str, Figure]``: the figures by file name (``"campbell.png"``), empty
  when the analysis draws none; all drawing is in :mod:`rotorsfd.plots`;
- ``to_dataset() -> xarray.Dataset``: the numbers, with units and long names;
- ``write(directory, plots=True) -> dict[str, Path]``: the files written by name,
  atomically, the figures through :func:`~rotorsfd.io.atomic.save_figures`; JSON through
  :func:`~rotorsfd.io.atomic.json_safe` (never NaN in a results file).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Protocol, runtime_checkable

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["AnalysisResult"]


@runtime_checkable
class AnalysisResult(Protocol):
    """What every analysis result provides (module docstring)."""

    def summary(self) -> str: ...

    def plot(self) -> dict[str, Figure]: ...

    def to_dataset(self) -> xr.Dataset: ...

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]: ...
