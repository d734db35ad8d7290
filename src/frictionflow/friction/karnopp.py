"""Karnopp's friction model (paper Eq. 5, generalised to F_s >= F_d)."""

from __future__ import annotations

import numpy as np

from ..core import layout
from ..parameters import MODEL_MAX, positive_real
from .base import FD, FS, STICK_FORCE, FrictionLaw
from .registry import register

VD = positive_real("vd", "V_d", "Karnopp stick-band half width", "law", 1e-3, upper=MODEL_MAX, sweepable=True,
                 dimension="velocity", dimensional_name="v_d")


@register
class Karnopp(FrictionLaw):
    """Karnopp's model: Coulomb friction with a stick band |V_r| <= V_d.

    ::

        F_c = F_d sgn(V_r)          if |V_r| >  V_d   (slip)
        F_c = F_s sgn(F_e)          if |V_r| <= V_d and |F_e| >= F_s
        F_c = F_e                   if |V_r| <= V_d and |F_e| <  F_s

    Parameters
    ----------
    fd:
        Kinetic friction F_d >= 0.
    fs:
        Maximum static friction F_s >= F_d (default F_d, the paper's choice).
    vd:
        Half width of the stick band V_d > 0 (paper: 1e-3).
    stick_force:
        ``"resultant"`` (F_e = X + 2 zeta X', default) or ``"spring"``
        (F_e = X, the paper's choice).
    """

    name = "karnopp"
    code = layout.KARNOPP
    parameters = (FD, FS, STICK_FORCE, VD)
    kernel_slots = {"vd": layout.VD}
    stick_rule = "band"

    def __init__(self, fd: float = 0.02, fs: float | None = None, vd: float = 1e-3, stick_force: str = "resultant") -> None:
        self._assign(fd=fd, fs=fs, vd=vd, stick_force=stick_force)

    @property
    def band(self) -> float:
        return self.vd

    def sliding_equilibrium(self, vb: float) -> float:
        # Inside the band the mass is held, not sliding: no sliding equilibrium.
        if abs(vb) > self.vd:
            return float(np.sign(vb) * self.fd)
        return float("nan")
