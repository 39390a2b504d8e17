"""Every analysis result has the one shape of :mod:`rotorsfd.analyses.protocol` (issue 16,
item 5): ``summary() -> str``, ``plot() -> {file name: Figure}``, ``to_dataset() ->
xarray.Dataset`` and ``write(directory, plots=True) -> {file name: Path}``, the figures
written being the ones ``plot()`` draws (and none with ``plots=False``)."""

from __future__ import annotations

import inspect
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.analyses.protocol import AnalysisResult

EXAMPLES = Path(__file__).parents[2] / "examples"


def _result_classes() -> list[type]:
    from rotorsfd.analyses.attractors_result import CensusResult
    from rotorsfd.analyses.bifurcation_curves import BifurcationCurves
    from rotorsfd.analyses.bifurcation_diagram import BifurcationDiagramResult
    from rotorsfd.analyses.calibrate import CalibrationResult
    from rotorsfd.analyses.dual_spool_response import DualSpoolResponseResult
    from rotorsfd.analyses.fold_curve import FoldCurve
    from rotorsfd.analyses.modal import ModalRunResult
    from rotorsfd.analyses.response_result import ResponseResult
    from rotorsfd.analyses.runup_simulation import RunUpResult
    from rotorsfd.analyses.simulation_result import SimulationResult
    from rotorsfd.analyses.spool_modal import SpoolModalResult
    from rotorsfd.analyses.stability_chart_result import ChartResult
    from rotorsfd.analyses.static import StaticResult
    from rotorsfd.analyses.torus_response import TorusResponseResult
    from rotorsfd.studies.sweep import SweepResult

    return [CensusResult, BifurcationCurves, BifurcationDiagramResult, CalibrationResult,
            DualSpoolResponseResult, FoldCurve, ModalRunResult, ResponseResult, RunUpResult,
            SimulationResult, SpoolModalResult, ChartResult, StaticResult,
            TorusResponseResult, SweepResult]


@pytest.mark.parametrize("cls", _result_classes(), ids=lambda c: c.__name__)
def test_every_result_class_has_the_protocol_signatures(cls):
    for name in ("summary", "plot", "to_dataset", "write"):
        assert callable(getattr(cls, name, None)), f"{cls.__name__}.{name} missing"
    for name in ("summary", "plot", "to_dataset"):
        params = list(inspect.signature(getattr(cls, name)).parameters.values())[1:]
        required = [p.name for p in params if p.default is inspect.Parameter.empty
                    and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
        assert not required, f"{cls.__name__}.{name} requires {required}"
    write = inspect.signature(cls.write).parameters
    names = list(write)[1:3]
    assert names == ["directory", "plots"], f"{cls.__name__}.write{tuple(names)}"
    assert write["plots"].default is True


def _check_result(result, tmp_path: Path) -> None:
    import xarray as xr
    from matplotlib.figure import Figure

    assert isinstance(result, AnalysisResult)
    text = result.summary()
    assert isinstance(text, str) and text.strip()
    figures = result.plot()
    assert isinstance(figures, dict)
    for name, fig in figures.items():
        assert name.endswith(".png") and isinstance(fig, Figure), name
    ds = result.to_dataset()
    assert isinstance(ds, xr.Dataset) and len(ds.data_vars) > 0
    paths = result.write(tmp_path / "with", plots=True)
    assert set(figures) <= set(paths), set(figures) - set(paths)
    for name, path in paths.items():
        assert Path(path).is_file() and Path(path).name == name, (name, path)
    bare = result.write(tmp_path / "without", plots=False)
    assert not [n for n in bare if n.endswith(".png")]
    assert set(bare) == set(paths) - set(figures)


def test_static_result(tmp_path):
    from rotorsfd import api

    cfg = api.load_config(EXAMPLES / "paper_pitching.toml",
                          ["analysis.modal.speeds=[0, 400, 800]"])
    result = api.run_static(cfg)
    _check_result(result, tmp_path)
    assert list(result.plot()) == ["static_deflection.png"]
    ds = result.to_dataset()
    # the Dataset holds the numbers of the table: y of the last node at the last speed
    last = [r for r in result.rows() if r[0] == 800.0][-1]
    assert float(ds["q"].values[-1, 4 * (result.node_x.size - 1)]) == last[4]


def test_modal_result(tmp_path):
    from rotorsfd import api

    cfg = api.load_config(EXAMPLES / "paper_rotor.toml",
                          ["analysis.modal.speeds=[0, 500, 1000, 1500]",
                           "analysis.modal.n_critical=2"])
    result = api.run_modal(cfg)
    _check_result(result, tmp_path)
    ds = result.to_dataset()
    np.testing.assert_array_equal(ds["critical_speed"].values,
                                  [c.speed_rad_s for c in result.critical_speeds])
    np.testing.assert_array_equal(ds["frequency"].values, result.campbell.frequencies)


def test_chart_result(tmp_path):
    from rotorsfd.analyses.stability_chart import ChartAxis, ChartResult
    from rotorsfd.stability.chart import StabilityChart

    x, y = np.linspace(200.0, 340.0, 8), np.linspace(0.0, 0.5, 5)
    m = np.ones((8, 5))
    m[2:4, 3:] = 1.07
    xa = ChartAxis("base.pitching.frequency", x, "rad/s")
    ya = ChartAxis("base.pitching.angle_amplitude", y, "rad")
    chart = StabilityChart(x, y, m, np.ones_like(m, complex), tol=1e-5,
                           names=(xa.name, ya.name))
    _check_result(ChartResult(chart, xa, ya, 250.0, title="chart"), tmp_path)


def test_census_result(tmp_path):
    from test_attractors import FRACTION, duffing_model

    from rotorsfd.analyses.attractors import CensusOptions, census_map
    from rotorsfd.analyses.attractors_result import CensusResult

    opts = CensusOptions(n_starts=8, steps_per_period=64, displacement_fraction=FRACTION,
                         velocity_fraction=FRACTION, max_periods=300, harmonics=5)
    result = CensusResult(census_map([duffing_model()], opts), ["x0", "v0"], "Duffing")
    _check_result(result, tmp_path)
    ds = result.to_dataset()
    assert ds.sizes["start"] == 8
    assert float(ds["basin_fraction"].sum()) == pytest.approx(1.0, abs=1e-12)


def _fold_table(n: int, value_column: str) -> dict[str, np.ndarray]:
    """A fold pair meeting at a cusp: Omega~ = 1.1 -+ 0.05 sqrt(1 - v / 4) (v in rad/s)."""
    v = np.linspace(0.0, 4.0, n)
    half = 0.05 * np.sqrt(1.0 - v / 4.0)
    ratio = np.r_[1.1 - half, (1.1 + half)[::-1]]
    return {"curve": np.zeros(2 * n, np.int64),
            "segment": np.r_[np.zeros(n, np.int64), np.ones(n, np.int64)],
            "s": np.arange(2.0 * n), value_column: np.r_[v, v[::-1]],
            "speed_rad_s": 800.0 * ratio, "speed_ratio": ratio,
            "max_eps": np.full(2 * n, 0.5), "aliasing": np.full(2 * n, 1e-9),
            "amp_1_m": np.full(2 * n, 2e-5)}


def test_fold_curve_result(tmp_path):
    """A synthetic fold curve: the Dataset holds the table's numbers with their units, and
    the CSV written holds the same numbers (an independent path: the CSV writer); the
    unstable width at v = 0 is the table's 1.15 - 1.05 = 0.1."""
    import csv

    from rotorsfd.analyses.fold_curve import CuspPoint, FoldCurve

    f = FoldCurve("base.pitching", (0.0, 5.0), 800.0, 3, 64, (1,), [840.0, 920.0], [],
                  None, {}, [CuspPoint(880.0, 1.1, 4.0, 0.5)], True, "ok", {"total": 1.0},
                  title="synthetic fold pair")
    f.table = _fold_table(21, f.value_column)
    _check_result(f, tmp_path)
    assert list(f.plot()) == ["fold_curve.png"]
    ds = f.to_dataset()
    for key, values in f.table.items():
        np.testing.assert_array_equal(ds[key].values, values)
    assert ds[f.value_column].attrs["units"] == "rad/s"
    assert ds["amp_1_m"].attrs["units"] == "m" and ds["speed_rad_s"].attrs["units"] == "rad/s"
    np.testing.assert_array_equal(ds["start_fold"].values, [840.0, 920.0])
    assert float(ds["cusp_value"].values[0]) == 4.0
    assert float(f.unstable_width([0.0])[0]) == pytest.approx(0.1, abs=1e-12)
    with open(tmp_path / "with" / "fold_curve.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    np.testing.assert_array_equal([float(r["speed_ratio"]) for r in rows],
                                  ds["speed_ratio"].values)


def test_bifurcation_curves_result(tmp_path):
    """A synthetic two-kind table: ``curves.nc`` read back equals the table (kind as
    text), the summary counts the points of each kind."""
    import xarray as xr

    from rotorsfd.analyses.bifurcation_curves import BifurcationCurves, TurningPoint

    b = BifurcationCurves("base.pitching", (0.0, 5.0), 800.0, 3, 12, 256, [840.0],
                          [900.0], {}, [TurningPoint("saddle-node", 880.0, 1.1, 4.0)],
                          None, None, [], title="synthetic curves")
    t = _fold_table(11, b.value_column)
    kind = np.asarray(["saddle-node"] * 12 + ["period-doubling"] * 10, dtype=object)
    b.table = {"kind": kind, **t}
    _check_result(b, tmp_path)
    assert list(b.plot()) == ["curves.png"]
    assert "12 saddle-node points, 10 period-doubling points" in b.summary()
    with xr.open_dataset(tmp_path / "with" / "curves.nc") as ds:
        assert list(ds["kind"].values) == list(kind)
        for key, values in t.items():
            np.testing.assert_array_equal(ds[key].values, values)
        assert ds["speed_ratio"].attrs["units"] == "1"
