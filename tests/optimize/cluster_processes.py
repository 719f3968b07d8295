"""A Dask scheduler and workers as processes started by a test, on 127.0.0.1 only.

Every process is started here, stopped by its own pid, and waited for with a
bound; ports are chosen free by the operating system (`--port 0`, the scheduler
file says which), and dashboards are off.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


class Cluster:
    """A Dask scheduler and workers, each a process started here, on 127.0.0.1."""

    def __init__(self, directory: Path):
        self.directory = directory
        self.env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(HERE), *sys.path])}
        self.processes: list[subprocess.Popen] = []
        self.workers: list[subprocess.Popen] = []
        self.scheduler: subprocess.Popen | None = None
        self.address = ""

    def _start(self, module: str, *arguments: str) -> subprocess.Popen:
        log = (self.directory / f"{module.rsplit('.', 1)[-1]}-{len(self.processes)}.log").open("w")
        process = subprocess.Popen(
            [sys.executable, "-m", module, *arguments],
            cwd=self.directory,
            env=self.env,
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
        )
        log.close()  # the child keeps its own descriptor
        self.processes.append(process)
        return process

    def start(self, workers: int = 2, nthreads: int = 1) -> None:
        """Start the scheduler, wait for its address (30 s at most), then the workers."""
        scheduler_file = self.directory / "scheduler.json"
        local = ("--host", "127.0.0.1", "--dashboard-address", "127.0.0.1:0", "--no-dashboard")
        self.scheduler = self._start(
            "distributed.cli.dask_scheduler",
            *local,
            *("--port", "0", "--scheduler-file", str(scheduler_file), "--no-jupyter"),
        )
        deadline = time.monotonic() + 30
        while not self.address:
            if self.scheduler.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"the Dask scheduler did not start: {self.logs()}")
            try:
                self.address = json.loads(scheduler_file.read_text())["address"]
            except (FileNotFoundError, json.JSONDecodeError, KeyError):
                time.sleep(0.05)
        for _ in range(workers):
            self.add_worker(nthreads)

    def add_worker(self, nthreads: int = 1) -> subprocess.Popen:
        """Start one more worker process with `nthreads` threads (no nanny)."""
        local = ("--host", "127.0.0.1", "--dashboard-address", "127.0.0.1:0", "--no-dashboard")
        worker = self._start(
            "distributed.cli.dask_worker",
            self.address,
            *local,
            *("--nthreads", str(nthreads), "--no-nanny"),
            *("--local-directory", str(self.directory)),
        )
        self.workers.append(worker)
        return worker

    def kill_scheduler(self) -> None:
        """SIGKILL the scheduler (as a lost machine would go) and reap it (10 s at most)."""
        os.kill(self.scheduler.pid, signal.SIGKILL)
        self.scheduler.wait(timeout=10)

    def logs(self) -> str:
        return "\n".join(path.read_text() for path in sorted(self.directory.glob("*.log")))

    def stop(self) -> None:
        """Workers first, then the scheduler (stopping both at once can hang a worker)."""
        stop([p for p in self.processes if p in self.workers])
        stop([p for p in self.processes if p not in self.workers])


def stop(processes: list[subprocess.Popen]) -> None:
    """SIGTERM, then SIGKILL whatever is still running after 5 s."""
    for process in processes:
        if process.poll() is None:
            process.terminate()
    for process in processes:
        try:
            process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=5)
