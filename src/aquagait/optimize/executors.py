"""Executors for `optimize`: local worker processes, or a Dask cluster (docs/optimize.md).

Both are `concurrent.futures.Executor`s: `submit(fn, *args) -> Future`, `map`,
`shutdown`, and `with` blocks. `optimize(executor=None)` needs neither: it
evaluates serially in this process. All three give the same numbers for the
same seed, because values are placed by sample index (see `evaluate`).

Start-up cost of the process pool, measured on a 2-core Linux machine with
2 workers: the first generation takes 0.43 s more than later ones (the
forkserver starts, then each worker imports aquagait, with Numba and MuJoCo,
on its first task; "spawn" costs the same within 0.01 s); after that a task
costs about 0.2 ms of overhead. The pool lives for the whole run, so this is
paid once, not per generation. Workers never import pycma (1 s): only the
parent process runs CMA-ES.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import math
import multiprocessing
import os
import pickle
import threading
import time
from concurrent.futures.process import BrokenProcessPool

log = logging.getLogger(__name__)

# Workers are forked from a clean single-threaded server process (or spawned
# where there is no forkserver), never forked from this one: a fork of a process
# with Numba's or MuJoCo's threads running can deadlock in the child. Spawned or
# forkserver children import the main module again: guard scripts that call
# `optimize` with `if __name__ == "__main__":`.
START_METHOD = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"

DIST_HINT = "pip install 'aquagait[dist]'"

ONE_THREAD = {
    "OPENBLAS_NUM_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "NUMBA_NUM_THREADS": "1",
}
"""Thread pools of a worker process: one thread each. A sample's work is
serial (Numba kernels, MuJoCo, small dense algebra), so a BLAS pool of one
thread per core in every worker would only make the workers fight for the
cores. Set in the environment the workers start from, unless already set."""


def available_cores() -> int:
    """The CPU cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


class ProcessExecutor(cf.Executor):
    """A pool of worker processes that replaces itself when a worker dies.

    A `ProcessPoolExecutor` whose worker is killed is broken for good: its
    pending futures raise `BrokenProcessPool` and so does every later submit.
    This one starts a fresh pool on the next submit (or `lost()`) instead,
    having killed every worker of the broken one, so `optimize` can resubmit
    the lost samples (`Settings.retries`) and the run goes on.
    Only a fresh pool that cannot take work either (its workers cannot start)
    makes a submit raise, which `evaluate` reports as `ExecutorLost`.

    A pool's death fails every task it held, not only the one whose worker
    died, so each of them spends a retry; a sample lost `retries + 1` times
    gets the penalty. That stays a per-sample penalty rather than
    `ExecutorLost`: a sample that kills its worker every time (a crash in
    native code) would kill it on any executor, and stopping would only make
    every resume stop at it again.

    Args:
        workers: worker processes; None: every core this process may use.
        start_method: multiprocessing start method ("forkserver" or "spawn").
    """

    def __init__(self, workers: int | None = None, start_method: str = START_METHOD):
        workers = available_cores() if workers is None else workers
        if not isinstance(workers, int) or workers < 1:
            raise ValueError(f"workers must be a positive integer or None, got {workers!r}")
        self.workers = workers
        self._context = multiprocessing.get_context(start_method)
        self._lock = threading.Lock()
        self._closed = False
        self._pool = self._new_pool()
        self._out: set[cf.Future] = set()  # the pool's tasks not yet done

    def describe(self) -> str:
        """The evaluators in words, e.g. "2 worker processes"."""
        return f"{self.workers} worker process{'es' * (self.workers != 1)}"

    def _new_pool(self) -> cf.ProcessPoolExecutor:
        for name, value in ONE_THREAD.items():  # read once, as each library loads
            os.environ.setdefault(name, value)
        return cf.ProcessPoolExecutor(self.workers, mp_context=self._context)

    def submit(self, fn, /, *args, **kwargs) -> cf.Future:
        """Run `fn(*args, **kwargs)` in a worker process; start a fresh pool if it broke."""
        with self._lock:
            if self._closed:
                raise RuntimeError("cannot submit to a ProcessExecutor after shutdown")
            try:
                future = self._pool.submit(fn, *args, **kwargs)
            except BrokenProcessPool:
                self._replace_broken_pool()
                future = self._pool.submit(fn, *args, **kwargs)
            out = self._out
            out.add(future)
        future.add_done_callback(out.discard)
        return future

    def lost(self) -> str:
        """Never lost: "". But a broken pool is replaced here too, not only on a submit.

        `evaluate` asks this while it waits, so a task that the broken pool
        never failed (see `_replace_broken_pool`) is failed within a poll and
        resubmitted, even when no other task of the generation is.
        """
        with self._lock:
            if not self._closed and getattr(self._pool, "_broken", False):
                self._replace_broken_pool()
        return ""

    def _replace_broken_pool(self) -> None:
        """Retire the broken pool for good and start a fresh one; call holding the lock.

        CPython's pool (3.11) breaks with races: a worker it starts on a submit
        while it is breaking is never terminated (its manager thread, and then
        interpreter exit, wait for it for ever), and a task submitted then may
        never be failed. So every worker of the old pool is killed, and every
        task of it still out fails with BrokenProcessPool, which `evaluate`
        takes for a lost sample.
        """
        log.warning("a worker process died; starting %d fresh ones", self.workers)
        _kill(self._pool)
        for future in list(self._out):
            with contextlib.suppress(cf.InvalidStateError):  # the pool failed it meanwhile
                future.set_exception(BrokenProcessPool("the worker pool broke"))
        self._pool, self._out = self._new_pool(), set()

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Stop the workers (waiting for running tasks when `wait`)."""
        with self._lock:
            self._closed = True
        self._pool.shutdown(wait=wait, cancel_futures=cancel_futures)

    def kill(self) -> None:
        """Stop now: drop the waiting tasks and kill the workers, whatever they are doing."""
        with self._lock:
            self._closed = True
            _kill(self._pool)

    def __exit__(self, exc_type, exc, traceback) -> bool:
        """A `with` block left normally waits for the running tasks; one left by an
        exception (an error, Ctrl-C, the command's SIGTERM) kills the workers instead,
        as a 3D sample can take minutes and nothing would take its value."""
        if exc_type is None:
            self.shutdown(wait=True)
        else:
            self.kill()
        return False


def _kill(pool: cf.ProcessPoolExecutor) -> None:
    """Shut ``pool`` down without waiting, dropping its queued tasks, and kill its workers."""
    workers = list((getattr(pool, "_processes", None) or {}).values())  # shutdown drops it
    pool.shutdown(wait=False, cancel_futures=True)
    for worker in workers:
        worker.kill()


def local_executor(workers: int | None = None) -> ProcessExecutor:
    """Worker processes on this machine; None: one per available core."""
    return ProcessExecutor(workers)


WORKER_WAIT = 60.0
"""Seconds a Dask executor may have no worker thread before it counts as lost."""

LOOK = 1.0
"""Seconds between a Dask executor's questions to its scheduler about its workers."""


class DaskExecutor(cf.Executor):
    """A Dask `Client`'s executor plus the client, closed together by `shutdown`.

    Tasks are submitted with `pure=False`, so a resubmitted sample is a new
    task rather than the lost one looked up again. Dask itself reruns a task
    whose worker died on another worker (up to `distributed.scheduler.
    allowed-failures` times, then `KilledWorker`, which `optimize` retries).

    The executor is lost (`lost()`, which `evaluate` asks while it waits) when
    its client loses the scheduler (the client cancels every task then, and its
    reconnection would hang every later submit), or when the scheduler has had
    no worker thread for `worker_wait` seconds (tasks would wait for ever).

    Args:
        client: a connected `distributed.Client`.
        worker_wait: seconds without any worker thread before the executor is
            lost [s]; positive.

    Attributes:
        client: the `distributed.Client`, e.g. for `client.scheduler_info()`.
        address: the scheduler's address.
    """

    def __init__(self, client, worker_wait: float = WORKER_WAIT):
        if not worker_wait > 0:
            raise ValueError(f"worker_wait must be a positive number of seconds: {worker_wait!r}")
        self.client, self.worker_wait = client, float(worker_wait)
        self.address = getattr(client.scheduler, "address", "?")
        self._executor = client.get_executor(pure=False)
        self._looked_at = -math.inf  # time.monotonic() of the last look at the workers
        self._without_workers_since: float | None = None
        self._lost = ""  # lost()'s last answer

    def _threads(self) -> dict[str, int]:
        """Threads of each worker connected to the scheduler now ({} if it does not answer)."""
        if self.client.status != "running":
            return {}
        try:
            return self.client.nthreads(callback_timeout=10 * LOOK)
        except (OSError, TimeoutError):
            return {}

    @property
    def workers(self) -> int:
        """Worker threads connected now, over all Dask workers: samples run at once."""
        return sum(self._threads().values())

    def describe(self) -> str:
        """The evaluators in words, e.g. "3 worker threads on 2 Dask workers"."""
        threads = self._threads()
        total = sum(threads.values())
        return (
            f"{total} worker thread{'s' * (total != 1)} on {len(threads)} "
            f"Dask worker{'s' * (len(threads) != 1)} at {self.address}"
        )

    def lost(self) -> str:
        """Why this executor can evaluate nothing more, or "" while it can.

        Lost: the client has lost its scheduler, or the scheduler has had no
        worker for `worker_wait` s. The scheduler is asked about its workers at
        most once per `LOOK` s.
        """
        if self.client.status != "running":
            return f"lost the Dask scheduler at {self.address} (its client is {self.client.status})"
        now = time.monotonic()
        if now - self._looked_at < LOOK:
            return ""
        self._looked_at = now
        if sum(self._threads().values()):
            self._without_workers_since = None
            return ""
        if self._without_workers_since is None:
            self._without_workers_since = now
        if now - self._without_workers_since < self.worker_wait:
            return ""
        self._lost = (
            f"the Dask scheduler at {self.address} has had no worker for "
            f"{self.worker_wait:g} s (DaskExecutor.worker_wait)"
        )
        return self._lost

    def submit(self, fn, /, *args, **kwargs) -> cf.Future:
        """Run `fn(*args, **kwargs)` on a Dask worker."""
        return self._executor.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Finish (or cancel) this executor's tasks and close the client; the cluster stays.

        A lost executor never waits: with the scheduler gone only the client is
        closed, at once (waiting for or cancelling its tasks would ask a scheduler
        that is not there); with no worker left its tasks are cancelled.
        """
        if self.client.status != "running":
            with _quiet("distributed.client"):  # its cancelled reconnection logs a traceback
                self.client.close(timeout=10)
            return
        try:
            self._executor.shutdown(wait=wait and not cancel_futures and not self._lost)
        finally:
            self.client.close()


@contextlib.contextmanager
def _quiet(logger: str):
    """Silence a logger below CRITICAL inside the block."""
    logger = logging.getLogger(logger)
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        logger.setLevel(level)


def dask_executor(
    address: str, timeout: float = 30.0, worker_wait: float = WORKER_WAIT
) -> DaskExecutor:
    """Connect to a running Dask scheduler, e.g. "tcp://127.0.0.1:8786" (extra `dist`).

    Args:
        address: the scheduler's address, as `dask scheduler` prints it.
        timeout: seconds to wait for the connection.
        worker_wait: seconds the scheduler may have no worker before the run
            stops with `ExecutorLost` (see `DaskExecutor`).

    Returns:
        A `DaskExecutor`; `shutdown()` (or leaving a `with` block) closes the
        client. The scheduler and its workers keep running.
    """
    try:
        from distributed import Client
    except ImportError as error:
        raise ImportError(
            f"evaluating on a Dask cluster needs the 'dist' extra: {DIST_HINT}"
        ) from error
    try:
        client = Client(address, timeout=timeout, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as error:
        raise ConnectionError(
            f"could not reach a Dask scheduler at {address!r} within {timeout:g} s ({error}). "
            "Start one with `dask scheduler --host 127.0.0.1` and workers with "
            "`dask worker tcp://HOST:PORT`, then pass the scheduler's tcp://HOST:PORT."
        ) from error
    return DaskExecutor(client, worker_wait)


def check_picklable(objective, executor) -> None:
    """Fail early, with advice, if `objective` cannot travel to `executor`'s workers."""
    if executor is None:
        return
    if isinstance(executor, ProcessExecutor | cf.ProcessPoolExecutor):
        dumps = pickle.dumps
    elif isinstance(executor, DaskExecutor) or hasattr(executor, "get_executor"):
        try:
            from cloudpickle import dumps  # Dask's serializer
        except ImportError:
            return
    else:
        return
    try:
        dumps(objective)
    except Exception as error:
        raise TypeError(
            f"the objective {objective!r} cannot be sent to worker processes ({error}); "
            "make it a module-level function or an instance of a module-level class"
        ) from error
