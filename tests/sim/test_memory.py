"""A grid whose fluid would not fit in memory is refused before anything is allocated."""

import re
import tracemalloc
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import aquagait as ag
from aquagait.grid import Grid
from aquagait.sim import GridTooLarge, memory
from aquagait.sim.fluids import BYTES_PER_CELL
from aquagait.sim.memory import available_memory, check_memory


def test_a_grid_of_4000_cubed_is_refused_with_the_estimate_and_nothing_allocated():
    fish = ag.creatures.get("fish")
    # 6.4e10 cells at 380 bytes: 24 TB, more than any machine these tests run on
    tracemalloc.start()
    with pytest.raises(GridTooLarge) as refused:
        ag.make_scene(fish, resolution=(4000, 4000, 4000), fluid="euler")
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 50e6  # a step's fields there would be terabytes; the model is megabytes
    message = str(refused.value)
    assert "4000x4000x4000 grid" in message and "24.3 TB" in message
    assert "380 bytes a cell" in message and "is available" in message
    assert isinstance(refused.value, ValueError)  # what the commands report as bad input


def test_normal_grids_pass_and_fluids_without_fields_take_none(eel):
    fish = ag.creatures.get("fish")
    for creature in (eel, fish):
        scene = ag.make_scene(creature, fluid="euler")
        assert scene.fluid.memory(scene.grid) < available_memory()
    # the simple fluid's grid only frames pictures: any size goes
    big = ag.make_scene(fish, resolution=(4000, 4000, 4000), fluid="simple")
    assert big.fluid.memory(big.grid) == 0 and ag.Vacuum().memory(big.grid) == 0


def test_the_refusal_follows_the_memory_available_and_its_suggestions_fit(eel, monkeypatch):
    need = ag.EulerFluid().memory(Grid(eel.resolution, eel.cell_size))
    assert need == 340 * np.prod(eel.resolution)  # 2D, float64
    monkeypatch.setattr("aquagait.sim.scene.available_memory", lambda: need)
    ag.make_scene(eel, fluid="euler")  # exactly enough
    monkeypatch.setattr("aquagait.sim.scene.available_memory", lambda: need // 3)
    with pytest.raises(GridTooLarge, match=r"128x64 grid of 0.01 m cells") as refused:
        ag.make_scene(eel, fluid="euler")
    fewer = re.search(r"e\.g\. (\d+)x(\d+) \(--resolution\)", str(refused.value)).groups()
    coarser = float(re.search(r"cells of ([\d.]+) m \(--cell-size\)", str(refused.value))[1])
    fits = ag.EulerFluid().memory(Grid(tuple(map(int, fewer)), eel.cell_size))
    assert need // 4 < fits <= need // 3
    same_domain = tuple(round(n * eel.cell_size / coarser) for n in eel.resolution)
    assert ag.EulerFluid().memory(Grid(same_domain, coarser)) <= need // 3
    # float32 face velocities take less
    assert ag.EulerFluid(dtype=np.float32).memory(Grid((100, 100), 0.01)) == 285 * 10**4
    # unknown memory: no refusal
    check_memory(Grid((4000, 4000, 4000), 0.01), 10**15, None)


def test_the_memory_available_reads_meminfo_and_the_cgroup(tmp_path):
    assert 0 < available_memory()
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal: 2048 kB\nMemFree: 512 kB\nMemAvailable: 1024 kB\n")
    assert memory._meminfo_available(str(meminfo)) == 1024 * 1024
    limit, usage = tmp_path / "memory.max", tmp_path / "memory.current"
    usage.write_text("300\n")
    limit.write_text("max\n")
    assert memory._cgroup_room([(str(limit), str(usage))]) is None  # no limit
    limit.write_text("1000\n")
    assert memory._cgroup_room([(str(tmp_path / "none"), str(usage)), (str(limit), str(usage))])
    assert memory._cgroup_room([(str(limit), str(usage))]) == 700


def test_the_estimate_bounds_a_real_scene_per_cell(eel):
    """The calibration, at small sizes: tracemalloc's peak over a scene's first steps rises
    with the cells by less than ``BYTES_PER_CELL`` (a whole swim measured 1.00x of it, the
    first steps 0.92x), and not by much less, or the estimate would refuse grids that fit.
    Two sizes, so that what does not grow with the grid (the body) cancels; each in a
    thread of its own, as its scratch is kept per thread (``aquagait.fluid.scratch``) and
    a thread that swam a larger grid before would count none."""

    def peak(resolution):
        tracemalloc.start()
        scene = ag.make_scene(eel, resolution=resolution, fluid="euler")
        state = ag.init_state(scene)
        for _ in range(3):
            state = ag.step(scene, state, ag.EulerFluid().max_dt / 3, eel.policy())
        top = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        return top

    def in_a_new_thread(resolution):
        with ThreadPoolExecutor(1) as thread:
            return thread.submit(peak, resolution).result()

    warm = ag.make_scene(eel, fluid="euler")  # the kernels compiled
    ag.step(warm, ag.init_state(warm), 1 / 270, eel.policy())
    small, large = (366, 182), (732, 364)
    per_cell = (in_a_new_thread(large) - in_a_new_thread(small)) / (np.prod(large) - np.prod(small))
    assert 0.8 * BYTES_PER_CELL[2, 8] < per_cell < BYTES_PER_CELL[2, 8]
