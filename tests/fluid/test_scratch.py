"""Per-thread scratch caches: one set of arrays per thread and key, kept between calls."""

import threading

import numpy as np

from aquagait.fluid.scratch import per_thread_cache


def _in_thread(fn):
    out = []
    thread = threading.Thread(target=lambda: out.append(fn()))
    thread.start()
    thread.join()
    return out[0]


def test_a_thread_gets_its_own_arrays_and_keeps_them():
    builds = []

    @per_thread_cache(maxsize=2)
    def work(n):
        builds.append(n)
        return np.zeros(n)

    mine = work(3)
    assert work(3) is mine  # kept between calls: no fresh pages
    theirs = _in_thread(lambda: (work(3), work(3)))
    assert theirs[0] is theirs[1] and theirs[0] is not mine
    assert builds == [3, 3]


def test_the_least_recently_used_key_goes_first():
    @per_thread_cache(maxsize=2)
    def work(n):
        return np.zeros(n)

    one, two = work(1), work(2)
    assert work(1) is one  # 1 is now the most recent
    work(3)  # evicts 2
    assert work(1) is one
    assert work(2) is not two
    work.cache_clear()
    assert work(1) is not one
