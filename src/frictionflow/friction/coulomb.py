"""Ideal Coulomb friction with static F_s >= kinetic F_d (a switch model)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import _validate as check
from ..core import friction as kf
from .base import FrictionLaw


class Coulomb(FrictionLaw):
    """Set-valued Coulomb friction, without a velocity band.

    While V_r = 0 the mass sticks (moves with the belt) as long as the force
    it needs, |F_e| with F_e = X + 2 zeta V_b (``resultant``) or X
    (``spring``), stays <= F_s; otherwise it slips with F_c = F_d sgn(V_r).
    This is a switch model in the sense of Leine et al. (1998).

    Parameters
    ----------
    fd, fs:
        Kinetic and maximum static friction, 0 <= F_d <= F_s (F_s defaults to F_d).
    stick_force:
        ``"resultant"`` (default) or ``"spring"``.
    rk4_band:
        Only for the fixed-step RK4 solver, which cannot represent the set-valued
        law: the half width of the velocity band it treats as stick (Karnopp's
        scheme).  The exact solver ignores it.
    """

    name = "coulomb"
    code = kf.COULOMB

    def __init__(self, fd: float = 0.02, fs: float | None = None, stick_force: str = "resultant", rk4_band: float = 1e-4) -> None:
        super().__init__(fd, fs, stick_force)
        self.rk4_band = check.positive("rk4_band", rk4_band)

    @property
    def band(self) -> float:
        return self.rk4_band

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        return np.full_like(np.asarray(speed, dtype=float), self.fd)
