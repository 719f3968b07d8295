"""Draw the creature library's pictures (README, docs/gallery.md) with aquagait's own renderer.

Run from the repository root: ``python tools/make_gallery.py [NAME ...]``. For
every library creature (or those named) it swims the shipped gait from rest
on the creature's default grid for ``SECONDS`` and writes
``docs/gallery/NAME.png``, the last frame as ``aquagait swim`` and
``aquagait render`` draw it (3D: 1280x720 from the creature's own view, the
wake's vortex surfaces and particle traces); then ``docs/library.png``, the
paper's Figure 1: every creature's picture in one labelled sheet (those not
named this time from their pictures already in ``docs/gallery``).

For the fish also ``docs/fish_swim.png``, a contact sheet of six frames of
its third second (from its own view, the side and above); for eel2d also
``docs/eel2d_swim.png``, the getting-started page's picture: the last frame of
``aquagait swim eel2d --seconds 4``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import aquagait as ag
from aquagait.app import draw_swim, picture_look, prepare_swim, run_swim

DOCS = Path(__file__).resolve().parents[1] / "docs"
SECONDS = 3.0
TILE = (640, 360)  # a creature's place in the library sheet [pixels]
COLUMNS = 3


def gallery(name: str) -> None:
    run = run_swim(prepare_swim(name, seconds=SECONDS))
    creature, trajectory = run.setup.creature, run.trajectory
    model = creature.model
    look = picture_look(model, default_view=creature.view)
    last = len(trajectory.time) - 1
    path = draw_swim(trajectory, model, DOCS / "gallery" / f"{name}.png", [last], **look)
    print(f"wrote {path}", flush=True)
    if name == "fish":
        fps = int(trajectory.fps)
        frames = range(2 * fps, 3 * fps, fps // 6)  # six pictures of the third second
        sheet = draw_swim(trajectory, model, DOCS / "fish_swim.png", frames,
                          **(look | {"width": 640, "height": 360}))  # fmt: skip
        print(f"wrote {sheet}", flush=True)
    if name == "eel2d":
        run = run_swim(prepare_swim(name, seconds=4.0))
        last = len(run.trajectory.time) - 1
        print(f"wrote {draw_swim(run.trajectory, model, DOCS / 'eel2d_swim.png', [last])}")


def library_sheet(names, path: Path) -> Path:
    """The creatures' gallery pictures, each fitted into a ``TILE`` with its name, in rows of
    ``COLUMNS``, written to ``path``."""
    import imageio.v2 as imageio
    from PIL import Image, ImageDraw, ImageFont

    width, height = TILE
    rows = -(-len(names) // COLUMNS)
    sheet = Image.new("RGB", (COLUMNS * width, rows * height), "white")
    font = ImageFont.load_default(size=26)
    for k, name in enumerate(names):
        picture = Image.fromarray(imageio.imread(DOCS / "gallery" / f"{name}.png")[..., :3])
        picture.thumbnail(TILE, Image.Resampling.LANCZOS)
        corner = np.array([k % COLUMNS * width, k // COLUMNS * height])
        offset = (np.array(TILE) - picture.size) // 2
        sheet.paste(picture, tuple(corner + offset))
        label = ImageDraw.Draw(sheet)
        at = tuple(corner + [14, 10])
        label.rectangle(label.textbbox(at, name, font=font), fill="white")  # over the picture
        label.text(at, name, fill=(20, 20, 20), font=font)
    sheet.save(path)
    return path


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", metavar="NAME",
                        help="library creatures to draw (default: all of them)")  # fmt: skip
    names = parser.parse_args().names or ag.creatures.names()
    for name in names:
        gallery(name)
    print(f"wrote {library_sheet(ag.creatures.names(), DOCS / 'library.png')}")
