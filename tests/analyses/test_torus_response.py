"""`rotorsfd response` under a harmonic base law: the torus branch (quasi-periodic response)
end to end, its files against a direct call of rotorsfd.quasiperiodic, the Lyapunov
column, and a bad input (one line, exit 2)."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd.cli import main
from rotorsfd.io.config import load_config
from rotorsfd.io.torus_files import torus_coefficients
from rotorsfd.model.build import build_system
from rotorsfd.plots.torus import component_label

PITCHING = ('pitching = { law = "harmonic", frequency = "120 rad/s", '
            'angle_amplitude = "0.01 rad" }')
C = 1.27e-4


def read_csv(path):
    with path.open() as fh:
        return list(csv.DictReader(fh))


@pytest.mark.slow   # about 9 s CPU: 12 torus points at tol 1e-10, the files and plots
def test_torus_response_end_to_end(tmp_path, capsys):
    """Omega~ 0.6 .. 0.61 (reference 800 rad/s) under harmonic pitching: exit 0, the files,
    the summary line; the 1X amplitude of the journal at the last speed in torus.csv and
    torus.nc equals the torus solved alone there by rotorsfd.quasiperiodic (1e-9 C)."""
    from rotorsfd.quasiperiodic import TorusLattice, solve_torus, torus_problem

    config = small_rotor_toml(tmp_path / "small.toml", base=PITCHING)
    out = tmp_path / "out"
    status = main(["response", str(config), "-o", str(out), "--set",
                   "analysis.response.speed_range.stop_ratio=0.61", "--set",
                   "analysis.response.harmonics=2", "--set",
                   "analysis.response.tolerance=1e-10", "--set",
                   "analysis.stability.enabled=false"])
    text = capsys.readouterr().out
    assert status == 0, text
    assert "quasi-periodic response (torus, harmonics of Omega and w_b)" in text
    assert "ok: reached the end of the range" in text
    assert {"torus.csv", "torus.nc", "torus_components.png", "torus_spectrum.png"} <= {
        p.name for p in out.iterdir()}
    rows = read_csv(out / "torus.csv")
    assert float(rows[-1]["speed_ratio"]) == pytest.approx(0.61, rel=1e-12)
    assert all(np.isfinite(float(v)) for r in rows for v in r.values())

    import xarray as xr

    with xr.open_dataset(out / "torus.nc") as ds:
        ds = ds.load()
    assert ds.attrs["H1"] == 2 and ds.attrs["H2"] == 2
    assert "rotorsfd_version" in ds.attrs and "harmonic" in ds.attrs["config_toml"]
    assert ds["k1"].attrs["long_name"] and ds["speed_rad_s"].attrs["units"] == "rad/s"
    assert all("units" in ds[v].attrs and "long_name" in ds[v].attrs for v in ds.variables)
    grid = tuple(int(g) for g in ds.attrs["grid"])
    X_file = torus_coefficients(ds)[-1]
    k1, k2 = ds["k1"].values, ds["k2"].values
    i10 = int(np.nonzero((k1 == 1) & (k2 == 0))[0][0])

    system = build_system(load_config(config))
    speed = float(ds["speed_rad_s"].values[-1])
    assert speed == pytest.approx(0.61 * 800.0, rel=1e-12)
    alone = solve_torus(torus_problem(system), speed, TorusLattice(2, 2), grid=grid,
                        tol=1e-10)
    direct = abs(alone.X[TorusLattice(2, 2).index(1, 0), 0]) / C
    assert abs(float(rows[-1]["amp_1_y_1_0"]) - direct) < 1e-9
    assert abs(abs(X_file[i10, 0]) / C - direct) < 1e-9
    assert direct > 1e-3            # a real line, not round-off


def test_two_base_frequencies_is_one_line(tmp_path, capsys):
    """A torus has one base frequency: pitching at 120 rad/s with a heave at 100 rad/s
    exits 2 with one line naming the field and both values."""
    heave = 'z = { law = "harmonic", frequency = "100 rad/s", amplitude = "0.1 mm" }'
    config = small_rotor_toml(tmp_path / "small.toml", base=PITCHING + "\n" + heave)
    status = main(["response", str(config), "-o", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert status == 2
    assert len(err.splitlines()) == 1, err
    assert "base.pitching.frequency" in err and "base.z has 100" in err, err


def test_component_labels():
    assert [component_label(*k) for k in ((1, 0), (1, -2), (0, 1), (2, 1), (0, 0))] == [
        "1X", "1X - 2 w_b", "1 w_b", "2X + 1 w_b", "static"]


@pytest.mark.slow   # about 10 s: five Lyapunov exponents of 200 rotor periods
def test_torus_response_lyapunov_column(tmp_path):
    """With stability on: the exponent at the first point in torus.csv equals
    torus_lyapunov started on that torus (same integration, 1e-9), every one of the
    five points is marked stable (exponent + uncertainty < 0: the damped small rotor)."""
    from rotorsfd.analyses.torus_response import run_torus_response
    from rotorsfd.quasiperiodic.torus_stability import torus_lyapunov

    config = load_config(small_rotor_toml(tmp_path / "small.toml", base=PITCHING),
                         ["analysis.response.speed_range.stop_ratio=0.66"])
    result = run_torus_response(config, search_path=tmp_path, progress=False)
    paths = result.write(tmp_path / "out")
    rows = read_csv(paths["torus.csv"])
    marked = [r for r in rows if r["stable"] != ""]
    assert len(marked) == min(5, len(rows)) and all(r["stable"] == "1" for r in marked)
    b = result.branch
    ly = torus_lyapunov(result.system, b.lattice, b.X[0], b.omega[0], b.wb[0])
    assert float(rows[0]["lyapunov_per_period"]) == pytest.approx(ly.per_period, abs=1e-9)
    assert ly.per_period < 0


def test_torus_file_round_trip_and_no_nan(tmp_path):
    """torus.nc keeps the coefficients (k1, k2 axes in lattice order) exactly, and a NaN
    is refused (never written)."""
    from types import SimpleNamespace

    from rotorsfd.io.torus_files import torus_dataset, write_torus_netcdf
    from rotorsfd.quasiperiodic import TorusLattice

    lat = TorusLattice(2, 1)
    rng = np.random.default_rng(1)
    X = rng.normal(size=(3, lat.nk, 8)) + 1j * rng.normal(size=(3, lat.nk, 8))
    branch = SimpleNamespace(lattice=lat, X=X, omega=np.array([500.0, 510.0, 520.0]),
                             wb=np.full(3, 120.0), iterations=np.array([3, 2, 2]),
                             aliasing=np.zeros(3), limit=np.full(3, 0.2), s=np.arange(3.0),
                             grid=(16, 8), success=True, message="ok")
    ds = torus_dataset(branch, reference_speed=800.0, deflection={1: np.ones(3)})
    path = write_torus_netcdf(ds, tmp_path / "torus.nc")
    import xarray as xr

    with xr.open_dataset(path) as back:
        assert np.array_equal(torus_coefficients(back), X)
        assert [tuple(k) for k in zip(back["k1"].values, back["k2"].values,
                                      strict=True)] == [tuple(k) for k in lat.k]
        assert back["speed_ratio"].values[1] == pytest.approx(510.0 / 800.0, rel=1e-15)
    branch.X = X.copy()
    branch.X[0, 0, 0] = np.nan
    with pytest.raises(ValueError, match="X_real"):
        write_torus_netcdf(torus_dataset(branch, reference_speed=800.0, deflection={}),
                           tmp_path / "bad.nc")
    assert not (tmp_path / "bad.nc").exists()
