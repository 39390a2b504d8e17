"""The files and the Dataset of a modal result (one spool or against a spool):
``critical_speeds.csv``, ``campbell.csv``, ``campbell.png``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.io import atomic
from rotorsfd.linear import CampbellResult

__all__ = ["modal_dataset", "write_modal"]


def modal_dataset(campbell: CampbellResult, rows: list[tuple[Any, ...]], reference: float,
                  title: str) -> Any:
    """A modal result's Dataset: the Campbell diagram, ``critical_speed`` [rad/s] with its
    ``critical_mode`` and ``critical_whirl`` over ``critical`` (``rows``: mode, whirl,
    speed_rad_s, ...), and the reference speed."""
    ds = campbell.to_dataset()
    ds["critical_mode"] = ("critical", np.array([r[0] for r in rows], dtype=np.int32))
    ds["critical_whirl"] = ("critical", np.array([str(r[1]) for r in rows]))
    ds["critical_speed"] = ("critical", np.array([float(r[2]) for r in rows]),
                            {"units": "rad/s", "long_name": "critical speed"})
    ds.attrs.update(reference_speed_rad_s=float(reference), title=title)
    return ds


def write_modal(result: Any, out: Path, header: tuple[str, ...], plots: bool
                ) -> dict[str, Path]:
    """``critical_speeds.csv`` (``header``: the columns of the result's
    ``critical_speeds_rows()``), ``campbell.csv`` and (``plots``) ``campbell.png``."""
    paths = {"critical_speeds.csv": atomic.write_csv(out / "critical_speeds.csv", header,
                                                     result.critical_speeds_rows())}
    with atomic.atomic_path(out / "campbell.csv") as tmp:
        result.campbell.to_csv(tmp)
    paths["campbell.csv"] = out / "campbell.csv"
    if plots:
        paths.update(atomic.save_figures(result.plot(), out))
    return paths
