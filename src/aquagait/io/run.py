"""Run directories: a run's settings, trajectory and metrics on disk (docs/swim.md).

A run directory holds

- ``config.json``: every resolved setting and the library versions
  (``library_versions``), so the run can be repeated;
- ``trajectory.npz``: the ``Trajectory`` frame by frame (``save_trajectory``);
- ``metrics.json``: the swim metrics (``aquagait.metrics``) and their units;

and, written by other modules, ``gait.json`` and ``swim.mp4``. JSON files are
strict JSON: an undefined number (``nan``, ``inf``) is written as ``null``.

``trajectory.npz`` arrays (F frames; shapes and units as in ``Trajectory``):
``time`` (F,), ``qpos`` (F, nq), ``qvel`` (F, nv), ``torque`` (F, nv),
``energy`` (F, nv), scalars ``dt``, ``fps`` and ``format``; when the model is
given, the root link's world pose ``root_position`` (F, 3) [m] and
``root_rotation`` (F, 3, 3); when the trajectory carries fluid frames,
``fluid_cell_size``, ``fluid_origin`` (F, dim), ``fluid_velocity``
(F, dim, *shape) and ``fluid_solid`` (F, *shape) (``aquagait.sim.FluidFrames``:
in 3D the whole volume, block-averaged on large grids, in half precision).
Format 1 (before 3D pictures) kept the mid-plane of a 3D grid and its
``fluid_plane_z``; such a file still loads, its fluid a 2D plane.
"""

from __future__ import annotations

import json
import math
import tempfile
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.model import Model
from aquagait.metrics import PATH_UNITS, UNITS
from aquagait.sim import FluidFrames, Trajectory

CONFIG, TRAJECTORY, METRICS = "config.json", "trajectory.npz", "metrics.json"
FORMAT = 2
LIBRARIES = ("aquagait", "numpy", "scipy", "numba", "mujoco")
_FRAME_ARRAYS = ("time", "qpos", "qvel", "torque", "energy")
_FLUID_ARRAYS = ("origin", "velocity", "solid")


@dataclass(frozen=True)
class Run:
    """A run directory read back: ``config`` and ``metrics`` (dicts, metrics None if absent)."""

    path: Path
    config: dict
    trajectory: Trajectory
    metrics: dict | None


def library_versions() -> dict:
    """Installed versions of aquagait and the libraries its numbers depend on (None: absent)."""
    versions = {}
    for name in LIBRARIES:
        try:
            versions[name] = version(name)
        except PackageNotFoundError:
            versions[name] = None
    return versions


def write_run(out, trajectory: Trajectory, config: dict, metrics=None, model=None) -> Path:
    """Write ``config.json``, ``trajectory.npz`` and (if given) ``metrics.json`` into ``out``.

    Args:
        out: the run directory; created if missing, files in it replaced.
        trajectory: the rollout.
        config: every resolved setting; ``versions`` is added if absent.
        metrics: a dict of numbers, or None.
        model: the creature, to store the root pose per frame; optional.

    Returns:
        The run directory.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / CONFIG, {**config, "versions": config.get("versions", library_versions())})
    save_trajectory(out / TRAJECTORY, trajectory, model)
    if metrics is not None:
        known = UNITS | PATH_UNITS
        units = {k: known[k] for k in metrics if k in known}
        write_json(out / METRICS, {**metrics, "units": units})
    return out


def prepare_directory(out) -> Path:
    """Create the directory ``out`` (and its parents) and prove it writable, before any work.

    Raises:
        OSError: it cannot be created or written; the message names the
            directory and the operating system's reason.
    """
    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out):
            pass
    except OSError as err:
        reason = err.strerror or str(err)
        raise OSError(f"cannot write the run directory {out}: {reason}") from None
    return out


def read_run(out) -> Run:
    """Read a run directory written by ``write_run``.

    Raises:
        FileNotFoundError: ``out`` is not a run directory (it names what is missing).
    """
    out = Path(out)
    if not (out / CONFIG).is_file():
        raise FileNotFoundError(f"{out} is not a run directory: it has no {CONFIG}")
    metrics = read_json(out / METRICS) if (out / METRICS).is_file() else None
    return Run(out, read_json(out / CONFIG), load_trajectory(out), metrics)


def save_trajectory(path, trajectory: Trajectory, model: Model | None = None) -> Path:
    """Write ``trajectory`` (and its fluid frames) to a compressed ``.npz`` (module docstring)."""
    arrays = {name: np.asarray(getattr(trajectory, name)) for name in _FRAME_ARRAYS}
    arrays.update(dt=trajectory.dt, fps=trajectory.fps, format=FORMAT)
    if model is not None:
        arrays["root_position"], arrays["root_rotation"] = _root_poses(model, trajectory)
    fluid = trajectory.fluid
    if fluid is not None:
        arrays.update({f"fluid_{name}": np.asarray(getattr(fluid, name)) for name in _FLUID_ARRAYS})
        arrays.update(fluid_cell_size=fluid.cell_size)
    path = Path(path)
    with path.open("wb") as f:  # a file object: numpy would append .npz to other names
        np.savez_compressed(f, **arrays)
    return path


def load_trajectory(path) -> Trajectory:
    """Read a trajectory from a ``.npz`` written by ``save_trajectory``, or from a run directory.

    Raises:
        FileNotFoundError: no such file.
        ValueError: the file is not an aquagait trajectory (it names the missing arrays).
    """
    path = Path(path)
    if path.is_dir():
        path = path / TRAJECTORY
    if not path.is_file():
        raise FileNotFoundError(f"no trajectory at {path}")
    with np.load(path) as data:
        missing = [k for k in (*_FRAME_ARRAYS, "dt", "fps") if k not in data.files]
        if missing:
            raise ValueError(f"{path} is not an aquagait trajectory: it lacks {missing}")
        fluid = None
        if "fluid_velocity" in data.files:
            fluid = FluidFrames(
                cell_size=float(data["fluid_cell_size"]),
                **{name: data[f"fluid_{name}"] for name in _FLUID_ARRAYS},
            )
        frames = {name: data[name] for name in _FRAME_ARRAYS}
        return Trajectory(**frames, dt=float(data["dt"]), fps=float(data["fps"]), fluid=fluid)


def write_json(path, obj) -> Path:
    """Write ``obj`` as indented, strict JSON; NumPy values become plain ones, nan and inf null."""
    path = Path(path)
    path.write_text(json.dumps(_plain(obj), indent=2, allow_nan=False) + "\n")
    return path


def read_json(path) -> dict:
    """Read a JSON file; the error names the file and the place of a syntax error."""
    path = Path(path)
    try:
        return json.loads(path.read_text())
    except json.JSONDecodeError as err:
        raise ValueError(f"{path} is not valid JSON: {err}") from None


def _plain(obj):
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple | np.ndarray):
        return [_plain(v) for v in obj]
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _root_poses(model: Model, trajectory: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    dynamics = Dynamics(model.mj)
    root = model.joints[0].link
    poses = [dynamics.link_poses(q) for q in trajectory.qpos]
    return np.array([p[root] for p, _ in poses]), np.array([r[root] for _, r in poses])
