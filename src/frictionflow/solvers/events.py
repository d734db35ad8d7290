"""What each solver's kernel codes mean, as public :class:`~frictionflow.modes.SwitchMode` values.

The compiled kernels record the mode entered at each switch in their own
codes (the exact kernel's SLIP_POS ... STICK = 1 ... 8, the adaptive
kernel's -1/0/+1).  Each solver has one table here, and
:func:`switch_modes` applies it when a :class:`~frictionflow.trajectory.Trajectory`
is built, so kernel codes never leave the solvers.  Fixed-step RK4 locates
no switches and has no table.
"""

from __future__ import annotations

from collections.abc import Mapping

from functools import lru_cache

import numpy as np

from ..core import exact as ke
from ..core import friction as kf
from ..modes import SwitchMode

#: the exact event-driven kernel (:mod:`frictionflow.core.exact`)
EXACT_EVENT_MODES: Mapping[int, SwitchMode] = {
    ke.SLIP_POS: SwitchMode.SLIP_POSITIVE,
    ke.SLIP_NEG: SwitchMode.SLIP_NEGATIVE,
    ke.STICK: SwitchMode.STICK,
    ke.HOLD: SwitchMode.BAND_HOLD,
    ke.SAT_POS: SwitchMode.BAND_SATURATED_POSITIVE,
    ke.SAT_NEG: SwitchMode.BAND_SATURATED_NEGATIVE,
    ke.EDGE_LO: SwitchMode.BAND_EDGE_LOWER,
    ke.EDGE_HI: SwitchMode.BAND_EDGE_UPPER,
}

#: the Dormand-Prince kernel (:mod:`frictionflow.core.dopri`): slip direction or stick
ADAPTIVE_EVENT_MODES: Mapping[int, SwitchMode] = {
    kf.SLIP_POS: SwitchMode.SLIP_POSITIVE,
    kf.SLIP_NEG: SwitchMode.SLIP_NEGATIVE,
    kf.STICK: SwitchMode.STICK,
}


def switch_modes(codes: np.ndarray, table: Mapping[int, SwitchMode]) -> np.ndarray:
    """``codes`` translated by ``table``, as an int8 array of :class:`SwitchMode` values.

    A code missing from the table is a kernel/table mismatch: refuse it
    rather than let a kernel code through.
    """
    codes = np.asarray(codes, dtype=np.int64)
    lookup, low = _LOOKUPS.get(id(table)) or _LOOKUPS.setdefault(id(table), _lookup(tuple(sorted(table.items()))))
    index = codes - low
    if index.size and (index.min() < 0 or index.max() >= len(lookup) or (lookup[index] == _MISSING).any()):
        unknown = sorted(set(codes.tolist()) - set(table))
        raise ValueError(f"kernel mode code(s) {unknown} have no SwitchMode in the table")
    return lookup[index]


_MISSING = np.int8(-128)
#: the dense lookup of each (module-constant) table, by identity: built once
_LOOKUPS: dict[int, tuple[np.ndarray, int]] = {}


@lru_cache(maxsize=8)
def _lookup(items: tuple[tuple[int, SwitchMode], ...]) -> tuple[np.ndarray, int]:
    """A dense array from kernel code (offset by the smallest) to SwitchMode value: one indexing per call."""
    low, high = items[0][0], items[-1][0]
    lookup = np.full(high - low + 1, _MISSING, dtype=np.int8)
    for code, mode in items:
        lookup[code - low] = mode
    return lookup, low
