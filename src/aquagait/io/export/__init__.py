"""A swim in the formats other tools read: USD, glTF, VTK for ParaView, one HTML page.

    data = swim_export(run.trajectory, model, "fish")       # poses, meshes, traces
    export_swim(data, "gltf", "runs/fish/swim.glb")          # written whole or not at all

Each format has its writer module, imported when asked for (each needs its
own optional library: the ``export`` extra):

- ``usd``: ``swim.usd``, the link meshes with time-sampled transforms, the
  traces as curves with per-vertex opacity and vorticity (Blender, Houdini);
- ``gltf``: ``swim.glb``, the link meshes with node animation (translation
  and rotation samplers): keyframes in Blender, any glTF viewer;
- ``vtk``: ``swim-vtk/``, the fluid per frame as image data and the body as
  polydata, each a ``.pvd`` time series (ParaView);
- ``html``: ``swim.html``, one self-contained page that plays the swim
  offline in any browser.

Units: metres and seconds, +z up, the trajectory's frame rate.
"""

from __future__ import annotations

import os
import shutil
from importlib import import_module
from pathlib import Path

from aquagait.io.export.data import TRACES, SwimExport, swim_export

FORMATS = {"usd": "swim.usd", "gltf": "swim.glb", "vtk": "swim-vtk", "html": "swim.html"}
"""Each format and the name it takes in a run directory by default."""


class ExportUnavailable(RuntimeError):
    """A format's library is not installed; the message says what to install."""


def export_swim(data: SwimExport, format: str, path) -> Path:
    """Write ``data`` as ``format`` to ``path``, whole or not at all.

    The writer writes beside ``path`` under a temporary name, which then
    replaces ``path``; if it fails, nothing is left behind and an old file
    at ``path`` is untouched.

    Raises:
        ValueError: an unknown format.
        ExportUnavailable: the format's library is missing (what to install).
    """
    check_format(format)
    writer = _writer(format)
    path = Path(path)
    partial = path.with_name(f".{path.name}.partial")
    _remove(partial)
    try:
        writer(data, partial)
        _remove(path)
        os.replace(partial, path)
    finally:
        _remove(partial)
    return path


def check_format(format: str) -> None:
    """Fail now, not after the work, where ``format``'s library is missing.

    Raises:
        ValueError: an unknown format.
        ExportUnavailable: the library is missing (what to install).
    """
    if format not in FORMATS:
        raise ValueError(f"unknown format {format!r}; formats: {', '.join(FORMATS)}")
    _writer(format)


def _writer(format: str):
    module = import_module(f"aquagait.io.export.{format}")
    try:
        module.check_available()
    except ImportError as err:
        install = getattr(module, "INSTALL", 'pip install "aquagait[export]"')
        raise ExportUnavailable(
            f"the {format} export needs {module.LIBRARY}, which cannot be imported ({err}); "
            f"install it with: {install}"
        ) from None
    return module.write


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    else:
        path.unlink(missing_ok=True)


__all__ = [
    "FORMATS",
    "TRACES",
    "ExportUnavailable",
    "SwimExport",
    "check_format",
    "export_swim",
    "swim_export",
]
