"""Compiling kernels ahead in a second process, and whether a kernel is in numba's cache.

A first run on an empty numba cache compiles its kernels one after another
on one core.  A second process (``python -m module``, a module that compiles
kernels) can compile the ones the run needs last on another core: numba
keeps each compiled kernel in a file, and the run loads it when it gets to
it.  Used by :mod:`frictionflow.analysis.precompile` (the single mass's
analysis) and :mod:`frictionflow.solvers.structure_precompile` (the
structure engine).  Outside ``core/`` on purpose: editing this module does
not drop the compiled kernels (``core/_cache.py`` hashes ``core/``).

Setting the environment variable ``FRICTIONFLOW_COMPILE_AHEAD=0`` starts no
second process (the test suite does, so that its workers have the cores).
"""

from __future__ import annotations

import os
import subprocess
import sys
from typing import Any

#: the environment variable that turns compiling ahead off ("0")
ENV = "FRICTIONFLOW_COMPILE_AHEAD"


def is_cached(kernel: Any) -> bool:
    """numba's cache holds ``kernel`` (a dispatcher compiled with ``cache=True``) for its current source and numba.

    A numba without these internals answers True, so that nothing is compiled ahead on a guess.
    """
    try:
        return bool(kernel._cache._cache_file._load_index())  # {} for a missing or stale index
    except Exception:  # numba's internals moved: assume cached
        return True


def usable_cores() -> int:
    """The cores this process may run on (its affinity where the platform tells it, e.g. a one-core batch job)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def compile_ahead(module: str, cached: bool) -> subprocess.Popen | None:
    """Start ``python -P -m module`` unless ``cached``, on one usable core, when turned off (:data:`ENV`) or when
    no process can be started; the child, or None (the run then compiles everything itself, as without it)."""
    if cached or os.environ.get(ENV) == "0" or usable_cores() < 2 or not sys.executable:
        return None
    try:  # -P: the working directory's files do not shadow the installed packages in the child
        return subprocess.Popen([sys.executable, "-P", "-m", module], stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError:  # a process limit, a sandbox: only the speed-up is lost
        return None
