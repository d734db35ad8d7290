"""Stribeck friction: Coulomb's stick rule with a falling (and optionally viscous) slip curve."""

from __future__ import annotations

import sys

from ..core import layout
from ..core.curve_stribeck import magnitude, partial, slope, terms  # noqa: F401  (the law's curve, re-exported)
from ..parameters import MODEL_MAX, nonnegative_real, positive_real
from .base import FD, FS, RK4_BAND, STICK_FORCE, FrictionLaw
from .registry import register

VS = positive_real("vs", "V_s", "Stribeck velocity", "law", 0.01, upper=MODEL_MAX, sweepable=True, dimension="velocity")
DELTA = positive_real("delta", "delta", "Stribeck exponent", "law", 2.0, upper=100.0, sweepable=True)
VISCOUS = nonnegative_real("viscous", "c_v", "viscous friction coefficient", "law", 0.0, upper=MODEL_MAX, sweepable=True,
                          dimension="damping")


@register
class Stribeck(FrictionLaw):
    """Coulomb's stick rule with a Stribeck curve in slip.

    ::

        F(V_r) = sgn(V_r) [F_d + (F_s - F_d) exp(-(|V_r| / V_s)^delta) + c_v |V_r|]

    While V_r = 0 the mass sticks as long as |F_e| <= F_s (as for
    :class:`~frictionflow.Coulomb`).

    Parameters
    ----------
    fd, fs:
        Kinetic level F_d and static level F_s >= F_d (the slip force at
        V_r -> 0; default 2 F_d).
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
    code = layout.STRIBECK
    parameters = (FD, FS.with_default(lambda v: 2.0 * v["fd"], "2 F_d"), STICK_FORCE, VS, DELTA, VISCOUS, RK4_BAND)
    kernel_slots = {"rk4_band": layout.VD, "vs": layout.LAW_A, "delta": layout.LAW_B, "viscous": layout.LAW_C}
    piecewise_constant = False
    magnitude = staticmethod(magnitude)
    slope = staticmethod(slope)

    def __init__(
        self,
        fd: float = 0.02,
        fs: float | None = None,
        vs: float = 0.01,
        delta: float = 2.0,
        viscous: float = 0.0,
        stick_force: str = "resultant",
        rk4_band: float = 1e-4,
    ) -> None:
        self._assign(fd=fd, fs=fs, vs=vs, delta=delta, viscous=viscous, stick_force=stick_force, rk4_band=rk4_band)

    def resolvable(self) -> bool:
        # (V_r / V_s)^delta overflows at every V_r a step can tell from 0 once V_s^delta is below the normal floats
        return self.vs ** self.delta >= sys.float_info.min
