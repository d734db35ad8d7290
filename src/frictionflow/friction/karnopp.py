"""Karnopp's friction model (paper Eq. 5, generalised to F_s >= F_d)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import _validate as check
from .base import FrictionLaw
from ..core import friction as kf


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
    code = kf.KARNOPP

    def __init__(
        self,
        fd: float = 0.02,
        fs: float | None = None,
        vd: float = 1e-3,
        stick_force: str = "resultant",
    ) -> None:
        super().__init__(fd, fs, stick_force)
        self.vd = check.positive("vd", vd)

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        return np.full_like(np.asarray(speed, dtype=float), self.fd)

    def sliding_equilibrium(self, vb: float) -> float:
        # Inside the band the mass would be held, not slide: X* solves X = F_e-balance.
        if abs(vb) > self.vd:
            return float(np.sign(vb) * self.fd)
        return float("nan")

    def as_dict(self) -> dict[str, Any]:
        d = super().as_dict()
        d["vd"] = self.vd
        return d
