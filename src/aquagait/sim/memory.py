"""Memory: what the machine has free for a scene, and the refusal of a grid that would not fit.

``make_scene`` asks the fluid model how many bytes its fields and scratch take
on the grid (``FluidModel.memory``) and refuses the grid, before anything is
allocated, when that is more than the memory available now. Without the
refusal a grid of 4000^3 cells is allocated lazily (NumPy's zeros are pages
the kernel maps on first touch) and the swim runs on for minutes before the
machine runs out.

Available memory [bytes]: on Linux ``MemAvailable`` of ``/proc/meminfo`` (free
memory plus the caches the kernel would give back), and, in a container, the
cgroup's limit less what it uses, whichever is smaller; elsewhere the free
physical pages (``os.sysconf``). Unknown: no refusal.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from aquagait.grid import Grid

CGROUP_FILES = (
    ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),  # cgroup v2
    (
        "/sys/fs/cgroup/memory/memory.limit_in_bytes",  # cgroup v1
        "/sys/fs/cgroup/memory/memory.usage_in_bytes",
    ),
)
"""The (limit, usage) files of this process's memory cgroup, v2 first."""


class GridTooLarge(ValueError):
    """A grid whose fluid would take more memory than the machine has available."""


def available_memory() -> int | None:
    """The memory this process may still allocate now [bytes], None where unknown
    (module docstring)."""
    known = [n for n in (_meminfo_available(), _cgroup_room()) if n is not None]
    if not known:
        try:
            known.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (AttributeError, ValueError, OSError):
            return None
    return min(known)


def check_memory(grid: Grid, needed: int, available: int | None) -> None:
    """Refuse ``grid`` when ``needed`` bytes are more than ``available``.

    Args:
        grid: the fluid grid.
        needed: what the fluid model takes on it [bytes] (``FluidModel.memory``).
        available: what the machine has free [bytes] (``available_memory``); None: no check.
    Raises:
        GridTooLarge: with the estimate, the memory available, and a resolution
            and a cell size that would fit.
    """
    if available is None or needed <= available:
        return
    cells = math.prod(grid.shape)
    shrink = (needed / available) ** (1 / grid.dim)  # per axis, to fit
    fewer = "x".join(str(max(2, int(n / shrink))) for n in grid.shape)
    raise GridTooLarge(
        f"the {'x'.join(map(str, grid.shape))} grid of {_metres(grid.cell_size)} m cells would "
        f"need about {_bytes(needed)} for the fluid ({needed / cells:.0f} bytes a cell), but "
        f"{_bytes(available)} is available: give at most {int(cells * available / needed):,} "
        f"cells, e.g. {fewer} (--resolution) of the same cells over a smaller domain, or the "
        f"same domain in cells of {_metres(grid.cell_size * shrink, up=True)} m (--cell-size)"
    )


def _meminfo_available(path: str = "/proc/meminfo") -> int | None:
    try:
        for line in Path(path).read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024  # the file counts kB
    except (OSError, ValueError, IndexError):
        pass
    return None


def _cgroup_room(files=CGROUP_FILES) -> int | None:
    for limit_path, usage_path in files:
        try:
            limit = Path(limit_path).read_text().strip()
            usage = int(Path(usage_path).read_text().strip())
        except (OSError, ValueError):
            continue
        if limit == "max" or int(limit) >= 2**60:  # no limit (v1 writes a huge number)
            return None
        return max(0, int(limit) - usage)
    return None


def _bytes(n: float) -> str:
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n / 1e3:.3g} kB"


def _metres(h: float, up: bool = False) -> str:
    """``h`` [m] to two significant figures, rounded up with ``up`` (a cell that fits)."""
    scale = 10.0 ** (math.floor(math.log10(h)) - 1)
    return f"{(math.ceil(h / scale - 1e-9) if up else round(h / scale)) * scale:.2g}"
