"""Ideal Coulomb friction with static F_s >= kinetic F_d (a switch model)."""

from __future__ import annotations

from ..core import layout
from .base import FD, FS, RK4_BAND, STICK_FORCE, FrictionLaw
from .registry import register


@register
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
    code = layout.COULOMB
    parameters = (FD, FS, STICK_FORCE, RK4_BAND)
    kernel_slots = {"rk4_band": layout.VD}

    def __init__(self, fd: float = 0.02, fs: float | None = None, stick_force: str = "resultant", rk4_band: float = 1e-4) -> None:
        self._assign(fd=fd, fs=fs, stick_force=stick_force, rk4_band=rk4_band)
