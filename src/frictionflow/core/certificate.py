"""A certificate that a slipping motion converges onto the sliding equilibrium without sticking again.

In pure slip (V_r = V_b - X' keeps the sign of V_b) the energy about the
equilibrium X* = F(V_b),

    E = 1/2 X'^2 + 1/2 (X - X*)^2,

obeys (multiply X'' + 2 zeta X' + X = F(V_b - X') by X' and use X* = F(V_b))

    dE/dtau = -X'^2 [2 zeta + s(X')],    s(u) = (F(V_b) - F(V_b - u)) / u,

with s(u) the secant slope of the slip curve between V_b - u and V_b (s(0) =
F'(V_b); the viscous term c_v |V_r| contributes c_v to every secant).  Inside
the disc E <= r^2 / 2 the velocity obeys |X'| <= r.  So if

    (a) r < |V_b| (minus the stick band for Karnopp): V_r cannot reach the stick
        boundary from inside the disc, and
    (b) 2 zeta + s(u) > 0 for every |u| <= r (the slope need not be monotone:
        only this secant bound counts),

then E never increases, the motion never leaves the disc, never sticks, and
by LaSalle's principle converges onto X* (E decreases whenever X' != 0).  Near
X* the decay rate is Re(-lambda) of the linearisation
lambda^2 + (2 zeta + F'(V_b)) lambda + 1 = 0.  An equilibrium with
2 zeta + F'(V_b) <= 0 has no such disc (condition (b) fails at u = 0): an
unstable equilibrium is never certified.

:func:`certified_radius` finds the largest such r by checking (b) on a grid of
``N_GRID`` secants in each direction and keeping a margin of the largest change
between neighbouring grid values (the secant is smooth in u), so a dip between
grid points cannot be missed for any slip curve with a bounded second
derivative at that resolution.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import TYPE_CHECKING, Callable

from numba import njit

from ._rebind import rebind
from .friction import slip_magnitude_of
from .layout import KARNOPP, LAW, VD

if TYPE_CHECKING:
    from ..friction.base import FrictionLaw

N_GRID = 512
#: grids tried, each over the first step of the one before where that step fails (the finest step, the room /
#: N_GRID^ZOOMS, keeps the secants far above their rounding)
ZOOMS = 3


@njit(cache=True)
def secant_margin(p, zeta, speed, u):
    """2 zeta + s(u) at belt speed |V_b| = ``speed`` (s(0): a central difference of the slip force)."""
    if u == 0.0:
        h = 1e-7 * speed
        return 2.0 * zeta + (slip_magnitude_of(p, speed + h) - slip_magnitude_of(p, speed - h)) / (2.0 * h)
    return 2.0 * zeta + (slip_magnitude_of(p, speed) - slip_magnitude_of(p, speed - u)) / u


@njit(cache=True)
def certified_radius(p, zeta, vb):
    """The largest r with (a) and (b) of the module docstring; 0 when there is none.

    Near a Hopf point (2 zeta + F'(V_b) just above 0) the disc is far
    smaller than the grid's step over the room: where the first step fails
    already, the search zooms into it (a grid of ``N_GRID`` over that step),
    up to ``ZOOMS`` times.
    """
    speed = abs(vb)
    room = speed - (p[VD] if int(p[LAW]) == KARNOPP else 0.0)  # (a): stay off the stick boundary
    if room <= 0.0 or not secant_margin(p, zeta, speed, 0.0) > 0.0:
        return 0.0
    span = room
    for _ in range(ZOOMS):
        r = _grid_radius(p, zeta, speed, span)
        if r > 0.0:
            return r * (1.0 - 1e-9)
        span /= N_GRID
    return 0.0


@njit(cache=True)
def _grid_radius(p, zeta, speed, span):
    """The largest r <= ``span`` with (b) on a grid of ``N_GRID`` steps over [0, span] (0: the first step fails)."""
    h = span / N_GRID
    r = span
    for side in (1.0, -1.0):
        prev = secant_margin(p, zeta, speed, 0.0)
        for i in range(1, N_GRID + 1):
            m = secant_margin(p, zeta, speed, side * i * h)
            # the secant may dip between grid points by about the change between them
            if not m > abs(m - prev):
                r = min(r, (i - 1) * h)
                break
            prev = m
    return r


@njit(cache=True)
def inside(x_eq, vb, r, x, v):
    """Is (x, v), slipping in the belt's direction, inside the certified disc of radius ``r`` about X* = ``x_eq``?"""
    return r > 0.0 and (vb - v) * vb > 0.0 and (x - x_eq) ** 2 + v * v <= r * r


def decay_rate(zeta: float, slope: float) -> float:
    """Re(-lambda) of the slowest eigenvalue of lambda^2 + (2 zeta + F') lambda + 1 = 0."""
    c = 2.0 * zeta + slope
    disc = 0.25 * c * c - 1.0
    return 0.5 * c if disc <= 0.0 else 0.5 * c - math.sqrt(disc)


def radius(law: "FrictionLaw", zeta: float, vb: float) -> float:
    """:func:`certified_radius` of a law object (0 for a user function numba cannot compile: no certificate)."""
    if law.compiled_slip:
        return float(certified_radius(law.kernel_params(), float(zeta), float(vb)))
    force = law.kernel_force()
    if force is None:
        return 0.0
    rebuilt = _user_radius(force)
    return float(rebuilt(law.kernel_params(), float(zeta), float(vb)))


@lru_cache(maxsize=32)
def _user_radius(force: Callable) -> Callable:
    import sys

    return rebind(sys.modules[__name__], ("secant_margin", "_grid_radius", "certified_radius"),
                  slip_magnitude_of=force)["certified_radius"]
