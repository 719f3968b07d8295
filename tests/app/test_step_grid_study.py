"""``aquagait check --convergence``: the step, grid and domain study, its table, files, errors."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app import SetupError
from aquagait.app.convergence import (
    CASES,
    convergence_study,
    enlarged_grid,
    format_convergence,
    refined_grid,
    write_convergence,
)
from aquagait.cli import main
from aquagait.io.run import read_json


@pytest.fixture(scope="module")
def study():
    return convergence_study("turtle2d", duration=0.2)


def test_every_case_swims_on_its_grid_and_step(study):
    turtle = ag.creatures.get("turtle2d")
    by_label = {s.case.label: s for s in study.swims}
    assert list(by_label) == [c.label for c in CASES]
    assert by_label["step / 6"].dt == pytest.approx(ag.EulerFluid().max_dt / 6)
    assert by_label["grid x2"].resolution == tuple(2 * n for n in turtle.resolution)
    assert by_label["grid x2"].cell_size == pytest.approx(turtle.cell_size / 2)
    # the domain: the same cell, 1.5x the cells, centred as the default, on its lattice
    default, larger = by_label["default"], by_label["domain x1.5"]
    assert larger.resolution == (96, 96) and larger.cell_size == default.cell_size
    lower = (np.asarray(default.origin) - larger.origin) / default.cell_size
    np.testing.assert_allclose(lower, (16, 16), atol=1e-9)  # whole cells: the same lattice
    assert all(s.distance > 0 and s.energy > 0 for s in study.swims)
    # the changes are the distances' ratios, as the verdicts print them
    assert study.step_change == pytest.approx(
        by_label["default"].distance / by_label["step / 6"].distance - 1
    )
    text = format_convergence(study)
    assert "grid x2" in text and "128x128" in text
    assert f"step: default vs step / 6: {study.step_change:+.1%}" in text
    assert study.domain_change == pytest.approx(default.distance / larger.distance - 1)
    assert f"domain: default vs domain x1.5: {study.domain_change:+.1%}" in text
    assert "96x96" in text and len(study.verdicts()) == 3


def test_the_refined_grid_keeps_the_domain():
    cells, h = refined_grid((64, 32, 32), 0.01, 1.5)
    assert cells == (96, 48, 48) and h * 96 == pytest.approx(0.64)


def test_the_enlarged_grid_adds_whole_cells_on_both_sides():
    assert enlarged_grid((64, 32, 32), 1.5) == (96, 48, 48)
    # 45 x 1.5 = 67.5: 67 keeps the centre on a cell centre, as 45 has it (68 would not)
    assert enlarged_grid((45, 28), 1.5) == (67, 42)
    assert enlarged_grid((45, 28), 1.0) == (45, 28)


def test_a_study_of_some_cases_leaves_the_other_verdicts_out():
    partial = convergence_study("turtle2d", duration=0.1, cases=CASES[:2])
    assert partial.step_change is None and partial.grid_change is None
    assert partial.domain_change is None
    assert partial.verdicts() == []


def test_bad_input_is_refused():
    with pytest.raises(SetupError, match="positive number of seconds"):
        convergence_study("turtle2d", duration=0)
    with pytest.raises(SetupError, match="unknown creature|no creature|not"):
        convergence_study("no-such-creature")


def test_the_files_round_trip(tmp_path, study):
    assert write_convergence(study, tmp_path) == ["convergence.txt", "convergence.json"]
    saved = read_json(tmp_path / "convergence.json")
    assert [s["case"] for s in saved["swims"]] == [c.label for c in CASES]
    assert saved["domain_change"] == pytest.approx(study.domain_change)
    assert saved["swims"][-1]["origin"] == pytest.approx(list(study.swims[-1].origin))
    text = (tmp_path / "convergence.txt").read_text()
    assert text == format_convergence(study) + "\n" and "domain x1.5" in text
    assert saved["fluid"]["near_body"] == ag.EulerFluid().near_body
    assert (tmp_path / "convergence.txt").read_text().startswith("turtle2d")


def test_the_command_prints_the_table(tmp_path, capsys):
    assert main(["check", "turtle2d", "--no-picture", "--convergence", "--seconds", "0.1",
                 "--out", str(tmp_path)]) == 0  # fmt: skip
    out = capsys.readouterr().out
    assert "grid x2" in out and "domain x1.5" in out and "convergence.json" in out
    assert f"{len(CASES)} swims" in out
    assert (tmp_path / "convergence.txt").exists()
