"""run_sweep: identical files serially, on a process pool and on a Dask LocalCluster; failed
points recorded; Ctrl-C leaves valid partial files; resume recomputes nothing finished."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from sweep_helpers import sweep_toml

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import load_config
from rotorsfd.studies import DaskExecutor, SyntheticTask, load_sweep, run_sweep
from rotorsfd.studies.executors import ProcessExecutor, SerialExecutor

FILES = ("sweep.nc", "summary.csv", "sweep.json")
AXES = {"elements.sfd.clearance_ratio": ["0.4 %", "0.5 %", "0.6 %"],
        "unbalance[0].magnitude": ["40 g*mm", "50 g*mm"]}
TASK = SyntheticTask(fail_above=0.0055)     # the 0.6 % row fails


@pytest.fixture(scope="module")
def config(tmp_path_factory):
    return load_config(sweep_toml(tmp_path_factory.mktemp("cfg") / "rotor.toml"))


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  host="127.0.0.1", protocol="tcp",
                                  dashboard_address=None) as c:
        yield c


def _bytes(directory: Path) -> dict[str, bytes]:
    return {f: (directory / f).read_bytes() for f in FILES}


def test_identical_files_serial_pool_dask(config, cluster, tmp_path):
    outs = {}
    for name, ex in (("serial", SerialExecutor()), ("pool", ProcessExecutor(2)),
                     ("dask", DaskExecutor(cluster.scheduler_address))):
        with ex:
            run_sweep(config, AXES, TASK, directory=tmp_path / name, executor=ex,
                      progress=False)
        outs[name] = _bytes(tmp_path / name)
    assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
    assert outs["serial"] == outs["pool"] == outs["dask"]
    a, b = load_sweep(tmp_path / "serial"), load_sweep(tmp_path / "dask")
    xr.testing.assert_identical(a, b)


def test_failed_points_recorded_and_rest_complete(config, tmp_path):
    result = run_sweep(config, AXES, TASK, directory=tmp_path, workers=1, progress=False)
    assert result.complete and result.counts() == {"ok": 4, "incomplete": 0, "failed": 2,
                                                   "pending": 0}
    ds = load_sweep(tmp_path)
    assert ds.sizes == {"elements_sfd_clearance_ratio": 3, "unbalance_0_magnitude": 2, "sample": 5}
    assert ds["elements_sfd_clearance_ratio"].attrs == {"long_name": "elements.sfd.clearance_ratio",
                                               "units": "1"}
    assert ds["unbalance_0_magnitude"].attrs["units"] == "kg*m"
    status = ds["status"].values
    assert status.tolist() == [[0, 0], [0, 0], [2, 2]]
    assert ds["status"].attrs["flag_meanings"] == "ok incomplete failed pending"
    assert str(ds["message"].values[2, 0]).startswith("synthetic failure")
    assert ds["message"].values[0, 0] == ""
    total = ds["total"].values
    np.testing.assert_array_equal(total[:2], [[0.00404, 0.00405], [0.00504, 0.00505]])
    assert np.isnan(total[2]).all()                           # masked _FillValue
    with xr.open_dataset(tmp_path / "sweep.nc", mask_and_scale=False) as raw:
        assert np.isnan(raw["total"].attrs["_FillValue"])
        assert raw["even"].attrs["_FillValue"] == -127        # bool -> int8 with fill
        assert raw["n_sample"].values[2].tolist() == [0, 0]   # no data at failed points
    lines = (tmp_path / "summary.csv").read_text().splitlines()
    assert lines[0] == ("elements_sfd_clearance_ratio,unbalance_0_magnitude_kg_m,point_id,status,"
                        "message,total,echo_0,echo_1,even,label")
    assert lines[1].startswith("0.004,4e-05,000000,ok,,0.00404,0.004,4e-05,")
    assert lines[5].startswith("0.006,4e-05,000004,failed,synthetic failure: 0.006 > 0.0055")
    assert lines[5].endswith(",,,,,")                          # empty = missing
    manifest = json.loads((tmp_path / "sweep.json").read_text())
    assert manifest["complete"] is True and manifest["counts"]["failed"] == 2
    # the task's echo columns prove each point ran with its own config values
    np.testing.assert_array_equal(ds["echo_0"].values[:2], [[0.004, 0.004], [0.005, 0.005]])


_CALLS: list[tuple[float, ...]] = []


class InterruptingTask(SyntheticTask):
    """Same spec as SyntheticTask; Ctrl-C (KeyboardInterrupt) at its 4th call."""

    def __call__(self, config, values):
        _CALLS.append(tuple(values.values()))
        if len(_CALLS) == 4:
            raise KeyboardInterrupt
        return super().__call__(config, values)


def test_interrupt_leaves_partial_result_and_resume_finishes(config, tmp_path):
    full = tmp_path / "full"
    run_sweep(config, AXES, TASK, directory=full, workers=1, progress=False)
    part = tmp_path / "part"
    _CALLS.clear()
    with pytest.raises(KeyboardInterrupt):
        run_sweep(config, AXES, InterruptingTask(fail_above=0.0055), directory=part,
                  workers=1, progress=False)
    ds = load_sweep(part)                                    # valid, marked partial
    assert ds.attrs["complete"] == 0 and ds.attrs["n_pending"] == 3
    assert ds["status"].values.ravel().tolist() == [0, 0, 0, 3, 3, 3]
    assert json.loads((part / "sweep.json").read_text())["complete"] is False
    assert "pending" in (part / "summary.csv").read_text()
    assert sorted(p.name for p in (part / "points").iterdir()) == [
        "000000.json", "000001.json", "000002.json"]          # no temporary files left
    log = tmp_path / "resume.log"
    result = run_sweep(config, AXES, SyntheticTask(fail_above=0.0055, log=str(log)),
                       directory=part, workers=2, progress=False, resume=True)
    assert result.computed == 3 and result.complete
    assert len(log.read_text().splitlines()) == 3            # only the pending points
    assert _bytes(part) == _bytes(full)
    again = run_sweep(config, AXES, TASK, directory=part, workers=1, progress=False,
                      resume=True)
    assert again.computed == 0 and _bytes(part) == _bytes(full)


def test_resume_recomputes_stale_and_retries_failed(config, tmp_path):
    run_sweep(config, AXES, TASK, directory=tmp_path, workers=1, progress=False)
    with pytest.raises(ConfigError, match="--resume"):
        run_sweep(config, AXES, TASK, directory=tmp_path, workers=1, progress=False)
    r = run_sweep(config, AXES, TASK, directory=tmp_path, workers=1, progress=False,
                  resume=True, retry_failed=True)
    assert r.computed == 2                                   # the failed points only
    changed = load_config(sweep_toml(tmp_path / "other.toml"),
                          ["elements.sfd.viscosity=0.006 Pa*s"])
    r = run_sweep(changed, AXES, TASK, directory=tmp_path, workers=1, progress=False,
                  resume=True)
    assert r.computed == 6                                   # another config: all stale


def test_resume_with_an_extended_grid_reuses_finished_values(config, tmp_path):
    run_sweep(config, {"elements.sfd.clearance_ratio": ["0.4 %", "0.5 %"]}, TASK,
              directory=tmp_path / "a", workers=1, progress=False)
    log = tmp_path / "log"
    extended = {"elements.sfd.clearance_ratio": ["0.3 %", "0.4 %", "0.45 %", "0.5 %"]}
    r = run_sweep(config, extended, SyntheticTask(fail_above=0.0055, log=str(log)),
                  directory=tmp_path / "a", workers=1, progress=False, resume=True)
    assert r.computed == 2 and len(log.read_text().splitlines()) == 2
    run_sweep(config, extended, TASK, directory=tmp_path / "b", workers=1, progress=False)
    assert _bytes(tmp_path / "a") == _bytes(tmp_path / "b")
    rec = json.loads((tmp_path / "a" / "points" / "000003.json").read_text())
    assert rec["index"] == [3] and rec["values"] == {"elements.sfd.clearance_ratio": 0.005}


def test_a_grid_invalid_everywhere_is_a_config_error(config, tmp_path):
    with pytest.raises(ConfigError, match=r"law = 'off'.*every grid point"):
        run_sweep(config, {"base.pitching.value": [1.0, 2.0]}, TASK, directory=tmp_path,
                  workers=1, progress=False)
    r = run_sweep(config, {"elements.sfd.clearance_ratio": [0.004, 1.5]}, TASK,
                  directory=tmp_path / "b", workers=1, progress=False)
    assert r.status("000001") == "failed"                   # one bad value: recorded
    assert "clearance" in r.records["000001"]["message"]


def test_a_folder_in_use_is_refused(config, tmp_path):
    from rotorsfd.studies.store import PointStore

    with PointStore(tmp_path).lock():
        with pytest.raises(ConfigError, match="another sweep is running"):
            run_sweep(config, AXES, TASK, directory=tmp_path, workers=1, progress=False)
    run_sweep(config, AXES, TASK, directory=tmp_path, workers=1, progress=False)


def test_grid_and_task_from_config(tmp_path):
    config = load_config(sweep_toml(tmp_path / "rotor.toml"))
    r = run_sweep(config, None, "synthetic", directory=tmp_path / "o", workers=1,
                  progress=False)
    assert r.grid.shape == (2, 3) and r.counts()["ok"] == 6
    with pytest.raises(ConfigError, match="allowed: response, simulate"):
        run_sweep(config, None, "stability", directory=tmp_path / "p", progress=False)


class DyingTask(SyntheticTask):
    """Kills its worker process at the last grid value (a crash, not an exception)."""

    def __call__(self, config, values):
        if list(values.values())[-1] > 4.5e-5:
            import os

            os._exit(3)
        return super().__call__(config, values)


def test_dead_worker_leaves_points_pending(config, tmp_path):
    with ProcessExecutor(2) as ex:
        r = run_sweep(config, AXES, DyingTask(), directory=tmp_path, executor=ex,
                      progress=False)
    assert not r.complete and r.lost >= 3 and "BrokenProcessPool" in r.lost_message
    assert r.counts()["pending"] >= 3 and r.counts()["failed"] == 0
    assert "PARTIAL" in r.summary()
    assert load_sweep(tmp_path).attrs["complete"] == 0
