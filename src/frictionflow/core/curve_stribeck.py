"""Stribeck's slip curve as compiled scalar functions (the kernels' side of :class:`frictionflow.friction.Stribeck`).

They live in the core, below the laws, because the kernels dispatch to them
(:mod:`.friction`); the law's module re-exports them.
"""

from __future__ import annotations

import math

from numba import njit

from . import layout


@njit(cache=True, inline="always")
def magnitude(fd, fs, vs, delta, visc, speed):
    """F(s) = F_d + (F_s - F_d) exp(-(s / V_s)^delta) + c_v s."""
    r = speed / vs
    # delta = 1 (the exponential law) without a pow call: r ** 1.0 is r exactly (pow is exact where
    # the result is representable), so the force is the same to the bit, a quarter of the adaptive step cheaper
    u = r if delta == 1.0 else r ** delta
    return fd + (fs - fd) * math.exp(-u) + visc * speed


@njit(cache=True, inline="always")
def slope(fd, fs, vs, delta, visc, speed):
    """F'(s); at s = 0 the limit from above (-inf for delta < 1 with F_s > F_d)."""
    if speed <= 0.0:
        if delta > 1.0 or fs == fd:
            return visc
        if delta == 1.0:
            return visc - (fs - fd) / vs
        return -math.inf
    u = (speed / vs) ** delta
    return visc - (fs - fd) * delta * u / speed * math.exp(-u)


@njit(cache=True, inline="always")
def partial(fd, fs, vs, delta, visc, speed, slot):
    """dF(s)/d(the parameter in kernel slot ``slot``) at s >= 0: the orbit engine's parameter derivatives."""
    u = (speed / vs) ** delta if speed > 0.0 else 0.0
    e = math.exp(-u)
    if slot == layout.FD:
        return 1.0 - e
    if slot == layout.FS:
        return e
    if slot == layout.LAW_A:  # V_s
        return (fs - fd) * e * u * delta / vs
    if slot == layout.LAW_B:  # delta
        return -(fs - fd) * e * u * math.log(speed / vs) if speed > 0.0 else 0.0
    if slot == layout.LAW_C:  # viscous
        return speed
    return 0.0


@njit(cache=True, inline="always")
def terms(fd, fs, vs, delta, visc, speed, slot):
    """(F, F', dF/d(slot parameter)) at speed > 0 with one exp and one power (the orbit engine's inner loop)."""
    r = speed / vs
    u = r * r if delta == 2.0 else r ** delta
    e = math.exp(-u)
    f = fd + (fs - fd) * e + visc * speed
    fp = visc - (fs - fd) * delta * u / speed * e
    ft = 0.0
    if slot == layout.FD:
        ft = 1.0 - e
    elif slot == layout.FS:
        ft = e
    elif slot == layout.LAW_A:
        ft = (fs - fd) * e * u * delta / vs
    elif slot == layout.LAW_B:
        ft = -(fs - fd) * e * u * math.log(r)
    elif slot == layout.LAW_C:
        ft = speed
    return f, fp, ft
