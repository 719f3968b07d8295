"""Short swims written to run directories and gathered for export, shared by the export tests."""

import pytest

import aquagait as ag
from aquagait.app import prepare_swim, run_swim
from aquagait.app.swim import write_swim
from aquagait.io import read_run
from aquagait.io.export import swim_export


def _exported(tmp_path_factory, name, seconds, resolution, cell_size, traces=200):
    out = tmp_path_factory.mktemp(name)
    setup = prepare_swim(name, seconds=seconds, resolution=resolution, cell_size=cell_size)
    write_swim(run_swim(setup), out)
    run = read_run(out)
    model = ag.creatures.get(name).model
    return out, swim_export(run.trajectory, model, name, traces=traces)


@pytest.fixture(scope="session")
def eel_export(tmp_path_factory):
    """(run directory, SwimExport) of eel2d swimming 0.3 s (10 frames) in the Euler fluid, 2D."""
    return _exported(tmp_path_factory, "eel2d", 0.3, (48, 24), 0.025)


@pytest.fixture(scope="session")
def fish_export(tmp_path_factory):
    """(run directory, SwimExport) of the fish swimming 0.2 s (7 frames) in the Euler fluid, 3D."""
    return _exported(tmp_path_factory, "fish", 0.2, (32, 24, 24), 0.008)
