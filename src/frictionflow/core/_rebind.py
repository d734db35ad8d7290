"""Kernels rebuilt around a user's slip function.

A compiled kernel reads the law's slip force as a module global.  For a
user-defined law, copies of the kernel's functions are made with that global
replaced and compiled afresh (not cached: the user's function lives in the
user's session).  Passing the function as an argument instead would make
numba refuse to cache the built-in kernels too.
"""

from __future__ import annotations

import types
from typing import Any, Callable

from numba import njit


def rebind(module: types.ModuleType, names: tuple[str, ...], compiled: bool = True, **globals_: Any) -> dict[str, Callable]:
    """Copies of ``module``'s compiled functions ``names`` (callees first) seeing ``globals_`` instead of its own.

    ``compiled=False`` keeps them as Python functions (for a user function numba cannot compile).
    """
    g = dict(vars(module))
    g.update(globals_)
    for name in names:
        code = getattr(module, name).py_func
        fn = types.FunctionType(code.__code__, g, name, code.__defaults__)
        g[name] = njit(fn) if compiled else fn
    return g
