"""Scratch arrays kept between calls, one set per thread (docs/development.md, "Layers").

The solver's kernels write into work vectors of several megabytes. Fresh
arrays cost a page fault per 4 KiB on first touch, more than a whole V-cycle
on a 64x32x32 grid, so the vectors are kept between solves. They must not be
shared between threads: a Dask worker runs one evaluation per thread, and two
solves writing the same vectors give wrong numbers without any error. So each
thread keeps its own, for as long as it lives (a worker's threads live as long
as the worker, so each pays for its pages once).

The kernels of the step (advection, pressure solve, voxelization) are compiled
with ``nogil=True``, so threads do step at once. Measured: two swims of
different gaits, one after the other, against the same two in two threads of
one process (same numbers, bit for bit), median of 5 tries on 2 cores, in four
sessions, two of them with other jobs running: the eel on its default 128x64
grid (1 s) 1.31x to 1.45x faster in threads, the fish on 64x32x32 (0.2 s)
1.16x to 1.80x (1.80x twice on a quieter machine); with the kernels holding
the GIL, 0.90x to 1.00x. The rest of a step (NumPy, MuJoCo, Python) still
takes turns.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable

_MISSING = object()


def per_thread_cache(maxsize: int):
    """Like ``functools.lru_cache(maxsize)``, but every thread has a cache of its own.

    Use it for the scratch arrays a solve writes into: what ``build(*key)``
    returns is shared by the calls of ONE thread only, so the caller may write
    into it freely as long as it is done with it before the same thread asks
    for the same key again (solves are not re-entrant within a thread).

    Args:
        maxsize: keys kept per thread; the least recently used goes first.
    Returns:
        a decorator for ``build(*key) -> value`` with hashable positional keys.
    """

    def decorate(build: Callable):
        local = threading.local()

        @functools.wraps(build)
        def cached(*key):
            cache = local.__dict__.setdefault("cache", {})  # insertion order = recency
            value = cache.pop(key, _MISSING)
            if value is _MISSING:
                value = build(*key)
            cache[key] = value
            if len(cache) > maxsize:
                del cache[next(iter(cache))]
            return value

        cached.cache_clear = lambda: local.__dict__.pop("cache", None)  # this thread's
        return cached

    return decorate
