"""Dahl's law (Dahl 1968): friction as a rate-independent elastic-plastic bristle, no static peak."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core import stiff
from ..parameters import Param
from .lugre import BRISTLE_FD, SIGMA0
from .registry import register
from .stateful import StatefulLaw

#: alpha >= 1 keeps the Jacobian bounded where the force saturates (u -> 0); F_C > 0 divides the deflection's rate
ALPHA = Param("alpha", "alpha", "Dahl exponent (stateful laws)", "law", 1.0, lower=1.0, upper=100.0, sweepable=True)


@register
class Dahl(StatefulLaw):
    """Dahl friction: the deflection z of the contact carries F = sigma0 z.

    ::

        z' = V_r |u|^alpha sgn(u),   u = 1 - sigma0 z sgn(V_r) / F_C

    Sliding steadily, sigma0 z = F_C sgn(V_r): F = F_C sgn(V_r) (no Stribeck
    peak, no viscous part: F_S = F_C).  Starting from rest the force rises with
    stiffness sigma0 and saturates at F_C.  The contact stores sigma0 z^2 / 2.

    Parameters
    ----------
    fd:
        Coulomb level F_C > 0.
    sigma0:
        Rest stiffness sigma0 > 0 (nondimensional: / k).
    alpha:
        Shape exponent alpha >= 1 (1: the usual choice; the Jacobian is bounded where the force saturates).
    """

    name = "dahl"
    code = stiff.DAHL
    parameters = (BRISTLE_FD, SIGMA0, ALPHA)
    record_names = ("fd", "sigma0", "alpha")
    internal_names = ("z",)

    def __init__(self, fd: float = 0.02, sigma0: float = 1e4, alpha: float = 1.0) -> None:
        self._assign(fd=fd, sigma0=sigma0, alpha=alpha)

    @property
    def fs(self) -> float:
        """The static level F_C, which Dahl's force never exceeds."""
        return self.fd

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        return np.full_like(np.asarray(speed, dtype=float), self.fd)

    def rate(self, vr: Any, z: np.ndarray) -> np.ndarray:
        vr = np.asarray(vr, dtype=float)
        u = 1.0 - self.sigma0 * np.asarray(z)[0] * np.sign(vr) / self.fd
        return (vr * np.abs(u) ** self.alpha * np.sign(u))[None]

    def force(self, vr: Any, z: np.ndarray) -> np.ndarray:
        return self.sigma0 * np.asarray(z, dtype=float)[0] + 0.0 * np.asarray(vr, dtype=float)

    def stored_energy(self, z: np.ndarray) -> np.ndarray:
        return 0.5 * self.sigma0 * np.asarray(z)[0] ** 2

    def internal_scale(self) -> np.ndarray:
        return np.array([self.fd / self.sigma0])

    def speed_scale(self) -> float:
        """The speed that saturates the contact in one time unit, F_C / sigma0 (Dahl has no velocity scale)."""
        return self.fd / self.sigma0
