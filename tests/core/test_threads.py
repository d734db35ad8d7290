"""Points spread over threads (core.threads) and the batched kernels' one retry loop (core.batch.with_room)."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from frictionflow.core import batch
from frictionflow.core.threads import over_points, pieces


@pytest.mark.parametrize("n, threads", [(1, 2), (7, 2), (100, 2), (100, 3), (5, 8)])
def test_pieces_cover_the_range_once_in_order(n, threads):
    cuts = pieces(n, threads)
    assert cuts[0][0] == 0 and cuts[-1][1] == n
    assert all(a < b for a, b in cuts)
    assert all(prev[1] == nxt[0] for prev, nxt in zip(cuts, cuts[1:]))
    assert len(cuts) <= threads * 8


def test_over_points_visits_every_point_once():
    seen = np.zeros(1000, dtype=np.int64)

    def kernel(j0, j1, scale):
        seen[j0:j1] += scale

    over_points(kernel, len(seen), 1)
    assert (seen == 1).all()


def test_over_points_raises_a_kernels_error():
    def kernel(j0, j1):
        if j0 <= 500 < j1:
            raise ValueError("point 500")

    with pytest.raises(ValueError, match="point 500"):
        over_points(kernel, 1000)


def test_over_points_on_one_thread_calls_once():
    calls = []
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        over_points(lambda j0, j1: calls.append((j0, j1)), 50)
    finally:
        numba.set_num_threads(before)
    assert calls == [(0, 50)]


def test_with_room_grows_only_for_the_points_that_filled_it():
    need = np.array([1, 5, 17, 3, 70, 2])
    attempts = np.zeros(len(need), dtype=np.int64)
    room = np.zeros(len(need), dtype=np.int64)

    def kernel(j0, j1, todo, cap, full):
        for j in todo[j0:j1]:
            attempts[j] += 1
            full[j] = need[j] > cap
            room[j] = cap

    batch.with_room(kernel, len(need), 4)
    assert (room >= need).all() and (room < 4 * np.maximum(need, 4)).all()  # the first room that fits
    assert list(attempts) == [1, 2, 3, 1, 4, 1]  # 4, 16, 64, 256


@pytest.mark.parametrize("kernel", ["exact", "adaptive"])
def test_batched_results_do_not_depend_on_the_first_room(kernel):
    """Points that overflow a tiny first buffer (8 samples) are run again with more room: the same rows."""
    from frictionflow import Coulomb, Stribeck

    zeta = np.array([0.05, 0.02, 0.05, 0.0])
    vb = np.array([0.01, 0.02, 0.3, 0.01])
    law = Coulomb(0.02, 0.04) if kernel == "exact" else Stribeck(0.02, 0.04, vs=0.05)
    p = np.tile(law.kernel_params(), (len(zeta), 1))
    x0, v0 = np.full(len(zeta), 0.02), vb.copy()

    def rows(cap):
        out = np.empty((len(zeta), batch.NR))
        if kernel == "exact":
            batch.exact_points(p, zeta, vb, x0, v0, 100.0, 1e-6, 3, 1e-13, out, cap=cap)
        else:
            batch.adaptive_points(p, zeta, vb, x0, v0, 100.0, batch.Ode(1e-10, 1e-13, 10_000_000), 1e-6, 3, 1e-9, out, cap=cap)
        return out

    np.testing.assert_array_equal(rows(8), rows(None))
