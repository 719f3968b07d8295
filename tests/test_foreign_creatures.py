"""A creature from a file: thin parts thickened for the fluid by default (--no-thicken keeps
them), and the side-car's say on which way is forward."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.resolve import creature_key
from aquagait.body import load_model
from aquagait.body.dynamics import describe
from aquagait.cli import main
from aquagait.creatures import AS_WRITTEN, THICKEN_CELLS

FISH = """<mujoco model="thin-finned fish">
  <worldbody>
    <body name="head"><freejoint/>
      <geom name="head" type="ellipsoid" size=".04 .01 .015"/>
      <body name="tail" pos="-.04 0 0">
        <joint name="tail" axis="0 0 1" range="-40 40"/>
        <geom name="fin" type="box" pos="-.02 0 0" size=".02 .001 .012"/>
      </body>
    </body>
  </worldbody>
</mujoco>"""


@pytest.fixture
def thin(tmp_path):
    path = tmp_path / "thin.xml"
    path.write_text(FISH)
    return path


def fin_width(creature) -> float:
    return 2 * describe(creature.model.mj).geom_size[1, 1]


def test_a_files_thin_parts_get_a_cell_and_as_written_keeps_them(thin):
    thick = ag.creatures.load(thin)
    assert fin_width(thick) == pytest.approx(THICKEN_CELLS * thick.cell_size)
    assert any("thickened for the fluid" in note for note in thick.model.notes)
    written = ag.creatures.resolve(ag.creatures.as_written(thin))
    assert written.as_written and fin_width(written) == pytest.approx(0.002)
    np.testing.assert_allclose(thick.model.link_mass, written.model.link_mass, rtol=1e-12)
    # a worker finds each again by its key
    assert creature_key(written) == str(thin.resolve()) + AS_WRITTEN
    assert ag.creatures.resolve(creature_key(written)) is written
    assert ag.creatures.resolve(creature_key(thick)) is thick


@pytest.mark.parametrize("name", ag.creatures.names())
def test_the_library_creatures_are_at_least_a_cell_thick_already(name):
    """Thickening leaves every library creature as it was built."""
    creature = ag.creatures.get(name)
    model = load_model(creature.source, thicken_to=THICKEN_CELLS * creature.cell_size)
    assert model.notes == creature.model.notes


def test_check_says_what_was_thickened_and_no_thicken_keeps_it(thin, tmp_path, capsys):
    assert main(["check", str(thin), "--no-picture", "--out", str(tmp_path / "a")]) == 0
    assert "'fin' 2 -> " in capsys.readouterr().out
    argv = ["check", str(thin), "--no-picture", "--no-thicken", "--out", str(tmp_path / "b")]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "thickened" not in out and "thin.xml" in out


def test_the_side_car_turns_a_creature_to_face_its_forward(thin):
    thin.with_name("thin.aquagait.json").write_text('{"forward": [0, -1]}')
    creature = ag.creatures.load(thin)
    assert creature.model.forward == (0.0, -1.0, 0.0)
    tail = describe(creature.model.mj).link_pos[1]  # at -x as written: turned to -y
    np.testing.assert_allclose(tail, [0.0, -0.04, 0.0], atol=1e-12)
    thin.with_name("thin.aquagait.json").write_text('{"forward": [0, 0, 0]}')
    with pytest.raises(ag.creatures.CreatureError, match="forward: must not be all zeros"):
        ag.creatures.load(thin)
