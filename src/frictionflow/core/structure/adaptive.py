"""Adaptive Dormand-Prince 5(4) for structures with any switch-rule law: located switches, per-contact modes.

The state is y = (q, q', W): the coordinates, their rates and the cumulative
work of every channel (:mod:`.work`'s order).  In a combination of contact
modes a slipping contact j pushes along e_j with sigma_j F_slip,j(|V_r,j|) N_j(q)
(its law's compiled slip curve, :func:`frictionflow.core.friction.slip_magnitude_of`)
and a stuck one is the constraint e_j . q' = b_j, held exactly as the exact
engine holds it: the projected acceleration and the held forces of
:mod:`.stick`, given the slipping contacts' forces of the moment as the
constant force of a :data:`~.combo.Split` whose K_eff is K.  The projection
keeps e_j . q' constant, and a Runge-Kutta step keeps every linear invariant,
so a stuck contact stays on its belt to rounding.

Events (the exact engine's slots, :data:`~.combo.N_SLOTS` per contact):
sigma_j V_r,j of a slipping contact, F_s,j N_j -+ lambda_j of a stuck one and
N_j (contact lost).  Each is watched at the step ends (steps are at most
``h_max``, a fraction of the fastest period), and also inside a step where its
ends have one sign: a cubic from the ends' values and slopes (a held force's
slopes from a parabola through the step before) that dips near 0 has its
bottom searched on the dense output, so that two crossings within one step (a
grazing stick) are not missed.  The first crossing is located
on the dense output with the bracketed root finder (:mod:`..roots`); the
contacts' new modes come from the stick rule (:func:`.stick.decide`) with every
contact's slip level taken at its speed of the moment, so that a Coulomb
structure switches exactly as in the exact engine.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

from .. import codes, roots
from ..assembly import Assembly
from ..dopri import (A21, A31, A32, A41, A42, A43, A51, A52, A53, A54, A61, A62, A63, A64, A65, B1, B3, B4, B5, B6,
                     C2, C3, C4, C5, _error_each, dense)
from ..friction import slip_magnitude_of
from ..hermite import hermite_min
from ..layout import FD, FS, STICK
from .combo import N_SLOTS, Split, split
from .run import MAX_ZERO, Result, record_switches, starting_modes, switch_modes
from .stick import acceleration, decide, hold_velocity, held, normal_load
from .work import contact_powers, element_powers

#: the run's settings: ``atol`` one absolute tolerance per component of y = (q, q', W) (the structure's own
#: scales of positions, velocities and works times the solver's atol), ``time`` the structure's own time scale
#: (what a step or a phase too short to resolve is measured against)
Opts = namedtuple("Opts", "t_end rtol atol h_max dense_dt max_steps time")
#: scratch: the stages K (7, m), y, y_new, a stage's input, the dense output, the contacts' forces, the
#: event values at the step's start and end, where each slot was last seen positive (armed) and the
#: cumulative work at the last sample written (the samples keep each sample's share); the event values a step
#: before the step's start and that step's length (``hp[0]``, 0 at a phase's first step)
Scratch = namedtuple("Scratch", "K y yn tmp ys f g0 g1 armed w_last gp hp")
#: an event value this close to 0 (relative to its size over the step) at a located switch is reached too
SIMULTANEOUS = 1e-12
#: a watched slot's Hermite cubic over a step dipping below this share of its smaller end value: its bottom is
#: looked for on the dense output (the cubic only sketches it)
DIP_SHARE = 0.05
#: golden-section steps at most for a dip's bottom (theta to ~1e-9)
DIP_STEPS = 45
GOLDEN = 0.3819660112501051


@njit(cache=True)
def effective(asm, v):
    """``asm`` with each contact's F_d slot its slip level at its speed now: the stick rule then reads F(|V_r|)."""
    law = asm.law.copy()
    for j in range(len(asm.belt)):
        law[j, FD] = slip_magnitude_of(asm.law[j], abs(asm.belt[j] - asm.contact_dir[j] @ v))
    return Assembly(asm.mass, asm.stiffness, asm.damping, asm.contact_dir, asm.belt, law, asm.normal,
                    asm.force_dir, asm.force_amp, asm.force_omega, asm.force_phi, asm.spring_dir, asm.spring_k,
                    asm.damper_dir, asm.damper_c, asm.q0, asm.v0)


@njit(cache=True)
def frozen(asm, sp, q, v, f):
    """The :data:`Split` of ``sp``'s modes with the slipping contacts' forces now as its constant force.

    ``f`` gets each slipping contact's friction force sigma F(|V_r|) N (0 for the stuck ones).
    """
    n = len(q)
    f0 = np.zeros(n)
    for j in range(len(asm.belt)):
        f[j] = 0.0
        if sp.modes[j] == STICK:
            continue
        speed = abs(asm.belt[j] - asm.contact_dir[j] @ v)
        f[j] = sp.modes[j] * slip_magnitude_of(asm.law[j], speed) * normal_load(asm, j, q)
        for a in range(n):
            f0[a] += f[j] * asm.contact_dir[j, a]
    return Split(sp.modes, sp.stuck, sp.R, sp.HE, asm.stiffness, f0)


@njit(cache=True)
def rhs(asm, sp, t, y, n, out, f):
    """y' into ``out``: (q', q'', each channel's power); ``f`` gets every contact's friction force."""
    q, v = y[:n], y[n:2 * n]
    cb = frozen(asm, sp, q, v, f)
    a = acceleration(asm, cb, q, v, t)
    if len(sp.stuck):
        _, fr = held(asm, cb, q, v, t)
        for i in range(len(sp.stuck)):
            f[sp.stuck[i]] = fr[i]
    for i in range(n):
        out[i] = v[i]
        out[n + i] = a[i]
    powers = out[2 * n:]  # the work channels: the exact engine's powers (:mod:`.work`)
    c = element_powers((asm.spring_k, asm.spring_dir, asm.damper_c, asm.damper_dir),
                       (asm.force_amp, asm.force_omega, asm.force_phi, asm.force_dir), q, v, t, powers)
    contact_powers(asm.belt, asm.contact_dir, sp.modes, f, v, c, powers)


@njit(cache=True)
def events(asm, sp, t, y, n, g, f):
    """The event slots at (q, q', t) into ``g`` (+inf where a slot is not watched; ``f``: room)."""
    q, v = y[:n], y[n:2 * n]
    for j in range(len(asm.belt)):
        g[N_SLOTS * j] = g[N_SLOTS * j + 1] = g[N_SLOTS * j + 2] = np.inf
        if np.any(asm.normal[j, 1:] != 0.0):
            g[N_SLOTS * j + 2] = normal_load(asm, j, q)
        if sp.modes[j] != STICK:
            g[N_SLOTS * j] = sp.modes[j] * (asm.belt[j] - asm.contact_dir[j] @ v)
    if len(sp.stuck) == 0:
        return
    rule, _ = held(asm, frozen(asm, sp, q, v, f), q, v, t)
    for i in range(len(sp.stuck)):
        j = sp.stuck[i]
        lim = asm.law[j, FS] * normal_load(asm, j, q)
        g[N_SLOTS * j] = lim - rule[i]
        g[N_SLOTS * j + 1] = lim + rule[i]


@njit(cache=True)
def slot_at(asm, sp, t, h, scr, n, theta, e):
    """Event slot ``e`` on the dense output of the step (t, h) at ``theta`` (the state left in ``scr.ys``)."""
    return slots_at(asm, sp, t, h, scr, n, theta)[e]


@njit(cache=True, inline="always")
def slot_slopes(asm, sp, scr, n, h, e, mid):
    """(g'(0), g'(1)) per unit theta of slot ``e`` over the step: a slipping contact's V_r and a normal load from
    q'' and q' at the ends (K[0], K[6]); a stuck contact's held-force slots (whose rate the step does not give)
    from the parabola through the ends and the previous step's start, or at a phase's first step through the
    ends and ``mid``, every slot's value at theta = 1/2."""
    j, kind = e // N_SLOTS, e % N_SLOTS
    if kind == 0 and sp.modes[j] != STICK:  # -sigma e . q''
        return -sp.modes[j] * h * ends_dot(asm.contact_dir, j, 0, scr.K, n), \
            -sp.modes[j] * h * ends_dot(asm.contact_dir, j, 0, scr.K, n, 6)
    if kind == 2:  # n . q'
        return h * ends_dot(asm.normal, j, 1, scr.K, 0), h * ends_dot(asm.normal, j, 1, scr.K, 0, 6)
    g0, g1 = scr.g0[e], scr.g1[e]
    if scr.hp[0] > 0.0:  # g0 + (g1 - g0) x + c x (x - 1) through theta = -r as well
        r = scr.hp[0] / h
        c = (scr.gp[e] - g0 + (g1 - g0) * r) / (r * (r + 1.0))
        return g1 - g0 - c, g1 - g0 + c
    gm = mid[e]
    return -3.0 * g0 + 4.0 * gm - g1, g0 - 4.0 * gm + 3.0 * g1


@njit(cache=True, inline="always")
def ends_dot(rows, j, skip, K, first, stage=0):
    """rows[j, skip:] . K[stage, first:first + len]: a slot's rate from a stage's slope (loops: no array views in
    the step's hot path)."""
    acc = 0.0
    for a in range(rows.shape[1] - skip):
        acc += rows[j, skip + a] * K[stage, first + a]
    return acc


@njit(cache=True, inline="always")
def is_held(sp, e):
    """Whether slot ``e`` is a stuck contact's held-force slot."""
    return e % N_SLOTS < 2 and sp.modes[e // N_SLOTS] == STICK


@njit(cache=True, inline="always")  # per slot and step: no call taking the records (each of their arrays counted)
def suspect(asm, sp, h, scr, n, e, mid):
    """Whether slot ``e``, positive at both ends of the step, may dip to 0 inside it: two crossings within one step
    (V_r touching 0 and back at a grazing stick, a held force touching its limit) leave the ends' signs alike.
    The cubic from the ends' values and slopes (:func:`slot_slopes`) has an interior minimum below
    :data:`DIP_SHARE` of the smaller end."""
    g0, g1 = scr.g0[e], scr.g1[e]
    if not (np.isfinite(g0) and np.isfinite(g1)):
        return False
    m0, m1 = slot_slopes(asm, sp, scr, n, h, e, mid)
    if not m0 < 0.0 < m1:  # no interior minimum
        return False
    s, val = hermite_min(g0, g1, m0, m1)
    return s >= 0.0 and val < DIP_SHARE * min(g0, g1)


@njit(cache=True)
def golden_reach(asm, sp, t, h, scr, n, e, sigma, level):
    """(theta, g) of the first point found inside the step where slot ``e`` has sigma g <= ``level``, searching
    the minimum of sigma g on the dense output by golden section; (-1, 0) where it stays above."""
    a, b = 0.0, 1.0
    x1, x2 = a + GOLDEN * (b - a), b - GOLDEN * (b - a)
    f1, f2 = sigma * slot_at(asm, sp, t, h, scr, n, x1, e), sigma * slot_at(asm, sp, t, h, scr, n, x2, e)
    for _ in range(DIP_STEPS):
        if f1 <= level:
            return x1, sigma * f1
        if f2 <= level:
            return x2, sigma * f2
        if f1 < f2:
            b, x2, f2 = x2, x1, f1
            x1 = a + GOLDEN * (b - a)
            f1 = sigma * slot_at(asm, sp, t, h, scr, n, x1, e)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = b - GOLDEN * (b - a)
            f2 = sigma * slot_at(asm, sp, t, h, scr, n, x2, e)
    return -1.0, 0.0


@njit(cache=True)
def dip_bottom(asm, sp, t, h, scr, n, e):
    """(theta, g) of the first point found <= 0 of slot ``e`` inside the step, searching its minimum on the dense
    output by golden section (the first root lies before that point); (-1, 0) where the minimum stays > 0."""
    return golden_reach(asm, sp, t, h, scr, n, e, 1.0, 0.0)


@njit(cache=True)
def bump_top(asm, sp, t, h, scr, n, e):
    """(theta, g) of a point found > 0 of slot ``e`` inside the step, searching its maximum on the dense output by
    golden section: a contact that left V_r = 0 its way and came back within the step (-1, 0: it stayed <= 0
    beyond rounding, the contact left the wrong way)."""
    floor = SIMULTANEOUS * (abs(scr.g1[e]) + abs(asm.belt[e // N_SLOTS]))
    return golden_reach(asm, sp, t, h, scr, n, e, -1.0, -floor)


@njit(cache=True)
def slots_at(asm, sp, t, h, scr, n, theta):
    """Every event slot on the dense output of the step (t, h) at ``theta``."""
    dense(scr.y, scr.K, h, theta, scr.ys, 2 * n)
    g = np.empty(len(scr.g0))
    events(asm, sp, t + theta * h, scr.ys, n, g, scr.f)
    return g


@njit(cache=True)
def first_root(asm, sp, t, h, scr, n):
    """(theta, slot) of the step's first event (armed slots that ended <= 0, or dipped to 0 inside the step:
    :func:`suspect`, :func:`dip_bottom`), located on the dense output.

    A slot that never was positive since the phase began (a contact leaving V_r = 0) and ends <= 0 is
    located after its bump inside the step where it has one (the contact left its way and came back:
    :func:`bump_top`), else taken at the step's end (it left the wrong way); (1.0, -1) when no slot crossed.
    """
    best, slot, located = 1.0, -1, False  # located: ``slot``'s time is a root (not a step's end)
    mid = np.empty(0)  # every slot at theta = 1/2, taken once a held-force slot needs it
    for e in range(len(scr.g1)):
        lo, glo, hi, ghi = 0.0, scr.g0[e], 1.0, scr.g1[e]
        if not scr.armed[e] and ghi <= 0.0 and e % N_SLOTS == 0 and sp.modes[e // N_SLOTS] != STICK:
            lo, glo = bump_top(asm, sp, t, h, scr, n, e)
            if lo < 0.0:
                if slot < 0:
                    slot = e
                continue
        elif ghi > 0.0:
            if not (scr.armed[e] and scr.g0[e] > 0.0):
                continue
            held_slot = is_held(sp, e)
            if held_slot and scr.hp[0] == 0.0 and len(mid) == 0:
                mid = slots_at(asm, sp, t, h, scr, n, 0.5)
            if held_slot and len(mid) and mid[e] <= 0.0:
                hi, ghi = 0.5, mid[e]
            elif suspect(asm, sp, h, scr, n, e, mid):
                hi, ghi = dip_bottom(asm, sp, t, h, scr, n, e)
                if hi < 0.0:
                    continue
            else:
                continue
        elif not scr.armed[e]:
            if slot < 0:
                slot = e
            continue
        b = roots.bracket(lo, hi, glo, ghi, 0.0, 4.0 * roots.EPS, 0.0, 200)
        while b.status == roots.RUNNING:
            b = roots.update(b, b.x, slot_at(asm, sp, t, h, scr, n, b.x, e))
        if b.hi < best or not located:
            best, slot, located = min(b.hi, best), e, True
    return best, slot


@njit(cache=True)
def reached(scr, slot, gs):
    """The slots reached at the located event: ``slot`` and every armed one within rounding of 0 or past it."""
    out = np.zeros(len(gs), dtype=np.bool_)
    for e in range(len(gs)):
        size = abs(scr.g0[e]) + abs(scr.g1[e])
        out[e] = e == slot or (scr.armed[e] and np.isfinite(gs[e]) and gs[e] <= SIMULTANEOUS * size)
    return out


@njit(cache=True)
def stages(asm, sp, t, h, scr, n):
    """One Dormand-Prince step of size h from (t, scr.y), K[0] known: the stages and y_new (K[6] its slope)."""
    K, y, yn, tmp, f = scr.K, scr.y, scr.yn, scr.tmp, scr.f
    m = len(y)
    for i in range(m):
        tmp[i] = y[i] + h * A21 * K[0, i]
    rhs(asm, sp, t + C2 * h, tmp, n, K[1], f)
    for i in range(m):
        tmp[i] = y[i] + h * (A31 * K[0, i] + A32 * K[1, i])
    rhs(asm, sp, t + C3 * h, tmp, n, K[2], f)
    for i in range(m):
        tmp[i] = y[i] + h * (A41 * K[0, i] + A42 * K[1, i] + A43 * K[2, i])
    rhs(asm, sp, t + C4 * h, tmp, n, K[3], f)
    for i in range(m):
        tmp[i] = y[i] + h * (A51 * K[0, i] + A52 * K[1, i] + A53 * K[2, i] + A54 * K[3, i])
    rhs(asm, sp, t + C5 * h, tmp, n, K[4], f)
    for i in range(m):
        tmp[i] = y[i] + h * (A61 * K[0, i] + A62 * K[1, i] + A63 * K[2, i] + A64 * K[3, i] + A65 * K[4, i])
    rhs(asm, sp, t + h, tmp, n, K[5], f)
    for i in range(m):
        yn[i] = y[i] + h * (B1 * K[0, i] + B3 * K[2, i] + B4 * K[3, i] + B5 * K[4, i] + B6 * K[5, i])
    rhs(asm, sp, t + h, yn, n, K[6], f)


@njit(cache=True)
def emit(out, der, i, asm, sp, t, y, n, scr):
    """Write sample ``i`` of state y at t in the modes of ``sp`` into the :data:`~..records.Samples` ``out``
    and its slopes (both ways) into the :data:`~..records.Derivatives` ``der``; False when full."""
    if i >= len(out.t):
        return False
    rhs(asm, sp, t, y, n, scr.tmp, scr.f)
    out.t[i] = t
    for r in range(2 * n):
        out.y[r, i] = y[r]
    for r in range(n):
        der.accel[r, i] = der.accel[n + r, i] = scr.tmp[n + r]
    nw = out.work.shape[1]
    for r in range(nw):
        out.work[i, r] = y[2 * n + r] - scr.w_last[r]
        scr.w_last[r] = y[2 * n + r]
        der.power[r, i] = der.power[nw + r, i] = scr.tmp[2 * n + r]
    for j in range(len(scr.f)):
        out.fc[j, i] = scr.f[j]
        out.mode[j, i] = sp.modes[j]
    return True


@njit(cache=True)
def arrive(der, i, asm, sp, t, y, n, scr):
    """The acceleration and powers (modes of ``sp``) sample ``i + 1`` at (t, y) is reached with, kept on sample ``i``."""
    if 0 <= i < der.accel.shape[1]:
        rhs(asm, sp, t, y, n, scr.tmp, scr.f)
        for r in range(n):
            der.accel[n + r, i] = scr.tmp[n + r]
        nw = der.power.shape[0] // 2
        for r in range(nw):
            der.power[nw + r, i] = scr.tmp[2 * n + r]


@njit(cache=True)
def initial(asm, minv):
    """(modes, q', contact lost or -1) at t = 0: slipping by the sign of V_r, the stick rule where it is 0."""
    q, v = asm.q0.copy(), asm.v0.copy()
    modes, lost = starting_modes(asm, q, v)
    if lost >= 0:
        return modes, v, lost
    decide(effective(asm, v), minv, q, v, 0.0, modes, modes == STICK)
    return modes, hold_velocity(asm, split(asm, minv, modes), v), -1


@njit(cache=True)
def start_phase(asm, sp, t, scr, n, leaving):
    """K[0] and the event values at the phase's start; a slot is armed where it is > 0 (not a leaving contact's V_r)."""
    rhs(asm, sp, t, scr.y, n, scr.K[0], scr.f)
    events(asm, sp, t, scr.y, n, scr.g0, scr.f)
    scr.hp[0] = 0.0  # no step before this one in the phase
    for e in range(len(scr.g0)):
        scr.armed[e] = scr.g0[e] > 0.0 and not (e % N_SLOTS == 0 and leaving[e // N_SLOTS] and sp.modes[e // N_SLOTS] != STICK)


@njit(cache=True)
def dense_grid(out, der, i, asm, sp, t, h, theta, scr, n, grid):
    """Samples of the dense grid (``grid`` = (next time, dt)) inside the step's [t, t + theta h); (i, next, ok)."""
    nxt, dt = grid
    while dt > 0.0 and nxt < t + theta * h:
        dense(scr.y, scr.K, h, (nxt - t) / h, scr.ys, len(scr.y))
        arrive(der, i - 1, asm, sp, nxt, scr.ys, n, scr)
        if not emit(out, der, i, asm, sp, nxt, scr.ys, n, scr):
            return i, nxt, False
        i, nxt = i + 1, nxt + dt
    return i, nxt, True


@njit(cache=True)
def step_size(err, h):
    """The next step after an accepted (err <= 1) or a rejected one."""
    if err > 1.0:
        return h * max(0.2, 0.9 * err ** -0.2)
    return h * min(5.0, max(0.2, 0.9 * max(err, 1e-10) ** -0.2))


@njit(cache=True)
def one_step(asm, sp, t, h, scr, n, opts):
    """One accepted step from (t, scr.y), K[0] known: (h taken, next h, theta, slot, status, tries).

    y_new and its stages are left in ``scr``, the event values at its end in ``scr.g1``; theta is where in
    the step the phase ends at an event (``slot`` >= 0), else 1.
    """
    tries = 0
    while True:
        tries += 1
        left = opts.t_end - t
        h = min(h, opts.h_max, left)
        if h < 1e-14 * (opts.time + abs(t)) and h < left:  # (the run's last sliver is no collapse of the step)
            return h, h, 0.0, -1, codes.TINY_STEP, tries
        stages(asm, sp, t, h, scr, n)
        err = _error_each(h, scr.K, scr.y, scr.yn, opts.rtol, opts.atol)
        if not np.isfinite(err):
            return h, h, 0.0, -1, codes.NOT_FINITE, tries
        if err <= 1.0:
            break
        h = step_size(err, h)
    events(asm, sp, t + h, scr.yn, n, scr.g1, scr.f)
    theta, slot = first_root(asm, sp, t, h, scr, n)
    return h, step_size(err, h), theta, slot, codes.OK, tries


@njit(cache=True)
def after_step(scr, h):
    """Move to the end (FSAL) of the step of length ``h`` and arm every slot now positive."""
    for i in range(len(scr.y)):
        scr.y[i] = scr.yn[i]
        scr.K[0, i] = scr.K[6, i]
    scr.hp[0] = h
    for e in range(len(scr.g0)):
        scr.gp[e] = scr.g0[e]
        scr.g0[e] = scr.g1[e]
        scr.armed[e] = scr.armed[e] or scr.g1[e] > 0.0


@njit(cache=True)
def scratch(asm, n, nw):
    """The run's :data:`Scratch` for ``n`` coordinates and ``nw`` work channels (a state of 2n + nw)."""
    k, m = len(asm.belt), 2 * n + nw
    return Scratch(np.zeros((7, m)), np.zeros(m), np.zeros(m), np.zeros(m), np.zeros(m), np.zeros(k),
                   np.zeros(N_SLOTS * k), np.zeros(N_SLOTS * k), np.zeros(N_SLOTS * k, dtype=np.bool_), np.zeros(nw),
                   np.zeros(N_SLOTS * k), np.zeros(1))


@njit(cache=True)
def switch(asm, minv, sp, te, scr, n, slot):
    """The located event at ``te`` (its state in ``scr.ys``): (new modes, leaving, lost contact or -1).

    The state after it goes to ``scr.y``: each newly stuck contact held on its belt.
    """
    gs = np.empty(len(scr.g0))
    events(asm, sp, te, scr.ys, n, gs, scr.f)
    new, leaving, lost = switch_modes(asm, sp.modes, reached(scr, slot, gs))
    if lost >= 0:
        return new, leaving, lost
    q, v = scr.ys[:n].copy(), scr.ys[n:2 * n].copy()
    decide(effective(asm, v), minv, q, v, te, new, leaving)
    v = hold_velocity(asm, split(asm, minv, new), v)
    for i in range(len(scr.y)):
        scr.y[i] = scr.ys[i]
    for i in range(n):
        scr.y[n + i] = v[i]
    return new, leaving, -1


@njit(cache=True, nogil=True)  # a model sweep runs several points at once on threads
def run(asm, minv, opts, out, events, der):
    """Integrate the structure ``asm`` from t = 0 to ``opts.t_end``; the :data:`~.run.Result`.

    The samples go to ``out`` (:data:`~..records.Samples`: y = (q, q'), a work column per channel), their
    slopes to ``der`` (:data:`~..records.Derivatives`), the switches to ``events``
    (:data:`~..records.Events`), as the exact engine (:func:`.run.run`) writes them.
    """
    n, k = len(asm.q0), len(asm.belt)
    scr = scratch(asm, n, out.work.shape[1])
    modes, v, lost = initial(asm, minv)
    sp = split(asm, minv, modes)
    for i in range(n):
        scr.y[i], scr.y[n + i] = asm.q0[i], v[i]
    if not emit(out, der, np.int64(0), asm, sp, 0.0, scr.y, n, scr):  # a literal 0 would compile emit once more
        return Result(codes.FULL, 0, 0, -1, np.nan)
    if lost >= 0:
        return Result(codes.CONTACT_LOST, 1, 0, lost, 0.0)
    leaving = np.zeros(k, dtype=np.bool_)
    for j in range(k):
        leaving[j] = modes[j] != STICK and asm.belt[j] - asm.contact_dir[j] @ v == 0.0
    t, h, i, nsw, zeros, steps = 0.0, 0.01 * opts.h_max, np.int64(1), np.int64(0), 0, 0  # (literals: callees twice)
    grid, floor = (opts.dense_dt, opts.dense_dt), 1e-13 * max(opts.time, opts.t_end)
    start_phase(asm, sp, t, scr, n, leaving)
    while True:
        hs, h, theta, slot, status, tries = one_step(asm, sp, t, h, scr, n, opts)
        steps += tries
        if status == codes.OK and steps > opts.max_steps:
            status = codes.STEP_CAP
        if status != codes.OK:
            return Result(status, i, nsw, -1, np.nan)
        i, nxt, ok = dense_grid(out, der, i, asm, sp, t, hs, theta, scr, n, grid)
        grid = (nxt, opts.dense_dt)
        if not ok:
            return Result(codes.FULL, i, nsw, -1, np.nan)
        if slot < 0:
            t = opts.t_end if t + hs >= opts.t_end else t + hs
            arrive(der, i - 1, asm, sp, t, scr.yn, n, scr)
            if not emit(out, der, i, asm, sp, t, scr.yn, n, scr):
                return Result(codes.FULL, i, nsw, -1, np.nan)
            i += 1
            if t >= opts.t_end:
                return Result(codes.OK, i, nsw, -1, np.nan)
            after_step(scr, hs)
            continue
        dense(scr.y, scr.K, hs, theta, scr.ys, len(scr.y))
        te = t + theta * hs
        arrive(der, i - 1, asm, sp, te, scr.ys, n, scr)
        new, leaving, lost = switch(asm, minv, sp, te, scr, n, slot)
        if lost >= 0:
            ok = emit(out, der, i, asm, sp, te, scr.ys, n, scr)
            return Result(codes.CONTACT_LOST if ok else codes.FULL, i + 1, nsw, lost, te)
        nsw = record_switches(events, nsw, te, sp.modes, new)
        sp = split(asm, minv, new)
        zeros = zeros + 1 if theta * hs <= floor else 0
        if zeros > MAX_ZERO + k:
            return Result(codes.STUCK, i, nsw, -1, np.nan)
        if not emit(out, der, i, asm, sp, te, scr.y, n, scr):
            return Result(codes.FULL, i, nsw, -1, np.nan)
        i, t, h = i + 1, te, hs
        if t >= opts.t_end:  # a switch at the end: nothing is left to run
            return Result(codes.OK, i, nsw, -1, np.nan)
        start_phase(asm, sp, t, scr, n, leaving)
