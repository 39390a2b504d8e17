"""Where grid points run: in this process, on a local process pool, or on a Dask cluster.

One interface (a subset of :mod:`concurrent.futures`) so the sweep has one code path::

    with make_executor(workers=None, scheduler=None) as ex:
        futures = [ex.submit(fn, arg) for arg in args]
        for fut in ex.as_completed(futures):
            fut.result()

- :class:`SerialExecutor`: runs each call lazily, in submission order, when
  ``as_completed`` reaches it (``workers=1``), with one BLAS thread.
- :class:`ProcessExecutor`: :class:`concurrent.futures.ProcessPoolExecutor` (forkserver),
  sized to the CPUs this process may use (``os.sched_getaffinity``); workers use
  single-threaded BLAS, ignore SIGINT (the parent stops them) and exit when the parent
  process dies (even by SIGKILL: no orphaned workers, and then the forkserver and the
  resource tracker, which live as long as the workers, exit too).
- :class:`DaskExecutor`: ``dask.distributed.Client(scheduler)``; ``submit`` /
  ``as_completed`` of distributed; single-threaded BLAS in each call (threadpoolctl).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing
import os
import select
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from typing import Any, Protocol

from rotorsfd.errors import ConfigError

BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS",
                         "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")


class FutureLike(Protocol):
    def result(self) -> Any: ...


class Executor(Protocol):
    """What the sweep needs from an executor."""

    workers: int
    description: str

    def submit(self, fn: Callable[..., Any], /, *args: Any) -> FutureLike: ...

    def share(self, obj: Any) -> Any: ...

    def as_completed(self, futures: Iterable[FutureLike]) -> Iterator[FutureLike]: ...

    def shutdown(self, interrupted: bool = False) -> None: ...

    def __enter__(self) -> Executor: ...

    def __exit__(self, *exc: Any) -> None: ...


def available_cpus() -> int:
    """CPUs this process may run on (affinity mask; ``os.cpu_count()`` elsewhere)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def single_threaded_blas() -> None:
    """Default the BLAS thread variables to 1 (effective in processes started after)."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


class _Base:
    workers = 1
    description = ""

    def __enter__(self) -> Any:
        return self

    def __exit__(self, exc_type: Any, exc: Any, tb: Any) -> None:
        self.shutdown(interrupted=exc_type is not None)

    def shutdown(self, interrupted: bool = False) -> None:
        pass

    def share(self, obj: Any) -> Any:
        """``obj`` as an argument for many calls (Dask: sent to the workers once)."""
        return obj


class _LazyFuture:
    def __init__(self, fn: Callable[..., Any], args: tuple[Any, ...]) -> None:
        self._fn, self._args = fn, args
        self._done = False
        self._value: Any = None
        self._error: BaseException | None = None

    def run(self) -> None:
        if not self._done:
            try:
                self._value = self._fn(*self._args)
            except Exception as exc:
                self._error = exc
            self._done = True

    def result(self) -> Any:
        self.run()
        if self._error is not None:
            raise self._error
        return self._value


class SerialExecutor(_Base):
    """Runs the calls one by one in this process, in submission order."""

    description = "serial (this process)"

    def submit(self, fn: Callable[..., Any], /, *args: Any) -> _LazyFuture:
        return _LazyFuture(fn, args)

    def as_completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        for fut in futures:
            with _one_blas_thread():
                fut.run()
            yield fut


def _exit_when_gone(pid: int) -> None:
    """Block until process ``pid`` has exited, then end this process at once."""
    try:
        fd = os.pidfd_open(pid)          # Linux >= 5.3: readable when the process exits
    except ProcessLookupError:
        os._exit(1)
    except (AttributeError, OSError):    # elsewhere: poll
        while True:
            time.sleep(0.5)
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                os._exit(1)
            except PermissionError:
                pass
    select.select([fd], [], [])
    os._exit(1)


def _init_worker(parent: int) -> None:
    threading.Thread(target=_exit_when_gone, args=(parent,), daemon=True,
                     name="rotorsfd-parent-watch").start()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in BLAS_THREAD_VARIABLES:
        os.environ[name] = "1"
    _one_blas_thread()  # also if numpy was loaded before (threadpoolctl: process-wide)


#: -W option handed to the resource tracker (it takes this process's warning options)
TRACKER_WARNINGS = "ignore::UserWarning:multiprocessing.resource_tracker"


def _quiet_resource_tracker() -> None:
    """No "leaked semaphore objects" warning from multiprocessing's resource tracker when
    the sweep is killed: the tracker then cleans them up, which is its job, and the
    warning tells the user nothing to do. Effective if the tracker is not running yet."""
    if TRACKER_WARNINGS not in sys.warnoptions:
        sys.warnoptions.append(TRACKER_WARNINGS)


class ProcessExecutor(_Base):
    """A local process pool of ``workers`` processes (default: the available CPUs)."""

    def __init__(self, workers: int | None = None) -> None:
        self.workers = max(1, workers or available_cpus())
        self.description = f"process pool, {self.workers} workers"
        single_threaded_blas()
        _quiet_resource_tracker()
        method = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() \
            else "spawn"
        self._pool = cf.ProcessPoolExecutor(self.workers, initializer=_init_worker,
                                            initargs=(os.getpid(),),
                                            mp_context=multiprocessing.get_context(method))

    def submit(self, fn: Callable[..., Any], /, *args: Any) -> cf.Future[Any]:
        return self._pool.submit(fn, *args)

    def as_completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        return cf.as_completed(list(futures))

    def shutdown(self, interrupted: bool = False) -> None:
        if not interrupted:
            self._pool.shutdown(wait=True)
            return
        processes = list(getattr(self._pool, "_processes", {}) .values())
        self._pool.shutdown(wait=False, cancel_futures=True)
        for p in processes:  # running points are abandoned, not awaited
            p.terminate()
        for p in processes:
            p.join(timeout=5)


def _one_blas_thread() -> Any:
    """A context with one BLAS thread (threadpoolctl), so that every executor computes
    with the same BLAS threading, hence the same rounding."""
    try:
        # optional dependency: threadpoolctl may be missing
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover
        return contextlib.nullcontext()
    return threadpool_limits(1)


def _limited(fn: Callable[..., Any], *args: Any) -> Any:
    """``fn(*args)`` with one BLAS thread (Dask workers run several calls at once)."""
    with _one_blas_thread():
        return fn(*args)


class DaskExecutor(_Base):
    """Grid points on a Dask distributed cluster at ``address`` (``tcp://HOST:PORT``)."""

    def __init__(self, address: str, timeout: float = 15.0) -> None:
        # deferred: distributed (loads dask, distributed, multiprocessing)
        from distributed import Client

        try:
            self._client = Client(address, timeout=timeout, set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise ConfigError("--scheduler", address, f"cannot connect ({exc})") from None
        info = self._client.scheduler_info()
        self.workers = max(1, sum(w.get("nthreads", 1) for w in info["workers"].values()))
        self.description = f"Dask cluster {address}, {self.workers} threads"
        self._futures: list[Any] = []

    def share(self, obj: Any) -> Any:
        return self._client.scatter(obj, broadcast=True, hash=False)

    def submit(self, fn: Callable[..., Any], /, *args: Any) -> Any:
        fut = self._client.submit(_limited, fn, *args, pure=False)
        self._futures.append(fut)
        return fut

    def as_completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        # deferred: distributed (loads dask, distributed, multiprocessing)
        from distributed import as_completed

        return iter(as_completed(list(futures), loop=self._client.loop))

    def shutdown(self, interrupted: bool = False) -> None:
        try:
            if interrupted and self._futures:
                self._client.cancel(self._futures)
        finally:
            self._client.close()


def make_executor(workers: int | None = None, scheduler: str | None = None) -> Executor:
    """Dask with ``scheduler``; serial for ``workers == 1``; else a process pool of
    ``workers`` (default: the available CPUs)."""
    if workers is not None and workers < 1:
        raise ConfigError("--workers", workers, "must be >= 1")
    if scheduler:
        return DaskExecutor(scheduler)
    n = workers or available_cpus()
    if n <= 1:
        return SerialExecutor()
    return ProcessExecutor(n)
