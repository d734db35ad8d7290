"""Many points spread over the cores: Python threads calling a compiled kernel that releases the GIL.

numba's ``parallel=True`` does the same for a ``prange`` loop, but compiling
each such kernel's parallel region costs seconds on a fresh cache (the loop
body is compiled again as a gufunc), which every new user and CI run pays.  A
point-range kernel compiled with ``nogil=True`` is compiled once, as any
kernel, and threads give the same parallelism.  Points differ in cost (some
stop early), so the range is cut into more pieces than threads and each
thread takes the next piece when it is done (dynamic scheduling).

The number of threads is numba's (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``),
so a user or a Dask worker that limits numba limits this too.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable

import numba

#: pieces per thread: enough to even out points of unequal cost, few enough that each is long
PIECES_PER_THREAD = 8


def pieces(n: int, threads: int, per_thread: int = PIECES_PER_THREAD) -> list[tuple[int, int]]:
    """``range(n)`` cut into contiguous ``(start, stop)`` pieces, about ``threads * per_thread`` of them."""
    count = max(1, min(n, threads * per_thread))
    size = -(-n // count)
    return [(s, min(n, s + size)) for s in range(0, n, size)]


def over_points(kernel: Callable[..., Any], n: int, *args: Any, per_thread: int = PIECES_PER_THREAD) -> None:
    """Call ``kernel(start, stop, *args)`` on pieces of ``range(n)``, in parallel over numba's threads.

    ``kernel`` must be compiled with ``nogil=True`` (else the threads take turns)
    and write only the points ``start .. stop-1`` of its outputs.
    ``per_thread``: pieces per thread (more for points that each cost many
    milliseconds, where a thread left without work at the end is what counts).
    """
    threads = numba.get_num_threads()
    if threads <= 1 or n <= 1:
        kernel(0, n, *args)
        return
    with ThreadPoolExecutor(max_workers=threads) as pool:
        for done in [pool.submit(kernel, start, stop, *args) for start, stop in pieces(n, threads, per_thread)]:
            done.result()  # re-raises a kernel's error here
