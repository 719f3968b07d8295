"""The headless 3D renderer: the creature shaded, particle traces over it (docs/pictures.md).

OpenGL through EGL with Mesa's software rasterizer (llvmpipe), driven by
moderngl, the ``render`` extra; moderngl is imported only when a context is
made, so importing this module needs none of it.

    meshes = link_meshes(model)                                # aquagait.body.meshes
    camera = view_camera("side", centre, extent, 640 / 480)    # aquagait.viz.camera
    with Renderer(meshes) as renderer:
        image = renderer.draw(*Dynamics(model.mj).link_poses(qpos), camera, traces, alpha)

The body is drawn once per link: each link's triangles, built once in the
link's own frame (``link_meshes``), are placed by that frame's world
pose, ``x = p + R x_link``. Shading is soft: Lambert from a key and a fill
light fixed to the camera (so the side the camera sees is lit in every
view), a hemisphere ambient (brighter from above, world +z, than from below)
and a faint Blinn-Phong highlight. Over the body, in this order: surfaces
(the wake's vortices: triangles in world coordinates with a colour and an
opacity per vertex, lit from both sides), then traces and lines (line
segments with a colour and an opacity per vertex). Both are alpha blended
and depth tested against the body, writing no depth of their own (what lies
behind the body is hidden; they do not hide each other).

The meshes come from ``aquagait.body.meshes``, the camera from
``aquagait.viz.camera`` (whose image convention ``draw`` follows: top row first).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aquagait.body.meshes import LinkMesh
from aquagait.viz.camera import Camera, unit

INSTALL_MODERNGL = 'pip install "aquagait[render]"'
INSTALL_EGL = "apt-get install libegl1 libgl1-mesa-dri"


class RenderUnavailable(RuntimeError):
    """No OpenGL for the 3D renderer here: moderngl is missing or EGL gives no context."""


BODY_VERTEX = """
#version 330
uniform mat4 view_projection;
uniform mat3 rotation;
uniform vec3 origin;
in vec3 in_position;
in vec3 in_normal;
in vec3 in_colour;
out vec3 world;
out vec3 normal;
out vec3 colour;
void main() {
    world = origin + rotation * in_position;
    normal = rotation * in_normal;
    colour = in_colour;
    gl_Position = view_projection * vec4(world, 1.0);
}
"""

BODY_FRAGMENT = """
#version 330
uniform vec3 eye;
uniform vec3 key;
uniform vec3 fill;
in vec3 world;
in vec3 normal;
in vec3 colour;
out vec4 pixel;
void main() {
    vec3 n = normalize(normal);
    float diffuse = 0.55 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, fill), 0.0);
    float sky = 0.18 + 0.12 * n.z;  // hemisphere ambient: brighter from above
    float highlight = pow(max(dot(n, normalize(key + normalize(eye - world))), 0.0), 30.0);
    pixel = vec4(min(colour * (sky + diffuse) + 0.12 * highlight, 1.0), 1.0);
}
"""

SURFACE_VERTEX = """
#version 330
uniform mat4 view_projection;
in vec3 in_position;
in vec3 in_normal;
in vec4 in_colour;
out vec3 normal;
out vec4 colour;
void main() {
    normal = in_normal;
    colour = in_colour;
    gl_Position = view_projection * vec4(in_position, 1.0);
}
"""

SURFACE_FRAGMENT = """
#version 330
uniform vec3 key;
uniform vec3 fill;
in vec3 normal;
in vec4 colour;
out vec4 pixel;
void main() {
    vec3 n = normalize(normal);  // lit from both sides: a surface, not a solid
    float diffuse = 0.5 * abs(dot(n, key)) + 0.2 * abs(dot(n, fill));
    pixel = vec4(min(colour.rgb * (0.45 + diffuse), 1.0), colour.a);
}
"""

TRACE_VERTEX = """
#version 330
uniform mat4 view_projection;
in vec3 in_position;
in vec4 in_colour;
out vec4 colour;
void main() {
    colour = in_colour;
    gl_Position = view_projection * vec4(in_position, 1.0);
}
"""

TRACE_FRAGMENT = """
#version 330
in vec4 colour;
out vec4 pixel;
void main() {
    pixel = colour;
}
"""


def egl_context():
    """A headless OpenGL 3.3 context through EGL (a moderngl ``Context``).

    Raises:
        RenderUnavailable: moderngl is not installed, or EGL gives no context;
            the message says what to install and why it failed.
    """
    try:
        import moderngl
    except ImportError as err:
        raise RenderUnavailable(
            f"the 3D renderer needs moderngl, which cannot be imported ({err}); "
            f"install it with: {INSTALL_MODERNGL}"
        ) from err
    try:
        return moderngl.create_standalone_context(backend="egl", require=330)
    except Exception as err:  # moderngl raises plain Exception for a missing library or display
        raise RenderUnavailable(
            f"no headless OpenGL 3.3 context through EGL ({err}); the renderer needs EGL and "
            f"Mesa's software renderer, on Debian or Ubuntu the packages libegl1 and "
            f"libgl1-mesa-dri: {INSTALL_EGL}"
        ) from err


class Renderer:
    """Draws a creature's links and particle traces into an RGB image, off screen.

    Holds one OpenGL context and the links' meshes on it; a context manager
    (``close`` releases the context and everything on it). Each ``draw``
    makes this renderer's context current, so several renderers may take turns
    in one thread, and threads may draw at once, each with its own renderer
    (one renderer draws in one thread at a time).

    Args:
        meshes: per link, its ``LinkMesh`` (``link_meshes(model)``).
        width, height: the picture [pixels].
        background: RGB in [0, 1].
        samples: multisampling per pixel (0 for none; 4 smooths edges).
        line_width: trace width [pixels].
        context: makes the OpenGL context (``egl_context``).
    """

    def __init__(self, meshes, width: int = 640, height: int = 480, background=(1.0, 1.0, 1.0),
                 samples: int = 0, line_width: float = 1.0, context=egl_context):  # fmt: skip
        if width < 1 or height < 1:
            raise ValueError(f"the picture needs a positive size, got {width} x {height}")
        self.width, self.height, self.background = int(width), int(height), tuple(background)
        self.line_width, self.nlinks = float(line_width), len(meshes)
        self._ctx = context()
        with self._ctx:
            self._body = self._ctx.program(vertex_shader=BODY_VERTEX, fragment_shader=BODY_FRAGMENT)
            self._trace = self._ctx.program(
                vertex_shader=TRACE_VERTEX, fragment_shader=TRACE_FRAGMENT
            )
            self._links = [self._upload(mesh) for mesh in meshes]
            self._trace_buffer = self._ctx.buffer(reserve=28)
            self._trace_vao = self._ctx.vertex_array(
                self._trace, [(self._trace_buffer, "3f 4f", "in_position", "in_colour")]
            )
            self._surface = self._ctx.program(
                vertex_shader=SURFACE_VERTEX, fragment_shader=SURFACE_FRAGMENT
            )
            self._image = self._framebuffer(0)
            self._target = self._framebuffer(samples) if samples else self._image

    def _upload(self, mesh: LinkMesh):
        """A link's vertex array on the GPU, or None for a link without geoms."""
        if len(mesh.triangles) == 0:
            return None
        attributes = np.hstack([mesh.vertices, mesh.normals, mesh.colours[:, :3]]).astype("f4")
        vertices = self._ctx.buffer(attributes.tobytes())
        indices = self._ctx.buffer(mesh.triangles.astype("i4").tobytes())
        return self._ctx.vertex_array(
            self._body, [(vertices, "3f 3f 3f", "in_position", "in_normal", "in_colour")], indices
        )

    def _framebuffer(self, samples: int):
        size = (self.width, self.height)
        return self._ctx.framebuffer(
            color_attachments=[self._ctx.renderbuffer(size, 4, samples=samples)],
            depth_attachment=self._ctx.depth_renderbuffer(size, samples=samples),
        )

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Release the OpenGL context and every object on it; ``draw`` no longer works."""
        if self._ctx is not None:
            self._ctx.release()
            self._ctx = None

    def draw(self, link_pos, link_rot, camera: Camera, traces=None, trace_alpha=None,
             trace_colour=(0.1, 0.2, 0.45), lines=(), trace_colours=None,
             surfaces=()) -> np.ndarray:  # fmt: skip
        """One picture: the links at their poses, then surfaces, traces and lines over them.

        Args:
            link_pos: (nlinks, 3) world origins of the links [m]; or (K, nlinks, 3)
                to draw the body K times (snapshots along its way).
            link_rot: (nlinks, 3, 3) their world rotations (``Dynamics.link_poses``);
                or (K, nlinks, 3, 3).
            camera: where the picture is taken from.
            traces: (N, L, 3) world positions [m] of N particles over their last
                L frames, oldest first; NaN where a trace is younger than L.
            trace_alpha: (N, L) opacity in [0, 1] at each position; default 1.
            trace_colour: RGB in [0, 1] of the traces, unless ``trace_colours``.
            lines: ``(points, rgb)`` or ``(points, rgba)`` pairs: polylines
                through (n, 3) world points [m] (a path to follow, a ground grid),
                hidden by the body; opaque unless an alpha is given.
            trace_colours: (N, L, 3) RGB in [0, 1] at each trace position.
            surfaces: ``SurfaceMesh`` items: triangles in world coordinates with a
                colour and opacity per vertex (the wake's vortices), their nearest
                layer blended in.
        Returns:
            (height, width, 3) uint8 RGB, top row first.
        """
        if self._ctx is None:
            raise RuntimeError("this Renderer is closed; make a new one to draw")
        link_pos, link_rot = np.asarray(link_pos, float), np.asarray(link_rot, float)
        if link_pos.ndim == 2:
            link_pos, link_rot = link_pos[None], link_rot[None]
        n = self.nlinks
        if link_pos.shape[1:] != (n, 3) or link_rot.shape != link_pos.shape[:2] + (3, 3):
            raise ValueError(f"link poses of shapes {link_pos.shape} and {link_rot.shape}; "
                             f"the renderer has {n} links: ({n}, 3) and ({n}, 3, 3), "
                             "or K of each")  # fmt: skip
        segments = None
        if traces is not None:
            segments = trace_segments(traces, trace_alpha, trace_colours, trace_colour)
        with self._ctx:
            self._target.use()
            self._target.clear(*self.background, 1.0, depth=1.0)
            view_projection = _gl(
                camera.projection_matrix(self.width / self.height) @ camera.view_matrix()
            )
            for pos, rot in zip(link_pos, link_rot, strict=True):
                self._draw_links(pos, rot, camera, view_projection)
            for surface in surfaces:
                self._draw_surface(surface, camera, view_projection)
            if segments is not None and len(segments):
                self._draw_traces(segments, view_projection)
            for points, colour in lines:
                colour = tuple(colour)
                alpha = colour[3] if len(colour) == 4 else 1.0
                points = np.asarray(points, dtype=float)[None]
                line = trace_segments(points, np.full(points.shape[:2], alpha), None, colour[:3])
                if len(line):
                    self._draw_traces(line, view_projection, 2 * self.line_width)
            if self._target is not self._image:
                self._ctx.copy_framebuffer(self._image, self._target)
            pixels = self._image.read(components=3, alignment=1)
        return np.frombuffer(pixels, np.uint8).reshape(self.height, self.width, 3)[::-1].copy()

    def _draw_links(self, link_pos, link_rot, camera: Camera, view_projection: bytes) -> None:
        import moderngl

        right, up, forward = camera.basis()
        self._ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        self._ctx.disable(moderngl.BLEND)
        self._ctx.depth_mask = True
        self._body["view_projection"].write(view_projection)
        self._body["eye"].value = tuple(camera.eye)
        key, fill = _lights(camera)
        self._body["key"].value, self._body["fill"].value = key, fill
        for vao, origin, rotation in zip(self._links, link_pos, link_rot, strict=True):
            if vao is not None:
                self._body["origin"].value = tuple(origin)
                self._body["rotation"].write(_gl(rotation))
                vao.render()

    def _draw_surface(self, surface: SurfaceMesh, camera: Camera, view_projection: bytes) -> None:
        import moderngl

        if len(surface.triangles) == 0:
            return
        attributes = np.hstack([surface.vertices, surface.normals, surface.colours]).astype("f4")
        vertices = self._ctx.buffer(attributes.tobytes())
        indices = self._ctx.buffer(np.asarray(surface.triangles, dtype="i4").tobytes())
        vao = self._ctx.vertex_array(
            self._surface,
            [(vertices, "3f 3f 4f", "in_position", "in_normal", "in_colour")],
            indices,
        )
        self._ctx.enable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self._ctx.disable(moderngl.CULL_FACE)
        self._surface["view_projection"].write(view_projection)
        key, fill = _lights(camera)
        self._surface["key"].value, self._surface["fill"].value = key, fill
        # Only the nearest layer is blended in: a pass that writes depth and no colour,
        # then colour where the depth is the nearest. Blending every layer instead darkens
        # each fold seen edge-on, and a marching-cubes surface has a fold at every cell.
        self._ctx.depth_mask = True
        self._ctx.blend_func = moderngl.ZERO, moderngl.ONE
        vao.render()
        self._ctx.depth_func = "<="
        self._ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        vao.render()
        self._ctx.depth_func = "<"
        for thing in (vao, indices, vertices):
            thing.release()

    def _draw_traces(self, segments: np.ndarray, view_projection: bytes,
                     width: float | None = None) -> None:  # fmt: skip
        import moderngl

        data = segments.astype("f4", copy=False).tobytes()
        if len(data) > self._trace_buffer.size:
            self._trace_buffer.orphan(2 * len(data))  # grow once, then reuse
        self._trace_buffer.write(data)
        self._ctx.enable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self._ctx.disable(moderngl.CULL_FACE)
        self._ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self._ctx.depth_mask = False  # traces are hidden by the body, never by each other
        self._ctx.line_width = self.line_width if width is None else width
        self._trace["view_projection"].write(view_projection)
        self._trace_vao.render(moderngl.LINES, vertices=len(segments))
        self._ctx.depth_mask = True


@dataclass(frozen=True)
class SurfaceMesh:
    """Triangles to draw see-through over the body (the wake's vortices): the nearest layer
    is blended over what lies behind it, and hides the traces and lines behind it.

    Attributes:
        vertices: (n, 3) world positions [m].
        normals: (n, 3) unit normals (either side: the surface is lit from both).
        colours: (n, 4) RGBA in [0, 1], the alpha its opacity.
        triangles: (m, 3) vertex indices.
    """

    vertices: np.ndarray
    normals: np.ndarray
    colours: np.ndarray
    triangles: np.ndarray


def _lights(camera: Camera) -> tuple[tuple, tuple]:
    """The key light, over the camera's left shoulder, and the fill, low on its right."""
    right, up, forward = camera.basis()
    return tuple(unit(0.4 * up - 0.3 * right - forward)), tuple(
        unit(0.6 * right - 0.2 * up - forward)
    )


def trace_segments(traces, alpha=None, colours=None, colour=(0.0, 0.0, 0.0)) -> np.ndarray:
    """The line segments of particle traces, as the renderer uploads them.

    Args:
        traces: (N, L, 3) positions [m], oldest first, NaN where a trace is younger.
        alpha: (N, L) opacity in [0, 1]; default 1.
        colours: (N, L, 3) RGB in [0, 1] at each position; default ``colour`` everywhere.
        colour: RGB in [0, 1] of every position without ``colours``.
    Returns:
        (2 S, 7) float32 rows (x, y, z, r, g, b, alpha): the two ends of each of
        the S segments whose ends are both finite.
    """
    traces = np.asarray(traces, dtype=np.float32)
    if traces.ndim != 3 or traces.shape[2] != 3:
        raise ValueError(f"traces must be (N, L, 3) positions, got shape {traces.shape}")
    alpha = (
        np.ones(traces.shape[:2], np.float32) if alpha is None else np.asarray(alpha, np.float32)
    )
    if alpha.shape != traces.shape[:2]:
        raise ValueError(f"trace_alpha must be (N, L) = {traces.shape[:2]}, got {alpha.shape}")
    if colours is None:
        colours = np.broadcast_to(np.asarray(colour, np.float32), traces.shape)
    colours = np.asarray(colours, np.float32)
    if colours.shape != traces.shape:
        raise ValueError(f"trace colours must be (N, L, 3) = {traces.shape}, got {colours.shape}")
    ends = np.concatenate([traces, colours, alpha[..., None]], axis=-1)
    known = np.isfinite(traces).all(axis=-1)
    keep = known[:, :-1] & known[:, 1:]
    return np.stack([ends[:, :-1][keep], ends[:, 1:][keep]], axis=1).reshape(-1, 7)


def _gl(matrix: np.ndarray) -> bytes:
    """A matrix as OpenGL reads a uniform: float32, column by column."""
    return np.ascontiguousarray(np.asarray(matrix).T, dtype="f4").tobytes()
