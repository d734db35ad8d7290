"""Compile the structure engine's later kernels in a second process while a first run compiles the rest.

On an empty numba cache the first exact run of a structure spends almost
three minutes compiling, one kernel after another on one core: the run loop
types its callees in order (the combination builder and the stick rule
first, the phase kernel ``to_event`` with the walk and the work quadrature
later, about a third of it), then the analysis compiles the state
evaluation (``states``) and the stretch kernel (``advance``).  numba keeps
every compiled kernel in a file, so a second process compiles the kernels
needed last, first, on another core: the run then finds them in the cache
when it gets to them.  Their arguments are made here with the types the run
gives them (a :data:`~frictionflow.core.structure.combo.Combo` of empty
arrays: ``to_event`` is compiled without building a combination; ``states``
and ``advance`` call the builder, which the run has cached by then).

Nothing starts when the run loop is cached already, on a single usable core or
when turned off (:mod:`frictionflow._compile_ahead`); a kernel the second
process has not finished is compiled by the run itself, as without it.  The
second process is stopped when the caller's work is done (:func:`first_use`).
"""

from __future__ import annotations

import sys
from contextlib import contextmanager
from typing import Callable, Iterator

import numba
import numpy as np

from .._compile_ahead import compile_ahead, is_cached
from ..core.structure import evaluate, run
from ..core.structure.combo import Combo
from ..core.structure.work import n_channels
from ..params import BeltOscillator
from ..system import System, assemble
from .structure_motion import buffers

#: each :data:`~frictionflow.core.structure.combo.Combo` field's (dtype, ndim): what a run's combinations hold
#: (C-contiguous; ``tests/structure/test_precompile.py`` checks it against built ones)
COMBO_FIELDS: dict[str, tuple[type, int]] = {
    "modes": (np.int8, 1), "stuck": (np.int64, 1), "Z": (np.float64, 2), "R": (np.float64, 2),
    "HE": (np.float64, 2), "keff": (np.float64, 2), "f0": (np.float64, 1), "lam": (np.complex128, 1),
    "V": (np.complex128, 2), "Vi": (np.complex128, 2), "VB": (np.complex128, 2), "D": (np.float64, 2),
    "dc": (np.float64, 1), "Dh": (np.float64, 2), "active": (np.bool_, 1), "W": (np.complex128, 2),
    "ZT": (np.float64, 2), "bs": (np.float64, 1), "rb": (np.float64, 1), "b1": (np.complex128, 1),
    "bh": (np.complex128, 2), "e1": (np.float64, 1), "WA": (np.float64, 2), "nz": (np.int32, 2),
}


def cached() -> bool:
    """The structure engine's run loop is in numba's cache (its callees then are too)."""
    return is_cached(run.run)


def empty_combo() -> Combo:
    """A :data:`~frictionflow.core.structure.combo.Combo` of empty arrays: the type of every combination."""
    return Combo(*(np.zeros((0,) * ndim, dtype=dtype) for dtype, ndim in COMBO_FIELDS.values()))


def kernels() -> list[tuple[Callable, tuple]]:
    """(kernel, signature) in the order the second process compiles them: the ones a first run needs last, first.

    The arguments are those :func:`frictionflow.core.structure.run.run` passes to ``to_event`` and those
    :class:`~frictionflow.motion.Motion` passes to ``states`` and ``advance``, on a one-dof structure.
    """
    asm = assemble(System.single_mass(BeltOscillator(0.05, 0.1)))
    minv, cb, n_work = np.linalg.inv(asm.mass), empty_combo(), n_channels(asm)
    out, _ = buffers(asm, 2)
    scr = run.scratch(asm, n_work)
    q, z = np.zeros(1), np.zeros(0)
    calls = [
        (run.to_event, (asm, cb, 0.0, 1.0, 1e-13, 0.0, 0.0, out, np.int64(1), np.zeros(n_work), scr)),
        (evaluate.states, (asm, minv, z, np.zeros((2, 0)), np.zeros((1, 0), dtype=np.int8), z, np.zeros((2, 0)))),
        (run.advance, (asm, minv, np.zeros(1, dtype=np.int8), q, q.copy(), 0.0, 1.0, n_work)),
    ]
    return [(kernel, tuple(numba.typeof(a) for a in args)) for kernel, args in calls]


def compile_kernels() -> None:
    """Compile (or load from the cache) each of :func:`kernels` for its signature."""
    for kernel, signature in kernels():
        kernel.compile(signature)


def in_background(ready: bool | None = None) -> Callable[[], None]:
    """Start compiling the later kernels in a child process unless the run loop is cached (``ready``: that answer,
    if known already); returns ``stop()``.

    Call ``stop()`` once the run and its analysis are done: a child still compiling is ended (what it has
    finished stays in the cache; numba writes each entry whole).
    """
    child = compile_ahead(__name__, cached() if ready is None else ready)
    if child is None:
        return lambda: None

    def stop() -> None:
        if child.poll() is None:
            child.terminate()
        child.wait()

    return stop


@contextmanager
def first_use() -> Iterator[None]:
    """Around a first structure run on an empty numba cache: say so in one line (on a terminal) and compile the later
    kernels :func:`in_background`, stopped on leaving."""
    ready = cached()
    if not ready and sys.stderr.isatty():
        print("frictionflow: compiling the structure engine (once per machine and version: a minute or two)",
              file=sys.stderr, flush=True)
    stop = in_background(ready)
    try:
        yield
    finally:
        stop()


if __name__ == "__main__":
    compile_kernels()
