"""``aquagait bench render``: wall time per picture of the headless 3D renderer.

Two measurements, each beside the time to encode the same frames to H.264 MP4
with imageio (the baseline, per frame, measured in the same run):

- ``bench_render``, the renderer alone (the figure of issue 14): a library
  creature at its reference pose, drifting a little from frame to frame,
  among random particle traces (random walks of ``length`` positions, some
  younger than that, opacity at random), seen by the 'follow' camera; timed:
  ``Renderer.draw`` per frame (trace upload, drawing, read-back), the mean
  after one warm-up frame. Target: ``TARGET_MS`` for 3,000 traces of 15
  positions at 640x480 on one core (llvmpipe on one thread).
- ``bench_pictures``, a whole 3D picture as ``aquagait swim`` and ``render``
  draw it (``aquagait.viz.volume``): a one-second fish swim on its default
  grid, every frame at 1280x720 with the wake drawn ``wake`` ('both': the
  Q-criterion, its vortex surfaces by marching cubes, the particles advected
  and their traces, the ground grid, the legend); timed: the whole
  ``volume_pictures`` run, per frame (``setup_ms``: what it does once per
  swim, the Q threshold and the cameras, spread over the frames), on one
  core. Target: ``PICTURE_TARGET_MS``.

llvmpipe reads its thread count (the environment variable ``LP_NUM_THREADS``)
once, when a process makes its first context, so ``bench_render(threads=1)``
times in a fresh Python process with the variable set.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import TextIO

import numpy as np

TARGET_MS = 100.0
"""Most milliseconds a picture may take at 640x480 with 3,000 traces, one core."""
PICTURE_TARGET_MS = 150.0
"""Most milliseconds a whole 3D picture (wake and all) may take at 1280x720, one core."""


def run(repeats: int, out: TextIO) -> list[dict]:
    """The renderer with llvmpipe's default threads and on one thread, ``repeats`` frames
    each; then whole pictures of a fish swim on one thread with each wake."""
    frames = max(repeats, 2)
    rows = [bench_render(frames=frames, out=out), bench_render(frames=frames, threads=1, out=out)]
    return rows + [bench_pictures(wake=wake, out=out) for wake in ("both", "q", "traces")]


def bench_pictures(
    wake: str = "both", seconds: float = 1.0, width: int = 1280, height: int = 720,
    threads: int = 1, out: TextIO = sys.stdout,
) -> dict:  # fmt: skip
    """Time whole 3D pictures of a fish swim (module docstring) and, as the baseline, MP4
    encoding of the same pictures; print both.

    Args:
        wake: 'both', 'q' or 'traces' (``aquagait.viz.volume.Look3D``).
        seconds: the swim, from rest on the fish's default grid (30 pictures a second).
        width, height: the pictures [pixels].
        threads: llvmpipe's rasterizer threads, timed in a fresh process.
        out: where the line goes.
    Returns:
        the settings and ``frame_ms`` (mean per picture, setup included), ``setup_ms``
        (the once-per-swim part, per picture), ``encode_ms``, ``ratio``, ``target_ms``.
    """
    settings = dict(wake=wake, seconds=seconds, width=width, height=height)
    row = _in_process_with(threads, settings, "measure_pictures")
    row.update(settings, threads=threads, target_ms=PICTURE_TARGET_MS)
    print(
        f"pictures fish {seconds:g} s swim, {width}x{height}, wake {wake}, llvmpipe threads "
        f"{threads}: {row['frame_ms']:.1f} ms per picture (target {PICTURE_TARGET_MS:.0f}; of "
        f"it {row['setup_ms']:.1f} once per swim), encode {row['encode_ms']:.1f} ms per frame, "
        f"ratio {row['ratio']:.2f}",
        file=out,
        flush=True,
    )
    return row


def measure_pictures(wake, seconds, width, height) -> dict:
    """Swim the fish, then draw and encode its pictures in this process: ms per picture."""
    import aquagait as ag
    from aquagait.app import prepare_swim, run_swim
    from aquagait.viz.volume import volume_pictures

    trajectory = run_swim(prepare_swim("fish", seconds=seconds)).trajectory
    model = ag.creatures.get("fish").model
    start = time.perf_counter()
    pictures = volume_pictures(trajectory, model, wake=wake, width=width, height=height)
    images = [next(pictures)]
    first = time.perf_counter()
    images += list(pictures)
    end = time.perf_counter()
    frame_ms = 1e3 * (end - start) / len(images)
    setup_ms = max(0.0, 1e3 * ((first - start) - (end - first) / (len(images) - 1)))
    encode_ms = _encode_ms(images)
    return dict(frame_ms=frame_ms, setup_ms=setup_ms / len(images), encode_ms=encode_ms,
                ratio=frame_ms / encode_ms)  # fmt: skip


def bench_render(
    frames: int = 30,
    traces: int = 3000,
    length: int = 15,
    width: int = 640,
    height: int = 480,
    creature: str = "fish",
    samples: int = 0,
    threads: int | None = None,
    out: TextIO = sys.stdout,
) -> dict:
    """Time the renderer and, as the baseline, MP4 encoding of the same frames; print both.

    Args:
        frames: frames timed (after one warm-up frame).
        traces, length: particle traces drawn, and positions per trace.
        width, height: the picture [pixels].
        creature: a library creature.
        samples: multisampling per pixel (0 for none).
        threads: llvmpipe's rasterizer threads (``LP_NUM_THREADS``), timed in a
            fresh process; None keeps this process and llvmpipe's default.
        out: where the line goes.
    Returns:
        the settings and ``frame_ms`` (mean per picture), ``encode_ms`` (per
        frame), ``ratio`` (frame over encode), ``target_ms``.
    """
    settings = dict(frames=frames, traces=traces, length=length, width=width,
                    height=height, creature=creature, samples=samples)  # fmt: skip
    row = measure(**settings) if threads is None else _in_process_with(threads, settings)
    row.update(settings, threads=threads or "default", target_ms=TARGET_MS)
    print(
        f"render {creature} {width}x{height}, {traces} traces x {length}, samples {samples}, "
        f"llvmpipe threads {row['threads']}: {row['frame_ms']:.1f} ms per frame "
        f"(target {TARGET_MS:.0f}), encode {row['encode_ms']:.1f} ms per frame, "
        f"ratio {row['ratio']:.2f}",
        file=out,
        flush=True,
    )
    return row


def measure(frames, traces, length, width, height, creature, samples) -> dict:
    """Draw and encode the frames in this process: ms per frame of each, and their ratio."""
    import aquagait as ag
    from aquagait.body.dynamics import Dynamics
    from aquagait.body.meshes import link_meshes
    from aquagait.viz.camera import view_camera
    from aquagait.viz.gl import Renderer

    model = ag.creatures.get(creature).model
    dynamics, rng = Dynamics(model.mj), np.random.default_rng(0)
    centre, extent = model.bounds.mean(axis=0), model.extent
    camera = view_camera("follow", centre, 2 * extent, width / height)
    paths, alpha = _random_traces(rng, centre, 2 * extent, traces, length + frames)
    images, seconds = [], []
    with Renderer(link_meshes(model), width, height, samples=samples) as renderer:
        for frame in range(frames + 1):  # the first is the warm-up
            qpos = model.qpos0.copy()
            qpos[0] += 0.002 * model.body_length * frame
            pose = dynamics.link_poses(qpos)
            window = slice(frame, frame + length)
            start = time.perf_counter()
            images.append(renderer.draw(*pose, camera, paths[:, window], alpha[:, window]))
            seconds.append(time.perf_counter() - start)
    frame_ms = 1e3 * float(np.mean(seconds[1:]))
    encode_ms = _encode_ms(images[1:])
    return dict(frame_ms=frame_ms, encode_ms=encode_ms, ratio=frame_ms / encode_ms)


def _random_traces(rng, centre, extent, count: int, length: int):
    """Random walks (count, length, 3) [m] starting in the box, opacity (count, length);
    a tenth of them younger than the window (NaN at their start)."""
    start = centre + (rng.random((count, 1, 3)) - 0.5) * extent
    steps = rng.normal(scale=0.01 * extent.max(), size=(count, length, 3))
    paths = start + np.cumsum(steps, axis=1)
    young = rng.random(count) < 0.1
    paths[young, : length // 2] = np.nan
    return paths, rng.random((count, length))


def _encode_ms(images) -> float:
    """Milliseconds per frame to write ``images`` to an H.264 MP4 (the baseline)."""
    import imageio.v2 as imageio

    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        writer = imageio.get_writer(Path(folder) / "bench.mp4", fps=30, codec="libx264",
                                    macro_block_size=2, ffmpeg_log_level="error")  # fmt: skip
        with writer:
            for image in images:
                writer.append_data(image)
        return 1e3 * (time.perf_counter() - start) / len(images)


def _in_process_with(threads: int, settings: dict, measure: str = "measure") -> dict:
    """``measure(**settings)`` (a function of this module) in a fresh Python process with
    ``LP_NUM_THREADS=threads``."""
    code = (f"import json, sys; from aquagait.bench.render import {measure} as measure; "
            "print(json.dumps(measure(**json.loads(sys.argv[1]))))")  # fmt: skip
    env = {**os.environ, "LP_NUM_THREADS": str(threads)}
    done = subprocess.run([sys.executable, "-c", code, json.dumps(settings)], env=env,
                          capture_output=True, text=True)  # fmt: skip
    if done.returncode != 0:
        raise RuntimeError(f"the renderer benchmark on {threads} thread(s) failed:\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])
