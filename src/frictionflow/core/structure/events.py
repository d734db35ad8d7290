"""The first event of a phase, with no root skipped between the points evaluated (a proof, not a step size).

Every event function is positive inside its mode's region (:mod:`.combo`).
The walk covers (0, tau_end] with intervals [a, b], h = b - a, and, for every
active function g, decides one of

* root-free: g(a), g(b) > r and the chord's bound is above r.  With M2 a
  bound on |g''| over the interval, g(a + t) >= c(t) = l(t) - M2 t (h - t) / 2
  (l the chord through the ends: the error of linear interpolation is
  g''(xi) t (t - h) / 2).  c is a convex quadratic; where its vertex lies
  outside [0, h] (|g(b) - g(a)| >= M2 h^2 / 2) its least value there is
  min(g(a), g(b)), else (g(a) + g(b)) / 2 - M2 h^2 / 8 - (g(b) - g(a))^2 / (2 M2 h^2)
  (:func:`chord_low`; never below the cruder min(g(a), g(b)) - M2 h^2 / 8).
  r = ROUNDING times the size of g's terms (:func:`.phase.size_of`): a
  function that comes within rounding of 0 is not certified clear of it.
  At a phase start where g(0) = 0 (a contact that just began to slip:
  ``departing``), g(s) >= g'(0) s - M2 s^2 / 2 > 0 when g'(0) > M2 h / 2, or
  with g'(0) >= 0, g(s) >= g''(0) s^2 / 2 - M3 s^3 / 6 > 0 when g''(0) > M3 h / 3;
* one root: g(a) > 0 >= g(b) and g' < 0 throughout.  g'(s) <= g'(a) + M2 (s - a)
  and g'(s) <= g'(b) + M2 (b - s), and the smaller of two numbers is at most
  their mean, so g'(s) <= (g'(a) + g'(b) + M2 h) / 2 on [a, b]: -g'(a) > M2 h
  (the first bound alone) or -(g'(a) + g'(b)) > M2 h suffices;
* undecided: the tests are tried again with a sharper M2 (below), then the
  interval is halved.

The sharper M2 (:func:`sharper_m2`): with M3 a bound on |g'''| over [a, b]
(:func:`.phase.bound`), |g''(s)| <= |g''(a)| + M3 (s - a) and
|g''(s)| <= |g''(b)| + M3 (b - s), so by the same mean
|g''| <= (|g''(a)| + |g''(b)| + M3 h) / 2 throughout.  g'' at the ends is
computed from z there; its rounding is less than ROUNDING EPS of the sum of
its terms' moduli, which M2 taken from |z| alone bounds, so that much of it
is added.  The crude M2 sums the modes' moduli (a decaying mode's term at
most a bound from its rates at the phase's start, :func:`.phase.rates_into`);
g''(a) and g''(b) keep their cancellations, so on an interval short beside
the modes' time scales the sharper bound is far below it and fewer intervals
are halved.

When every function is decided, the earliest root is the event.  The
candidate whose chord crosses 0 first is located in its proven bracket
(g(a) > 0 >= g(b), g' < 0 throughout) by Halley's steps from
g' = Re(W (lam z + beta)) + ... and g'', which z(tau) gives at little cost
(:func:`.phase.event_rate`), kept inside the bracket and closing it from
both sides, with Illinois' point as the safeguard (:func:`..roots.update_halley`), to
2 EPS of the root's size or to a point where g is within rounding of 0
(ROUNDING EPS of its terms' size: the root is known no better than that
from g; the run counts such a function as reached).  Another candidate, with g(a) > 0 and one root
in [a, b], has that root after the located t when g(t) > 0; it is located
(in [a, t]) only where g(t) <= 0.  An interval that reaches ``floor`` undecided is a touch: a
function within rounding (or M2 floor^2 / 8, ~1e-25 of its size) of 0
that need not cross; it is reported as an event at the end nearer 0 (``graze``), and the
stick rule decides what follows (a slipping contact whose V_r touches 0
tangentially may stick there).
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

from ..roots import RUNNING, bracket, update_halley
from ..options import NO_RUNTIME
from .phase import (Mags, abs_into, bound, bound_of, event_rate, event_raw, longest, magnitudes_into,
                    modal_raw, mode_bounds, next_death, rates_into, size_of)

EPS = 2.220446049250313e-16
#: a function within this many EPS of the size of its terms of 0 counts as touching 0
ROUNDING = 16.0


@njit(cache=True, inline="always")
def values(cb, ph, om, tau, z, g):
    """Fill ``g`` with the active event functions at ``tau`` (``z`` = z(tau))."""
    active, e0, e1, dh, w, theta = cb.active, ph.e0, ph.e1, cb.Dh, cb.W, ph.theta
    for e in range(len(g)):
        if active[e]:
            g[e] = event_raw(e0, e1, dh, w, theta, om, e, tau, z)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: no reference counting of the records' arrays
def locate(cb, ph, om, e, a, b, ga, gb, room):
    """The root of event function ``e`` in [a, b] (g(a) > 0 >= g(b)): the far end of the final bracket, by
    :func:`..roots.update_halley`'s points (g', g'' from z at little cost), or a point where g is within rounding of 0
    (ROUNDING EPS of the size of its terms at a: there the root is known as well as g allows).

    ``room``: the walk's :data:`Room` (|z(a)| in its moduli, its ``zr`` room for z).
    """
    ftol = ROUNDING * EPS * size_of(cb, ph, e, a, room.mg.z)
    br = bracket(a, b, ga, gb, 0.0, 2.0 * EPS, ftol, 200, 0.0)
    z = room.zr
    lam, z0, b0, b1, bh, theta = cb.lam, ph.z0, ph.b0, ph.b1, ph.bh, ph.theta  # no record passed in the loop
    e0, e1, dh, w = ph.e0, ph.e1, cb.Dh, cb.W
    spare = np.bool_(True)  # (a literal True would compile update_halley once more for it)
    while br.status == RUNNING:
        x = br.x
        modal_raw(lam, z0, b0, b1, bh, theta, om, x, z)
        fx = event_raw(e0, e1, dh, w, theta, om, e, x, z)
        d1, d2 = event_rate(cb, ph, om, e, x, z, 1), event_rate(cb, ph, om, e, x, z, 2)
        br, spare = update_halley(br, x, fx, d1, d2, spare)
    return br.hi


@njit(cache=True, inline="always")
def chord_low(ga, gb, h, m2):
    """The least value over [a, a + h] of the chord through (a, ``ga``), (a + h, ``gb``) less m2 t (h - t) / 2
    (the module's docstring): a lower bound on g there when ``m2`` bounds |g''|."""
    d, c = gb - ga, m2 * h * h
    if 2.0 * abs(d) >= c:  # the vertex is outside [a, a + h] (or m2 h^2 = 0): the least value is at an end
        return min(ga, gb)
    return 0.5 * (ga + gb) - c / 8.0 - d * d / (2.0 * c)


@njit(cache=True, inline="always")
def certify(cb, ph, om, e, a, h, room, start, m2):
    """1: root-free on [a, a + h]; 2: exactly one root there; 0: undecided: :func:`verdict`'s tests with ``m2``
    bounding |g_e''| over the interval."""
    za, ga, gb = room.za, room.ga[e], room.gb[e]
    if gb > 0.0:
        low = chord_low(ga, gb, h, m2)  # (size_of >= 0: at or below 0 the test fails, no size needed)
        if ga > 0.0 and low > 0.0 and low > ROUNDING * EPS * size_of(cb, ph, e, a + h, room.mg.z):
            return 1
        if start:
            g1 = event_rate(cb, ph, om, e, a, za, 1)
            if g1 > m2 * h / 2.0:
                return 1
            if g1 >= 0.0 and event_rate(cb, ph, om, e, a, za, 2) > bound(cb, om, e, a, h, room.mg, 3) * h / 3.0:
                return 1
        return 0
    if ga > 0.0:
        g1 = event_rate(cb, ph, om, e, a, za, 1)
        if -g1 > m2 * h or -(g1 + event_rate(cb, ph, om, e, a + h, room.zb, 1)) > m2 * h:
            return 2
    return 0


@njit(cache=True, inline="always")
def sharper_m2(cb, ph, om, e, a, h, room):
    """(|g''(a)| + |g''(b)| + M3 h) / 2 + ROUNDING EPS times M2 from |z| alone (``room.dzc``): a bound on |g_e''|
    over [a, b = a + h] from g'' at its ends (the module's docstring)."""
    m3 = bound(cb, om, e, a, h, room.mg, 3)
    d2a = event_rate(cb, ph, om, e, a, room.za, 2)
    d2b = event_rate(cb, ph, om, e, a + h, room.zb, 2)
    return 0.5 * (abs(d2a) + abs(d2b) + m3 * h) + ROUNDING * EPS * bound_of(cb, om, e, room.dzc)


@njit(cache=True, inline="always")
def verdict(cb, ph, om, e, a, h, room, start, m2):
    """1: root-free on [a, a + h]; 2: exactly one root there; 0: undecided (``start``: g(a) = 0 departing).

    ``room``: the walk's :data:`Room` (z and |z| at a, z at a + h, g at both ends); ``m2``: the bound on
    |g_e''| over the interval (:func:`.phase.bound`).  Where that decides nothing the tests run again with
    :func:`sharper_m2` when it is smaller.
    """
    for sharper in range(2):  # one copy of the tests inlined, not two: they are most of the walk's compile time
        v = certify(cb, ph, om, e, a, h, room, start, m2)
        if v != 0 or sharper:
            return v
        m2s = sharper_m2(cb, ph, om, e, a, h, room)
        if m2s >= m2:
            return 0
        m2 = m2s
    return 0


@njit(cache=True, inline="always")
def decide_interval(cb, ph, om, a, h, room):
    """(all decided, any root) over the active functions on [a, a + h] (``room``: the walk's :data:`Room`).

    ``room.clear[e]``: function e is proven root-free up to there (an interval
    that was halved for another function's sake needs no second proof);
    ``room.dz``, ``room.dzc``: room for the modes' terms of the bounds (:func:`.phase.mode_bounds`), shared by
    all functions;
    ``room.open[e]``: set where function e is left undecided (what :func:`nearest_zero` reads).
    """
    decided, root = True, False
    gb, departing, clear, dz, open_ = room.gb, room.dep, room.clear, room.dz, room.open
    mode_bounds(cb, om, a, h, room.mg, dz, room.dzc)
    for e in range(len(gb)):
        open_[e] = False
        if not cb.active[e] or clear[e] >= a + h:
            continue
        v = verdict(cb, ph, om, e, a, h, room, departing[e] and a == 0.0, bound_of(cb, om, e, dz))
        if v == 1:
            clear[e] = a + h
        open_[e] = v == 0
        decided = decided and v != 0
        root = root or gb[e] <= 0.0
    return decided, root


@njit(cache=True, inline="always")
def first_crossing(cb, ga, gb):
    """The slot, among the active functions with g(a) > 0 >= g(b), whose chord crosses 0 first; -1: none."""
    best, slot = 2.0, np.int64(-1)  # (a literal -1 would compile locate once more for it)
    for e in range(len(ga)):
        if cb.active[e] and gb[e] <= 0.0 < ga[e]:
            x = ga[e] / (ga[e] - gb[e])
            if x < best:
                best, slot = x, e
    return slot


@njit(cache=True, **NO_RUNTIME)
def earliest(cb, ph, om, a, b, room):
    """(tau, slot) of the earliest root among the functions that are <= 0 at b (each with one root in [a, b]
    where it is > 0 at a), ``room`` the walk's :data:`Room` (:func:`locate`), its ``zb`` then z at the earliest
    root so far.

    The function whose chord crosses first is located first; another is located only where it is <= 0 at
    that root (the module's docstring), in [a, root].
    """
    ga, gb, zt = room.ga, room.gb, room.zb
    first = first_crossing(cb, ga, gb)
    best, slot, fresh = b, -1, False
    if first >= 0:
        best, slot = locate(cb, ph, om, first, a, b, ga[first], gb[first], room), first
    for e in range(len(ga)):
        if not cb.active[e] or gb[e] > 0.0 or e == first:
            continue
        if ga[e] <= 0.0:  # (a departing function at or below 0 at b: the event is at b)
            if slot < 0:
                best, slot = b, e
            continue
        if not fresh:
            modal_raw(cb.lam, ph.z0, ph.b0, ph.b1, ph.bh, ph.theta, om, best, zt)
            fresh = True
        gt = event_raw(ph.e0, ph.e1, cb.Dh, cb.W, ph.theta, om, e, best, zt)
        if gt <= 0.0:
            t = locate(cb, ph, om, e, a, best, ga[e], gt, room)
            if t < best:
                best, slot, fresh = t, e, False
    return best, slot


@njit(cache=True, **NO_RUNTIME)
def nearest_zero(a, b, room):
    """(tau, slot): among the functions :func:`decide_interval` left undecided on [a, b] (``room.open``; not
    departing at the start), the end of [a, b] nearest 0."""
    best, tau, slot = 1.0e300, b, -1
    ga, gb, dep = room.ga, room.gb, room.dep
    for e in range(len(ga)):
        if room.open[e] and not (dep[e] and a == 0.0):
            for t, g in ((a, ga[e]), (b, gb[e])):
                if t > 0.0 and g < best:
                    best, tau, slot = g, t, e
    return tau, slot


@njit(cache=True, inline="always")
def copy(src, dst):
    """dst[:] = src element by element (a slice is a view, which needs numba's runtime)."""
    for i in range(len(src)):
        dst[i] = src[i]


#: the walk's room: z at both ends, the functions at both ends, the modes' bound terms, how far each function
#: is proven clear, the departing flags, z for the root finder, the moduli (:data:`.phase.Mags`), the functions
#: the last interval left undecided and the modes' bound terms from |z| alone
Room = namedtuple("Room", "za zb ga gb dz clear dep zr mg open dzc")


@njit(cache=True)
def new_room(m, k, nf, departing):
    """A :data:`Room` for ``m`` modes, ``k`` event slots and ``nf`` forces, its arrays views of three
    allocations (a record taken here would be reference-counted: the records' parts are filled by :func:`walk`)."""
    zs, xs, bh = np.empty(3 * m, dtype=np.complex128), np.empty(3 * k + 8 * m), np.empty((m, nf))
    g = 3 * k
    mg = Mags(xs[g + m:g + 2 * m], xs[g + 2 * m:g + 3 * m], xs[g + 3 * m:g + 4 * m], bh, xs[g + 4 * m:g + 5 * m],
              xs[g + 5 * m:g + 6 * m], xs[g + 6 * m:g + 7 * m])
    return Room(zs[:m], zs[m:2 * m], xs[:k], xs[k:2 * k], xs[g:g + m], xs[2 * k:g], departing.copy(), zs[2 * m:], mg,
                np.zeros(k, dtype=np.bool_), xs[g + 7 * m:])


@njit(cache=True, inline="always")
def prepare(cb, ph, om, room):
    """Fill ``room`` at tau = 0: z(0) (the phase's z0: the closed form at 0 is z0 exactly), |z(0)|, the phase's
    moduli (with the decaying modes' rates at 0), the functions (0 where departing: a
    function within rounding of 0 departs too), no function proven clear yet."""
    za, ga, dep, az = room.za, room.ga, room.dep, room.mg.z
    copy(ph.z0, za)
    magnitudes_into(cb, ph, room.mg)
    rates_into(cb, ph, om, room.mg)
    copy(ph.e0, ga)
    for e in range(len(ga)):
        room.clear[e] = -1.0
    values(cb, ph, om, 0.0, za, ga)
    abs_into(za, az)
    for e in range(len(ga)):
        if cb.active[e] and ga[e] <= ROUNDING * EPS * size_of(cb, ph, e, 0.0, az):
            dep[e] = True
        if dep[e]:
            ga[e] = 0.0


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted in the loop
def walk(cb, ph, om, tau_end, h0, floor, room):
    """(tau, slot, graze): the phase's first event in (0, tau_end]; slot -1: none (tau = tau_end).

    ``room``: a :data:`Room` (:func:`new_room`) with the departing flags set, the rest filled here; ``h0`` the
    longest interval while every mode lives, ``floor`` the shortest.  Once a fast decaying mode has died
    (:data:`.phase.DEAD`) the longest interval follows the modes left: a stiff damper's mode would otherwise hold
    every interval of a long phase to its own time constant (the bounds allow longer ones by then).
    """
    za, zb, ga, gb, az = room.za, room.zb, room.ga, room.gb, room.mg.z
    prepare(cb, ph, om, room)
    a, h = 0.0, h0
    until = next_death(cb.lam, 0.0)
    copy(ga, gb)
    lam, z0, b0, b1, bh, theta = cb.lam, ph.z0, ph.b0, ph.b1, ph.bh, ph.theta
    while a < tau_end:
        b = min(a + h, tau_end)
        modal_raw(lam, z0, b0, b1, bh, theta, om, b, zb)
        values(cb, ph, om, b, zb, gb)
        decided, root = decide_interval(cb, ph, om, a, b - a, room)
        if not decided and b - a > floor:
            h = 0.5 * (b - a)
            continue
        if root:
            tau, slot = earliest(cb, ph, om, a, b, room)
            return tau, slot, False
        if not decided:
            tau, slot = nearest_zero(a, b, room)
            if slot >= 0:
                return tau, slot, True
        if b >= until:
            h0, until = max(h0, longest(cb.lam, om, b, tau_end)), next_death(cb.lam, b)
        a, h = b, min(2.0 * h, h0)
        copy(zb, za)
        abs_into(za, az)
        copy(gb, ga)
    return tau_end, -1, False
