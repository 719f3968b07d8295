"""A swim as a USD stage (``swim.usd``, binary usdc), for Blender, Houdini and usdview.

The layout, in metres (``metersPerUnit`` 1), +z up, one time code per frame
(time code f is frame f, ``timeCodesPerSecond`` = ``framesPerSecond`` = fps):

    /Swim                 Xform, the default prim
        /<link>           Xform per link: time-sampled translate (double3) and
                          orient (quatf, w x y z), the link frame's world pose
            /Mesh         the link's triangles in the link frame: points,
                          normals, displayColor and displayOpacity per vertex
        /Traces           BasisCurves (linear): the particle traces

The traces are one prim whose points and curveVertexCounts are time-sampled:
at frame f a curve per particle with at least two known positions, oldest
first, with ``primvars:displayOpacity`` (the wake's opacity) and
``primvars:vorticity`` (|omega| [1/s] where the particle was, at the frame it
was there) per vertex. One prim whose topology changes from sample to sample
is what USD readers play as animated curves (Houdini, usdview, Blender's
cache); a prim per frame or per particle would multiply the stage's prims by
the frames or by the particles, and padding young traces to a fixed length
would invent positions.

The root layer's customLayerData records the aquagait version and the
creature's name.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aquagait.io.export.data import SwimExport
from aquagait.io.run import library_versions

LIBRARY = "usd-core"
"""The pip package that provides ``pxr``."""

ROOT = "/Swim"
TRACES = "Traces"
TRACE_WIDTH = 0.0015
"""A trace's width as a fraction of the body's length (1.5 mm for a 1 m eel)."""
TRACE_COLOUR = (0.85, 0.9, 1.0)
"""The traces' displayColor (RGB); their opacity carries the vorticity."""


def check_available() -> None:
    """Import ``pxr`` (usd-core); raises ImportError where it is missing."""
    import pxr.Usd  # noqa: F401


def write(data: SwimExport, path: Path) -> None:
    """Write ``data`` as a binary USD (usdc) stage at exactly ``path``, whatever its suffix.

    Args:
        data: the swim (``swim_export``); positions [m], time codes = frames.
        path: the file to write.
    Raises:
        OSError: USD could not write ``path``.
    """
    from pxr import Usd, UsdGeom

    # The stage's anonymous layer is usdc, and Export keeps a layer's format
    # for a file name USD does not know (the dispatcher's ``.swim.usd.partial``).
    stage = Usd.Stage.CreateInMemory("swim.usdc")
    _describe(stage, data)
    stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, ROOT).GetPrim())
    for i, name in enumerate(_prim_names(data.link_names)):
        link = f"{ROOT}/{name}"
        _place_link(stage, link, data.link_pos[:, i], data.link_quat[:, i])
        if len(data.meshes[i].triangles):
            _link_mesh(stage, f"{link}/Mesh", data.meshes[i])
    if data.traces is not None:
        _traces(stage, f"{ROOT}/{TRACES}", data)
    if not stage.GetRootLayer().Export(str(path)):
        raise OSError(f"USD could not write {path}")


def _describe(stage, data: SwimExport) -> None:
    """Units, up axis, frame rate, time range and where the stage came from."""
    from pxr import UsdGeom

    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    stage.SetTimeCodesPerSecond(data.fps)
    stage.SetFramesPerSecond(data.fps)
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(data.frames - 1)
    layer = stage.GetRootLayer()
    layer.documentation = f"aquagait swim of {data.name} ({data.dim}D), {data.frames} frames"
    layer.customLayerData = {
        "aquagaitVersion": library_versions()["aquagait"] or "unknown",
        "creature": data.name,
        "simulationDim": data.dim,
    }


def _prim_names(link_names) -> list[str]:
    """Valid, distinct USD prim names for the links (none named like the traces' prim)."""
    from pxr import Tf

    taken, names = {TRACES}, []
    for i, link in enumerate(link_names):
        base = Tf.MakeValidIdentifier(link or f"link{i}")
        name, k = base, 1
        while name in taken:
            name, k = f"{base}_{k}", k + 1
        taken.add(name)
        names.append(name)
    return names


def _place_link(stage, path: str, pos: np.ndarray, quat: np.ndarray) -> None:
    """A link's Xform posed per frame: x_world = pos[f] + R(quat[f]) x_link.

    Args:
        pos: (F, 3) the link frame's world origin [m].
        quat: (F, 4) its rotation (w, x, y, z).
    """
    from pxr import Gf, UsdGeom

    xform = UsdGeom.Xform.Define(stage, path)
    translate, orient = xform.AddTranslateOp(), xform.AddOrientOp()  # applied orient first
    for f, (p, q) in enumerate(zip(pos.tolist(), quat.tolist(), strict=True)):
        translate.Set(Gf.Vec3d(*p), f)
        orient.Set(Gf.Quatf(q[0], q[1], q[2], q[3]), f)


def _link_mesh(stage, path: str, mesh) -> None:
    """A link's triangles in its own frame (``LinkMesh``: positions [m], RGBA per vertex)."""
    from pxr import UsdGeom

    prim = UsdGeom.Mesh.Define(stage, path)
    prim.CreatePointsAttr(_vec3f(mesh.vertices))
    prim.CreateExtentAttr(_extent(mesh.vertices))
    prim.CreateFaceVertexCountsAttr(_ints(np.full(len(mesh.triangles), 3)))
    prim.CreateFaceVertexIndicesAttr(_ints(mesh.triangles.ravel()))
    prim.CreateNormalsAttr(_vec3f(mesh.normals))
    prim.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    # The triangles as they are: a default (catmullClark) mesh is rounded off by renderers.
    prim.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    vertex = UsdGeom.Tokens.vertex
    prim.CreateDisplayColorPrimvar(vertex).Set(_vec3f(mesh.colours[:, :3]))
    prim.CreateDisplayOpacityPrimvar(vertex).Set(_floats(mesh.colours[:, 3]))


def _traces(stage, path: str, data: SwimExport) -> None:
    """The particle traces as one BasisCurves prim, its points time-sampled per frame.

    A trace's unknown (NaN) positions are its oldest ones (``particle_traces``),
    so its known positions, in order, are one curve.
    """
    from pxr import Sdf, UsdGeom

    width = TRACE_WIDTH * _body_length(data)
    curves = UsdGeom.BasisCurves.Define(stage, path)
    curves.CreateTypeAttr(UsdGeom.Tokens.linear)
    curves.CreateWidthsAttr(_floats([width]))
    curves.SetWidthsInterpolation(UsdGeom.Tokens.constant)
    curves.CreateDisplayColorPrimvar(UsdGeom.Tokens.constant).Set(_vec3f([TRACE_COLOUR]))
    points, counts = curves.CreatePointsAttr(), curves.CreateCurveVertexCountsAttr()
    extent = curves.CreateExtentAttr()
    opacity = curves.CreateDisplayOpacityPrimvar(UsdGeom.Tokens.vertex)
    if data.fluid is not None:
        omega = _trace_vorticity(data)
        vorticity = UsdGeom.PrimvarsAPI(curves).CreatePrimvar(
            "vorticity", Sdf.ValueTypeNames.FloatArray, UsdGeom.Tokens.vertex
        )
    for f in range(data.frames):
        known = np.isfinite(data.traces[f, :, :, 0])
        count = known.sum(axis=1)
        known &= (count >= 2)[:, None]  # a single position is no curve
        at = data.traces[f][known]
        points.Set(_vec3f(at), f)
        counts.Set(_ints(count[count >= 2]), f)
        opacity.Set(_floats(data.trace_alpha[f][known]), f)
        if data.fluid is not None:
            vorticity.Set(_floats(omega[f][known]), f)
        if len(at):  # no curves (the first frame): the extent is held from the next
            extent.Set(_extent(at, pad=width / 2), f)


def _trace_vorticity(data: SwimExport) -> np.ndarray:
    """(F, N, L) float32 |omega| [1/s] at each trace position, at the frame the particle was there.

    Position l of frame f's traces is position l + 1 of frame f - 1's (the
    traces shift by one each frame, as ``wake``'s opacity does), so each
    frame samples only the particles' current positions.
    """
    from aquagait.sim.particles import sample, vorticity_magnitude

    fluid, dim = data.fluid, data.fluid.dim
    omega = np.zeros(data.traces.shape[:3], np.float32)
    for f in range(data.frames):
        now = np.nan_to_num(data.traces[f, :, -1, :dim])  # a 2D swim's traces: z = 0 appended
        if f:
            omega[f, :, :-1] = omega[f - 1, :, 1:]
        magnitude = vorticity_magnitude(fluid, f).astype(np.float32)
        omega[f, :, -1] = sample(magnitude, fluid.origin[f], fluid.cell_size, now)
    return omega


def _body_length(data: SwimExport) -> float:
    """The longest side of the body's bounding box at the first frame [m] (1 m without meshes)."""
    points = [data.link_pos[0, i] + mesh.vertices @ data.link_rot[0, i].T
              for i, mesh in enumerate(data.meshes) if len(mesh.vertices)]  # fmt: skip
    if not points:
        return 1.0
    return float(np.ptp(np.concatenate(points), axis=0).max()) or 1.0


def _vec3f(values):
    """A VtVec3fArray of (n, 3) values."""
    from pxr import Vt

    return Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(values, np.float32).reshape(-1, 3))


def _floats(values):
    from pxr import Vt

    return Vt.FloatArray.FromNumpy(np.ascontiguousarray(values, np.float32).ravel())


def _ints(values):
    from pxr import Vt

    return Vt.IntArray.FromNumpy(np.ascontiguousarray(values, np.int32).ravel())


def _extent(points, pad: float = 0.0):
    """The (2, 3) box [low, high] around (n, 3) points, grown by ``pad`` [m]."""
    points = np.asarray(points)
    return _vec3f([points.min(axis=0) - pad, points.max(axis=0) + pad])
