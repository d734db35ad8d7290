"""The Dormand-Prince kernel's parts: a user's slip law reaches every one that reads the slip force.

A user-defined law runs copies of the functions in ``dopri.KERNEL_FUNCS``
whose global ``slip_force`` is the user's (:mod:`frictionflow.core._rebind`).
A function left off the list keeps the built-in dispatch by law code, which
cannot evaluate the user's function; the comparisons of a user law with the
built-in one it restates (tests/solvers) see that only where their runs pass
through the function (the early stop at a section does not, in a simulation).
Read from the source: the functions' global names.
"""

from __future__ import annotations

from numba.core.registry import CPUDispatcher

from frictionflow.core import dopri


def _compiled_functions() -> dict[str, CPUDispatcher]:
    return {name: f for name, f in vars(dopri).items()
            if isinstance(f, CPUDispatcher) and f.py_func.__module__ == dopri.__name__}


def _reading_slip_force() -> set[str]:
    """The module's compiled functions that name ``slip_force``, themselves or through a callee of the module."""
    funcs = _compiled_functions()
    names = {name: set(f.py_func.__code__.co_names) for name, f in funcs.items()}
    reading = {"slip_force"}
    grown = True
    while grown:
        more = {name for name, used in names.items() if used & reading} - reading
        reading |= more
        grown = bool(more)
    return reading - {"slip_force"}


def test_every_function_reading_the_slip_force_is_rebuilt_for_a_user_law():
    # ``run`` dispatches to the two variants; the solver does that itself for a user law
    missing = _reading_slip_force() - set(dopri.KERNEL_FUNCS) - {"run"}
    assert not missing, f"add to dopri.KERNEL_FUNCS: {sorted(missing)}"


def test_the_list_names_compiled_functions_of_the_module_callees_first():
    funcs = _compiled_functions()
    assert set(dopri.KERNEL_FUNCS) <= set(funcs)
    position = {name: i for i, name in enumerate(dopri.KERNEL_FUNCS)}
    for name in dopri.KERNEL_FUNCS:
        callees = set(funcs[name].py_func.__code__.co_names) & set(position) - {name}
        assert all(position[c] < position[name] for c in callees), name
