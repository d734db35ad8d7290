"""Kernels rebuilt around a user's slip function.

A compiled kernel reads the law's slip force as a module global.  For a
user-defined law, copies of the kernel's functions are made with that global
replaced and compiled afresh (not cached: the user's function lives in the
user's session).  Passing the function as an argument instead would make
numba refuse to cache the built-in kernels too.

The copies get a qualified name of their own (:data:`REBOUND` before the
original's).  numba names a compiled function's symbol after its module,
qualified name, argument types and a per-process counter; a cached kernel
carries the counter of the process that compiled it.  A copy named like its
original could therefore get the very symbol of a cached kernel's callee
(same name, same counter value in this process), and the JIT links a cached
kernel loaded later to the copy already loaded (the callee symbols are weak):
a sweep of a built-in law would then run the user's slip force.  No cached
kernel has a name starting with :data:`REBOUND`.
"""

from __future__ import annotations

import types
from typing import Any, Callable

from numba import njit

#: the first part of every rebound copy's qualified name (never a cached kernel's)
REBOUND = "<rebound>"


def rebind(module: types.ModuleType, names: tuple[str, ...], compiled: bool = True, **globals_: Any) -> dict[str, Callable]:
    """Copies of ``module``'s compiled functions ``names`` (callees first) seeing ``globals_`` instead of its own.

    ``compiled=False`` keeps them as Python functions (for a user function numba cannot compile).
    """
    g = dict(vars(module))
    g.update(globals_)
    for name in names:
        code = getattr(module, name).py_func
        fn = types.FunctionType(code.__code__, g, name, code.__defaults__)
        fn.__qualname__ = f"{REBOUND}.{code.__qualname__}"  # never a cached kernel's symbol (module docstring)
        g[name] = njit(fn, cache=False, **_inlining(module, name)) if compiled else fn
    return g


def _inlining(module: types.ModuleType, name: str) -> dict[str, Any]:
    """The inlining options (numba's ``inline``, LLVM's ``forceinline``) ``module.name`` was compiled with.

    A copy keeps them: the user's kernel has the structure of the built-in one (a part inlined
    there is inlined here, so its calls cost no reference counting of their arrays either).
    """
    options = getattr(module, name).targetoptions
    return {key: options[key] for key in ("inline", "forceinline") if key in options}
