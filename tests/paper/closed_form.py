"""Closed forms derived for the tests of the paper reproduction (independent of the code under test).

Slipping forward (V_r > V_d) the friction is the constant F_d, so Eq. 4 is the
linear oscillator X'' + 2 zeta X' + X = F_d about X* = F_d.  With
w = sqrt(1 - zeta^2) and y = X - F_d,

    y(s) = exp(-zeta s) (y0 cos ws + (v0 + zeta y0)/w sin ws),   s = tau - tau0.

Case I (zeta = 0, F_s = F_d, F_e = X): inside the band with |X| < F_d the law
gives F_c = X, so X'' = 0 and X' stays at the band edge V_b - V_d until
X = F_d; the motion then leaves tangentially onto the slip circle of radius
r = V_b - V_d about (F_d, 0), which touches the band edge again without
entering it.  On that circle X' = r sin(tau + phase) and P_f = F_d X':

    P_fin = P_df = F_d r / pi,   TR_B = max|X| / F_d = (F_d + r) / F_d,  period 2 pi.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad


def slip(t: np.ndarray | float, t0: float, x0: float, v0: float, fd: float, zeta: float):
    """X and X' of free forward slip from (x0, v0) at t0 (zeta < 1)."""
    w = math.sqrt(1.0 - zeta * zeta)
    s = np.asarray(t, dtype=float) - t0
    y0 = x0 - fd
    b = (v0 + zeta * y0) / w
    e = np.exp(-zeta * s)
    c, sn = np.cos(w * s), np.sin(w * s)
    x = fd + e * (y0 * c + b * sn)
    v = e * ((w * b - zeta * y0) * c - (zeta * b + w * y0) * sn)
    return x, v


def slip_averages(t0: float, t1: float, start: tuple[float, float, float], fd: float, zeta: float) -> dict[str, float]:
    """Eq. 9 over [t0, t1] of free slip from ``start`` = (tau, X, X'), by adaptive quadrature."""
    ts, xs, vs = start

    def v(t: float) -> float:
        return float(slip(t, ts, xs, vs, fd, zeta)[1])

    span = t1 - t0
    p_dv = quad(lambda t: 2 * zeta * v(t) ** 2, t0, t1, limit=200, epsabs=0.0, epsrel=1e-11)[0] / span
    p_in = quad(lambda t: max(fd * v(t), 0.0), t0, t1, limit=400, epsabs=0.0, epsrel=1e-10)[0] / span
    p_out = quad(lambda t: max(-fd * v(t), 0.0), t0, t1, limit=400, epsabs=0.0, epsrel=1e-10)[0] / span
    return {"P_dv": p_dv, "P_fin": p_in, "P_df": p_out}


def case1_circle(vb: float, vd: float, fd: float) -> dict[str, float]:
    """Case I's steady cycle for V_b > V_d (module docstring)."""
    r = vb - vd
    return {"radius": r, "P_fin": fd * r / math.pi, "TR_B": (fd + r) / fd, "period": 2 * math.pi}
