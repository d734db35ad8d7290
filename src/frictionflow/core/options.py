"""Compile options the kernels share; whether a kernel is in numba's cache, and compiling ahead in a second
process.

``NO_RUNTIME`` compiles a kernel without numba's runtime: no atomic
reference counts on the arrays of the records it takes, which in tight loops
cost more than the arithmetic.  Such a kernel must allocate nothing (its
callers make the room).  The option is underscore-prefixed in numba, so it
is applied only where the installed numba has it.
"""

from __future__ import annotations

import os
import subprocess
import sys

try:
    from numba.core.cpu import CPUTargetOptions

    NO_RUNTIME: dict[str, bool] = {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}
except ImportError:  # a numba without that module: compile with the runtime
    NO_RUNTIME = {}


def is_cached(kernel) -> bool:
    """numba's cache holds ``kernel`` (a dispatcher compiled with ``cache=True``): its index file exists.

    A numba without these internals answers True, so that nothing is compiled ahead on a guess.
    """
    try:
        return os.path.exists(kernel._cache._cache_file._index_path)
    except AttributeError:
        return True


def compile_ahead(module: str, cached: bool) -> subprocess.Popen | None:
    """Start ``python -m module`` (a module that compiles kernels into numba's cache) unless ``cached`` or on one
    core; the child process, or None.

    A first run compiles its kernels one after another on one core; the child compiles the ones the run needs
    last on another, and the run loads them from the cache when it gets to them.
    """
    if cached or (os.cpu_count() or 1) < 2:
        return None
    return subprocess.Popen([sys.executable, "-m", module], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
