"""What each solver's kernel codes mean, as public :class:`~frictionflow.modes.SwitchMode` values.

The compiled kernels record the mode entered at each switch in their own
codes (the exact kernel's SLIP_POS ... STICK = 1 ... 8, the adaptive
kernel's -1/0/+1).  Each solver has one table, stated in
:mod:`frictionflow.core.event_modes` (below the engines: the closed-form
interpolant reads it too) and re-exported here; :func:`switch_modes`
applies it when a :class:`~frictionflow.trajectory.Trajectory` is built, so
kernel codes never leave the solvers.  Fixed-step RK4 locates
no switches and has no table.
"""

from __future__ import annotations

from collections.abc import Mapping

from functools import lru_cache

import numpy as np

from ..core.event_modes import ADAPTIVE_EVENT_MODES, EXACT_EVENT_MODES  # noqa: F401  (re-exported: the solvers' tables)
from ..modes import SwitchMode


def switch_modes(codes: np.ndarray, table: Mapping[int, SwitchMode]) -> np.ndarray:
    """``codes`` translated by ``table``, as an int8 array of :class:`SwitchMode` values.

    A code missing from the table is a kernel/table mismatch: refuse it
    rather than let a kernel code through.
    """
    codes = np.asarray(codes, dtype=np.int64)
    translation = _TRANSLATIONS.get(id(table)) or _TRANSLATIONS.setdefault(id(table), _translation(tuple(sorted(table.items()))))
    # one C loop over bytes (numpy's indexing and reductions cost ~1 us each per call at this size);
    # codes outside int8 would wrap in the cast: checked first
    if codes.size and (codes.min() < -128 or codes.max() > 127):
        _refuse(codes, table)
    modes = bytearray(codes.astype(np.int8).tobytes()).translate(translation)
    if _MISSING_BYTE in modes:
        _refuse(codes, table)
    return np.frombuffer(modes, dtype=np.int8)


def _refuse(codes: np.ndarray, table: Mapping[int, SwitchMode]) -> None:
    unknown = sorted(set(codes.tolist()) - set(table))
    raise ValueError(f"kernel mode code(s) {unknown} have no SwitchMode in the table")


_MISSING = np.int8(-128)
_MISSING_BYTE = bytes([int(_MISSING) & 0xFF])
#: the byte translation of each (module-constant) table, by identity: built once
_TRANSLATIONS: dict[int, bytes] = {}


@lru_cache(maxsize=8)
def _translation(items: tuple[tuple[int, SwitchMode], ...]) -> bytes:
    """A 256-byte table from kernel code (as an int8's byte) to its SwitchMode value's byte, -128 where missing."""
    out = bytearray(_MISSING_BYTE * 256)
    for code, mode in items:
        if not (-128 <= code <= 127 and -128 < int(mode) <= 127):
            raise ValueError(f"kernel mode code {code} or SwitchMode {mode!r} outside int8")
        out[code & 0xFF] = int(mode) & 0xFF
    return bytes(out)
