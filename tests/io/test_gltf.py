"""The glTF writer: read back with pygltflib, its animated meshes land where the swim put them.

The accessors are decoded here with numpy from the BIN chunk, not by the
writer's own code, so a wrong offset, type or axis convention shows up as
wrong world points.
"""

import dataclasses
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

from aquagait.io.export import export_swim

gl = pytest.importorskip("pygltflib")

_DTYPES = {5126: np.float32, 5125: np.uint32}
_WIDTHS = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}
_Y_UP_TO_Z_UP = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])  # glTF (x, y, z) -> aquagait


def _exported(data, tmp_path):
    path = export_swim(data, "gltf", tmp_path / "swim.glb")
    gltf = gl.GLTF2().load_binary(path)
    return path, gltf, gltf.binary_blob()


def _read(gltf, blob, index):
    """Accessor ``index`` as a (count, width) array, decoded from the BIN chunk."""
    accessor = gltf.accessors[index]
    view = gltf.bufferViews[accessor.bufferView]
    assert view.byteStride is None  # tightly packed
    width, dtype = _WIDTHS[accessor.type], _DTYPES[accessor.componentType]
    start = view.byteOffset + (accessor.byteOffset or 0)
    return np.frombuffer(blob, dtype, accessor.count * width, start).reshape(-1, width)


def _matrix(xyzw):
    """Rotation matrix of a unit quaternion stored as glTF does, (x, y, z, w)."""
    x, y, z, w = np.asarray(xyzw, float)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])  # fmt: skip


def _channels(gltf, blob):
    """{(node, 'translation' | 'rotation'): (input times, output values)} of the animation."""
    (animation,) = gltf.animations
    out = {}
    for channel in animation.channels:
        sampler = animation.samplers[channel.sampler]
        assert sampler.interpolation == "LINEAR"
        out[channel.target.node, channel.target.path] = (
            _read(gltf, blob, sampler.input)[:, 0],
            _read(gltf, blob, sampler.output),
        )
    return out


@pytest.mark.parametrize("swim", ["eel_export", "fish_export"])
def test_animated_meshes_land_on_the_swims_world_points(swim, request, tmp_path):
    _, data = request.getfixturevalue(swim)
    _, gltf, blob = _exported(data, tmp_path)
    root = gltf.nodes[gltf.scenes[gltf.scene].nodes[0]]
    assert root.name == data.name
    # The root turns +z up into +y up: aquagait's z axis is glTF's y axis.
    assert np.allclose(_matrix(root.rotation) @ [0, 0, 1], [0, 1, 0])
    links = [gltf.nodes[child] for child in root.children]
    assert tuple(node.name for node in links) == data.link_names
    assert all(not node.children for node in links)  # siblings: world poses, no chain
    channels = _channels(gltf, blob)
    for link, child in enumerate(root.children):
        times, translation = channels[child, "translation"]
        rotation_times, rotation = channels[child, "rotation"]
        assert np.array_equal(times, data.time.astype(np.float32))
        assert np.array_equal(rotation_times, times)
        (primitive,) = gltf.meshes[links[link].mesh].primitives
        vertices = _read(gltf, blob, primitive.attributes.POSITION)
        mesh = data.meshes[link]
        for f in (0, data.frames // 2, data.frames - 1):
            link_world = translation[f] + vertices @ _matrix(rotation[f]).T
            y_up = link_world @ _matrix(root.rotation).T
            expected = data.link_pos[f, link] + mesh.vertices @ data.link_rot[f, link].T
            assert np.abs(y_up @ _Y_UP_TO_Z_UP.T - expected).max() < 1e-5


@pytest.mark.parametrize("swim", ["eel_export", "fish_export"])
def test_meshes_keep_their_triangles_normals_colours_and_bounds(swim, request, tmp_path):
    _, data = request.getfixturevalue(swim)
    _, gltf, blob = _exported(data, tmp_path)
    root = gltf.nodes[gltf.scenes[0].nodes[0]]
    for link, child in enumerate(root.children):
        mesh, (primitive,) = data.meshes[link], gltf.meshes[gltf.nodes[child].mesh].primitives
        attributes = primitive.attributes
        assert np.array_equal(_read(gltf, blob, primitive.indices), mesh.triangles.reshape(-1, 1))
        assert np.allclose(_read(gltf, blob, attributes.NORMAL), mesh.normals, atol=1e-6)
        assert np.allclose(_read(gltf, blob, attributes.COLOR_0), mesh.colours, atol=1e-6)
        position = gltf.accessors[attributes.POSITION]
        stored = _read(gltf, blob, attributes.POSITION)
        assert position.min == stored.min(0).tolist() and position.max == stored.max(0).tolist()
        assert gltf.materials[primitive.material].pbrMetallicRoughness.baseColorFactor == [1] * 4
    time = gltf.accessors[gltf.animations[0].samplers[0].input]
    assert time.min == [0] and time.max == [pytest.approx(data.time[-1])]


def test_the_file_says_what_made_it_and_in_what_units(eel_export, tmp_path):
    _, data = eel_export
    _, gltf, _ = _exported(data, tmp_path)
    assert gltf.asset.version == "2.0" and gltf.asset.generator.startswith("aquagait ")
    assert gltf.asset.extras == {"creature": "eel2d", "fps": data.fps, "units": "m"}
    assert gltf.materials[0].doubleSided is False


def test_a_link_without_triangles_gets_a_node_without_mesh(eel_export, tmp_path):
    _, data = eel_export
    empty = dataclasses.replace(data.meshes[0], triangles=np.zeros((0, 3), int))
    _, gltf, blob = _exported(dataclasses.replace(data, meshes=[empty, *data.meshes[1:]]), tmp_path)
    head_index, trunk_index = gltf.nodes[0].children[:2]
    assert gltf.nodes[head_index].mesh is None and gltf.nodes[trunk_index].mesh is not None
    assert len(gltf.meshes) == len(data.link_names) - 1
    channels = _channels(gltf, blob)  # the meshless link is still animated
    assert (head_index, "translation") in channels and (head_index, "rotation") in channels


@pytest.mark.parametrize("swim", ["eel_export", "fish_export"])
def test_the_binary_layout_follows_the_glb_rules(swim, request, tmp_path):
    _, data = request.getfixturevalue(swim)
    path, gltf, blob = _exported(data, tmp_path)
    raw = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", raw)
    assert (magic, version, length) == (b"glTF", 2, len(raw))
    json_length, json_kind = struct.unpack_from("<I4s", raw, 12)
    bin_length, bin_kind = struct.unpack_from("<I4s", raw, 20 + json_length)
    assert (json_kind, bin_kind) == (b"JSON", b"BIN\0")
    assert json_length % 4 == 0 and bin_length % 4 == 0 and 28 + json_length + bin_length == length
    (buffer,) = gltf.buffers
    assert buffer.uri is None and buffer.byteLength <= bin_length <= buffer.byteLength + 3
    for view in gltf.bufferViews:
        assert view.buffer == 0 and view.byteOffset % 4 == 0
        assert view.byteOffset + view.byteLength <= buffer.byteLength
    for accessor in gltf.accessors:
        assert 0 <= accessor.bufferView < len(gltf.bufferViews) and accessor.count >= 1
        view = gltf.bufferViews[accessor.bufferView]
        size = np.dtype(_DTYPES[accessor.componentType]).itemsize
        offset = accessor.byteOffset or 0
        assert offset % size == 0 and (view.byteOffset + offset) % size == 0
        assert offset + accessor.count * _WIDTHS[accessor.type] * size <= view.byteLength


VALIDATOR = Path(__file__).parents[2] / "tools" / "gltf-validate.mjs"
"""Khronos's glTF validator run by Node (tools/system-packages.sh installs it from npm)."""


def _validator() -> list[str] | None:
    """The validator's command line: Node with the npm package, or Khronos's binary."""
    installed = VALIDATOR.parent / "node" / "node_modules" / "gltf-validator"
    if shutil.which("node") and installed.is_dir():
        return ["node", str(VALIDATOR)]
    return ["gltf_validator"] if shutil.which("gltf_validator") else None


@pytest.mark.skipif(_validator() is None, reason="the glTF validator is not installed: run "
                    "tools/system-packages.sh (npm install --prefix tools/node)")  # fmt: skip
def test_the_khronos_validator_finds_no_errors(eel_export, tmp_path):
    _, data = eel_export
    path, _, _ = _exported(data, tmp_path)
    report = subprocess.run([*_validator(), str(path)], capture_output=True, text=True,
                            timeout=120)  # fmt: skip
    assert report.returncode == 0, report.stdout + report.stderr  # 1: errors in the report
