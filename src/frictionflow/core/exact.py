"""Exact event-driven integration of piecewise-constant friction laws.

Between switches the motion is a closed form (:mod:`.closed_form`); only the
switching instants are searched, by bracketed safeguarded Newton iteration on
the closed form, to about machine precision.  The friction modes:

============  ==========================================  ============
mode          friction force F_c                          motion
============  ==========================================  ============
SLIP_POS      +F_d   (V_r above the band / > 0)           OSC about F_d
SLIP_NEG      -F_d                                        OSC about -F_d
STICK         X + 2 zeta V_b (Coulomb: X' = V_b held)     LIN
HOLD          F_e (Karnopp band, |F_e| < F_s)             LIN or EXP
SAT_POS/NEG   +-F_s (Karnopp band, |F_e| >= F_s)          OSC about +-F_s
EDGE_LO/HI    X + 2 zeta X' (Filippov sliding on a band   LIN
              edge: Karnopp with F_e = X pushes the mass
              out of the band while slip pushes it back)
============  ==========================================  ============

Which mode follows a switch is decided by consistency: a mode is taken only if
the motion stays inside its region for a positive time, judged by the value
and the first two time derivatives of each of its boundary functions.  A
trajectory that touches a boundary within rounding without crossing it
(grazing) does not switch.

The stick rules here and in :mod:`.friction`.  Where the rule is the same it is
called from there: the held force (:func:`~.friction.held_force`), Coulomb's
stick rule (:func:`~.friction.holds_within`, with this kernel's tolerances:
:func:`stick_holds`), and in the region fallback (:func:`region_mode`) the
slip direction by V_r (:func:`~.friction.band_mode`) and the band's side of
F_s (:func:`~.friction.band_side`).  Two things stay here:

* *Karnopp's band as modes* (HOLD, SAT_POS/NEG, EDGE_LO/HI, their order
  :data:`KARNOPP_ORDER` and HOLD's EXP motion with F_e = X): only this kernel
  integrates the band phase by phase; RK4 evaluates the band's force at each
  step (:func:`~.friction.band_force`) and needs no modes, and the Filippov
  sliding on a band edge exists only between two closed-form phases.
* *The consistency test* (:func:`consistent`) of the slip and band modes:
  each region as linear boundaries a X + b X' - c (the switch search's event
  functions, :func:`mode_boundaries`), judged on the value and the first two
  time derivatives with tolerances scaled by the rounding of each term and of
  f (``ftol``).  Coulomb's STICK is the shared rule with tolerances of the
  same kind; :func:`~.friction.rest_mode` (the adaptive, tangent and flow map
  kernels) calls it with fixed relative margins.  Within rounding of
  |F_e - f| = F_s, where every stick exit is located, the two tolerances
  choose differently, so each engine keeps its own (one rule, two
  tolerances).

The kernel emits samples -- phase starts, zeros of X' (where X' is set to
exactly 0), extremes of X' and of X + 2 zeta X', the start of the tail, an
optional dense grid, and the end -- each with the exact cumulative work
integrals, so that the section records and the steady-state classifier of
:mod:`.sections` apply unchanged and see exact values.

Harmonic forcing f = F_ex cos(Omega tau + phi) (``p[FEX]`` > 0) runs in
:func:`run_forced`: slip phases carry the closed-form harmonic particular
solution, stick phases hold F_e - f(tau), and every event function (switch
boundaries, zeros of X', X'', X' + 2 zeta X'', of a held F_c) is searched by
walking with a certified bound on its second derivative, so that no short
excursion is stepped over; the stroboscopic times k 2 pi / Omega are samples
too.  Unforced runs never enter it (bit-identical to before).

Speed: the helpers on the hot path take and return scalars (a mode's
boundaries are a tuple, not an array): every call of a compiled function
with an array argument costs two atomic reference-count updates per array,
more than the closed form itself.  The arrays are touched in :func:`run`
and in the functions it inlines only.

Replication (:func:`run`, ``replicate``): an unforced phase's computation
reads the state at its start, not the absolute time, so a stick-slip cycle
that returns to a bitwise-equal switch state repeats bit for bit from there;
it is copied (times accumulated by the same additions) instead of integrated
again, within the limits that keep the copy identical to the integration
(:func:`_replicate`); not with a dense grid or the periodic stop.

:func:`run`'s last two arguments are flags (plain booleans, one compiled
signature for every caller): ``replicate`` (on or off) and
``periodic_stop``, whether the periodic stop (``stop_periodic``: the section
values repeat to ``rtol`` for ``min_periods`` periods) is looked for.  The
façade, whose runs never stop early, passes (replicate, False); the batched
sweeps (False, True).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from . import codes
from . import closed_form as cf
from . import sections as sec
from .friction import (COULOMB, FD, FEX, FS, KARNOPP, LAW, OMEGA, PHI, RESULTANT, VD, band_mode, band_side, held_force,
                       holds_within, stick_friction)
from .layout import N_WORK
from .records import (DENSE_DT, MIN_PERIODS, STOP_PERIODIC, STOP_RTOL, STOP_TERMINAL, T_END, T_TAIL, V0, VB, X0, ZETA,
                      record_switch)
from .samples import emit

SLIP_POS, SLIP_NEG, HOLD, SAT_POS, SAT_NEG, EDGE_LO, EDGE_HI, STICK = range(1, 9)
FC_CONST, FC_RES, FC_SPRING = 0, 1, 2
# The closed forms know two laws, one per stick rule: COULOMB (switch) and KARNOPP (band).  The functions
# below branch on ``law == COULOMB`` and take the other branch as Karnopp's band; :func:`closed_form_law`,
# at every entry, refuses any other code.
KARNOPP_ORDER = np.array([SLIP_POS, SLIP_NEG, SAT_POS, SAT_NEG, HOLD, EDGE_LO, EDGE_HI])
COULOMB_ORDER = np.array([STICK, SLIP_POS, SLIP_NEG])

# status codes
DONE, FULL, STUCK = codes.OK, codes.FULL, codes.STUCK
EPS = 2.220446049250313e-16
#: rows of the ``ev`` arrays of :func:`boundaries` (a mode has at most 4 boundaries)
MAX_EVENTS_PER_MODE = 5
#: a sample at least every WINDOW of a long phase
WINDOW = 16.0 * math.pi
#: the friction mode recorded for each mode: +1 slip+, -1 slip-, 0 stick (band, edge)
FRICTION_MODE = (0, 1, -1, 0, 0, 0, 0, 0, 0)
#: replication (:func:`run`): at most this many samples in the repeating stretch
REP_CAP = 512


@njit(cache=True)
def dynamics(mode, zeta, fd, fs, res):
    """(motion type, constant force, kind of F_c) of a mode."""
    if mode == SLIP_POS:
        return cf.OSC, fd, FC_CONST
    if mode == SLIP_NEG:
        return cf.OSC, -fd, FC_CONST
    if mode == SAT_POS:
        return cf.OSC, fs, FC_CONST
    if mode == SAT_NEG:
        return cf.OSC, -fs, FC_CONST
    if mode == HOLD and not res:
        return (cf.EXP if zeta > 0.0 else cf.LIN), 0.0, FC_SPRING
    return cf.LIN, 0.0, FC_RES


@njit(cache=True, inline="always")
def settles_analytically(fmode, v):
    """Whether a final phase (friction mode ``fmode``, from velocity ``v``) has a known end: a slip decays onto
    the sliding equilibrium, a stick at rest stays; a band held against the spring alone (Karnopp's spring
    rule) still moves, its damper braking X' to 0, and is judged on its samples."""
    return fmode != 0 or v == 0.0


@njit(cache=True)
def closed_form_law(p):
    """The law code of the force record ``p``: COULOMB (the switch rule) or KARNOPP (the band); any other
    law's slip force is not constant (ValueError)."""
    law = int(p[LAW])
    if law != COULOMB and law != KARNOPP:
        raise ValueError("core.exact: the closed forms need a piecewise-constant law (Coulomb's or Karnopp's code)")
    return law


@njit(cache=True)
def friction_force(fck, force, x, v, zeta):
    if fck == FC_CONST:
        return force
    if fck == FC_SPRING:
        return x
    return stick_friction(x, zeta, v, 0.0)


@njit(cache=True)
def mode_boundaries(mode, law, zeta, vb, fd, fs, vd, res):
    """(n, ((a, b, c, s), ...)): the mode holds while s (a X + b X' - c) > 0 for each of the first n of 4."""
    be = 2.0 * zeta if res else 0.0  # F_e = X + be X'
    z = (0.0, 0.0, 0.0, 0.0)
    if law == COULOMB:
        if mode == SLIP_POS:
            return 1, ((0.0, 1.0, vb, -1.0), z, z, z)
        if mode == SLIP_NEG:
            return 1, ((0.0, 1.0, vb, 1.0), z, z, z)
        # STICK at X' = V_b: F_e with X' = V_b
        return 2, ((1.0, 0.0, fs - be * vb, -1.0), (1.0, 0.0, -fs - be * vb, 1.0), z, z)
    lo = vb - vd  # lower band edge (V_r = +V_d)
    hi = vb + vd
    if mode == SLIP_POS:
        return 1, ((0.0, 1.0, lo, -1.0), z, z, z)
    if mode == SLIP_NEG:
        return 1, ((0.0, 1.0, hi, 1.0), z, z, z)
    if mode == EDGE_LO:
        # slip+ pushes back: F_d - X - 2 zeta X' > 0; the band pushes out: -2 zeta X' < 0; F_e < F_s
        return 3, ((-1.0, -2.0 * zeta, -fd, 1.0), (0.0, 2.0 * zeta, 0.0, 1.0), (1.0, be, fs, -1.0), z)
    if mode == EDGE_HI:
        # slip- pushes back: -F_d - X - 2 zeta X' < 0; the band pushes out: -2 zeta X' > 0; F_e > -F_s
        return 3, ((1.0, 2.0 * zeta, -fd, 1.0), (0.0, 2.0 * zeta, 0.0, -1.0), (1.0, be, -fs, 1.0), z)
    band = ((0.0, 1.0, lo, 1.0), (0.0, 1.0, hi, -1.0))
    if mode == HOLD:
        return 4, (band[0], band[1], (1.0, be, fs, -1.0), (1.0, be, -fs, 1.0))
    if mode == SAT_POS:
        return 3, (band[0], band[1], (1.0, be, fs, 1.0), z)
    if mode == SAT_NEG:
        return 3, (band[0], band[1], (1.0, be, -fs, -1.0), z)
    return 2, (band[0], band[1], z, z)


@njit(cache=True)
def boundaries(mode, law, zeta, vb, fd, fs, vd, res, ev):
    """Fill ``ev[k] = (a, b, c, s)`` (:func:`mode_boundaries`); returns how many."""
    n, bs = mode_boundaries(mode, law, zeta, vb, fd, fs, vd, res)
    for k in range(n):
        for i in range(4):
            ev[k, i] = bs[k][i]
    return n


@njit(cache=True, forceinline=True)
def law_record(law, fd, fs, vd, res):
    """The law record of :func:`consistent` and :func:`select_mode`: (law code, F_d, F_s, V_d, resultant), typed alike everywhere."""
    return (np.int64(law), float(fd), float(fs), float(vd), bool(res))


@njit(cache=True, forceinline=True)
def stick_holds(fs, res, zeta, vb, x, f, df, ddf, ftol):
    """Coulomb's STICK at X' = V_b: the shared rule (:func:`~.friction.holds_within`) with this kernel's tolerances.

    While sticking the held force F_e - f moves at the rate V_b - f' and
    curves at -f''.  "On the limit" and "not moving" are within 256 ulps of
    the size of the terms that make the held force (X, F_s -+ 2 zeta V_b, f,
    and ``ftol``, the rounding of f) and of its rate (V_b, f'): every stick
    exit is located to a few ulps of time, so the held force found there is
    on F_s only to that rounding, and the rate decides.  (The other kernels'
    fixed relative margin, :func:`~.friction.holds`, would let the rounding
    of the located exit choose; a far side -F_s within rounding needs F_s
    itself within rounding of 0, which the laws exclude.)
    """
    held = held_force(x, zeta, vb, res, f)
    be = 2.0 * zeta if res else 0.0
    c = abs(fs - be * vb) if held >= 0.0 else abs(fs + be * vb)  # the near boundary's constant
    tol0 = 256.0 * EPS * (abs(x) + c + abs(f)) + ftol + 1e-300
    tol1 = 256.0 * EPS * (abs(vb) + abs(df)) + 1e-300
    return holds_within(held, vb - df, -ddf, fs - tol0, fs + tol0, tol1)


@njit(cache=True)
def consistent(mode, lw, zeta, vb, x, v, f=0.0, df=0.0, ddf=0.0, ftol=0.0):
    """Does the motion stay in ``mode``'s region for a positive time from (x, v)?

    ``lw``: the law record (law code, F_d, F_s, V_d, resultant), :func:`law_record`.
    ``f, df, ddf``: the external force and its first two rates there.  Every
    boundary is a function of X - f and X' (:func:`mode_boundaries`: its
    coefficient of X multiplies X - f), and slip feels f in X''.  ``ftol``:
    the rounding of f itself, which is set by F_ex and the size of its
    argument Omega tau + phi, not by |f| (near a zero of f, or where X - f is
    a difference of nearly equal terms, |f| and |X| understate it).
    """
    law, fd, fs, vd, res = lw
    # A switch is located to a few ulps of time; X' there is then off the boundary
    # by |X''| times that: far below this tolerance, far above rounding.
    vtol = 1e-10 * (abs(vb) + abs(v) + vd + abs(x) + fs)
    if law == KARNOPP and (mode == EDGE_LO or mode == EDGE_HI):
        edge = vb - vd if mode == EDGE_LO else vb + vd
        if abs(v - edge) > vtol:
            return False
        if res or zeta == 0.0:
            return False  # the band holds the mass itself: no sliding on its edge
    if law == COULOMB and mode == STICK:
        return abs(v - vb) <= vtol and stick_holds(fs, res, zeta, vb, x, f, df, ddf, ftol)
    dyn, force, _ = dynamics(mode, zeta, fd, fs, res)
    a = j = 0.0  # X'' and its rate (LIN)
    if dyn == cf.OSC:
        a = force - x - 2.0 * zeta * v + f
        j = -v - 2.0 * zeta * a + df
    elif dyn == cf.EXP:
        a = -2.0 * zeta * v
        j = -2.0 * zeta * a
    n, bs = mode_boundaries(mode, law, zeta, vb, fd, fs, vd, res)
    for k in range(n):
        ca, cb, cc, s = bs[k]
        g0 = s * (ca * x + cb * v - cc - ca * f)
        tol0 = 256.0 * EPS * (abs(ca * x) + abs(cb * v) + abs(cc) + abs(ca * f)) + abs(ca) * ftol + 1e-300
        if g0 > tol0:
            continue
        if g0 < -tol0:
            return False
        g1 = s * (ca * v + cb * a - ca * df)
        # X'' is a difference of terms of size |F| + |X| + 2 zeta |X'|: its rounding scale
        tol1 = 256.0 * EPS * (abs(ca * v) + abs(cb) * (abs(force) + abs(x) + 2.0 * zeta * abs(v) + abs(f)) + abs(ca * df)) + 1e-300
        if g1 > tol1:
            continue
        if g1 < -tol1:
            return False
        g2 = s * (ca * a + cb * j - ca * ddf)
        if g2 < 0.0:
            return False
    return True


@njit(cache=True, forceinline=True)
def mode_order(law):
    """The modes of law code ``law`` in the order :func:`select_mode` tries them (Coulomb's switch, else the band)."""
    return COULOMB_ORDER if law == COULOMB else KARNOPP_ORDER


@njit(cache=True)
def select_mode(lw, zeta, vb, x, v, f=0.0, df=0.0, ddf=0.0, ftol=0.0):
    """The mode the motion continues in from (x, v); -1 if none is consistent.  (lw, f, ftol: see :func:`consistent`.)"""
    order = mode_order(lw[0])
    for m in order:
        if consistent(m, lw, zeta, vb, x, v, f, df, ddf, ftol):
            return m
    return -1


@njit(cache=True)
def region_mode(law, zeta, vb, fd, fs, vd, res, x, v, f=0.0):
    """The mode by region alone (a fallback when no mode is consistent; f: the external force).

    The shared rules of :mod:`.friction`: the slip direction by V_r
    (:func:`~.friction.band_mode`; Coulomb's switch is a band of width 0),
    inside Karnopp's band the side of F_s the held force is on
    (:func:`~.friction.band_side`).
    """
    coulomb = law == COULOMB
    d = band_mode(v, vb, 0.0 if coulomb else vd)
    if d > 0:
        return SLIP_POS
    if d < 0:
        return SLIP_NEG
    if coulomb:
        return STICK
    side = band_side(held_force(x, zeta, v, res, f), fs)
    if side > 0:
        return SAT_POS
    if side < 0:
        return SAT_NEG
    return HOLD


# -- switch times ---------------------------------------------------------------------------------
@njit(cache=True)
def _g(co, dyn, zeta, force, x0, v0, a, b, c, t):
    """g = a X + b X' - c and g' at t, and (X, X') there."""
    x, v, acc = cf.state_with(co, dyn, zeta, force, x0, v0, t)
    return a * x + b * v - c, a * v + b * acc, x, v


@njit(cache=True)
def _refine(co, dyn, zeta, force, x0, v0, a, b, c, s, lo, hi):
    """First time in (lo, hi] where s g <= 0, given s g(hi) <= 0 and g monotone on [lo, hi].

    Returns the time and (X, X') there -- NaN when that is ``hi`` and ``hi``
    was not evaluated here.  Newton's iteration from the middle, kept inside
    the bracket.  (The switch times are the same to the last bit as those
    recorded before issue 9: a faster iteration lands on a neighbouring
    double, and in undamped runs the difference shows in quantities that are
    rounding noise.)
    """
    t = 0.5 * (lo + hi)
    x_hi = v_hi = np.nan
    for _ in range(200):
        g, dg, x, v = _g(co, dyn, zeta, force, x0, v0, a, b, c, t)
        if s * g > 0.0:
            lo = t
        else:
            hi, x_hi, v_hi = t, x, v
        if hi - lo <= 2.0 * EPS * hi:
            break
        # Newton from the current point, kept inside the bracket
        tn = t - g / dg if dg != 0.0 else 0.5 * (lo + hi)
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi)
        elif abs(tn - t) <= 2.0 * EPS * abs(tn):
            # converged to rounding: return the side of the root that is outside
            if s * g <= 0.0:
                return t, x, v
            tn = min(hi, t + 4.0 * EPS * abs(t))
            gn, _, xn, vn = _g(co, dyn, zeta, force, x0, v0, a, b, c, tn)
            if s * gn <= 0.0:
                return tn, xn, vn
            break
        t = tn
    return hi, x_hi, v_hi


@njit(cache=True)
def _search(co, dyn, zeta, force, x0, v0, a, b, c, s, horizon):
    """First crossing of one boundary in (0, horizon]: (time or inf, never crossed at all, X, X' there).

    g is monotone between its critical points; a crossing is bracketed on the
    first such interval whose end lies outside.  A critical point outside by
    less than 1e-12 of g's scale is a touch (grazing), not a crossing.
    ``never`` certifies that no crossing can come after the horizon either.
    X and X' at the crossing are NaN where they were not evaluated.  ``reach``
    (last): the latest time compared with the horizon; the result is the
    same for every horizon above it (so that a repeated phase is known to
    repeat bit for bit: :func:`run`'s replication).
    """
    if dyn == cf.LIN:
        # g = g0 + g1 t exactly: no bracketing needed (and none of its rounding)
        g0, g1, _, _ = _g(co, dyn, zeta, force, x0, v0, a, b, c, 0.0)
        if s * g1 >= 0.0:
            return np.inf, True, np.nan, np.nan, 0.0
        tc = -g0 / g1
        if tc > horizon:
            return np.inf, False, np.nan, np.nan, horizon
        while True:  # the first representable time on the outside
            g, _, x, v = _g(co, dyn, zeta, force, x0, v0, a, b, c, tc)
            if s * g <= 0.0:
                break
            tc = np.nextafter(tc, np.inf)
        if tc < 0.0:
            return 0.0, False, np.nan, np.nan, 0.0
        return tc, False, x, v, tc
    scale = abs(a * x0) + abs(b * v0) + abs(c) + 1e-300
    graze = 1e-12 * scale  # a critical point this close to the boundary only touches it
    tiny = 256.0 * EPS * scale  # a g that stays on the boundary (within rounding) does not cross it
    g_inf = s * (a * force - c)
    period = 2.0 * math.pi if dyn == cf.OSC and zeta == 0.0 else np.inf
    env, rate = cf.envelope(co, dyn, zeta, a, b)
    t_a = 0.0
    # the critical points of g, generated as needed (most phases end at the first or second)
    t_b, step = cf.first_critical(co, dyn, a, b, 0.0)
    while True:
        last = t_b >= horizon  # the horizon ends the last interval
        if last:
            t_b = horizon
        gb, _, _, _ = _g(co, dyn, zeta, force, x0, v0, a, b, c, t_b)
        if s * gb < -(tiny if last else graze):
            tc, xc, vc = _refine(co, dyn, zeta, force, x0, v0, a, b, c, s, t_a, t_b)
            return tc, False, xc, vc, t_b
        if g_inf > 0.0 and env * math.exp(-rate * t_b) < g_inf:
            return np.inf, True, np.nan, np.nan, t_b  # the decaying oscillation stays inside for ever
        if t_b >= period:
            return np.inf, True, np.nan, np.nan, t_b  # undamped: g repeats with period 2 pi
        if last:
            break
        t_a = t_b
        t_b += step
    # Nothing up to the horizon; after its last critical point g is monotone: can it cross later?
    never = False
    if dyn == cf.EXP and zeta == 0.0:
        _, dgh, _, _ = _g(co, dyn, zeta, force, x0, v0, a, b, c, horizon)
        never = s * dgh >= 0.0
    elif dyn == cf.EXP:
        never = s * (a * (x0 + v0 / (2.0 * zeta)) - c) > 0.0  # s g(inf): X -> x0 + v0 / (2 zeta), X' -> 0
    elif dyn == cf.OSC and zeta >= 1.0:
        never = g_inf > 0.0 and cf.first_critical(co, dyn, a, b, horizon)[0] == np.inf
    return np.inf, never, np.nan, np.nan, horizon


@njit(cache=True)
def first_switch(co, dyn, zeta, force, x0, v0, n_b, bs, t_max):
    """Earliest boundary crossing in (0, t_max]: (time, boundary index, never, X, X' there, reach).

    ``co``: the phase's coefficients; ``n_b, bs``: its boundaries
    (:func:`mode_boundaries`).  ``never`` is True when no boundary can ever
    be crossed from here: the phase lasts for ever (the run has reached its
    final phase).  X and X' are NaN where the search did not evaluate them.
    ``reach``: the result is the same for every t_max above it (:func:`_search`).
    """
    best = np.inf
    which = -1
    never = True
    xb = vb = np.nan
    reach = 0.0
    for k in range(n_b):
        a, b, c, s = bs[k]
        tc, nv, xc, vc, rk = _search(co, dyn, zeta, force, x0, v0, a, b, c, s, min(t_max, best))
        # (a search cut at an earlier boundary's crossing reaches that, and depends on t_max only through min(t_max, best))
        reach = max(reach, rk)
        if tc < best:
            best, which, xb, vb = tc, k, xc, vc
        never = never and nv
    return best, which, never and which < 0, xb, vb, reach


@njit(cache=True)
def next_event(dyn, zeta, force, x0, v0, ev, n_ev, t_max, crit=None):
    """Earliest crossing of the boundaries ``ev[:n_ev]`` (:func:`boundaries`) in (0, t_max]: (time, index, never).

    See :func:`first_switch`.  ``crit`` is not used (kept for callers).
    """
    bs = ((ev[0, 0], ev[0, 1], ev[0, 2], ev[0, 3]), (ev[1, 0], ev[1, 1], ev[1, 2], ev[1, 3]),
          (ev[2, 0], ev[2, 1], ev[2, 2], ev[2, 3]), (ev[3, 0], ev[3, 1], ev[3, 2], ev[3, 3]))  # rows past n_ev unused
    co = cf.coefficients(dyn, zeta, force, x0, v0)
    tau, which, never, _, _, _ = first_switch(co, dyn, zeta, force, x0, v0, min(n_ev, 4), bs, t_max)
    return tau, which, never


# -- samples and work integrals ---------------------------------------------------------------------
@njit(cache=True)
def _fc_zero(dyn, fck, zeta, x0, v0, t_max):
    """When a state-dependent F_c crosses 0 in (0, t_max) (P_f changes sign there), else inf."""
    if fck == FC_RES and v0 != 0.0:  # LIN: X + 2 zeta V_0 = x0 + v0 t + 2 zeta v0
        t = -(x0 + 2.0 * zeta * v0) / v0
    elif fck == FC_SPRING and v0 != 0.0:
        if dyn == cf.EXP:
            c = 2.0 * zeta
            arg = 1.0 + c * x0 / v0
            if not (0.0 < arg < 1.0):
                return np.inf
            t = -math.log(arg) / c
        else:
            t = -x0 / v0
    else:
        return np.inf
    return t if 0.0 < t < t_max else np.inf


@njit(cache=True)
def _piece(dyn, fck, zeta, vb, force, slipping, xa, va, xb, vb_, L):
    """The work integrals over one piece (P_f of one sign): (W_dv, W_fin, W_fout, W_heat)."""
    w_dv = 2.0 * zeta * cf.integral_v2(dyn, zeta, force, xa, va, L)
    if fck == FC_CONST:
        pf = force * (xb - xa)
    elif fck == FC_SPRING:
        pf = 0.5 * (xb * xb - xa * xa)
    else:
        pf = va * ((xa + 2.0 * zeta * va) * L + 0.5 * va * L * L)
    heat = force * (vb * L - (xb - xa)) if slipping else 0.0
    return w_dv, max(pf, 0.0), max(-pf, 0.0), heat


@njit(cache=True)
def _window(co, dyn, zeta, t, ta, tz, tt, dense_dt):
    """The sources of samples in the window of a phase that starts at ``ta`` (times from the phase start).

    (c0, s0, c1, s1, c2, s2, tz, tt, j, td, tw): the next zero of X', extreme
    of X' and of X + 2 zeta X' after ``ta`` with their steps; the zero of a
    state-dependent F_c and the start of the tail if still ahead; the dense
    grid (index, time); the window's end, ``ta`` + :data:`WINDOW`.  Inf: none.
    A phase is walked in windows, each source restarting at the window's
    start, so that the sample times are those of the window-by-window walk
    the golden outputs were recorded with.
    """
    c0, s0 = cf.first_critical(co, dyn, 1.0, 0.0, ta)  # X' = 0
    c1, s1 = cf.first_critical(co, dyn, 0.0, 1.0, ta)  # extremes of X'
    c2, s2 = np.inf, np.inf
    if zeta > 0.0:
        c2, s2 = cf.first_critical(co, dyn, 1.0, 2.0 * zeta, ta)  # of X + 2 zeta X'
    j = td = np.inf
    if dense_dt > 0.0:
        j = math.floor((t + ta) / dense_dt) + 1.0
        td = j * dense_dt - t
    return c0, s0, c1, s1, c2, s2, (tz if tz > ta else np.inf), (tt if tt > ta else np.inf), j, td, ta + WINDOW


@njit(cache=True)
def _next_sample(src, t, dense_dt):
    """(time, source, sources advanced): the earliest next time of the sources (:func:`_window`).

    source: 0 a zero of X', 1 another, 2 the window's end.  On a tie the
    window's end comes first (a point on it belongs to neither window), then
    the sources in their order; the others give the same time again next,
    and the caller drops the repeat.
    """
    c0, s0, c1, s1, c2, s2, tz, tt, j, td, tw = src
    tb = min(min(c0, c1), min(c2, tz), min(min(tt, td), tw))
    kind = 1
    if tb == tw:
        kind = 2
    elif tb == c0:
        kind = 0
        c0 += s0
    elif tb == c1:
        c1 += s1
    elif tb == c2:
        c2 += s2
    elif tb == tz:
        tz = np.inf
    elif tb == tt:
        tt = np.inf
    else:
        j += 1.0
        td = j * dense_dt - t
    return tb, kind, (c0, s0, c1, s1, c2, s2, tz, tt, j, td, tw)


@njit(cache=True)
def _repeated(ring, m, n_max, n_min, rtol, noise):
    """Maxima and minima of X repeat to rtol of the amplitude (not below ``noise``), as the classifier judges them."""
    if n_min == 0:
        return False
    tol = max(rtol * (ring[m - 1] - ring[3 * m - 1]), noise)
    return (sec.ring_repeats(ring[:m], ring[m : 2 * m], n_max, tol, rtol)
            and sec.ring_repeats(ring[2 * m : 3 * m], ring[3 * m :], n_min, tol, rtol))


#: the settings of a run, unpacked once (:func:`_settings`; numba keeps a named tuple of scalars in registers)
Settings = namedtuple("Settings", "t_end zeta vb dense_dt t_tail law fd fs vd res stop_periodic stop_terminal rtol")
#: a phase of :func:`run`: its closed form (``co``, ``dyn``, ``force``, the kind ``fck`` of F_c), the belt
#: speed, its friction mode, and its start (t, x, v)
Phase = namedtuple("Phase", "co dyn zeta force fck vb fmode t x v")
#: replication (:func:`_replicate`): the reference switch (x, v, mode, its sample k and event ne, time t),
#: phases seen, and once the stretch since it repeats its length in samples and events and in time; copied:
#: the switches copied so far
Stretch = namedtuple("Stretch", "x v mode k ne t n_phase n_rows n_ev period copied")


@njit(cache=True, inline="always")
def _settings(run, p):
    """The :data:`Settings` of the run record ``run`` and the force record ``p`` (:func:`closed_form_law` checks the law)."""
    return Settings(run[T_END], run[ZETA], run[VB], run[DENSE_DT], run[T_TAIL], closed_form_law(p), p[FD], p[FS], p[VD],
                    p[RESULTANT] != 0.0, run[STOP_PERIODIC] != 0.0, run[STOP_TERMINAL] != 0.0, run[STOP_RTOL])


@njit(cache=True, forceinline=True)
def _enter(s, x, v):
    """(mode, X') of the unforced motion that continues from (x, v): the consistent mode, else the region's."""
    mode = select_mode(law_record(s.law, s.fd, s.fs, s.vd, s.res), s.zeta, s.vb, x, v)
    if mode < 0:
        mode = region_mode(s.law, s.zeta, s.vb, s.fd, s.fs, s.vd, s.res, x, v)
    return mode, (s.vb if mode == STICK else v)


@njit(cache=True, inline="always")
def _replication(s, replicate, periodic_stop):
    """(on, rel, rp, n_rel, reach): whether :func:`run` replicates (:func:`_replicate`), the array of its stretch, no reference yet."""
    on = replicate and s.dense_dt == 0.0 and not (s.stop_periodic and periodic_stop)
    rel = np.zeros(REP_CAP if on else 1)
    return on, rel, Stretch(0.0, 0.0, np.int64(0), np.int64(0), 0, 0.0, 0, -1, -1, 0.0, 0), np.int64(-1), 0.0


@njit(cache=True, forceinline=True)
def _phase_end(s, mode, dfk, x, v, t):
    """How the unforced phase from (x, v) at t ends: (ph, T, which, never, xe, ve, reach).

    ``dfk``: its :func:`dynamics`; ``ph``: the :data:`Phase`; T its length (up to t_end if no boundary is
    crossed before, ``which`` = -1); (xe, ve) the state at its end; never,
    reach: :func:`first_switch`'s.
    """
    dyn, force, fck = dfk
    co = cf.coefficients(dyn, s.zeta, force, x, v)
    n_b, bs = mode_boundaries(mode, s.law, s.zeta, s.vb, s.fd, s.fs, s.vd, s.res)
    tau, which, never, xe, ve, reach = first_switch(co, dyn, s.zeta, force, x, v, n_b, bs, s.t_end - t)
    T = tau if which >= 0 else s.t_end - t
    if which < 0 or math.isnan(xe):
        xe, ve, _ = cf.state_with(co, dyn, s.zeta, force, x, v, T)
    return Phase(co, dyn, s.zeta, force, fck, s.vb, FRICTION_MODE[mode], t, x, v), T, which, never, xe, ve, reach


@njit(cache=True, inline="always")
def _add_piece(w, ph, xa, va, xb, vb_, L):
    """Add the work integrals of one piece of the phase ``ph`` (:func:`_piece`) to ``w``."""
    d0, d1, d2, d3 = _piece(ph.dyn, ph.fck, ph.zeta, ph.vb, ph.force, ph.fmode != 0, xa, va, xb, vb_, L)
    w[0] += d0
    w[1] += d1
    w[2] += d2
    w[3] += d3


@njit(cache=True, inline="always")
def _push_rel(rel, n_rel, r, ok):
    """Append ``r`` to the replication's stretch ``rel`` (a sample's time in its phase, or -T at a phase end);
    -1 (the stretch is not repeatable) when it is full or not ``ok``."""
    if n_rel < REP_CAP and ok:
        rel[n_rel] = r
        return n_rel + 1
    return -1


@njit(cache=True, inline="always")
def _sections_at(ring, sc, s, vzero, xb, t_abs, acc):
    """The periodic stop's record of a sample (X = ``xb`` at ``t_abs``; ``vzero``: a zero of X', X'' = ``acc``).

    ``ring``: X and times of the last maxima, then minima, of X, a quarter
    each; ``sc``: (how many maxima, minima, the largest |X| sampled).
    Returns (sc, stop): stop once the maxima and minima repeat (:func:`_repeated`).
    """
    n_max, n_min, x_seen = sc
    x_seen = max(x_seen, abs(xb))
    stop = False
    if vzero and s.stop_periodic:
        m = len(ring) // 4
        if acc < 0.0:  # a maximum of X
            sec.push_section(ring[:m], ring[m : 2 * m], xb, t_abs)
            n_max += 1
        else:
            sec.push_section(ring[2 * m : 3 * m], ring[3 * m :], xb, t_abs)
            n_min += 1
        stop = acc < 0.0 and _repeated(ring, m, n_max, n_min, s.rtol, 1e-13 * max(x_seen, abs(s.vb), s.fd))
    return (n_max, n_min, x_seen), stop


@njit(cache=True, forceinline=True)
def _phase_sources(ph, T, s, n_rel):
    """(tz, tt, src, n_rel): the zero of a state-dependent F_c and the tail's start inside the phase ``ph`` of
    length T (inf: none), its first window (:func:`_window`), and the replication's ``n_rel`` (-1 if the tail
    starts inside: this stretch does not repeat)."""
    tz = _fc_zero(ph.dyn, ph.fck, ph.zeta, ph.x, ph.v, T)
    tt = s.t_tail - ph.t if 0.0 < s.t_tail - ph.t < T else np.inf
    return tz, tt, _window(ph.co, ph.dyn, ph.zeta, ph.t, 0.0, tz, tt, s.dense_dt), (-1 if tt < np.inf else n_rel)


@njit(cache=True, forceinline=True)
def _next_in_phase(ph, T, src, ta, tz, tt, dense_dt):
    """The next sample inside the phase ``ph`` after ``ta``: (tb, kind, src, X, X', X'') (:func:`_next_sample`); tb >= T: none.

    A zero of X' (kind 0) has X' set to exactly 0: the section crossing is then a sample.
    (No arrays here: the loop that writes the samples stays in :func:`run`, see :mod:`.samples`.)
    """
    while True:
        tb, kind, src = _next_sample(src, ph.t, dense_dt)
        if tb >= T:
            return tb, kind, src, 0.0, 0.0, 0.0
        if kind == 2:
            src = _window(ph.co, ph.dyn, ph.zeta, ph.t, tb, tz, tt, dense_dt)
        if tb <= ta:
            continue  # the same time from another source
        xb, vb_, acc = cf.state_with(ph.co, ph.dyn, ph.zeta, ph.force, ph.x, ph.v, tb)
        return tb, kind, src, xb, (0.0 if kind == 0 else vb_), acc


@njit(cache=True, inline="always")
def _copy_stretch(rel, outs, events, rp, t, k, ne):
    """Copy the repeating stretch of ``rp`` (:data:`Stretch`) once after sample ``k`` - 1 and event ``ne`` - 1,
    its times accumulated from ``t`` by the same additions as the integration (t + T, t + tb); returns the time reached."""
    out_t, out_y, out_fc, out_mode, out_w = outs
    ev_t, ev_mode, ev_contact = events
    tc = t
    e = ne
    for i in range(rp.n_rows):
        r = rel[i]
        src = rp.k + 1 + i
        if r < 0.0:  # a phase start: t += T, as integrated
            tc = tc + (-r)
            out_t[k + i] = tc
            ev_t[e] = tc
            ev_mode[e] = ev_mode[rp.ne + e - ne]
            ev_contact[e] = 0
            e += 1
        else:
            out_t[k + i] = tc + r
        # this engine's closed forms are the single mass's: the state (X, X') and one contact
        out_y[0, k + i] = out_y[0, src]
        out_y[1, k + i] = out_y[1, src]
        out_fc[0, k + i] = out_fc[0, src]
        out_mode[0, k + i] = out_mode[0, src]
        for j in range(N_WORK):
            out_w[k + i, j] = out_w[src, j]
    return tc


@njit(cache=True, inline="always")
def _copy_while(rp, reach, rel, outs, events, s, t, k, ne):
    """Copy the repeating stretch of ``rp`` (:func:`_replicate`) while no copy meets the tail's start or comes within
    the search horizon ``reach`` of t_end, and it fits: (t, k, ne, rp) after the copies."""
    margin = 1e-9 * (1.0 + s.t_end)  # the rounding of times within a stretch, generously
    copied = rp.copied
    while (t + reach + margin < s.t_end and not (t < s.t_tail < t + rp.period + margin)
           and k + rp.n_rows <= len(outs[0]) and ne + rp.n_ev <= len(events[0])):
        t = _copy_stretch(rel, outs, events, rp, t, k, ne)
        k += rp.n_rows
        ne += rp.n_ev
        copied += rp.n_ev
    return t, k, ne, Stretch(rp.x, rp.v, rp.mode, rp.k, rp.ne, rp.t, rp.n_phase, rp.n_rows, rp.n_ev, rp.period, copied)


@njit(cache=True, forceinline=True)
def _replicate(rp, n_rel, reach, sw):
    """Replication at the start of a phase (:func:`run`, ``replicate``), ``sw`` = (mode, x, v, t, k, ne) there.

    A phase's computation reads the state at its start and its length only,
    not the absolute time (except the horizon t_end - t, the tail's start,
    the dense grid and the early-stop rules).  So once a switch leaves the
    motion in a state bitwise equal to that of the reference switch ``rp``
    (:data:`Stretch`) and the stretch since it was recorded whole in ``rel``
    (``n_rel`` samples; -1: not recorded or not repeatable), it repeats bit
    for bit: it is copied (:func:`_copy_while`).  Without a repeat the
    reference moves to phases 0, 1, 2, 4, 8, ... (Brent: any cycle is met).
    Returns (rp, n_rel, reach, copy): copy the stretch now.
    """
    mode, x, v, t, k, ne = sw
    same = (mode == rp.mode and x == rp.x and v == rp.v and math.copysign(1.0, x) == math.copysign(1.0, rp.x)
            and math.copysign(1.0, v) == math.copysign(1.0, rp.v))
    if same and rp.n_rows < 0 and n_rel == k - 1 - rp.k:  # the stretch repeats: fixed from now on
        rp = Stretch(rp.x, rp.v, rp.mode, rp.k, rp.ne, rp.t, rp.n_phase, n_rel, ne - rp.ne, t - rp.t, rp.copied)
        n_rel = -1
    copy = same and rp.n_rows > 0
    if not copy and rp.n_rows < 0 and rp.n_phase & (rp.n_phase - 1) == 0:
        rp = Stretch(x, v, mode, k - 1, ne, t, rp.n_phase, rp.n_rows, rp.n_ev, rp.period, rp.copied)
        n_rel, reach = 0, 0.0
    return Stretch(rp.x, rp.v, rp.mode, rp.k, rp.ne, rp.t, rp.n_phase + 1, rp.n_rows, rp.n_ev, rp.period, rp.copied), n_rel, reach, copy


@njit(cache=True)
def run(run, p, samples, events, t_mode, replicate, periodic_stop):
    """Integrate from (x0, v0) at t = 0 to ``t_end`` switch by switch (unforced: F_ex > 0 goes to :func:`run_forced`).

    ``run``: the run record (:func:`.records.run_record`; its ODE slots are
    not read); ``p``: the force record (:mod:`.layout`).  Samples go to
    ``samples`` = (t, x, v, fc, mode, work), switches to ``events`` = (t,
    mode, contact) (:mod:`.records`).  Returns (k, ne, status, t_terminal, t_stop):
    the numbers of samples and of switches (all counted, ``events`` keeps
    those that fit; FULL: an output array was too short); when the final
    phase (no boundary is ever crossed again) began, or -1 (its friction
    mode goes to ``t_mode[0]``); where the run stopped early
    (``stop_periodic``, ``stop_terminal``), else ``t_end``.  ``replicate``
    and ``periodic_stop``: see the module's docstring (``t_mode[1]``, if
    present, receives the number of switches copied).
    """
    s = _settings(run, p)
    t_end, zeta = s.t_end, s.zeta
    outs = (samples[0], samples[1], samples[2], samples[3], samples[4])
    w = np.zeros(N_WORK)  # the work integrals since the last sample (emit restarts them)
    ring = np.zeros(4 * (int(run[MIN_PERIODS]) + 2))  # (np.zeros as for w: one allocation routine to compile)
    sc = (0, 0, abs(run[X0]))
    t, x = 0.0, run[X0]
    mode, v = _enter(s, x, run[V0])
    k, ne, zero_len, t_terminal = np.int64(0), np.int64(0), 0, -1.0  # k, ne not literals: emit, _replicate compile once
    rep, rel, rp, n_rel, reach = _replication(s, replicate, periodic_stop)
    while True:
        # a phase starts (the run's start, or a switch) or the run ends: a sample
        dyn, force, fck = dynamics(mode, zeta, s.fd, s.fs, s.res)
        if not emit(outs, k, t, x, v, friction_force(fck, force, x, v, zeta), FRICTION_MODE[mode], w):
            return k, ne, FULL, t_terminal, t
        k += 1
        if t >= t_end:
            break
        if rep and zero_len == 0:
            rp, n_rel, reach, copy = _replicate(rp, n_rel, reach, (mode, x, v, t, k, ne))
            if copy:
                t, k, ne, rp = _copy_while(rp, reach, rel, outs, events, s, t, k, ne)
        ph, T, which, never, xe, ve, reach_p = _phase_end(s, mode, (dyn, force, fck), x, v, t)
        if n_rel >= 0:  # (-1 unless replicating)
            reach = max(reach, (t - rp.t) + reach_p)
        if never and t_terminal < 0.0:
            t_terminal = t
            t_mode[0] = FRICTION_MODE[mode]
            # undamped, a final slip circles X* (periodic); a spring-rule band still moves (X'' = -2 zeta X')
            if s.stop_terminal and zeta > 0.0 and settles_analytically(FRICTION_MODE[mode], v):
                return k, ne, DONE, t_terminal, t
        tz, tt, src, n_rel = _phase_sources(ph, T, s, n_rel)  # the samples inside, each with the work since the last
        ta, xa, va = 0.0, x, v
        while True:
            tb, kind, src, xb, vb_, acc = _next_in_phase(ph, T, src, ta, tz, tt, s.dense_dt)
            if tb >= T:
                break
            _add_piece(w, ph, xa, va, xb, vb_, tb - ta)
            if not emit(outs, k, t + tb, xb, vb_, friction_force(fck, force, xb, vb_, zeta), ph.fmode, w):
                return k, ne, FULL, t_terminal, t + ta
            k += 1
            if n_rel >= 0:  # (-1 unless replicating)
                n_rel = _push_rel(rel, n_rel, tb, True)
            ta, xa, va = tb, xb, vb_
            if not periodic_stop:
                continue
            sc, stop = _sections_at(ring, sc, s, kind == 0, xb, t + tb, acc)
            if stop:
                return k, ne, DONE, t_terminal, t + tb
        _add_piece(w, ph, xa, va, xe, ve, T - ta)  # the last piece: its work goes with the switch's sample
        x, v = xe, ve
        if which < 0:
            t = t_end  # the run ends inside the phase: its last sample, at the top of the loop
            continue
        t += T
        if n_rel >= 0:  # (-1 unless replicating)
            n_rel = _push_rel(rel, n_rel, -T, T > 8.0 * EPS * (1.0 + t_end))  # shorter: the zero-length count reads t
        mode, v = _enter(s, x, v)  # the switch: which mode continues?
        zero_len = zero_len + 1 if T <= 4.0 * EPS * (1.0 + t) else 0
        if zero_len > 8:
            return k, ne, STUCK, t_terminal, t
        ne = record_switch(events, ne, t, mode)
    if len(t_mode) > 1:
        t_mode[1] = rp.copied
    return k, ne, DONE, t_terminal, t_end


# -- harmonic forcing ---------------------------------------------------------------------------------
# With f = F_ex cos(Omega tau + phi) the slip phases carry the harmonic particular solution and the
# holding force of stick phases varies in time (cf.forced_phase).  Event functions are no longer
# monotone between closed-form critical points; every one is G = a X + b X' + d X'' - e f - c, and its
# roots are bracketed by walking with a certified bound on |G''| (cf.bound_at): from t, G cannot leave
# the band s G > -graze before the first root of s G(t) + s G'(t) u - M u^2 / 2, and it must cross where
# the upper parabola s G(t) + s G'(t) u + M u^2 / 2 does (G is monotone up to there).  A short
# excursion of G beyond the boundary is never stepped over.

@njit(cache=True, inline="always")
def _d2g(dyn, zeta, om, fn, acc, jerk, f):
    """G'' of the event function ``fn`` (:func:`next_root`) from X'', X''' and f.

    X'''' from the equation of motion: OSC X'' = F + f - X - 2 zeta X', so
    X'''' = f'' - X'' - 2 zeta X'''; EXP X'''' = -2 zeta X'''; LIN 0 (X''' = 0).
    """
    a, b, d, e, _ = fn
    snap = -om * om * f - acc - 2.0 * zeta * jerk if dyn == cf.OSC else -2.0 * zeta * jerk
    return a * acc + b * jerk + d * snap + e * om * om * f


@njit(cache=True)
def _gf(ph, fn, t):
    """G, G' and G'' at t of the event function ``fn`` (:func:`next_root`) with (X, X') there."""
    co, dyn, zeta, force, pz, fz, om = ph
    a, b, d, e, c = fn
    st = cf.forced_eval(co, dyn, zeta, force, pz, fz, om, t)
    x, v, acc, jerk, f, df = st[0], st[1], st[2], st[3], st[4], st[5]
    g = a * x + b * v + d * acc - e * f - c
    return g, a * v + b * acc + d * jerk - e * df, _d2g(dyn, zeta, om, fn, acc, jerk, f), st


@njit(cache=True, inline="always")
def _halley(t, g, dg, d2g):
    """Halley's step from t (cubic convergence: two steps from the walk's bracket end, mostly); NaN if undefined."""
    den = 2.0 * dg * dg - g * d2g
    return t - 2.0 * g * dg / den if den != 0.0 else np.nan


@njit(cache=True)
def _refine_forced(ph, fn, s, lo, hi, g_hi, dg_hi, d2g_hi, st_hi):
    """The first time in (lo, hi] where s G <= 0, given s G(hi) <= 0 (G, G', G'' there; ``st_hi``: the motion there, :func:`cf.forced_eval`): (t, the motion there).

    Halley's iteration from ``hi``, kept inside the bracket and used while
    |G| at least halves (else bisection).  Once a step is below rounding the
    root is within ulps: an iterate on the outside is the answer; one on the
    inside probes an ulp or two further, so the bracket closes to a few ulps.
    """
    t = _halley(hi, g_hi, dg_hi, d2g_hi)
    if not (lo < t < hi):
        t = 0.5 * (lo + hi)
    g_prev = abs(g_hi)
    for _ in range(400):
        g, dg, d2g, st = _gf(ph, fn, t)
        if s * g > 0.0:
            lo = t
        else:
            hi, st_hi = t, st
        if hi - lo <= 4.0 * EPS * hi:
            break
        tn = _halley(t, g, dg, d2g)
        if abs(tn - t) <= 2.0 * EPS * abs(t):  # converged: the root is within ulps
            if s * g <= 0.0:
                return t, st  # on the outside already
            tn = t + 2.0 * EPS * abs(t)  # probe the other side
        elif abs(g) > 0.5 * g_prev:  # Halley is not converging: bisect
            tn = 0.5 * (lo + hi)
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi)
        g_prev = abs(g)
        t = tn
    return hi, st_hi


# The event table of a forced phase (run_forced): per event function G = a X + b X' + d X'' - e f - c a row of
# constants -- its coefficients, those of its bound on |G''| (cf.bound_at) and its graze level -- and apart
# its side, the one thing a walk changes.  Tuples of six slots (the most a mode has: Karnopp's saturated
# band, 3 boundaries and 3 sample functions), not an array: a compiled function taking an array, or an
# array bound to another name in the loops of run_forced, costs two atomic reference-count updates each time.
EA, EB, ED, EE, EC, EK1, EK2, EKP, EGRAZE = range(9)
NO_EVENT = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True)
def bound_consts(ph, x, v, fn):
    """(K1, K2, Kp, graze) of the event function ``fn`` = (a, b, d, e, c) in a phase starting at (x, v) (:func:`next_root`)."""
    co, dyn, zeta, force, pz, fz, om = ph
    a, b, d, e, c = fn
    K1, K2 = cf.free_bound(co, dyn, zeta, a, b, d)
    hz = complex(a - om * om * d, om * b) * pz - e * fz  # the harmonic part: Re(hz e^{i Omega t})
    mz = cf.modulus(hz)
    scale = abs(a * x) + abs(b * v) + abs(d) * (abs(force) + abs(x) + 2.0 * zeta * abs(v)) + abs(c) + mz + abs(e) * cf.modulus(fz)
    # an excursion beyond 0 smaller than 1e-12 of the scale is a touch, not a crossing
    return K1, K2, om * om * mz, 1e-12 * scale + 1e-300


@njit(cache=True, forceinline=True)
def _decide(ev, side, live, st):
    """The side of the event function ``ev`` at the walk's start (state ``st``): ``side`` if set, else from G
    (or G' where G is on 0 within the graze level)."""
    if side != 0.0 or not live:
        return side
    x, v, acc, jerk, f, df = st[0], st[1], st[2], st[3], st[4], st[5]
    g = ev[EA] * x + ev[EB] * v + ev[ED] * acc - ev[EE] * f - ev[EC]
    dg = ev[EA] * v + ev[EB] * acc + ev[ED] * jerk - ev[EE] * df
    return 1.0 if g > ev[EGRAZE] or (g >= -ev[EGRAZE] and dg >= 0.0) else -1.0


@njit(cache=True, forceinline=True)
def _reach(ev, s, last, live, ph, t, st):
    """(u, on_zero, last) of one event function at t (motion ``st``): the walk may step u; ``on_zero``: it is
    within its graze level of crossing (the walk stands); ``last``: the last walk time it was on its side."""
    if not live:
        return np.inf, False, last
    co, dyn = ph[0], ph[1]
    x, v, acc, jerk, f, df, e1, e2 = st[0], st[1], st[2], st[3], st[4], st[5], st[6], st[7]
    g = ev[EA] * x + ev[EB] * v + ev[ED] * acc - ev[EE] * f - ev[EC]
    dg = ev[EA] * v + ev[EB] * acc + ev[ED] * jerk - ev[EE] * df
    sg = s * g
    sdg = s * dg
    if sg > 0.0:
        last = t
    ahead = sg + ev[EGRAZE]
    if ahead <= 0.0:
        return 0.0, True, last
    return parabola_step(ahead, sdg, cf.bound_at(co, dyn, ev[EK1], ev[EK2], ev[EKP], t, e1, e2)), False, last


@njit(cache=True, forceinline=True)
def parabola_step(ahead, sdg, m2):
    """The walk's step (:func:`next_root`): how far an event function with s G + graze = ``ahead`` > 0,
    s G' = ``sdg`` and |G''| <= ``m2`` from here on is known not to reach -graze (its parabola bounds)."""
    if sdg < 0.0:
        disc = sdg * sdg - 2.0 * m2 * ahead
        if disc >= 0.0:
            return 2.0 * ahead / (-sdg + math.sqrt(disc))
        return 2.0 * ahead / (-sdg + math.sqrt(sdg * sdg + 2.0 * m2 * ahead))
    return (sdg + math.sqrt(sdg * sdg + 2.0 * m2 * ahead)) / m2


@njit(cache=True, forceinline=True)
def _fold(step, r):
    """The walk's step after one more event function's :func:`_reach` ``r``: 0 once one stands on its zero."""
    u, on_zero = r[0], r[1]
    return 0.0 if on_zero else min(step, u)


@njit(cache=True, forceinline=True)
def _below(ev, s, live, st):
    """Whether the event function ``ev`` (side ``s``) has crossed at the motion ``st``: beyond its touch level."""
    if not live:
        return False
    x, v, acc, f = st[0], st[1], st[2], st[4]
    g = ev[EA] * x + ev[EB] * v + ev[ED] * acc - ev[EE] * f - ev[EC]
    return not s * g > 0.0 and not s * g > -ev[EGRAZE]  # on 0 within the touch level: not (yet) a crossing


@njit(cache=True, forceinline=True)
def _cross(ev, s, last, i, nb, ph, t, st, found):
    """``found`` = (index, time, motion) of the earliest crossing so far, with event function ``i`` (``ev``, side
    ``s``, crossed at t: motion ``st``) refined: the earlier wins; a boundary (i < nb) wins a tie to ulps over a
    sample function."""
    dyn, zeta, om = ph[1], ph[2], ph[6]
    x, v, acc, jerk, f, df = st[0], st[1], st[2], st[3], st[4], st[5]
    g = ev[EA] * x + ev[EB] * v + ev[ED] * acc - ev[EE] * f - ev[EC]
    fn = (ev[EA], ev[EB], ev[ED], ev[EE], ev[EC])
    dg = ev[EA] * v + ev[EB] * acc + ev[ED] * jerk - ev[EE] * df
    tr, sr = _refine_forced(ph, fn, s, last, t, g, dg, _d2g(dyn, zeta, om, fn, acc, jerk, f), st)
    best, tb = found[0], found[1]
    boundary_tie = i < nb and best >= nb and tr <= tb + 8.0 * EPS * (1.0 + tb)
    if tr < tb or boundary_tie:
        return i, tr, sr
    return found


@njit(cache=True, forceinline=True)
def _walk_step(tab, sides, lasts, n, ph, t, t1, st):
    """(step, lasts): how far the walk may go from t (the nearest of the event functions' reaches, :func:`_reach`)."""
    r0 = _reach(tab[0], sides[0], lasts[0], n > 0, ph, t, st)
    r1 = _reach(tab[1], sides[1], lasts[1], n > 1, ph, t, st)
    r2 = _reach(tab[2], sides[2], lasts[2], n > 2, ph, t, st)
    r3 = _reach(tab[3], sides[3], lasts[3], n > 3, ph, t, st)
    r4 = _reach(tab[4], sides[4], lasts[4], n > 4, ph, t, st)
    r5 = _reach(tab[5], sides[5], lasts[5], n > 5, ph, t, st)
    step = _fold(_fold(_fold(_fold(_fold(_fold(t1 - t, r0), r1), r2), r3), r4), r5)
    return step, (r0[2], r1[2], r2[2], r3[2], r4[2], r5[2])


@njit(cache=True, forceinline=True)
def _crossing(tab, sides, lasts, n, nb, ph, t, st):
    """The earliest crossing at t (:func:`_cross` over the event functions that crossed, in order): (index or -1,
    time, motion).  Which crossed is read slot by slot; the few that did are refined in one loop (one copy of
    the refinement in the compiled code, not one per slot)."""
    crossed = (_below(tab[0], sides[0], n > 0, st), _below(tab[1], sides[1], n > 1, st),
               _below(tab[2], sides[2], n > 2, st), _below(tab[3], sides[3], n > 3, st),
               _below(tab[4], sides[4], n > 4, st), _below(tab[5], sides[5], n > 5, st))
    found = (-1, np.inf, st)
    if not (crossed[0] or crossed[1] or crossed[2] or crossed[3] or crossed[4] or crossed[5]):
        return found
    for i in range(n):
        if crossed[i]:
            found = _cross(tab[i], sides[i], lasts[i], i, nb, ph, t, st, found)
    return found


@njit(cache=True, forceinline=True)
def next_root(ph, table, t0, st0, t1):
    """The first crossing of any of the event functions in (t0, t1]: (index or -1, time, the motion there, sides).

    ``table`` = (tab, sides, n, nb) (:func:`_event_table`): function i is
    G_i = a X + b X' + d X'' - e f - c (``tab[i]``); it starts on side
    ``sides[i]`` (s G > 0; 0: decided at t0 from G, or G' where G is on 0;
    the sides decided are returned).  The functions are walked together,
    one evaluation of the motion per step: from t, G_i stays above -graze
    until the first root of s G + s G' u - M u^2 / 2 (M: the bound on
    |G_i''|), and must go below it where s G + s G' u + M u^2 / 2 does,
    monotonically.  The next point is the nearest of these; a function that
    has crossed there is refined (the earliest wins; boundaries, the first
    ``nb``, on a tie to ulps).  ``st0``: the motion at t0
    (:func:`cf.forced_eval`); with no crossing the time is t1 and the motion
    is that at t1.
    """
    co, dyn, zeta, force, pz, fz, om = ph
    tab, sides, n, nb = table
    sides = (_decide(tab[0], sides[0], n > 0, st0), _decide(tab[1], sides[1], n > 1, st0),
             _decide(tab[2], sides[2], n > 2, st0), _decide(tab[3], sides[3], n > 3, st0),
             _decide(tab[4], sides[4], n > 4, st0), _decide(tab[5], sides[5], n > 5, st0))
    lasts = (t0, t0, t0, t0, t0, t0)
    t = t0
    st = st0
    while True:
        step, lasts = _walk_step(tab, sides, lasts, n, ph, t, t1, st)
        if step > 0.0:
            tn = min(t + step, t1)
            t = tn if tn > t else min(np.nextafter(t, np.inf), t1)  # at least an ulp: no standing still
            st = cf.forced_eval(co, dyn, zeta, force, pz, fz, om, t)
        best, tb, stb = _crossing(tab, sides, lasts, n, nb, ph, t, st)
        if best >= 0:
            return best, tb, stb, sides
        if t >= t1:
            return -1, t1, st, sides


#: what the work integrals of a forced phase's pieces read (:func:`_piece_work`): its motion (``dyn``,
#: ``force``), the kind ``fck`` of F_c, the belt speed, the forcing (``fex``, ``om``) and the friction mode
ForcedPiece = namedtuple("ForcedPiece", "dyn fck zeta vb force fex om fmode")
#: the forcing of :func:`run_forced`: f = fex cos(om tau + phi), of period 2 pi / om
Forcing = namedtuple("Forcing", "fex om phi period")
#: the known sample times of a forced phase, from its start (:func:`_clock`): the tail's start, the
#: dense grid's (index j, time td), the next stroboscopic index, the window's end
Clock = namedtuple("Clock", "tt j td strobe tw")


@njit(cache=True)
def _forced_piece(pc, theta, xa, va, xb, vb_, L):
    """The work integrals over one piece of a forced phase: (W_dv, W_fin, W_fout, W_heat, W_ex).

    ``pc``: :data:`ForcedPiece`; theta: the forcing's phase at the piece's
    start.  F_c = F - held force where the interface holds (F_e - f):
    P_f = X' F_e - X' f there.
    """
    co, pz, fz = cf.forced_phase(pc.dyn, pc.zeta, pc.force, xa, va, pc.fex, pc.om, theta)
    v2, w_ex = cf.forced_work(co, pc.dyn, pc.zeta, pc.force, pz, fz, pc.om, L)
    return _piece_work(pc, xa, va, xb, vb_, L, v2, w_ex)


@njit(cache=True)
def _piece_work(pc, xa, va, xb, vb_, L, v2, w_ex):
    """The work integrals over one piece given int X'^2 (``v2``) and int X' f (``w_ex``) over it (:func:`_forced_piece`)."""
    fck, zeta, force = pc.fck, pc.zeta, pc.force
    if fck == FC_CONST:
        pf = force * (xb - xa)
    elif fck == FC_SPRING:
        pf = 0.5 * (xb * xb - xa * xa) - w_ex
    else:
        pf = va * ((xa + 2.0 * zeta * va) * L + 0.5 * va * L * L) - w_ex
    heat = force * (pc.vb * L - (xb - xa)) if pc.fmode != 0 else 0.0
    return 2.0 * zeta * v2, max(pf, 0.0), max(-pf, 0.0), heat, w_ex


@njit(cache=True, forceinline=True)
def forced_piece_work(pc, wr, a, b, L, theta):
    """The work integrals (N_WORK) of the piece of length L from ``a`` to ``b`` = (motion, X, X').

    ``wr`` = (from_start, rep): rebuilt per piece (:func:`_forced_piece`, at
    the forcing's phase theta) unless ``from_start``, else from the phase's
    representation ``rep`` (:func:`cf.work_rep`) between the two motions.
    Returned, not added to the run's array here: a callee taking an array
    costs two atomic reference-count updates per call.
    """
    from_start, rep = wr
    sta, xa, va = a
    stb, xb, vb_ = b
    if from_start:
        v2, wx = cf.work_between(rep, pc.dyn, sta[8], sta[9], stb[8], stb[9], L)
        return _piece_work(pc, xa, va, xb, vb_, L, v2, wx)
    return _forced_piece(pc, theta, xa, va, xb, vb_, L)


@njit(cache=True)
def sample_functions(dyn, fck, zeta):
    """(m, fns): the first m of ``fns`` are the functions whose roots are samples in a phase.

    X', X'', X' + 2 zeta X'' (OSC; the last if zeta > 0), or the held F_c.
    """
    none = (0.0, 0.0, 0.0, 0.0, 0.0)
    if dyn == cf.OSC:
        return (3 if zeta > 0.0 else 2), ((0.0, 1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0, 0.0), (0.0, 1.0, 2.0 * zeta, 0.0, 0.0))
    if fck == FC_SPRING:
        return 1, ((1.0, 0.0, 0.0, 1.0, 0.0), none, none)
    return 1, ((1.0, 2.0 * zeta, 0.0, 1.0, 0.0), none, none)


@njit(cache=True, forceinline=True)
def event_row(ph, x, v, fns, i):
    """Row ``i`` of a forced phase's event table (:func:`_event_table`) from its functions ``fns`` = (n, nb, bs, sf)."""
    n, nb, bs, sf = fns
    if i >= n:
        return NO_EVENT
    if i < nb:
        ba, bb, bc, _ = bs[i]
        fn = (ba, bb, 0.0, ba, bc)
    else:
        fn = sf[i - nb]
    K1, K2, Kp, graze = bound_consts(ph, x, v, fn)
    return (fn[0], fn[1], fn[2], fn[3], fn[4], K1, K2, Kp, graze)


@njit(cache=True, forceinline=True)
def _event_table(ph, s, mode, fck, x, v):
    """A forced phase's event functions: (tab, sides, n, nb), ``n`` of them, the first ``nb`` the boundaries.

    The mode's boundaries a (X - f) + b X' - c, with their sides, then the
    sample functions (:func:`sample_functions`: side 0, decided by the walk).
    """
    dyn, zeta = ph[1], ph[2]
    nb, bs = mode_boundaries(mode, s.law, zeta, s.vb, s.fd, s.fs, s.vd, s.res)
    m, sf = sample_functions(dyn, fck, zeta)
    fns = (nb + m, nb, bs, sf)
    tab = (event_row(ph, x, v, fns, 0), event_row(ph, x, v, fns, 1), event_row(ph, x, v, fns, 2),
           event_row(ph, x, v, fns, 3), event_row(ph, x, v, fns, 4), event_row(ph, x, v, fns, 5))
    sides = (bs[0][3] if nb > 0 else 0.0, bs[1][3] if nb > 1 else 0.0, bs[2][3] if nb > 2 else 0.0,
             bs[3][3] if nb > 3 else 0.0, 0.0, 0.0)
    return tab, sides, nb + m, nb


@njit(cache=True, forceinline=True)
def _clock(s, t, strobe, period):
    """The :data:`Clock` of a phase starting at t: the tail, the dense grid, the stroboscopic times after t, a window."""
    tt = s.t_tail - t if 0.0 < s.t_tail - t else np.inf
    j = td = np.inf
    if s.dense_dt > 0.0:
        j = math.floor(t / s.dense_dt) + 1.0
        td = j * s.dense_dt - t
    while strobe * period <= t:
        strobe += 1
    return Clock(tt, j, td, strobe, WINDOW)


@njit(cache=True, forceinline=True)
def _tick(ck, tb, ts, t, s, period):
    """(the clock past its source at tb, the sample's absolute time): tb is the earliest of ``ck``'s times (ts: the stroboscopic one)."""
    tt, j, td, strobe, tw = ck
    t_abs = t + tb
    if tb == tt:
        tt = np.inf
    elif tb == td:
        j += 1.0
        td = j * s.dense_dt - t
    elif tb == ts:
        t_abs = strobe * period  # the stroboscopic time itself, not t + (its phase time)
        strobe += 1
    else:
        tw = tb + WINDOW
    return Clock(tt, j, td, strobe, tw), t_abs


@njit(cache=True, forceinline=True)
def _forced_start(ph, s, t, strobe, period):
    """(wr, sta, clock) of a forced phase ``ph`` (:func:`next_root`) starting at t: how its work integrals are
    computed (:func:`forced_piece_work`), the motion at its start, its known sample times (:func:`_clock`)."""
    co, dyn, zeta, force, pz, fz, om = ph
    # the work integrals from this representation (OSC critically or over-damped: rebuilt per piece)
    wr = (dyn != cf.OSC or co[0] == cf.UNDER, cf.work_rep(co, dyn, zeta, pz, fz, om))
    return wr, cf.forced_eval(co, dyn, zeta, force, pz, fz, om, 0.0), _clock(s, t, strobe, period)


@njit(cache=True, forceinline=True)
def crossed_sample(table, i, v):
    """(the table with sample function ``i`` on its other side now, X'): X' (``v``) is exactly 0 at a zero of X'."""
    tab, sd, n, nb = table
    sides = (-sd[0] if i == 0 else sd[0], -sd[1] if i == 1 else sd[1], -sd[2] if i == 2 else sd[2],
             -sd[3] if i == 3 else sd[3], -sd[4] if i == 4 else sd[4], -sd[5] if i == 5 else sd[5])
    ev = tab[i]
    return (tab, sides, n, nb), (0.0 if ev[EB] == 1.0 and ev[EA] == 0.0 and ev[ED] == 0.0 else v)


@njit(cache=True, forceinline=True)
def _enter_forced(s, x, v, f, df, ddf, ftol):
    """(mode, X') of the forced motion that continues from (x, v) under f and its rates (:func:`_enter`, :func:`consistent`).

    At a switch, f and f' come from the same evaluation as (X, X'): the
    switch was located on them (G <= 0 there), and f recomputed from the
    absolute time differs by F_ex times the rounding of the argument, which
    at tau ~ 1e2 exceeds a boundary's rounding tolerance where X - f is a
    difference of near-equal terms (stick under the resultant rule with
    2 zeta V_b ~ F_s): stick would be taken again with zero length.
    """
    mode = select_mode(law_record(s.law, s.fd, s.fs, s.vd, s.res), s.zeta, s.vb, x, v, f, df, ddf, ftol)
    if mode < 0:
        mode = region_mode(s.law, s.zeta, s.vb, s.fd, s.fs, s.vd, s.res, x, v, f)
    return mode, (s.vb if mode == STICK else v)


@njit(cache=True)
def run_forced(run, p, samples, events, t_mode):
    """:func:`run` under the external force of ``p`` (F_ex > 0), with the same records (the stop slots not used).

    Samples as unforced (phase starts, zeros of X' set to 0, extremes of X'
    and of X + 2 zeta X', zeros of a held F_c, the tail's start, the dense
    grid, the end) and the stroboscopic times k 2 pi / Omega.  No early
    stop: the X' = 0 section repeats only for the autonomous system.
    Returns as :func:`run` (t_terminal = -1: no final phase is certified).
    """
    s = _settings(run, p)
    zeta, t_end = s.zeta, s.t_end
    fo = Forcing(p[FEX], p[OMEGA], p[PHI], 2.0 * math.pi / p[OMEGA])
    fex, om, phi, _ = fo
    outs = (samples[0], samples[1], samples[2], samples[3], samples[4])
    w = np.zeros(N_WORK)
    t, x = 0.0, run[X0]
    mode, v = _enter_forced(s, x, run[V0], fex * math.cos(phi), -fex * om * math.sin(phi), -om * om * fex * math.cos(phi), 0.0)
    # strobe: the next stroboscopic index (k = 0 is the start); not literals: emit and _forced_start would
    # compile once more for them
    k, ne, zero_len, strobe = np.int64(0), 0, 0, np.int64(1)
    while True:
        dyn, force, fck = dynamics(mode, zeta, s.fd, s.fs, s.res)
        theta = om * t + phi
        fnow = fex * math.cos(theta)
        if not emit(outs, k, t, x, v, friction_force(fck, force, x, v, zeta) - (fnow if fck != FC_CONST else 0.0), FRICTION_MODE[mode], w):
            return k, ne, FULL, -1.0, t
        k += 1
        if t >= t_end:
            break
        co, pz, fz = cf.forced_phase(dyn, zeta, force, x, v, fex, om, theta)
        ph = (co, dyn, zeta, force, pz, fz, om)
        table = _event_table(ph, s, mode, fck, x, v)
        pc = ForcedPiece(dyn, fck, zeta, s.vb, force, fex, om, FRICTION_MODE[mode])
        # the phase's samples (the loop that writes them stays here: see :mod:`.samples`)
        wr, sta, ck = _forced_start(ph, s, t, strobe, fo.period)
        ta, xa, va, horizon = 0.0, x, v, t_end - t
        while True:
            ts = ck.strobe * fo.period - t
            tk = min(min(ck.tt, ck.td), min(ts, ck.tw))
            i, tb, stb, sides = next_root(ph, table, ta, sta, min(tk, horizon))
            table = (table[0], sides, table[2], table[3])
            xb, vb_ = stb[0], stb[1]
            if i >= 0 and i < table[3]:
                break  # a boundary: the phase ends
            t_abs = t + tb
            if i >= 0:
                table, vb_ = crossed_sample(table, i, vb_)
            else:
                if tk >= horizon:
                    tb = horizon  # the run ends inside the phase
                    break
                tb = tk
                ck, t_abs = _tick(ck, tb, ts, t, s, fo.period)
                if tb <= ta:
                    continue  # the same time from another source
            dw = forced_piece_work(pc, wr, (sta, xa, va), (stb, xb, vb_), tb - ta, om * (t + ta) + phi)
            for q in range(N_WORK):
                w[q] += dw[q]
            fb = fex * math.cos(om * t_abs + phi) if fck != FC_CONST else 0.0
            if not emit(outs, k, t_abs, xb, vb_, friction_force(fck, force, xb, vb_, zeta) - fb, pc.fmode, w):
                return k, ne, FULL, -1.0, t + ta
            k += 1
            ta, xa, va, sta = tb, xb, vb_, stb
        dw = forced_piece_work(pc, wr, (sta, xa, va), (stb, xb, vb_), tb - ta, om * (t + ta) + phi)
        for q in range(N_WORK):
            w[q] += dw[q]
        which, T, ste, strobe = i, tb, stb, ck.strobe
        x, v = ste[0], ste[1]
        if which < 0:
            t = t_end
            continue
        t = t + T
        mode, v = _enter_forced(s, x, v, ste[4], ste[5], -om * om * ste[4], 8.0 * EPS * fex * (1.0 + abs(om * t + phi)))
        zero_len = zero_len + 1 if T <= 4.0 * EPS * (1.0 + t) else 0
        if zero_len > 8:
            return k, ne, STUCK, -1.0, t
        if ne < len(events.t):  # written here, not by record_switch: see the event table's comment
            events.t[ne], events.mode[ne], events.contact[ne] = t, mode, 0
        ne += 1
    return k, ne, DONE, -1.0, t_end
