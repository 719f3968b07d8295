"""Draw the README's pictures of the creature library, each by aquagait's own renderer.

Run from the repository root: ``python tools/make_gallery.py [NAME ...]``. For
every library creature (or those named) it swims the shipped gait from rest
on the creature's default grid and writes ``docs/gallery/NAME.png``, the last
frame as ``aquagait render`` draws it (3D creatures from the 'follow' view);
for the fish also ``docs/fish_swim.png``, a contact sheet of six frames of
its second cycle, three-quarters from behind; for eel2d also
``docs/eel2d_swim.png``, the README's first picture: the last frame of
``aquagait swim eel2d --seconds 4``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import aquagait as ag
from aquagait.app import prepare_swim, run_swim
from aquagait.viz import render_swim

DOCS = Path(__file__).resolve().parents[1] / "docs"
SECONDS = 3.0
SMALL = {"width": 480, "height": 360}  # 3D pictures for the README


def gallery(name: str) -> None:
    run = run_swim(prepare_swim(name, seconds=SECONDS))
    model, trajectory = run.setup.creature.model, run.trajectory
    last = len(trajectory.time) - 1
    look = SMALL if model.dim == 3 else {}
    path = render_swim(trajectory, model, DOCS / "gallery" / f"{name}.png", [last], **look)
    print(f"wrote {path}")
    if name == "fish":
        fps = int(trajectory.fps)
        frames = range(fps, 2 * fps, fps // 6)  # six pictures of the second second
        small = {"width": 320, "height": 240}
        sheet = render_swim(trajectory, model, DOCS / "fish_swim.png", frames, view="follow",
                            **small)  # fmt: skip
        print(f"wrote {sheet}")
    if name == "eel2d":
        run = run_swim(prepare_swim(name, seconds=4.0))
        last = len(run.trajectory.time) - 1
        print(f"wrote {render_swim(run.trajectory, model, DOCS / 'eel2d_swim.png', [last])}")


if __name__ == "__main__":
    for name in sys.argv[1:] or ag.creatures.names():
        gallery(name)
