"""The result of a stability chart: its axes, the max |Floquet multiplier| over the grid,
the files (``chart.nc``, ``chart.png``) and the Figure 6 style plot."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.io import atomic
from rotorsfd.io.provenance import netcdf_attrs
from rotorsfd.stability.chart import StabilityChart

__all__ = ["ChartAxis", "ChartResult"]


@dataclass(frozen=True)
class ChartAxis:
    """A chart axis: the parameter path, its values (SI) and units."""

    path: str
    values: NDArray[np.float64]
    units: str

    @property
    def name(self) -> str:
        """Dimension name (the path with '.' and brackets as '_')."""
        # deferred: studies.grid (loads pydantic, multiprocessing)
        from rotorsfd.studies.grid import slug

        return slug(self.path)


@dataclass
class ChartResult:
    """The stability chart: ``chart.max_abs[i, j]`` at ``(x.values[i], y.values[j])``."""

    chart: StabilityChart
    x: ChartAxis
    y: ChartAxis
    speed: float | None
    natural_frequencies: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    title: str = ""
    config_toml: str = ""       # the resolved configuration it was run from, if any

    @property
    def stable(self) -> NDArray[np.bool_]:
        return self.chart.stable

    def to_dataset(self) -> Any:
        """xarray Dataset: max_abs_multiplier, stable, critical multiplier, axes with units,
        the base-frame natural frequencies at the chart speed (constant part)."""
        ds = self.chart.to_dataset()
        for ax in (self.x, self.y):
            ds[ax.name].attrs.update(units=ax.units, long_name=ax.path)
        ds["max_abs_multiplier"].attrs.update(units="1", long_name="max |Floquet multiplier|")
        ds["stable"].attrs.update(units="1",
                                  long_name=f"1 if max |mu| <= 1 + {self.chart.tol:g}")
        for part in ("re", "im"):
            ds[f"critical_{part}"].attrs.update(
                units="1", long_name=f"{dict(re='real', im='imaginary')[part]} part of the "
                "Floquet multiplier of largest modulus")
        ds["natural_frequency"] = ("mode", self.natural_frequencies)
        ds["natural_frequency"].attrs.update(
            units="rad/s", long_name="damped natural frequencies of the constant part "
            "(base rates at their mean) at the chart speed")
        ds.attrs.update(title=self.title, x=self.x.path, y=self.y.path,
                        speed_rad_s=float("nan") if self.speed is None else self.speed,
                        **netcdf_attrs())
        if self.config_toml:
            ds.attrs["config_toml"] = self.config_toml
        return ds

    def _words(self) -> dict[str, Any]:
        return {"tol": self.chart.tol, "speed": self.speed,
                "title": self.title or "Stability chart"}

    def plot_on(self, ax: Any) -> Any:
        """Figure 6 style on ``ax`` (:func:`rotorsfd.plots.chart.chart_axes`): unstable
        points shaded by max |mu| (white: stable), the boundary max |mu| = 1 + tol in
        black, islands ringed, the axes in words with their units, the title (wrapped,
        never cut) saying what the grid shows; returns ``ax``."""
        from rotorsfd.plots.chart import chart_axes  # deferred: matplotlib

        x, y = self.x, self.y
        return chart_axes(ax, x.values, y.values, self.chart.max_abs,
                          x_label=f"{x.path} [{x.units}]", y_label=f"{y.path} [{y.units}]",
                          **self._words())

    def plot(self) -> dict[str, Any]:
        """``chart.png``: :meth:`plot_on` on a figure of its own."""
        from rotorsfd.plots.chart import chart_figure  # deferred: matplotlib

        x, y = self.x, self.y
        return {"chart.png": chart_figure(x.values, y.values, self.chart.max_abs,
                                          x_path=x.path, y_path=y.path, x_units=x.units,
                                          y_units=y.units, **self._words())}

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """``chart.nc`` and (if ``plots``) ``chart.png`` written atomically into
        ``directory``."""
        out = Path(directory)
        paths = {"chart.nc": atomic.write_netcdf(self.to_dataset(), out / "chart.nc")}
        if plots:
            paths.update(atomic.save_figures(self.plot(), out, dpi=130))
        return paths

    def summary(self) -> str:
        """Points, unstable share and the largest multiplier."""
        ch = self.chart
        n_bad = int((~ch.stable).sum())
        i, j = np.unravel_index(int(np.argmax(ch.max_abs)), ch.max_abs.shape)
        return (f"stability chart {self.x.path} x {self.y.path}: {ch.max_abs.size} points, "
                f"{n_bad} unstable; max |mu| = {ch.max_abs[i, j]:.6g} at "
                f"{self.x.path} = {self.x.values[i]:.6g} {self.x.units}, "
                f"{self.y.path} = {self.y.values[j]:.6g} {self.y.units}")
