"""Kernels rebuilt around a user's slip function.

A compiled kernel reads the law's slip force as a module global.  For a
user-defined law, copies of the kernel's functions are made with that global
replaced and compiled afresh.  Passing the function as an argument instead
would make numba refuse to cache the built-in kernels too.

The copies get a qualified name of their own (:data:`REBOUND` before the
original's).  numba names a compiled function's symbol after its module,
qualified name, argument types and a per-process counter; a cached kernel
carries the counter of the process that compiled it.  A copy named like its
original could therefore get the very symbol of a cached kernel's callee
(same name, same counter value in this process), and the JIT links a cached
kernel loaded later to the copy already loaded (the callee symbols are weak):
a sweep of a built-in law would then run the user's slip force.

numba keys a cached kernel on its source file, name and signature, not on the
globals it read.  So copies are cached only when every global
replaced is a compiled function of the package's kernel sources, and the names of
what was bound are part of the copies' name (:func:`binding_tag`): two
bindings never share a cached kernel, and a copy's cache is dropped with the
package's when any kernel source changes (:mod:`._cache`).  Other copies
(a test's throw-away force, a Python function) are compiled afresh in each
process and never cached.
"""

from __future__ import annotations

import types
from typing import Any, Callable

from numba import njit

from ._cache import SOURCE_DIRS

#: the first part of every rebound copy's qualified name (never a built-in kernel's)
REBOUND = "<rebound>"
#: the package's modules whose functions a cached copy may be bound to: those whose sources the cache watches
WATCHED = tuple(f"{__name__.split('.', 1)[0]}.{d}." for d in SOURCE_DIRS)


def rebind(module: types.ModuleType, names: tuple[str, ...], compiled: bool = True, **globals_: Any) -> dict[str, Callable]:
    """Copies of ``module``'s compiled functions ``names`` (callees first) seeing ``globals_`` instead of its own.

    ``compiled=False`` keeps them as Python functions (for a user function numba cannot compile).  Compiled
    copies are kept in numba's cache when every global bound is one of the package's compiled functions
    (the module's docstring), and compiled afresh in each process otherwise.
    """
    tag = binding_tag(globals_) if compiled else None
    prefix = REBOUND if tag is None else f"{REBOUND}[{tag}]"
    g = dict(vars(module))
    g.update(globals_)
    for name in names:
        code = getattr(module, name).py_func
        fn = types.FunctionType(code.__code__, g, name, code.__defaults__)
        fn.__qualname__ = f"{prefix}.{code.__qualname__}"  # never a built-in kernel's symbol (module docstring)
        g[name] = njit(fn, cache=tag is not None, **_inlining(module, name)) if compiled else fn
    return g


def binding_tag(globals_: dict[str, Any]) -> str | None:
    """``name=module.function`` for each global bound, sorted, when each is a compiled function whose source
    :mod:`._cache` watches (:data:`WATCHED`); None otherwise: such copies are not cached, as another function of
    the same name could not be told apart from it."""
    parts = []
    for key, value in sorted(globals_.items()):
        func = getattr(value, "py_func", None)
        module = getattr(func, "__module__", None) or ""
        if not module.startswith(WATCHED):
            return None
        parts.append(f"{key}={module.split('.', 1)[1]}.{func.__qualname__}")
    return ",".join(parts) or None


def _inlining(module: types.ModuleType, name: str) -> dict[str, Any]:
    """The inlining options (numba's ``inline``, LLVM's ``forceinline``) ``module.name`` was compiled with.

    A copy keeps them: the user's kernel has the structure of the built-in one (a part inlined
    there is inlined here, so its calls cost no reference counting of their arrays either).
    """
    options = getattr(module, name).targetoptions
    return {key: options[key] for key in ("inline", "forceinline") if key in options}
