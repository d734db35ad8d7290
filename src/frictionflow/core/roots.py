"""A bracketed scalar root finder, stated once for the compiled kernels and for Python.

The method is Illinois false position (Dowell and Jarratt, 1971): the next
point is the secant of the bracket's ends; the end that stays twice in a row
has its value halved, so the secant crosses the root and the bracket closes
from both sides (order ~1.44 at a simple root) instead of stalling on one
side as plain regula falsi does on a convex function.  Two safeguards make
the number of points bounded whatever f: a secant that falls outside the
bracket or on an end (rounding, an end whose value is 0, an overflow) is
replaced by bisection, and so is the next point after :data:`STALL` points
that did not halve the bracket (a root of high multiplicity, f = x^9, keeps
one end for ever otherwise), so the bracket at least halves every
``STALL + 1`` points.

Illinois rather than Brent: it is what the kernels' switch and event
location did before this module, so their roots (of the schemes' own
solutions, to a few rounding units) stay what they were -- bit for bit
except where the stall safeguard now cuts a slow run short (a few 1e-14 of
a forced continuation's event parameter) -- its state is a handful of
numbers, and a caller's own better guess (a Newton step, see :func:`steer`)
slots in as the next point (:func:`update_newton` and :func:`update_halley` do so where f', f'' are cheap).

Reverse communication: f is evaluated by the caller, which keeps whatever f
needs (the kernels' step buffers, a continuation's solutions) and whatever it
makes (the state at the point) out of this module::

    b = bracket(lo, hi, f_lo, f_hi, xtol, rtol, ftol, maxiter)
    while b.status == RUNNING:
        b = update(b, b.x, f(b.x))
    root = b.hi

The record :class:`Bracket` is a named tuple (nothing is allocated in the
kernels).  ``hi`` is the end whose value has f(hi)'s sign or is 0: kernels
that must stand past an event (on its far side) take it.  Converged means the
bracket is no wider than ``xtol + rtol max(|hi|, xscale)`` (xscale: the size
below which |x| no longer scales the tolerance, 0 for the plain relative
rule), or a point had |f| <= ``ftol`` (the bracket then closes on it), or no
float is left strictly inside.
:func:`find_root` is the same loop for a Python callable.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

#: status codes
RUNNING, CONVERGED, NO_SIGN_CHANGE, MAX_ITER = range(4)
#: points in a row that did not halve the bracket before a bisection
STALL = 3
EPS = 2.220446049250313e-16
_TINY = 2.2250738585072014e-308  # the smallest normal float

#: the state of a search.  x: the point to evaluate next (while RUNNING); side: +1 the last point
#: replaced hi, -1 it replaced lo, 0 none yet; n: points evaluated; width: the bracket's width when it
#: last halved; stall: points since then
Bracket = namedtuple("Bracket", ["lo", "hi", "flo", "fhi", "x", "side", "n", "status",
                                 "width", "stall", "xtol", "rtol", "ftol", "maxiter", "xscale"])


@njit(cache=True)
def _same_sign(f, ref):
    """f has the strict sign of ref (a product would underflow for small values)."""
    return f > 0.0 if ref > 0.0 else f < 0.0


@njit(cache=True)
def _bisect(lo, hi):
    m = 0.5 * (lo + hi)
    return m if math.isfinite(m) else 0.5 * lo + 0.5 * hi  # lo + hi overflows near the largest floats


@njit(cache=True)
def _secant(lo, hi, flo, fhi):
    """The secant's zero through the ends; NaN where it does not exist."""
    den = fhi - flo
    if den == 0.0:
        return math.nan
    w = fhi * (hi - lo)
    if _TINY <= abs(w) < math.inf:
        return hi - w / den
    return hi - (hi - lo) * (fhi / den)  # the product under- or overflows: scale first


@njit(cache=True)
def _next(b, lo, hi, flo, fhi, side, n):
    """The record after the bracket moved to (lo, hi): converged, out of points, or its next point.

    ``b`` is the record before the move: its settings, and the width and stall count it carries.
    """
    w = abs(hi - lo)
    width, stall = b.width, b.stall
    if w <= 0.5 * width:
        width, stall = w, 0
    else:
        stall += 1
    x = hi
    if w <= b.xtol + b.rtol * max(abs(hi), b.xscale):
        status = CONVERGED
    elif n >= b.maxiter:
        status = MAX_ITER
    else:
        a, c = min(lo, hi), max(lo, hi)
        x = _secant(lo, hi, flo, fhi) if stall < STALL else math.nan
        if not a < x < c:
            x = _bisect(lo, hi)
        status = RUNNING if a < x < c else CONVERGED  # no float strictly inside: as close as it gets
    return Bracket(lo, hi, flo, fhi, x, side, n, status, width, stall, b.xtol, b.rtol, b.ftol, b.maxiter, b.xscale)


@njit(cache=True)
def bracket(lo, hi, flo, fhi, xtol, rtol, ftol, maxiter, xscale=0.0):
    """The record of a search on [lo, hi] with f(lo) = flo, f(hi) = fhi (either order of the ends).

    An end with f = 0 is the root at once (the bracket closes on it, hi
    first); ends of one strict sign (or a NaN) give NO_SIGN_CHANGE.
    """
    lo, hi, flo, fhi = float(lo), float(hi), float(flo), float(fhi)
    xtol, rtol, ftol, maxiter, xscale = float(xtol), float(rtol), float(ftol), int(maxiter), float(xscale)
    if fhi == 0.0 or flo == 0.0:
        r, fr = (hi, fhi) if fhi == 0.0 else (lo, flo)
        return Bracket(r, r, fr, fr, r, 0, 0, CONVERGED, 0.0, 0, xtol, rtol, ftol, maxiter, xscale)
    if not ((flo < 0.0 < fhi) or (fhi < 0.0 < flo)):
        return Bracket(lo, hi, flo, fhi, hi, 0, 0, NO_SIGN_CHANGE, 0.0, 0, xtol, rtol, ftol, maxiter, xscale)
    start = Bracket(lo, hi, flo, fhi, hi, 0, 0, RUNNING, math.inf, 0, xtol, rtol, ftol, maxiter, xscale)
    return _next(start, lo, hi, flo, fhi, np.int64(0), np.int64(0))  # (not literals: _next compiles once)


@njit(cache=True)
def update(b, x, fx):
    """The record after f(x) = fx at a point x strictly inside the bracket (normally b.x): Illinois' rule."""
    x, fx = float(x), float(fx)
    lo, hi, flo, fhi, side = b.lo, b.hi, b.flo, b.fhi, b.side
    if _same_sign(fx, flo):
        lo, flo = x, fx
        if side == -1:
            fhi *= 0.5  # hi stayed twice: weigh it down so the next secant lands beyond the root
        side = -1
    else:
        hi, fhi = x, fx  # an exact 0 (or a NaN) joins hi: hi is the end that has arrived
        if side == 1:
            flo *= 0.5
        side = 1
    n = b.n + 1
    if abs(fx) <= b.ftol:
        return Bracket(x, x, fx, fx, x, side, n, CONVERGED, 0.0, 0, b.xtol, b.rtol, b.ftol, b.maxiter, b.xscale)
    return _next(b, lo, hi, flo, fhi, side, n)


@njit(cache=True)
def steer(b, guess):
    """The record with its next point replaced by ``guess`` where that is strictly inside (a Newton step, say)."""
    if min(b.lo, b.hi) < guess < max(b.lo, b.hi):
        return Bracket(b.lo, b.hi, b.flo, b.fhi, float(guess), b.side, b.n, b.status, b.width, b.stall,
                       b.xtol, b.rtol, b.ftol, b.maxiter, b.xscale)
    return b


@njit(cache=True)
def update_newton(b, x, fx, dfx):
    """:func:`update` with f'(x) = dfx known: the next point from Newton's step where it is safe.

    A Newton iteration alone converges to the root from one side and leaves
    the bracket's far end where it was.  So the next point is the Newton
    estimate r = x - fx / dfx moved a quarter of the tolerance beyond r, away
    from x: once r is that close to the root the point falls on its other
    side and the bracket closes from both sides.  Illinois' point stays
    where the point is not strictly inside the bracket, where dfx is 0 or not
    finite, and after :data:`STALL` points that did not halve the bracket
    (its bisection), so the bracket still halves at least every ``STALL + 1``
    points whatever f and dfx.
    """
    b = update(b, x, fx)
    if b.status != RUNNING or b.stall >= STALL or not (dfx != 0.0 and math.isfinite(dfx)):
        return b
    return steer_past(b, x, x - fx / dfx)


@njit(cache=True, inline="always")
def steer_past(b, x, r):
    """The record steered to the estimate ``r`` moved a quarter of the tolerance beyond it, away from ``x``: near
    the root the point falls on its other side and the bracket closes from both sides."""
    d = 0.25 * tolerance(b, r)
    return steer(b, r + d if r > x else r - d)


@njit(cache=True)
def update_halley(b, x, fx, dfx, d2fx, spare):
    """(record, spare): :func:`update` with f'(x) = dfx and f''(x) = d2fx known, the next point from Halley's
    step moved past it as :func:`update_newton` moves Newton's.

    A step that converges from one side does not halve the bracket, and after :data:`STALL` such points the
    record bisects.  Once, while ``spare``, a step shorter than the tolerance is taken all the same: its point
    lies within rounding of the root and closes the bracket; the bisection's bound on the points still holds
    after it.  Illinois' point stays where the step is not finite or not inside the bracket.
    """
    b = update(b, x, fx)
    den = 2.0 * dfx * dfx - fx * d2fx
    if b.status != RUNNING or not (den != 0.0 and math.isfinite(den)):
        return b, spare
    r = x - 2.0 * fx * dfx / den
    short = abs(r - x) <= tolerance(b, r)
    if b.stall >= STALL and not (spare and short):
        return b, spare
    return steer_past(b, x, r), spare and not (b.stall >= STALL and short)


@njit(cache=True)
def tolerance(b, x):
    """The record's x tolerance at x: ``xtol + rtol max(|x|, xscale)``."""
    return b.xtol + b.rtol * max(abs(x), b.xscale)


def find_root(f, lo, hi, xtol=0.0, rtol=4 * EPS, ftol=0.0, maxiter=200, xscale=0.0):
    """(root, status, points evaluated) for a Python callable f on [lo, hi], by the same rule (see the module's docstring)."""
    b = bracket(lo, hi, f(lo), f(hi), xtol, rtol, ftol, maxiter, xscale)
    while b.status == RUNNING:
        b = update(b, b.x, f(b.x))
    return b.hi, b.status, b.n
