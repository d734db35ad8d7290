"""The LuGre law (Canudas de Wit, Olsson, Astrom and Lischinsky 1995): bristles with deflection z."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core import stiff
from ..parameters import MODEL_MAX, nonnegative_real, positive_real
from .base import FD, FS
from .registry import register
from .stateful import StatefulLaw
from .stribeck import DELTA, VS

#: the bristles' stiffness and damping reach far beyond the oscillator's scale (sigma0 ~ 1e5 k in the classic example)
BRISTLE_MAX = 1e12
SIGMA0 = positive_real("sigma0", "sigma_0", "bristle stiffness (stateful laws)", "law", 1e4, upper=BRISTLE_MAX,
                       dimension="stiffness", sweepable=True)
SIGMA1 = nonnegative_real("sigma1", "sigma_1", "bristle damping (stateful laws)", "law", 100.0, upper=BRISTLE_MAX,
                          dimension="damping", sweepable=True)
SIGMA2 = nonnegative_real("sigma2", "sigma_2", "viscous friction (stateful laws)", "law", 0.0, upper=MODEL_MAX,
                          dimension="damping", sweepable=True)
#: the laws with bristles divide by g(V_r) >= F_C (their rate), and their Jacobian at V_r = 0 holds |V_r|^(delta - 1):
#: F_C > 0 (so F_S >= F_C > 0 too) and delta >= 1, declared so that the options' help and the checks say the same
BRISTLE_FD = FD.narrowed(lower_open=True)
BRISTLE_FS = FS.narrowed(lower_open=True)
BRISTLE_DELTA = DELTA.narrowed(lower=1.0, lower_open=False)


@register
class LuGre(StatefulLaw):
    """LuGre friction: the average deflection z of elastic bristles carries the force.

    ::

        z' = V_r - sigma0 |V_r| z / g(V_r),   g(V_r) = F_C + (F_S - F_C) exp(-(|V_r| / v_s)^delta)
        F  = sigma0 z + sigma1 z' + sigma2 V_r

    Sliding steadily at V_r the bristles settle at sigma0 z = g(V_r) sgn(V_r)
    and F = g(V_r) sgn(V_r) + sigma2 V_r; below F_S the mass moves elastically
    (presliding, stiffness sigma0).  The contact stores sigma0 z^2 / 2.

    Parameters
    ----------
    fd:
        Coulomb level F_C > 0.
    fs:
        Static level F_S >= F_C (default F_C).
    vs:
        Stribeck velocity v_s > 0.
    delta:
        Stribeck exponent delta >= 1 (the Jacobian is bounded at V_r = 0).
    sigma0:
        Bristle stiffness sigma0 > 0 (nondimensional: / k).
    sigma1:
        Bristle damping sigma1 >= 0 (nondimensional: omega_0 / k).
    sigma2:
        Viscous coefficient sigma2 >= 0 (nondimensional: omega_0 / k).
    """

    name = "lugre"
    code = stiff.LUGRE
    parameters = (BRISTLE_FD, BRISTLE_FS, VS, BRISTLE_DELTA, SIGMA0, SIGMA1, SIGMA2)
    record_names = ("fd", "fs", "vs", "delta", "sigma0", "sigma1", "sigma2")
    internal_names = ("z",)

    def __init__(self, fd: float = 0.02, fs: float | None = None, vs: float = 0.01, delta: float = 2.0,
                 sigma0: float = 1e4, sigma1: float = 100.0, sigma2: float = 0.0) -> None:
        self._assign(fd=fd, fs=fs, vs=vs, delta=delta, sigma0=sigma0, sigma1=sigma1, sigma2=sigma2)

    def stribeck(self, speed: Any) -> np.ndarray:
        """g(|V_r|) = F_C + (F_S - F_C) exp(-(|V_r| / v_s)^delta)."""
        s = np.abs(np.asarray(speed, dtype=float))
        return self.fd + (self.fs - self.fd) * np.exp(-((s / self.vs) ** self.delta))

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        """|F| sliding steadily at ``speed``: g(speed) + sigma2 speed."""
        s = np.abs(np.asarray(speed, dtype=float))
        return self.stribeck(s) + self.sigma2 * s

    def slip_slope(self, speed: float) -> float:
        s = abs(float(speed))
        u = s / self.vs
        return float(-(self.fs - self.fd) * np.exp(-u**self.delta) * self.delta * u ** (self.delta - 1.0) / self.vs
                     + self.sigma2)

    def rate(self, vr: Any, z: np.ndarray) -> np.ndarray:
        vr = np.asarray(vr, dtype=float)
        return (vr - self.sigma0 * np.abs(vr) * np.asarray(z)[0] / self.stribeck(vr))[None]

    def force(self, vr: Any, z: np.ndarray) -> np.ndarray:
        vr = np.asarray(vr, dtype=float)
        return self.sigma0 * np.asarray(z)[0] + self.sigma1 * self.rate(vr, z)[0] + self.sigma2 * vr

    def stored_energy(self, z: np.ndarray) -> np.ndarray:
        return 0.5 * self.sigma0 * np.asarray(z)[0] ** 2

    def internal_scale(self) -> np.ndarray:
        return np.array([self.fs / self.sigma0])

    def speed_scale(self) -> float:
        return self.vs
