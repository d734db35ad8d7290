"""Compile options the kernels share.

``NO_RUNTIME`` compiles a kernel without numba's runtime: no atomic
reference counts on the arrays of the records it takes, which in tight loops
cost more than the arithmetic.  Such a kernel must allocate nothing (its
callers make the room).  The option is underscore-prefixed in numba, so it
is applied only where the installed numba has it.
"""

from __future__ import annotations

try:
    from numba.core.cpu import CPUTargetOptions

    NO_RUNTIME: dict[str, bool] = {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}
except ImportError:  # a numba without that module: compile with the runtime
    NO_RUNTIME = {}
