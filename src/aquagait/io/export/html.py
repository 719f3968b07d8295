"""One self-contained HTML page that plays a swim offline, from file:// in any browser.

The page holds the swim as JSON in ``<script type="application/json"
id="aquagait-swim">`` and the viewer (three.js and ``tools/viewer/viewer.js``,
bundled into one script by ``tools/build_viewer.sh``, shipped in ``viewer/``)
inline after it: no module imports, nothing fetched. The viewer draws the link
meshes and the particle traces, with play/pause, a scrub slider over frames,
traces shown or hidden, and an orbit camera about +z.

The JSON (each array ``{"dtype", "shape", "data"}``, ``data`` the base64 of
its little-endian bytes; F frames, nl links, N traces of L positions)::

    name, dim, fps, frames
    time        (F,) float32 [s]
    link_pos    (F, nl, 3) float32 [m], world origin of each link's frame
    link_quat   (F, nl, 4) float32 (w, x, y, z), the links' world rotations
    links       per link: name; vertices, normals (n, 3) float32 and
                triangles (m, 3) uint32 in the link's frame; colours (n, 4)
                uint8 RGBA
    traces      null, or count N, length L, and
        points  (P, 3) float32 [m], NaN-free
        alpha   (P,) uint8, each point's opacity x 255, before the fade
        fade    (L,) float32, the factor on the opacity at position k of a trace
        size    (F, N) how many positions trace i has at frame f: its newest,
                the last ``size`` of the L (the older ones are NaN: younger)
        stride  the step between a trace's successive points in ``points``
        last    (F, N) uint32, the index in ``points`` of each trace's newest
                point; absent when it is f N + i

So position k of trace i at frame f, for k >= L - size, is point
``last - (L - 1 - k) stride`` with opacity ``alpha / 255 fade[k]``.

A trace is a particle's last L positions (``aquagait.sim.particles.wake``),
frame f's trace i is frame f - 1's shifted by one, and its opacity is the
vorticity where the particle was, faded along the trace. Then ``points``
and ``alpha`` hold each particle's once per frame, (F, N) in order,
``stride`` is N and ``last`` is absent: L times smaller than every frame's
traces. Traces without that structure are written as they are: each trace's
positions one after another with their opacity, ``fade`` 1, ``stride`` 1,
and ``last``. Either way, what is drawn is the data to within float32 and
1/255 in opacity; a NaN position's opacity (never drawn) is not kept.
"""

from __future__ import annotations

import base64
import json
from importlib import resources
from pathlib import Path

import numpy as np

from aquagait.io.export.data import SwimExport

LIBRARY = "the bundled viewer"
"""What the writer needs: three.js and the viewer bundled by ``tools/build_viewer.sh``."""

INSTALL = "bash tools/build_viewer.sh (in a source checkout; installed packages ship it)"

VIEWER = "viewer.js"
LICENSE = "THREE-LICENSE"
_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<!--
{licence}
-->
<style>
html, body {{ margin: 0; height: 100%; overflow: hidden; background: #fff;
  font: 13px/1.4 system-ui, sans-serif; color: #223; }}
canvas {{ display: block; }}
#info {{ position: fixed; top: 8px; left: 10px; white-space: pre;
  background: rgba(255, 255, 255, 0.75); padding: 2px 6px; border-radius: 3px; }}
#bar {{ position: fixed; left: 10px; right: 10px; bottom: 8px; display: flex; gap: 10px;
  align-items: center; }}
#play {{ width: 5em; }}
#scrub {{ flex: 1; }}
</style>
</head>
<body>
<div id="info">{title}</div>
<div id="bar"><button id="play" type="button">Play</button>
<input id="scrub" type="range" min="0" max="0" step="1" value="0">
<label><input id="traces" type="checkbox" checked> traces</label></div>
<script type="application/json" id="aquagait-swim">{swim}</script>
<script>{viewer}</script>
</body>
</html>
"""


def check_available() -> None:
    """Raise ImportError where the bundled viewer is missing (a source checkout not built)."""
    if not _viewer_file(VIEWER).is_file():
        raise ImportError(
            f"the bundled viewer {_viewer_file(VIEWER)} is missing; "
            "build it with tools/build_viewer.sh (needs node and npm)"
        )


def write(data: SwimExport, path) -> None:
    """Write ``data`` as one HTML page at exactly ``path``.

    Args:
        data: the swim (``aquagait.io.export.swim_export``).
        path: the file to write.
    """
    viewer = _viewer_file(VIEWER).read_text(encoding="utf-8")
    if "</script" in viewer.lower():  # it would end the page's script early
        raise ValueError(f"{_viewer_file(VIEWER)} contains '</script'; rebuild it")
    licence = _viewer_file(LICENSE).read_text(encoding="utf-8").replace("--", "- -")
    swim = json.dumps(payload(data), separators=(",", ":")).replace("</", "<\\/")
    title = _escape(data.name)
    page = _PAGE.format(title=title, licence=licence.strip(), swim=swim, viewer=viewer)
    Path(path).write_text(page, encoding="utf-8")


def payload(data: SwimExport) -> dict:
    """The swim as the page's JSON (the module docstring gives its fields)."""
    return {
        "name": data.name,
        "dim": int(data.dim),
        "fps": float(data.fps),
        "frames": int(data.frames),
        "time": _array(data.time, "<f4"),
        "link_pos": _array(data.link_pos, "<f4"),
        "link_quat": _array(data.link_quat, "<f4"),
        "links": [
            {
                "name": name,
                "vertices": _array(mesh.vertices, "<f4"),
                "normals": _array(mesh.normals, "<f4"),
                "colours": _array(_bytes(mesh.colours), "u1"),
                "triangles": _array(mesh.triangles, "<u4"),
            }
            for name, mesh in zip(data.link_names, data.meshes, strict=True)
        ],
        "traces": None if data.traces is None else _traces(data.traces, data.trace_alpha),
    }


def decode(array: dict) -> np.ndarray:
    """An array of the page's JSON as numpy (for tests and readers of the page)."""
    raw = base64.b64decode(array["data"])
    return np.frombuffer(raw, dtype=np.dtype(array["dtype"]).newbyteorder("<")).reshape(
        array["shape"]
    )


def _traces(traces: np.ndarray, alpha: np.ndarray | None) -> dict:
    """Traces (F, N, L, 3) with NaN where younger, and their opacity (F, N, L), as JSON."""
    frames, count, length, _ = traces.shape
    finite = np.isfinite(traces).all(axis=-1)  # a 2D swim's young positions are (NaN, NaN, 0)
    traces = np.where(finite[..., None], traces, np.float32(np.nan)).astype(np.float32)
    alpha = np.where(finite, 1.0 if alpha is None else np.clip(alpha, 0, 1), 0.0)
    size = np.cumprod(finite[..., ::-1], axis=-1).sum(axis=-1)  # the newest that are finite
    out = {"count": count, "length": length, "size": _array(size, np.min_scalar_type(length))}
    tracks = _particle_tracks(traces, alpha, size)
    if tracks is not None:
        points, point_alpha, fade = tracks
        return out | {"points": _array(points.reshape(-1, 3), "<f4"), "stride": count,
                      "alpha": _array(_bytes(point_alpha).ravel(), "u1"),
                      "fade": _array(fade, "<f4")}  # fmt: skip
    newest = np.arange(length) >= length - size[..., None]
    last = np.maximum(np.cumsum(size.ravel()) - 1, 0).reshape(frames, count)
    return out | {"points": _array(traces[newest], "<f4"), "stride": 1,
                  "alpha": _array(_bytes(alpha[newest]), "u1"),
                  "fade": _array(np.ones(length), "<f4"), "last": _array(last, "<u4")}  # fmt: skip


def _particle_tracks(traces, alpha, size):
    """Each particle's position (F, N, 3) and opacity (F, N) once per frame, and the fade
    (L,) along a trace, where they give back ``traces`` and ``alpha``; else None.

    The fade at position k is the median over particles of the opacity there over the
    particle's opacity when it was at that position (the newest position's, fade 1).
    """
    frames, _, length, _ = traces.shape
    head, head_alpha = np.nan_to_num(traces[:, :, -1]), alpha[:, :, -1]
    fade = np.ones(length)
    for k in range(max(length - frames, 0), length - 1):
        lag = length - 1 - k  # position k of frame f's trace is the particle's at f - lag
        then, now = head_alpha[: frames - lag], alpha[lag:, :, k]
        seen = (then > 0.1) & (size[lag:] > lag)
        fade[k] = np.median(now[seen] / then[seen]) if seen.any() else 1.0
    kept = np.arange(length) >= length - size[..., None]
    lags = np.arange(frames)[:, None, None] - (length - 1 - np.arange(length))
    frame_then = np.maximum(lags, 0)  # (F, 1, L): the frame each position was the newest
    particle = np.arange(traces.shape[1])[None, :, None]
    rebuilt = np.where(kept[..., None], head[frame_then, particle], np.float32(np.nan))
    rebuilt_alpha = np.where(kept, _bytes(head_alpha)[frame_then, particle] / 255 * fade, 0.0)
    younger_than_the_swim = np.all(size <= np.arange(1, frames + 1)[:, None])
    if (younger_than_the_swim and np.array_equal(rebuilt, traces, equal_nan=True)
            and np.abs(rebuilt_alpha - alpha).max(initial=0) <= 1 / 255):  # fmt: skip
        return head, head_alpha, fade
    return None


def _bytes(fraction: np.ndarray) -> np.ndarray:
    """Values in [0, 1] as uint8 x 255."""
    return np.rint(np.clip(fraction, 0, 1) * 255).astype(np.uint8)


def _array(values, dtype) -> dict:
    values = np.ascontiguousarray(values, dtype=np.dtype(dtype).newbyteorder("<"))
    return {
        "dtype": values.dtype.name,
        "shape": list(values.shape),
        "data": base64.b64encode(values.tobytes()).decode("ascii"),
    }


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _viewer_file(name: str) -> Path:
    return Path(str(resources.files("aquagait.io.export") / "viewer" / name))
