"""Two swims in two threads of one process give the serial result, bit for bit.

A Dask worker runs one evaluation per thread (``dask worker`` starts one thread
per core), so nothing an evaluation writes may be shared between threads:
solver workspaces, MuJoCo scratch data and its caches belong to the thread
(docs/development.md, "Layers"). The threads here share ONE scene, as a worker
shares the scene it caches, and swim different gaits, so any shared scratch
state would mix the two swims.

Interleaving is forced rather than hoped for: the interpreter's switch
interval drops to a microsecond, so the threads trade the GIL between almost
every pair of bytecodes (the Numba kernels hold it while they run; MuJoCo's
and NumPy's calls may release it). Each of the former shared scratch states
alone made every test here fail: the one ``MjData`` of ``Dynamics`` (diverged
swims, different values) and the process-wide PCG vectors (solver failures).
The process-wide multigrid levels could not be seen while the V-cycle kernel
holds the GIL from start to end; compiled with ``nogil=True`` they failed too.
"""

from __future__ import annotations

import sys
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.optimize import SwimObjective, prepare_optimization
from aquagait.optimize import optimize

EEL_GRID = ((40, 28), 0.032)
"""Coarse cells, and room for the 0.5 m eel swinging with 8 cells of water a side."""

FISH_GRID = ((28, 20, 22), 0.01)
"""1 cm cells, and room for the 10 cm fish with 8 cells of water a side."""


@pytest.fixture
def interleaved():
    """Switch threads as often as the interpreter can (restored afterwards)."""
    before = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    yield
    sys.setswitchinterval(before)


def _concurrently(*jobs):
    """Run the jobs in as many threads, started together; their results in order."""
    barrier = threading.Barrier(len(jobs))

    def run(job):
        barrier.wait()
        return job()

    with ThreadPoolExecutor(len(jobs)) as pool:
        return [f.result() for f in [pool.submit(run, job) for job in jobs]]


def _swim(scene, policy, seconds):
    return lambda: ag.rollout(scene, ag.init_state(scene), policy, seconds, record_fluid=False)


def _two_gaits(creature):
    """The default gait and a slower, reversed-phase one: two different swims."""
    other = creature.default_gait.copy()
    amplitudes = [i for i, n in enumerate(creature.gait.names) if n.startswith("amplitude")]
    phases = [i for i, n in enumerate(creature.gait.names) if n.startswith("phase")]
    other[amplitudes] *= 0.6
    other[phases] *= -1
    return creature.policy(), creature.policy(other)


def _assert_same(got, expected):
    for a, b in zip(got, expected, strict=True):
        for name in ("time", "qpos", "qvel", "torque", "energy"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name


@pytest.mark.parametrize(
    ("name", "grid", "seconds"), [("eel2d", EEL_GRID, 0.4), ("fish", FISH_GRID, 0.2)]
)
def test_two_swims_in_threads_equal_serial_swims(interleaved, name, grid, seconds):
    creature = ag.creatures.get(name)
    scene = ag.make_scene(creature, *grid, fluid="euler")
    swims = [_swim(scene, policy, seconds) for policy in _two_gaits(creature)]
    serial = [swim() for swim in swims]
    assert not np.array_equal(serial[0].qpos, serial[1].qpos)  # the swims differ
    _assert_same(_concurrently(*swims), serial)
    _assert_same([swim() for swim in swims], serial)  # and serial again after threads


def test_objective_in_a_thread_pool_equals_serial(interleaved):
    objective = SwimObjective("eel2d", *EEL_GRID, fluid="euler", seconds=0.3)
    creature = ag.creatures.get("eel2d")
    samples = [creature.default_gait * s for s in (1.0, 0.8, 0.6, 0.4)]
    serial = [objective(x) for x in samples]
    with ThreadPoolExecutor(2) as pool:
        threaded = list(pool.map(objective, samples))
    assert threaded == serial


def test_optimization_with_a_thread_pool_equals_serial(interleaved):
    setup = prepare_optimization(
        "eel2d", generations=2, popsize=4, seed=3, resolution=EEL_GRID[0],
        cell_size=EEL_GRID[1], cycles=0.2,
    )  # fmt: skip
    serial = optimize(setup.problem, setup.settings)
    with ThreadPoolExecutor(2) as pool:
        threaded = optimize(setup.problem, setup.settings, executor=pool)
    assert np.array_equal(threaded.best_x, serial.best_x)
    assert threaded.best_f == serial.best_f
    assert (threaded.evaluations, threaded.stopped) == (serial.evaluations, serial.stopped)
    assert all(row["failures"] == 0 for row in threaded.history)
    timeless = [{k: v for k, v in row.items() if k != "elapsed"} for row in serial.history]
    assert [{k: v for k, v in row.items() if k != "elapsed"} for row in threaded.history] == (
        timeless
    )
