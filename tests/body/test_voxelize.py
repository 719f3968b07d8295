"""Voxelizing links: volumes and surfaces against exact shapes, face bookkeeping, owners,
pockets, meshes against primitives, and the creatures' mass."""

import pickle

import numpy as np
import pytest

import aquagait as ag
from aquagait.body import Dynamics, load_model
from aquagait.body.dynamics import describe, mesh_faces
from aquagait.body.voxelize import Voxels, body_shape, voxelize
from aquagait.fluid.cells import seal_pockets
from aquagait.grid import Grid

DEPTH = 0.04
RNG_SEED = 20110807  # SIGGRAPH 2011


def planar(inner: str) -> str:
    """A planar (2D) model whose root link holds ``inner`` (geoms and child bodies)."""
    return f"""<mujoco><custom><numeric name="aquagait_depth" data="{DEPTH}"/></custom>
      <default><geom density="1000"/></default>
      <worldbody><body name="root">
        <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
        <joint type="hinge" axis="0 0 1" range="-90 90"/>{inner}</body></worldbody></mujoco>"""


def free(inner: str, asset: str = "") -> str:
    """A 3D model with a free root link holding ``inner``."""
    return f"""<mujoco><asset>{asset}</asset><default><geom density="1000"/></default>
      <worldbody><body name="root"><freejoint/>{inner}</body></worldbody></mujoco>"""


def rot_z(theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def random_rotation(rng) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def centred_grid(model, resolution, h, offset=None) -> Grid:
    """The creature's grid centred on its centre of mass at qpos0 (as make_scene does)."""
    centre = Dynamics(model.mj).center_of_mass(model.qpos0)[: model.dim]
    origin = centre - np.asarray(resolution) * h / 2 + (0 if offset is None else offset)
    return Grid(tuple(resolution), h, tuple(origin))


@pytest.fixture(scope="module")
def eel():
    creature = ag.creatures.get("eel2d")
    return creature, body_shape(creature.model, creature.cell_size)


@pytest.fixture(scope="module")
def fish():
    creature = ag.creatures.get("fish")
    return creature, body_shape(creature.model, creature.cell_size)


# --- exact shapes -----------------------------------------------------------------

R = 0.05


@pytest.fixture(scope="module", params=[2, 3], ids=["disc", "sphere"])
def ball(request):
    dim = request.param
    if dim == 2:
        return load_model(planar(f'<geom type="cylinder" size="{R} {DEPTH / 2}"/>'))
    return load_model(free(f'<geom type="sphere" size="{R}"/>'))


def random_poses(ball_model, h, count, rng):
    """Grids around a ball at random sub-cell offsets, and random rotations of it."""
    dim, n = ball_model.dim, int(np.ceil(3 * R / h))
    for _ in range(count):
        origin = rng.uniform(-1.5 * R - h, -1.5 * R, dim)
        rot = rot_z(rng.uniform(0, 2 * np.pi)) if dim == 2 else random_rotation(rng)
        yield Grid((n,) * dim, h, tuple(origin)), np.zeros((1, 3)), rot[None]


@pytest.mark.parametrize("cells_per_radius", [6, 12])
def test_ball_volume_matches_exact_and_shrinks_with_h(ball, cells_per_radius):
    # Counting lattice points in a smooth convex body errs by O(R^(2/3)) points in 2D
    # (van der Corput) and less in 3D: relative O((h/R)^(4/3)), constant ~1 measured
    # at 0.3 of it. Averaged over random offsets the count is unbiased (E[N h^d] = V).
    h, dim = R / cells_per_radius, ball.dim
    exact = np.pi * R**2 if dim == 2 else 4 / 3 * np.pi * R**3
    shape = body_shape(ball, h)
    rng = np.random.default_rng(RNG_SEED + cells_per_radius)
    errors = []
    for grid, pos, rot in random_poses(ball, h, 16, rng):
        errors.append(voxelize(shape, grid, pos, rot).solid.sum() * h**dim / exact - 1)
    errors = np.array(errors)
    assert np.abs(errors).max() < (h / R) ** (4 / 3)
    assert abs(errors.mean()) < 4 * errors.std() / np.sqrt(errors.size) + 1e-3


@pytest.mark.parametrize("cells_per_radius", [6, 12])
def test_ball_classification_is_exact_away_from_the_surface(ball, cells_per_radius):
    h = R / cells_per_radius
    shape = body_shape(ball, h)
    rng = np.random.default_rng(RNG_SEED)
    for grid, pos, rot in random_poses(ball, h, 4, rng):
        solid = voxelize(shape, grid, pos, rot).solid
        radius = np.sqrt(sum(c**2 for c in grid.cell_centers()))
        # (tri)linear interpolation of |p| - R errs by s^2/8 times the Hessian's trace, 1/r
        sure = np.abs(radius - R) > shape.spacing**2 / (4 * (R - shape.spacing)) + 1e-7
        np.testing.assert_array_equal(solid[sure], (radius < R)[sure])


@pytest.mark.parametrize("cells_per_radius", [6, 12])
def test_ball_surface_overcounts_by_the_staircase_factor(ball, cells_per_radius):
    # A convex digital shape is row- and column-convex, so its faces number twice the
    # lattice lines it meets along each axis: 2(2R/h +- 1) per axis in 2D, giving
    # m h = 8R +- 4h (4/pi of 2 pi R); in 3D twice the digital area of the three
    # projected discs, 6 pi R^2 (1.5 x 4 pi R^2) within O(h/R).
    h, dim = R / cells_per_radius, ball.dim
    shape = body_shape(ball, h)
    rng = np.random.default_rng(RNG_SEED + 1)
    for grid, pos, rot in random_poses(ball, h, 6, rng):
        faces = voxelize(shape, grid, pos, rot).face_count
        if dim == 2:
            assert abs(faces * h - 8 * R) <= 4 * h + 1e-12
        else:
            assert abs(faces * h**2 / (4 * np.pi * R**2) - 1.5) < 1.5 * h / R


# --- face bookkeeping ---------------------------------------------------------------


def brute_force_faces(solid: np.ndarray) -> set:
    """(axis, face index) of every interior face between a solid and a fluid cell."""
    faces = set()
    for axis in range(solid.ndim):
        low = np.take(solid, range(solid.shape[axis] - 1), axis=axis)
        high = np.take(solid, range(1, solid.shape[axis]), axis=axis)
        for index in np.argwhere(low != high):
            index[axis] += 1
            faces.add((axis, *index.tolist()))
    return faces


def check_faces(voxels: Voxels, grid: Grid):
    dim = grid.dim
    assert voxels.solid.shape == voxels.owner.shape == grid.shape
    np.testing.assert_array_equal(voxels.solid, voxels.owner >= 0)
    m = voxels.face_count
    assert voxels.face_index.shape == (m, dim) and voxels.face_center.shape == (m, 3)
    np.testing.assert_array_equal(voxels.face_weight, 0.0)  # a staircase face is wall
    np.testing.assert_array_equal(voxels.face_share, 1.0)
    face, cells, signs = voxels.sides()
    order = np.argsort(face)
    np.testing.assert_array_equal(face[order], np.arange(m))  # water on exactly one side
    cells, signs = cells[order], signs[order]
    assert set(np.unique(signs)) <= {-1.0, 1.0}
    centres = [grid.face_centers(axis) for axis in range(dim)]
    for f in range(m):
        axis, sign = voxels.face_axis[f], signs[f]
        step = np.eye(dim, dtype=int)[axis]
        fluid = cells[f]
        solid = fluid - int(sign) * step  # the normal points from the solid into the fluid
        assert not voxels.solid[tuple(fluid)] and voxels.solid[tuple(solid)]
        assert voxels.owner[tuple(solid)] == voxels.face_link[f]
        index = voxels.face_index[f]
        np.testing.assert_array_equal(index, fluid + (sign < 0) * step)
        assert 0 < index[axis] < grid.shape[axis]  # never on the open border
        centre = [c[tuple(index)] for c in centres[axis]] + [0.0] * (3 - dim)
        np.testing.assert_allclose(voxels.face_center[f], centre, atol=1e-12)
    listed = {
        (int(a), *map(int, i)) for a, i in zip(voxels.face_axis, voxels.face_index, strict=True)
    }
    assert len(listed) == m
    assert listed == brute_force_faces(voxels.solid)


def test_faces_of_every_geom_type_at_a_bent_pose(snake, snake_dynamics):
    # conftest's snake: ellipsoid, sphere, capsule, box, cylinder and mesh, skew joints
    rng = np.random.default_rng(RNG_SEED)
    bend = rng.normal(size=snake.nv)
    bend[:6] = 0  # the free root stays: the body stays in the grid
    q = snake_dynamics.integrate(snake.qpos0, bend, 0.5)
    pos, rot = snake_dynamics.link_poses(q)
    h = 0.012
    grid = Grid((40, 40, 40), h, tuple(pos.mean(axis=0) - 20 * h))
    voxels = voxelize(body_shape(snake, h), grid, pos, rot)
    assert voxels.solid[:, 0].any()  # the body crosses the border: no coupled face there
    assert voxels.face_count > 100
    assert set(np.unique(voxels.owner[voxels.solid])) == set(range(len(snake.links)))
    check_faces(voxels, grid)


def test_faces_of_the_eel_at_a_bent_pose(eel):
    creature, shape = eel
    model = creature.model
    q = model.qpos0.copy()
    q[[model.joint(j).qpos for j in ("j1", "j2", "j3", "j4")]] = [0.6, -0.7, 0.7, -0.5]
    grid = centred_grid(model, creature.resolution, creature.cell_size)
    check_faces(voxelize(shape, grid, *Dynamics(model.mj).link_poses(q)), grid)


def test_no_body_in_the_grid_gives_no_solid_and_no_faces(eel):
    creature, shape = eel
    grid = Grid((16, 8), 0.01, (5.0, 5.0))
    voxels = voxelize(shape, grid, *Dynamics(creature.model.mj).link_poses(creature.model.qpos0))
    assert not voxels.solid.any() and voxels.face_count == 0
    assert voxels.face_index.shape == (0, 2) and voxels.face_center.shape == (0, 3)
    assert voxels.first_entries().size == 0  # was [0], an index into nothing


# --- owners -------------------------------------------------------------------------

EEL_BENT = [0.4, -0.5, 0.6, -0.7]


def test_cells_near_each_link_centre_belong_to_it(eel):
    creature, shape = eel
    model = creature.model
    dynamics, facts = Dynamics(model.mj), describe(model.mj)
    q = model.qpos0.copy()
    q[[model.joint(j).qpos for j in ("j1", "j2", "j3", "j4")]] = EEL_BENT
    pos, rot = dynamics.link_poses(q)
    h = 0.004  # the tail is 1.1 cm wide at its middle: nearly 3 cells
    grid = centred_grid(model, (320, 160), h)
    voxels = voxelize(body_shape(model, h), grid, pos, rot)
    for k in range(len(model.links)):
        rest_centre = facts.geom_box[facts.geom_link == k].mean(axis=(0, 1)) - facts.link_pos[k]
        centre = pos[k] + rot[k] @ facts.link_rot[k].T @ rest_centre
        assert voxels.owner[grid.cell_of(centre[:2])] == k
    assert np.array_equal(np.unique(voxels.owner), np.arange(-1, 5))


def test_overlapping_links_split_where_they_are_equally_deep():
    # two adjacent boxes, x in [-0.05, 0.05] and [0.01, 0.11]: equally deep at x = 0.03
    model = load_model(
        planar(
            '<geom type="box" size=".05 .05 .02"/><body name="b" pos=".06 0 0">'
            '<joint type="hinge" axis="0 0 1" range="-90 90"/>'
            '<geom type="box" size=".05 .05 .02"/></body>'
        ),
        forward=(1.0, 0.0),  # its root is at the -x end, where a fish's head would be
    )
    h = 0.005
    grid = Grid((40, 40), h, (-0.0999, -0.1002))
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    voxels = voxelize(body_shape(model, h), grid, pos, rot)
    x, y = grid.cell_centers()
    middle = np.abs(y) < 0.02  # there the x faces are the nearest
    both = middle & (x > 0.01) & (x < 0.05)
    assert both.sum() > 20
    np.testing.assert_array_equal(voxels.owner[both], np.where(x[both] < 0.03, 0, 1))


@pytest.mark.parametrize("which", ["eel", "fish"])
def test_a_translation_by_whole_cells_shifts_the_voxels_exactly(which, eel, fish):
    creature, shape = eel if which == "eel" else fish
    model = creature.model
    dynamics = Dynamics(model.mj)
    q = model.qpos0.copy()
    joints = [j for j in model.joints if j.link != 0]
    q[[j.qpos for j in joints]] = np.array(EEL_BENT[: len(joints)]) / 2
    pos, rot = dynamics.link_poses(q)
    grid = centred_grid(model, creature.resolution, creature.cell_size, offset=0.3e-3)
    cells = np.array([3, -2, 1][: model.dim])
    before = voxelize(shape, grid, pos, rot)
    moved = pos.copy()
    moved[:, : model.dim] += cells * grid.cell_size
    after = voxelize(shape, grid, moved, rot)
    axes = tuple(range(model.dim))
    np.testing.assert_array_equal(after.owner, np.roll(before.owner, cells, axis=axes))

    def faces(v, step):
        rows = zip(v.face_axis, v.face_index + step, v.sides()[2], v.face_link, strict=True)
        return {(int(a), *map(int, i), float(s), int(k)) for a, i, s, k in rows}

    assert faces(after, 0) == faces(before, cells)


def test_pickled_shape_voxelizes_the_same(fish):
    creature, shape = fish
    model = creature.model
    copy = pickle.loads(pickle.dumps(shape))
    grid = centred_grid(model, creature.resolution, creature.cell_size)
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    np.testing.assert_array_equal(
        voxelize(copy, grid, pos, rot).owner, voxelize(shape, grid, pos, rot).owner
    )


# --- meshes -------------------------------------------------------------------------

BOX = (0.06, 0.025, 0.035)


def box_mesh(half) -> str:
    corners = np.array(np.meshgrid(*[[-a, a] for a in half], indexing="ij")).reshape(3, -1).T
    return f'<mesh name="box" vertex="{" ".join(f"{v:.6f}" for v in corners.ravel())}"/>'


@pytest.mark.parametrize("dim", [2, 3])
def test_a_box_mesh_voxelizes_like_the_box(dim):
    half = BOX[:2] + (DEPTH / 2,) if dim == 2 else BOX
    primitive = f'<geom type="box" size="{" ".join(map(str, half))}"/>'
    if dim == 2:
        mesh_model = planar('<geom type="mesh" mesh="box"/>').replace(
            "<mujoco>", f"<mujoco><asset>{box_mesh(half)}</asset>"
        )
        models = load_model(planar(primitive)), load_model(mesh_model)
    else:
        mesh_model = free('<geom type="mesh" mesh="box"/>', box_mesh(half))
        models = load_model(free(primitive)), load_model(mesh_model)
    h = 0.01
    shapes = [body_shape(m, h) for m in models]
    rng = np.random.default_rng(RNG_SEED)
    for _ in range(4):
        rot = rot_z(rng.uniform(0, 6)) if dim == 2 else random_rotation(rng)
        pos = np.append(rng.uniform(-h, h, dim), np.zeros(3 - dim))[None]
        grid = Grid((20,) * dim, h, (-0.1,) * dim)
        a, b = (voxelize(s, grid, pos, rot[None]).solid for s in shapes)
        differ = np.argwhere(a != b)
        assert len(differ) <= 0.02 * a.sum()
        # where they differ the cell centre is within the bake's edge error of the surface
        points = np.column_stack([c[tuple(differ.T)] for c in grid.cell_centers()])
        local = np.abs((np.pad(points, ((0, 0), (0, 3 - dim))) - pos) @ rot)[:, :dim]
        excess = (local - np.array(half[:dim])).max(axis=1)
        assert np.all(np.abs(excess) <= shapes[1].spacing)


def l_prism(dim: int) -> str:
    """A non-convex L (2 x 2 cm square less its 1 x 1 cm upper right quarter), given with faces."""
    outline = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]) * 0.01 - 0.01
    n = len(outline)
    z = DEPTH / 2 if dim == 2 else 0.01
    vertices = np.concatenate([np.c_[outline, -z * np.ones(n)], np.c_[outline, z * np.ones(n)]])
    faces = []
    for a, b, c in [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]:  # a fan from the inner corner
        faces += [(a, c, b), (a + n, b + n, c + n)]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    asset = (
        f'<mesh name="L" vertex="{" ".join(f"{v:.6f}" for v in vertices.ravel())}" '
        f'face="{" ".join(str(v) for f in faces for v in f)}"/>'
    )
    geom = '<geom type="mesh" mesh="L"/>'
    if dim == 2:
        return planar(geom).replace("<mujoco>", f"<mujoco><asset>{asset}</asset>")
    return free(geom, asset)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_non_convex_mesh_keeps_its_notch(dim):
    model = load_model(l_prism(dim))
    volume = 3e-4 * (DEPTH if dim == 2 else 0.02)
    assert model.mass / 1000 == pytest.approx(volume, rel=1e-6)  # MuJoCo's mass: not the hull
    h = 0.001
    grid = Grid((30,) * dim, h, (-0.015,) * dim)
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    solid = voxelize(body_shape(model, h), grid, pos, rot).solid
    centres = grid.cell_centers()
    x, y = centres[0], centres[1]
    inside = (np.abs(x) < 0.01) & (np.abs(y) < 0.01) & ~((x > 0) & (y > 0))
    if dim == 3:
        inside &= np.abs(centres[2]) < 0.01
    np.testing.assert_array_equal(solid, inside)  # no cell centre lies on the surface


def test_mesh_faces_are_outward_and_hold_the_mass(fish):
    model = fish[0].model
    facts, faces = describe(model.mj), mesh_faces(model.mj)
    for g, tri in enumerate(faces):
        v = facts.geom_vertices[g]
        assert tri.min() >= 0 and tri.max() < len(v)
        volume = np.einsum("ij,ij->", v[tri[:, 0]], np.cross(v[tri[:, 1]], v[tri[:, 2]])) / 6
        assert volume * 1000 == pytest.approx(facts.link_mass[facts.geom_link[g]], rel=1e-6)
    assert mesh_faces(load_model(free('<geom type="sphere" size=".1"/>')).mj) == (None,)


# --- pockets ------------------------------------------------------------------------

# A square frame of four bars (10 x 10 cm outside, 8 x 8 cm inside), one bar per link.
FRAME = planar(
    '<geom type="box" pos="0 -.045 0" size=".05 .005 .02"/>'
    '<body name="right"><joint type="hinge" axis="0 0 1" range="-90 90"/>'
    '<geom type="box" pos=".045 0 0" size=".005 .05 .02"/>'
    '<body name="top"><joint type="hinge" axis="0 0 1" range="-90 90"/>'
    '<geom type="box" pos="0 .045 0" size=".05 .005 .02"/>'
    '<body name="left"><joint type="hinge" axis="0 0 1" range="-90 90"/>'
    '<geom type="box" pos="-.045 0 0" size=".005 .05 .02"/></body></body></body>'
)


def test_fluid_enclosed_by_a_frame_of_links_is_sealed_and_owned():
    model = load_model(FRAME)
    h = 0.004
    grid = Grid((40, 40), h, (-0.0801, -0.0797))
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    voxels = voxelize(body_shape(model, h), grid, pos, rot)
    x, y = grid.cell_centers()
    hollow = (np.abs(x) < 0.04) & (np.abs(y) < 0.04)
    assert hollow.sum() > 300 and voxels.solid[hollow].all()
    np.testing.assert_array_equal(seal_pockets(voxels.solid), voxels.solid)  # nothing left
    assert not hollow[tuple(voxels.sides()[1].T)].any()  # no coupled face inside
    # pocket cells take the nearest wall's link: bottom 0, right 1, top 2, left 3
    for link, point in enumerate([(0, -0.03), (0.03, 0), (0, 0.03), (-0.03, 0)]):
        assert voxels.owner[grid.cell_of(point)] == link


def test_fluid_inside_a_hollow_box_is_sealed_and_owned():
    walls = "".join(
        f'<geom type="box" pos="{" ".join(map(str, 0.045 * e))}" '
        f'size="{" ".join(map(str, np.where(e != 0, 0.005, 0.05)))}"/>'
        for e in np.vstack([np.eye(3), -np.eye(3)])
    )
    model = load_model(free(walls))
    # a wall t thick, tilted, leaves no 6-connected gap when t >= h |n|_1 (<= h sqrt(3))
    h = 0.005
    grid = Grid((36, 36, 36), h, (-0.0901, -0.0922, -0.0893))
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    rot = random_rotation(np.random.default_rng(RNG_SEED))[None]
    voxels = voxelize(body_shape(model, h), grid, pos, rot)
    inner = np.max(np.abs(np.stack(grid.cell_centers(), -1) @ rot[0]), axis=-1) < 0.035
    assert inner.sum() > 100 and (voxels.owner[inner] == 0).all()
    np.testing.assert_array_equal(seal_pockets(voxels.solid), voxels.solid)


# --- the creatures ------------------------------------------------------------------


@pytest.mark.parametrize("which", ["eel", "fish"])
def test_creature_volume_matches_its_mass(which, eel, fish):
    # Averaged over sub-cell offsets of the grid the count is unbiased; one offset errs
    # by the staircase, up to ~8% for the eel, 3.5 cells wide, and ~7% for the fish,
    # whose 6 mm caudal fin is one or two 5 mm cells thick depending on the offset.
    creature, shape = eel if which == "eel" else fish
    model = creature.model
    volume = model.mass / 1000  # water density: the creatures are neutrally buoyant
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    rng = np.random.default_rng(RNG_SEED)
    errors = []
    for _ in range(16):
        offset = rng.uniform(0, creature.cell_size, model.dim)
        grid = centred_grid(model, creature.resolution, creature.cell_size, offset)
        count = voxelize(shape, grid, pos, rot).solid.sum()
        errors.append(count * grid.cell_volume * (model.depth or 1) / volume - 1)
    assert abs(np.mean(errors)) < 0.01
    assert np.abs(errors).max() < (0.12 if which == "eel" else 0.09)


# --- bad input ----------------------------------------------------------------------


def test_bad_input_is_refused_with_a_clear_message(eel, fish):
    creature, shape = eel
    model = creature.model
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    grid = centred_grid(model, creature.resolution, creature.cell_size)
    with pytest.raises(ValueError, match=r"link_pos has shape \(4, 3\); this body needs \(5, 3\)"):
        voxelize(shape, grid, pos[:4], rot)
    with pytest.raises(ValueError, match=r"link_rot has shape \(5, 9\)"):
        voxelize(shape, grid, pos, rot.reshape(5, 9))
    with pytest.raises(ValueError, match="rotation matrices"):
        voxelize(shape, grid, pos, 2 * rot)
    with pytest.raises(ValueError, match="turn about z only"):
        voxelize(shape, grid, pos, rot @ random_rotation(np.random.default_rng(1)))
    with pytest.raises(ValueError, match="the grid is 3D but the body is 2D"):
        voxelize(shape, Grid((8, 8, 8), 0.01), pos, rot)
    with pytest.raises(ValueError, match="rebuild it with body_shape"):
        voxelize(shape, Grid((8, 8), 0.001), pos, rot)
    with pytest.raises(ValueError, match="cell_size must be a positive length"):
        body_shape(model, -0.01)
    fish_creature, fish_shape = fish
    fish_pos, fish_rot = Dynamics(fish_creature.model.mj).link_poses(fish_creature.model.qpos0)
    with pytest.raises(ValueError, match="the grid is 2D but the body is 3D"):
        voxelize(fish_shape, grid, fish_pos, fish_rot)
