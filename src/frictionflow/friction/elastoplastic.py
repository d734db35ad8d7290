"""The elasto-plastic law (Dupont, Hayward, Armstrong and Altpeter 2002): LuGre with true stiction."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core import stiff
from ..parameters import positive_real
from .lugre import BRISTLE_DELTA, BRISTLE_FD, BRISTLE_FS, BRISTLE_MAX, SIGMA0, SIGMA1, SIGMA2, LuGre
from .registry import register
from .stribeck import VS

Z_BA = positive_real("z_ba", "z_ba", "break-away deflection (elasto-plastic law)", "law", 1e-6, upper=BRISTLE_MAX,
                    dimension="length", sweepable=True)


@register
class ElastoPlastic(LuGre):
    """The elasto-plastic law: LuGre's bristles, purely elastic below a break-away deflection.

    ::

        z' = V_r - alpha(z, V_r) |V_r| z / z_ss(V_r),   z_ss = g(V_r) / sigma0
        F  = sigma0 z + sigma1 z' + sigma2 V_r

    with LuGre's g, and alpha = 0 while |z| <= z_ba (or z and V_r differ in
    sign), 1 from |z| >= z_ss, and (1 + sin(pi (|z| - (z_ss + z_ba)/2) / (z_ss - z_ba))) / 2
    between: below break-away the contact does not creep, so a held load
    stays held without drift (LuGre's bristles creep).

    Parameters
    ----------
    fd, fs, vs, delta, sigma0, sigma1, sigma2:
        As :class:`~frictionflow.LuGre`.
    z_ba:
        Break-away deflection, 0 < z_ba < F_C / sigma0.
    """

    name = "elastoplastic"
    code = stiff.ELASTOPLASTIC
    parameters = (BRISTLE_FD, BRISTLE_FS, VS, BRISTLE_DELTA, SIGMA0, SIGMA1, SIGMA2, Z_BA)
    record_names = ("fd", "fs", "vs", "delta", "sigma0", "sigma1", "sigma2", "z_ba")

    def __init__(self, fd: float = 0.02, fs: float | None = None, vs: float = 0.01, delta: float = 2.0,
                 sigma0: float = 1e4, sigma1: float = 100.0, sigma2: float = 0.0, z_ba: float = 1e-6) -> None:
        self._assign(fd=fd, fs=fs, vs=vs, delta=delta, sigma0=sigma0, sigma1=sigma1, sigma2=sigma2, z_ba=z_ba)

    def _check_values(self) -> None:
        super()._check_values()
        top = self.fd / self.sigma0
        if not self.z_ba < top:
            raise ValueError(f"z_ba must be in (0, fd/sigma0 = {top:g}) for friction={self.name} "
                             f"(below every steady deflection), got {self.z_ba!r}")

    def plastic_fraction(self, vr: Any, z: Any) -> np.ndarray:
        """alpha(z, V_r), elementwise."""
        vr, z = np.broadcast_arrays(np.asarray(vr, dtype=float), np.asarray(z, dtype=float))
        zss = self.stribeck(vr) / self.sigma0
        az = np.abs(z)
        w = np.maximum(zss - self.z_ba, 1e-300)
        mid = 0.5 * np.sin(np.pi * (az - 0.5 * (zss + self.z_ba)) / w) + 0.5
        alpha = np.where(az >= zss, 1.0, mid)
        return np.where((z * vr <= 0.0) | (az <= self.z_ba), 0.0, alpha)

    def rate(self, vr: Any, z: np.ndarray) -> np.ndarray:
        vr = np.asarray(vr, dtype=float)
        zz = np.asarray(z)[0]
        return (vr - self.plastic_fraction(vr, zz) * np.abs(vr) * zz * self.sigma0 / self.stribeck(vr))[None]
