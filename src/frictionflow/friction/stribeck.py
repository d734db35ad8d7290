"""Stribeck friction and user-defined slip laws."""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from .. import _validate as check
from ..core import friction as kf
from .base import FrictionLaw


class Stribeck(FrictionLaw):
    """Coulomb's stick rule with a Stribeck curve in slip.

    ::

        F(V_r) = sgn(V_r) [F_d + (F_s - F_d) exp(-(|V_r| / V_s)^delta) + c_v |V_r|]

    While V_r = 0 the mass sticks as long as |F_e| <= F_s (as for
    :class:`~frictionflow.friction.Coulomb`).

    Parameters
    ----------
    fd, fs:
        Kinetic level F_d and static level F_s >= F_d (the slip force at V_r -> 0).
    vs:
        Stribeck velocity V_s > 0.
    delta:
        Stribeck exponent delta > 0 (2: Gaussian, 1: exponential decay).
    viscous:
        Viscous friction coefficient c_v >= 0.
    stick_force:
        ``"resultant"`` (default) or ``"spring"``.
    rk4_band:
        Stick band for the fixed-step RK4 solver only.
    """

    name = "stribeck"
    code = kf.STRIBECK
    piecewise_constant = False

    def __init__(
        self,
        fd: float = 0.02,
        fs: float = 0.04,
        vs: float = 0.01,
        delta: float = 2.0,
        viscous: float = 0.0,
        stick_force: str = "resultant",
        rk4_band: float = 1e-4,
    ) -> None:
        super().__init__(fd, fs, stick_force)
        self.vs = check.positive("vs", vs)
        self.delta = check.positive("delta", delta)
        self.viscous = check.nonnegative("viscous", viscous)
        self.rk4_band = check.positive("rk4_band", rk4_band)

    @property
    def band(self) -> float:
        return self.rk4_band

    def _fill_kernel_params(self, p: np.ndarray) -> None:
        p[kf.VS] = self.vs
        p[kf.DELTA] = self.delta
        p[kf.VISC] = self.viscous

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        s = np.asarray(speed, dtype=float)
        return self.fd + (self.fs - self.fd) * np.exp(-((s / self.vs) ** self.delta)) + self.viscous * s

    def slip_slope(self, vr: float) -> float:
        """dF/dV_r at V_r = vr > 0."""
        u = (vr / self.vs) ** self.delta
        return -(self.fs - self.fd) * self.delta * u / vr * math.exp(-u) + self.viscous if vr > 0 else float("-inf")

    def hopf_damping(self, vb: float) -> float:
        """zeta at which the sliding equilibrium at belt speed vb changes stability: 2 zeta + F'(V_b) = 0."""
        return -0.5 * self.slip_slope(abs(vb))

    def as_dict(self) -> dict[str, Any]:
        return super().as_dict() | {"vs": self.vs, "delta": self.delta, "viscous": self.viscous}


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
    """

    name = "user"
    code = kf.STRIBECK  # only the adaptive solver runs it, with the user's function
    piecewise_constant = False

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
        super().__init__(float(func(1e2)) if fd is None else fd, f0 if fs is None else fs, stick_force)

    @property
    def band(self) -> float:  # pragma: no cover - RK4 does not run user laws
        raise AttributeError("user slip laws run only with the adaptive solver")

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        return np.vectorize(lambda s: float(self.func(float(s))), otypes=[float])(speed)

    def slip_slope(self, vr: float) -> float:
        if self.dfunc is not None:
            return float(self.dfunc(vr))
        h = 1e-6 * max(abs(vr), 1e-6)
        return (float(self.func(vr + h)) - float(self.func(vr - h))) / (2 * h)

    def as_dict(self) -> dict[str, Any]:
        return super().as_dict() | {"func": getattr(self.func, "__name__", repr(self.func))}

    def __hash__(self) -> int:
        return id(self)

    def __eq__(self, other: object) -> bool:
        return self is other
