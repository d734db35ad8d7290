"""The cubic law's slip curve as compiled scalar functions (the kernels' side of :class:`frictionflow.friction.Cubic`).

They live in the core, below the laws, because the kernels dispatch to them
(:mod:`.friction`); the law's module re-exports them.
"""

from __future__ import annotations

from numba import njit

from . import layout


@njit(cache=True, inline="always")
def magnitude(fd, mu_s, k1, k3, unused, speed):
    """F(s) = mu_s - k_1 s + k_3 s^3."""
    return mu_s - k1 * speed + k3 * speed * speed * speed


@njit(cache=True, inline="always")
def slope(fd, mu_s, k1, k3, unused, speed):
    """F'(s) = -k_1 + 3 k_3 s^2."""
    return -k1 + 3.0 * k3 * speed * speed


@njit(cache=True, inline="always")
def partial(fd, mu_s, k1, k3, unused, speed, slot):
    """dF(s)/d(the parameter in kernel slot ``slot``): mu_s, k1, k3 (F_d is derived from them, not a parameter)."""
    if slot == layout.FS:
        return 1.0
    if slot == layout.LAW_A:
        return -speed
    if slot == layout.LAW_B:
        return speed * speed * speed
    return 0.0
