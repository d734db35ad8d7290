"""Compile the batched kernels with 8-wide vectors on CPUs that have AVX-512.

LLVM's loop vectoriser picks 4-wide vectors on AVX-512 machines by default;
the batched kernels, which integrate lanes in lock step, run about twice as
fast 8-wide.  The width is an LLVM option global to the process, so it is set
only while the batched kernels compile (a one-lane warm-up call) and reset
afterwards.  While it is set LLVM reports every loop it did not vectorise on
file descriptor 2, so that is silenced for the duration.  Set
``FRICTIONFLOW_VECTOR_WIDTH=0`` to keep LLVM's choice.
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from typing import Iterator


def _wanted_width() -> int:
    width = os.environ.get("FRICTIONFLOW_VECTOR_WIDTH", "8")
    try:
        w = int(width)
    except ValueError:
        return 0
    if w <= 0:
        return 0
    try:
        import llvmlite.binding as llvm

        return w if "+avx512f" in llvm.get_host_cpu_features().flatten() else 0
    except Exception:  # pragma: no cover - an llvmlite without these hooks
        return 0


@contextmanager
def wide_vectors() -> Iterator[None]:
    """Compile what is called inside with the wider vector width (if any)."""
    width = _wanted_width()
    if not width:
        yield
        return
    import llvmlite.binding as llvm

    saved = os.dup(2)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 2)
        llvm.set_option("frictionflow", f"-force-vector-width={width}")
        yield
    finally:
        llvm.set_option("frictionflow", "-force-vector-width=0")
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)
