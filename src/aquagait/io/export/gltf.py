"""The swim as binary glTF 2.0 (``swim.glb``): the link meshes with node animation.

Blender imports it as keyframes, any glTF viewer plays it. The layout:

- one scene whose only top node, named after the creature, turns aquagait's
  +z up into glTF's +y up (-90 degrees about x); units stay metres;
- under it one node per link (``link_names``), each holding the link's
  mesh (none for a link without triangles). Links are siblings, not a chain:
  their poses are world poses, ``x = p + R x_link``;
- one animation, ``swim``: for every link a translation (VEC3) and a
  rotation (VEC4, x y z w) sampler, LINEAR, over the frame times [s].

The file (glTF 2.0 specification, section 4.4, "GLB File Format
Specification"): a 12-byte header, then a JSON chunk padded with spaces and
a BIN chunk padded with zeros, each to a multiple of 4 bytes. The BIN chunk
holds one buffer, one bufferView per accessor, every view starting on a
4-byte boundary (so every float32 or uint32 accessor is aligned, section
3.6.2.4) and packed tight (no byteStride).
"""

from __future__ import annotations

import math
import struct
from pathlib import Path

import numpy as np

from aquagait.io.export.data import SwimExport
from aquagait.io.run import library_versions

LIBRARY = "pygltflib"
"""What ``pip install`` needs for this format."""

Z_UP_TO_Y_UP = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]
"""The root's rotation (x, y, z, w): -90 degrees about x, so +z up becomes glTF's +y up."""

_FLOAT, _UNSIGNED_INT = 5126, 5125  # glTF componentType codes
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963  # bufferView targets
_TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}


def check_available() -> None:
    """Raise ImportError where pygltflib is missing."""
    import pygltflib  # noqa: F401


def write(data: SwimExport, path: Path) -> None:
    """Write ``data`` as a binary glTF (``.glb``) at exactly ``path``, whatever its suffix.

    Args:
        data: the swim: link poses per frame [m], link meshes in link frames [m],
            frame times [s].
        path: the file to write.
    """
    import pygltflib as gl

    blob = _Blob(gl)
    times = blob.accessor(data.time[:, None])
    quat_xyzw = data.link_quat[..., [1, 2, 3, 0]]  # glTF stores (x, y, z, w)
    extras = {"creature": data.name, "fps": data.fps, "units": "m"}
    root = gl.Node(name=data.name, rotation=Z_UP_TO_Y_UP, extras=extras)
    nodes, meshes, channels, samplers = [root], [], [], []
    for link, name in enumerate(data.link_names):
        node = gl.Node(
            name=name,
            translation=data.link_pos[0, link].tolist(),
            rotation=quat_xyzw[0, link].tolist(),
        )
        if len(data.meshes[link].triangles):
            node.mesh = len(meshes)
            meshes.append(_mesh(gl, blob, data.meshes[link], name))
        root.children.append(len(nodes))
        for channel, values in (("translation", data.link_pos), ("rotation", quat_xyzw)):
            output = blob.accessor(values[:, link])
            samplers.append(gl.AnimationSampler(input=times, output=output, interpolation="LINEAR"))
            target = gl.AnimationChannelTarget(node=len(nodes), path=channel)
            channels.append(gl.AnimationChannel(sampler=len(samplers) - 1, target=target))
        nodes.append(node)
    gltf = gl.GLTF2(
        asset=gl.Asset(version="2.0", generator=f"aquagait {_version()}", extras=extras),
        scene=0,
        scenes=[gl.Scene(name=data.name, nodes=[0])],
        nodes=nodes,
        meshes=meshes,
        materials=[_material(gl)],
        animations=[gl.Animation(name="swim", channels=channels, samplers=samplers)],
        accessors=blob.accessors,
        bufferViews=blob.views,
        buffers=[gl.Buffer(byteLength=len(blob.data))],
    )
    text = gltf.gltf_to_json(separators=(",", ":"), indent=None)
    Path(path).write_bytes(_glb(text.encode("utf-8"), bytes(blob.data)))


def _version() -> str:
    return library_versions()["aquagait"] or "unknown"


def _mesh(gl, blob: _Blob, mesh, name: str):
    """A glTF mesh of one ``LinkMesh``: positions [m] and normals in the link frame, RGBA."""
    attributes = gl.Attributes(
        POSITION=blob.accessor(mesh.vertices, _ARRAY_BUFFER),
        NORMAL=blob.accessor(mesh.normals, _ARRAY_BUFFER),
        COLOR_0=blob.accessor(mesh.colours, _ARRAY_BUFFER),
    )
    indices = blob.accessor(mesh.triangles.reshape(-1, 1), _ELEMENT_ARRAY_BUFFER)
    primitive = gl.Primitive(attributes=attributes, indices=indices, material=0)
    return gl.Mesh(name=name, primitives=[primitive])


def _material(gl):
    """White, so the vertex colours (COLOR_0) show as they are; one-sided (closed meshes).

    Not metallic (glTF's default is fully metallic, which would darken the colours).
    """
    pbr = gl.PbrMetallicRoughness(baseColorFactor=[1.0, 1.0, 1.0, 1.0], metallicFactor=0.0)
    return gl.Material(name="aquagait", pbrMetallicRoughness=pbr, doubleSided=False)


class _Blob:
    """The binary buffer as it fills: bytes, one bufferView per accessor, the accessors."""

    def __init__(self, gl):
        self.gl, self.data, self.views, self.accessors = gl, bytearray(), [], []

    def accessor(self, values: np.ndarray, target: int | None = None) -> int:
        """Append (count, width) ``values`` as float32, or uint32 if integer; return the index.

        min and max are of the stored values, per component (required for
        POSITION and animation inputs, section 3.6.2.5; kept for all).
        """
        integer = np.issubdtype(values.dtype, np.integer)
        values = np.ascontiguousarray(values, np.uint32 if integer else np.float32)
        raw = values.tobytes()
        view = self.gl.BufferView(buffer=0, byteOffset=len(self.data), byteLength=len(raw))
        view.target = target
        self.data += raw + bytes(-len(raw) % 4)  # the next view starts 4-byte aligned
        self.views.append(view)
        self.accessors.append(
            self.gl.Accessor(
                bufferView=len(self.views) - 1,
                componentType=_UNSIGNED_INT if integer else _FLOAT,
                count=len(values),
                type=_TYPES[values.shape[1]],
                min=values.min(axis=0).tolist() if len(values) else None,
                max=values.max(axis=0).tolist() if len(values) else None,
            )
        )
        return len(self.accessors) - 1


def _glb(json_chunk: bytes, bin_chunk: bytes) -> bytes:
    """The GLB container: header, JSON chunk (space-padded), BIN chunk (zero-padded)."""
    body = b""
    for kind, content, pad in ((b"JSON", json_chunk, b" "), (b"BIN\0", bin_chunk, b"\0")):
        content += pad * (-len(content) % 4)
        body += struct.pack("<I4s", len(content), kind) + content
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body
