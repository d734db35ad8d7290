"""User-defined slip laws: any function of the relative speed, with Coulomb's stick rule."""

from __future__ import annotations

from functools import lru_cache
from typing import Any, Callable

import numpy as np

from ..core import layout
from .base import FD, FS, STICK_FORCE, FrictionLaw
from .registry import register


@lru_cache(maxsize=32)
def compiled_force(func: Callable[[float], float]) -> Callable[[np.ndarray, float], float] | None:
    """``func`` as a compiled ``(p, speed) -> |F|`` (the kernels' signature), or None if numba cannot compile it."""
    from numba import njit
    from numba.core.registry import CPUDispatcher

    jitted = func if isinstance(func, CPUDispatcher) else njit(func)

    @njit
    def user_force(p, speed):
        return jitted(speed)

    try:
        user_force(np.zeros(layout.N_PARAMS), 0.5)
    except Exception:  # not numba-compilable: the kernels run it in Python
        return None
    return user_force


@register
class SlipLaw(FrictionLaw):
    """A user-defined slip law with Coulomb's stick rule.

    Parameters
    ----------
    func:
        ``func(speed) -> float``: the friction magnitude while slipping at
        relative speed ``speed`` > 0.  A numba-compilable function (plain
        ``math``/``numpy`` code, or already ``numba.njit``-ed) runs compiled;
        anything else runs in the Python version of the adaptive solver.
    fs:
        Maximum static friction F_s (defaults to ``func(0)``).
    fd:
        Reference friction level used for TR_B and the default X(0) (defaults
        to ``func`` at 100 V_b-independent units, i.e. ``func(1e2)``).
    dfunc:
        Optional derivative of ``func`` (for the equilibrium's stability); by
        default a central difference.
    stick_force:
        The force held while sticking: ``resultant`` X + 2 zeta X' (default)
        or ``spring`` X (the paper's).
    """


    name = "user"
    code = layout.STRIBECK  # only the adaptive solver runs it, rebuilt around the user's function
    parameters = (FD, FS, STICK_FORCE)
    piecewise_constant = False
    configurable = False
    compiled_slip = False  # the kernels' dispatch by code cannot evaluate the user's function

    def __init__(
        self,
        func: Callable[[float], float],
        fs: float | None = None,
        fd: float | None = None,
        dfunc: Callable[[float], float] | None = None,
        stick_force: str = "resultant",
    ) -> None:
        if not callable(func):
            raise ValueError(f"func must be callable, got {func!r}")
        self.func = func
        self.dfunc = dfunc
        f0 = float(func(0.0))
        self._assign(fd=float(func(1e2)) if fd is None else fd, fs=f0 if fs is None else fs, stick_force=stick_force)

    def kernel_force(self) -> Callable[[np.ndarray, float], float] | None:
        return compiled_force(self.func)

    @property
    def band(self) -> None:
        return None  # RK4 does not run user laws

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        return np.vectorize(lambda s: float(self.func(float(s))), otypes=[float])(speed)

    def slip_slope(self, speed: float) -> float:
        if self.dfunc is not None:
            return float(self.dfunc(speed))
        h = 1e-6 * max(abs(speed), 1e-6)
        return (float(self.func(speed + h)) - float(self.func(speed - h))) / (2 * h)

    def as_dict(self) -> dict[str, Any]:
        return super().as_dict() | {"func": getattr(self.func, "__name__", repr(self.func))}

    def __hash__(self) -> int:
        return id(self)

    def __eq__(self, other: object) -> bool:
        return self is other
