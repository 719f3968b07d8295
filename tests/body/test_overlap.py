"""The overlap volume of non-adjacent links: none at rest, exact boxes, refused input."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.body import Dynamics, load_model
from aquagait.body.overlap import MAX_OVERLAP_SAMPLES, overlap_volume
from aquagait.body.voxelize import body_shape

DEPTH = 0.04
HALF = np.array([0.05, 0.015, 0.02])


def chain(dim: int) -> str:
    """Three boxes in a chain (a - b - c): a and c are not adjacent."""
    half = np.append(HALF[:2], DEPTH / 2) if dim == 2 else HALF
    size = " ".join(map(str, half))
    inner = (
        f'<geom type="box" size="{size}"/><body name="b" pos="-.1 0 0">'
        f'<joint type="hinge" axis="0 0 1" range="-90 90"/><geom type="box" size="{size}"/>'
        f'<body name="c" pos="-.1 0 0"><joint type="hinge" axis="0 0 1" range="-90 90"/>'
        f'<geom type="box" size="{size}"/></body></body>'
    )
    if dim == 2:  # a planar root (x, y, theta) and the prism depth
        custom = f'<custom><numeric name="aquagait_depth" data="{DEPTH}"/></custom>'
        root = (
            '<joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>'
            '<joint type="hinge" axis="0 0 1" range="-90 90"/>'
        )
    else:
        custom, root = "", "<freejoint/>"
    return (
        f'<mujoco>{custom}<default><geom density="1000"/></default>'
        f'<worldbody><body name="a">{root}{inner}</body></worldbody></mujoco>'
    )


@pytest.mark.parametrize("name", ["eel2d", "fish"])
def test_no_overlap_at_the_reference_pose(name):
    creature = ag.creatures.get(name)
    model = creature.model
    shape = body_shape(model, creature.cell_size)
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    assert overlap_volume(shape, pos, rot, model.body_length / 100) == 0.0


@pytest.mark.parametrize("dim", [2, 3])
def test_overlap_of_a_chain_folded_back_onto_itself(dim):
    model = load_model(chain(dim))
    shape = body_shape(model, 0.01)
    rot = np.repeat(np.eye(3)[None], 3, axis=0)
    shift = np.array([0.037, 0.011, 0.006 if dim == 3 else 0.0])
    # c pushed into a (not adjacent); b deep into both (adjacent: does not count)
    pos = np.array([[0, 0, 0], [0.02, 0.005, 0], shift])
    if dim == 2:
        exact = np.prod(2 * HALF[:2] - np.abs(shift[:2])) * DEPTH
        lengths = 2 * HALF[:2] - np.abs(shift[:2])
    else:
        exact = np.prod(2 * HALF - np.abs(shift))
        lengths = 2 * HALF - np.abs(shift)
    spacing = 0.0007
    # an axis-aligned box of side L holds L/s +- 1 lattice points per axis; the baked
    # faces are exact away from the box edges, where they err by s_bake / 2
    tolerance = exact * np.sum((spacing + shape.spacing) / lengths)
    assert overlap_volume(shape, pos, rot, spacing) == pytest.approx(exact, abs=tolerance)
    pos[2] = [-0.2, 0, 0]  # c back in line: only the adjacent pairs overlap
    assert overlap_volume(shape, pos, rot, spacing) == 0.0


def test_bad_spacing_and_a_lattice_over_budget_are_refused():
    model = load_model(chain(3))
    shape = body_shape(model, 0.01)
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    with pytest.raises(ValueError, match="spacing must be a positive length"):
        overlap_volume(shape, pos, rot, 0.0)
    # the chain spans about 0.3 x 0.03 x 0.04 m: 1e-4 m needs ~3.6e9 lattice points
    with pytest.raises(ValueError, match=f"more than {MAX_OVERLAP_SAMPLES}; use a larger"):
        overlap_volume(shape, pos, rot, 1e-4)
    with pytest.raises(ValueError, match=r"link_pos has shape \(2, 3\); this body needs \(3, 3\)"):
        overlap_volume(shape, pos[:2], rot, 0.01)
