"""Helpers shared by the benchmark scripts: timing by best of repeats, in one process."""

from __future__ import annotations

import platform
import time
from typing import Callable


def best_of(fn: Callable[[], object], repeat: int = 3, clock: Callable[[], float] = time.perf_counter) -> float:
    """Smallest time of ``repeat`` calls (the least disturbed by other load): wall time, or ``clock``'s
    (``time.process_time``: CPU time)."""
    best = float("inf")
    for _ in range(repeat):
        t = clock()
        fn()
        best = min(best, clock() - t)
    return best


def header(title: str) -> None:
    import os

    print(f"# {title}")
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
