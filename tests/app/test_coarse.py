"""Coarse-to-fine optimization: the coarse grid, and a run that ranks coarse and answers fine."""

import json

import pytest

import aquagait as ag
from aquagait.app import prepare_optimization
from aquagait.app.coarse import coarse_grid
from aquagait.cli import main


def test_the_coarse_grid_spans_the_same_water_and_keeps_the_clearance_in_metres(eel):
    grid = coarse_grid(eel, (128, 64), 0.01, 2)
    assert grid.resolution == (64, 32) and grid.cell_size == pytest.approx(0.02)
    assert grid.clearance == 4  # 8 cells of 1 cm: 4 of 2 cm
    fish = ag.creatures.get("fish")
    coarse = coarse_grid(fish, fish.resolution, fish.cell_size, 2)
    # half of 64x32x32 leaves the 45 mm tall fin less than 4 + 2 cells of 1 cm from the walls
    assert coarse.resolution == (32, 16, 18)
    fluid = ag.sim.EulerFluid(clearance=coarse.clearance)
    ag.make_scene(fish, coarse.resolution, coarse.cell_size, fluid=fluid)  # it holds the fish
    assert "thinnest: 'caudal'" in coarse.notes[0]  # 5 mm: half a 10 mm cell


def test_a_factor_that_does_not_coarsen_is_refused(eel):
    with pytest.raises(ValueError, match="factor must be a number > 1"):
        coarse_grid(eel, (128, 64), 0.01, 1.0)


def test_the_setup_ranks_on_the_coarse_grid_and_refines_on_the_target(eel):
    setup = prepare_optimization("eel2d", resolution=(64, 32), cell_size=0.02, coarse=2)
    assert (setup.objective.resolution, setup.objective.cell_size) == ((32, 16), 0.04)
    assert setup.objective.clearance == 4 and setup.target.clearance is None
    assert (setup.target.resolution, setup.target.cell_size) == ((64, 32), 0.02)
    assert setup.problem.refine is setup.target and setup.settings.refine_top == 2
    assert setup.config()["target_grid"] == [(64, 32), 0.02]
    plain = prepare_optimization("eel2d", resolution=(64, 32), cell_size=0.02)
    assert plain.problem.refine is None and plain.target is plain.objective


def test_the_optimize_command_searches_coarse_and_swims_the_best_on_the_target_grid(tmp_path):
    out = tmp_path / "run"
    argv = ["optimize", "eel2d", "--coarse", "2", "--refine-top", "1", "--generations", "2"]
    argv += ["--popsize", "3", "--workers", "1", "--resolution", "64", "32"]
    assert main([*argv, "--cell-size", "0.02", "--out", str(out), "--no-video"]) == 0
    log = (out / "optimization.csv").read_text().splitlines()
    header, rows = log[0].split(","), [row.split(",") for row in log[1:]]
    refined = [row[header.index("refinements")] for row in rows]
    assert refined == ["2", "3"]  # the start on the target grid, then one a generation
    config = json.loads((out / "config.json").read_text())
    assert config["resolution"] == [64, 32]  # the best gait swims on the target grid
    assert config["optimization"]["resolution"] == [32, 16]
    settings = config["optimization"]["fluid_settings"]  # what the samples were ranked in
    assert settings["boundary"] == "voxelize_subcell" and settings["clearance"] == 4
