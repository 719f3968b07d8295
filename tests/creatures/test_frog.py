"""The frog (paper Figure 12, Table 1): 18 hinges, 18 parameters by mirroring, hind legs first."""

import pytest

import aquagait as ag
from aquagait.app.swim import prepare_swim, run_swim
from aquagait.body.shape import body_shape, link_thickness
from aquagait.creatures import get

HIND = ("hip_abd", "hip_flex", "knee", "ankle", "tmt", "foot_twist")
FORE = ("shoulder_abd", "shoulder_flex", "elbow")
RHO = 1000.0


@pytest.fixture(scope="module")
def frog():
    return get("frog")


def test_frog_matches_table_1(frog):
    assert frog.dim == 3
    assert len(frog.model.actuated_dofs) == 18
    assert frog.gait.size == 18  # 9 left DOFs x (amplitude, phase); the right ones mirror them
    assert frog.resolution == (96, 80, 56)  # the paper: 96x64x48; ours holds a wide kick
    assert frog.gait.period == 1.0 and frog.gait.offset == 0.0
    assert frog.gait.free == ("amplitude", "phase")


def test_right_limbs_mirror_the_left_and_hind_legs_are_optimized_first(frog):
    mirror = {dof: (source, sign) for dof, source, sign in frog.gait.mirror}
    assert mirror == {f"{n}_r": (f"{n}_l", -1) for n in HIND + FORE}
    hind, fore = frog.gait.groups
    assert set(hind) == {f"{n}_{s}" for n in HIND for s in "lr"}
    assert set(fore) == {f"{n}_{s}" for n in FORE for s in "lr"}
    # the hind group's parameters are the 12 of the left hind leg, the fore group's the other 6
    names = frog.gait.names
    assert {names[i] for i in frog.gait.group_indices(0)} == {
        f"{k}[{n}_l]" for k in ("amplitude", "phase") for n in HIND
    }
    assert len(frog.gait.group_indices(1)) == 6


def test_mirrored_limbs_are_reflections(frog):
    """Left and right links have equal masses and reflected rest positions (x-z plane)."""
    model = frog.model
    pos, _ = ag.make_scene(frog, fluid="none").dynamics.link_poses(model.qpos0)
    for left in (n for n in model.links if n.endswith("_l")):
        i, j = model.links.index(left), model.links.index(left[:-1] + "r")
        assert model.link_mass[i] == pytest.approx(model.link_mass[j], rel=1e-6)
        assert pos[j] == pytest.approx(pos[i] * [1, -1, 1], abs=1e-9)


def test_every_link_is_at_least_one_and_a_half_cells_thick_at_the_default_grid(frog):
    """The fluid sees a part only if it is about two cells across (STYLE: thin fins are
    thickened): the tarsi, forelimbs and web plates are 7 mm, two cells of 3.5 mm; the default
    grid's cells are 4 mm (a wider grid at the paper's cost, frog.py), where the hull's
    12-sided sections measure 6.2 mm, 1.54 cells, and the sub-cell faces see 96-100% of every
    link's volume (``aquagait check``)."""
    shape = body_shape(frog.model, frog.cell_size, refine=4)
    assert link_thickness(shape).min() / frog.cell_size >= 1.5


def test_frog_is_frog_sized_with_heavy_hind_legs(frog):
    model = frog.model
    mass = dict(zip(model.links, model.link_mass, strict=True))
    assert 0.05 < model.mass < 0.08  # tens of grams: an 8 cm ranid
    assert mass["body"] == pytest.approx(0.036, rel=0.05)
    hind = sum(mass[f"{n}_{s}"] for n in ("thigh", "shank", "tarsus", "foot") for s in "lr")
    fore = sum(mass[f"{n}_{s}"] for n in ("upperarm", "forearm") for s in "lr")
    assert hind > 5 * fore
    # the web: a trapezoid 4 cm long, 8 -> 28 mm wide, 7 mm thick, of water
    assert mass["foot_l"] == pytest.approx(RHO * 0.04 * (0.008 + 0.028) / 2 * 0.007, rel=1e-3)


def test_shipped_kick_swims_forward_straight_with_the_hind_legs():
    """One cycle on a coarse grid (5 mm cells, 64x52x32: the kick's widest pose with 8
    cells of water): the frog ends ahead of where it started, does not turn (the gait is
    mirror-symmetric), and the hind legs do nearly all the work."""
    setup = prepare_swim("frog", seconds=1.0, resolution=(64, 52, 32), cell_size=0.005)
    run = run_swim(setup)
    q = run.trajectory.qpos
    assert q[-1, 0] > 0.003  # metres forward in the first cycle from rest
    assert abs(q[-1, 1]) < 1e-3  # no sideways drift
    energy = run.trajectory.energy[-1]
    names = setup.creature.model.dof_names[-len(energy) :]
    hind = sum(e for n, e in zip(names, energy, strict=True) if n.rsplit("_", 1)[0] in HIND)
    assert hind > 0.9 * energy.sum()
