"""Parameter studies: sweeps over config fields, run serially, on a local process pool or
on a Dask cluster, stored point by point (resumable), combined into labelled files.

>>> from rotorsfd.studies import run_sweep
>>> result = run_sweep(config, {"elements.sfd.clearance_ratio": ["0.4 %", "0.5 %"]}, "response",
...                    directory="out", workers=2)
>>> result.summary()
"""

from rotorsfd.studies.executors import (
    DaskExecutor,
    ProcessExecutor,
    SerialExecutor,
    available_cpus,
    make_executor,
)
from rotorsfd.studies.grid import Axis, Grid, GridPoint, grid_from_axes, grid_from_config
from rotorsfd.studies.store import PointStore
from rotorsfd.studies.sweep import SweepResult, load_sweep, run_sweep, sweep_dataset
from rotorsfd.studies.tasks import (
    PointOutput,
    ResponseTask,
    SyntheticTask,
    Task,
    make_task,
    unstable_intervals,
)

__all__ = [
    "Axis",
    "DaskExecutor",
    "Grid",
    "GridPoint",
    "PointOutput",
    "PointStore",
    "ProcessExecutor",
    "ResponseTask",
    "SerialExecutor",
    "SweepResult",
    "SyntheticTask",
    "Task",
    "available_cpus",
    "grid_from_axes",
    "grid_from_config",
    "load_sweep",
    "make_executor",
    "make_task",
    "run_sweep",
    "sweep_dataset",
    "unstable_intervals",
]
