"""The run loop: phase after phase, each to its first certified event, the stick rule at every event.

Samples are written at the start, at every switch (after the new modes are
decided, with the state made to satisfy the stuck contacts' constraints
exactly), on an optional dense grid and at the end, into the shared records
(:mod:`..records`): ``Samples`` (y = (q, q'), a row per contact, the work of
every channel (:mod:`.work`) since the previous sample) and ``Events`` (each
switch: time, mode entered, contact).  A normal load reaching 0
ends the run with :data:`~frictionflow.core.codes.CONTACT_LOST`.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

from .. import codes
from ..layout import STICK
from .combo import N_SLOTS, build, build_from, find, keep, lookup, new_cache, same_modes
from .events import EPS, ROUNDING, Room, new_room as new_walk_room, values, walk
from ..options import NO_RUNTIME
from .phase import (Mags, abs_into, longest, modal_into, size_of, start, start_in, start_room, state_at,
                    state_fill)
from .stick import decide_in, friction_forces_into, hold_velocity_into, new_room, normal_load
from .work import accumulate, integrate, new_room as new_work_room

#: what a run ends with: status, samples written, switches counted, the lost contact and when (-1, nan)
Result = namedtuple("Result", "status n_samples n_switches lost_contact lost_time")
#: a function within this fraction of its size of 0 at an event counts as reached too (simultaneous switches)
SIMULTANEOUS = 1e-13
#: zero-length phases in a row before the run gives up (STUCK)
MAX_ZERO = 8


#: the run's room, made once (:func:`scratch`): the state (q, q'), the modes an event leads to, the contacts leaving
#: V_r = 0, the slots reached, z(tau) (2n: a phase's length is a view), the walk's :data:`~.events.Room` (full
#: length), the work quadrature's (:func:`.work.accumulate`), the stick rule's (:data:`.stick.Room`) and the phase
#: start's (:data:`.phase.StartRoom`)
Scratch = namedtuple("Scratch", "q v new leaving hit z walk work rule start")


@njit(cache=True)
def scratch(asm, n_work):
    """The run's :data:`Scratch` (``n_work``: the work channels)."""
    n, k, nf = len(asm.q0), len(asm.belt), len(asm.force_amp)
    ns, m = N_SLOTS * k, 2 * n
    work_room = new_work_room(n_work, k, m, n)
    return Scratch(asm.q0.copy(), asm.v0.copy(), np.zeros(k, dtype=np.int8), np.zeros(k, dtype=np.bool_),
                   np.zeros(ns, dtype=np.bool_), np.zeros(m, dtype=np.complex128),
                   new_walk_room(m, ns, nf, np.zeros(ns, dtype=np.bool_)), work_room, new_room(n, k),
                   start_room(n, k, nf))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def emit(out, i, asm, cb, q, v, t, acc, room):
    """Write sample ``i`` into the :data:`~..records.Samples` ``out``; False when they are full.

    ``acc`` holds the work since the previous sample; it is written and restarts from zero (``room``: a
    :data:`.stick.Room`).
    """
    if i >= len(out.t):
        return False
    n = len(q)
    out.t[i] = t
    for a in range(n):
        out.y[a, i], out.y[n + a, i] = q[a], v[a]
    friction_forces_into(asm, cb, q, v, t, out.fc[:, i], room)
    for j in range(len(cb.modes)):
        out.mode[j, i] = cb.modes[j]
    for c in range(len(acc)):
        out.work[i, c], acc[c] = acc[c], 0.0
    return True


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def next_event(cb, ph, om, span, floor, leaving, room):
    """(tau, slot): the phase's first event in (0, ``span``] (:func:`.events.walk` in ``room``, views of the phase's
    length); slot -1: none."""
    for e in range(len(room.dep)):
        room.dep[e] = False
    for j in range(len(leaving)):  # a contact that left V_r = 0 and slips: its V_r starts from 0
        room.dep[N_SLOTS * j] = leaving[j] and cb.modes[j] != STICK
    tau, slot, _ = walk(cb, ph, om, span, longest(cb.lam, om, 0.0, span), floor, room)
    return tau, slot


@njit(cache=True, inline="always")
def phase_room(walk_room, m):
    """The walk's :data:`~.events.Room` for a phase of ``m`` modal coordinates: views of the run's."""
    w, g = walk_room, walk_room.mg
    return Room(w.za[:m], w.zb[:m], w.ga, w.gb, w.dz[:m], w.clear, w.dep, w.zr[:m],
                Mags(g.z[:m], g.b0[:m], g.b1[:m], g.bh[:m], g.lam[:m], g.w[:m], g.u[:m]), w.open, w.dzc[:m])


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def mark_reached(cb, ph, om, tau, slot, room, out):
    """Mark in ``out`` the event slots reached at ``tau``: the located one and any other within rounding of 0 or
    past it (``room``: the phase's walk room, free after the walk: z(tau), |z(tau)| and the functions there)."""
    z, g, az = room.zb, room.gb, room.mg.z
    modal_into(cb, ph, om, tau, z)
    values(cb, ph, om, tau, z, g)
    abs_into(z, az)
    for e in range(len(g)):
        if cb.active[e]:
            out[e] = e == slot or g[e] <= SIMULTANEOUS * size_of(cb, ph, e, tau, az)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def finish(asm, cb, ph, om, ta, tb, acc, scr):
    """Add the work over [ta, tb] of the phase (local times) to ``acc``; (q, q') at ``tb`` into ``scr.q``, ``scr.v``."""
    if tb - ta > 0.0:
        accumulate(asm, cb, ph, om, ta, tb, acc, scr.work)
    state_fill(cb, ph, om, tb, scr.z, scr.q, scr.v)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def switch_into(cb, ph, om, tau, slot, scr, room):
    """:func:`switch_modes` of the slots reached at ``tau`` into ``scr.new``, ``scr.leaving``; the contact whose load
    is lost or -1 (``room``: the phase's walk room, free after the walk)."""
    hit, g = scr.hit, room.gb
    for e in range(len(hit)):
        hit[e], g[e] = False, ph.e0[e]
    mark_reached(cb, ph, om, tau, slot, room, hit)
    return modes_into(cb.modes, hit, scr.new, scr.leaving)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def modes_into(modes, hit, new, leaving):
    """:func:`switch_modes` into ``new`` and ``leaving``; the contact whose load is lost or -1."""
    for j in range(len(modes)):
        new[j], leaving[j] = modes[j], False
    for e in range(len(hit)):
        if not hit[e]:
            continue
        j, kind = e // N_SLOTS, e % N_SLOTS
        if kind == 2:
            return j
        leaving[j] = True
        if modes[j] == STICK:
            new[j] = 1 if kind == 0 else -1  # F_s N - lambda = 0: lambda = +F_s N
        else:
            new[j] = STICK
    return -1


@njit(cache=True)
def switch_modes(asm, modes, hit):
    """(new modes before the stick rule, the contacts leaving V_r = 0, the contact whose load is lost or -1)."""
    k = len(modes)
    new, leaving = np.empty(k, dtype=np.int8), np.empty(k, dtype=np.bool_)
    lost = modes_into(modes, hit, new, leaving)
    return new, leaving, lost


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def record_switches(events, nsw, t, old, new):
    """Count (and write into the :data:`~..records.Events` while there is room) each contact whose mode changed;
    the new count."""
    for j in range(len(old)):
        if old[j] != new[j]:
            if nsw < len(events.t):
                events.t[nsw], events.mode[nsw], events.contact[nsw] = t, new[j], j
            nsw += 1
    return nsw


@njit(cache=True)
def starting_modes(asm, q, v):
    """(modes, contact lost or -1) at the start, before the stick rule: slipping by the sign of V_r, 0 where
    it is 0 to the rounding of its terms (every engine starts so).

    V_r = belt - e . q' of a start meant to stick is rarely 0 in binary
    (3 x -0.1 is not -0.3): within ROUNDING EPS of its terms' size it is
    taken as 0 and the stick rule decides, as it would have for the exact
    decimals; the run then holds the stuck contacts' velocities on their belts.
    """
    k = len(asm.belt)
    modes = np.zeros(k, dtype=np.int8)
    for j in range(k):
        if normal_load(asm, j, q) <= 0.0:
            return modes, j
        e = asm.contact_dir[j]
        vr = asm.belt[j] - e @ v
        size = abs(asm.belt[j]) + np.abs(e) @ np.abs(v)
        modes[j] = 0 if abs(vr) <= ROUNDING * EPS * size else (1 if vr > 0.0 else -1)
    return modes, -1


@njit(cache=True)
def initial(asm, minv, cache, scr):
    """(modes, contact lost or -1) at t = 0: slipping by the sign of V_r, the stick rule where it is 0 (the run then
    holds the stuck contacts' velocities)."""
    q, v = scr.q, scr.v
    modes, lost = starting_modes(asm, q, v)
    if lost >= 0:
        return modes, lost
    decide_in(asm, minv, q, v, 0.0, modes, modes == STICK, cache, scr.rule, True)
    return modes, -1


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def dense_samples(out, i, asm, cb, ph, om, tau, tau_last, next_t, dense_dt, acc, scr):
    """Emit the dense grid's points before ``tau``; (samples written, local time reached, next grid time, ok)."""
    while dense_dt > 0.0 and next_t < ph.t0 + tau:
        tl = next_t - ph.t0
        finish(asm, cb, ph, om, tau_last, tl, acc, scr)
        if not emit(out, i, asm, cb, scr.q, scr.v, next_t, acc, scr.rule):
            return i, tl, next_t, False
        i, tau_last, next_t = i + 1, tl, next_t + dense_dt
    return i, tau_last, next_t, True


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the phase's records are views of the run's rooms
def to_event(asm, cb, t, span, floor, dense_dt, next_t, out, i, acc, scr):
    """One phase of ``cb`` from (``scr.q``, ``scr.v``) at ``t`` to its first event in (0, ``span``]
    (:func:`next_event`): the dense grid's samples before it (from ``next_t``), its work into ``acc``, (q, q') there
    into ``scr.q``, ``scr.v`` and, at an event, the modes it leads to into ``scr.new``, ``scr.leaving``
    (:func:`switch_into`).

    Returns (tau, slot or -1 at ``span``, the contact whose load is lost or -1, samples written, next grid time, ok:
    False when the samples are full).  The run's whole per-phase work in one kernel without numba's runtime: the
    records it makes and reads cost no reference counts here.  (Its steps are compiled apart on purpose: inlined
    here, the walk and the work quadrature compile about twice as long.)
    """
    om = asm.force_omega
    ph = start_in(cb, asm, scr.q, scr.v, t, scr.start)
    room = phase_room(scr.walk, len(cb.lam))
    tau, slot = next_event(cb, ph, om, span, floor, scr.leaving, room)
    tau_last, ok = 0.0, True
    if dense_dt > 0.0:
        i, tau_last, next_t, ok = dense_samples(out, i, asm, cb, ph, om, tau, 0.0, next_t, dense_dt, acc, scr)
    if not ok:
        return tau, slot, -1, i, next_t, False
    finish(asm, cb, ph, om, tau_last, tau, acc, scr)
    lost = switch_into(cb, ph, om, tau, slot, scr, room) if slot >= 0 else -1
    return tau, slot, lost, i, next_t, True


@njit(cache=True, nogil=True)  # a model sweep runs several points at once on threads
def run(asm, minv, t_end, dense_dt, out, events):
    """Integrate the structure ``asm`` from t = 0 to ``t_end`` into the records ``out`` (:data:`~..records.Samples`)
    and ``events`` (:data:`~..records.Events`); the :data:`Result`."""
    k = len(asm.belt)
    cache = new_cache(asm, minv)
    acc = np.zeros(out.work.shape[1])
    scr = scratch(asm, len(acc))
    q, v, new, leaving, sr = scr.q, scr.v, scr.new, scr.leaving, scr.rule
    modes, lost = initial(asm, minv, cache, scr)
    t = 0.0
    cb = lookup(cache, asm, minv, modes if lost < 0 else np.zeros(k, dtype=np.int8))
    if lost < 0:
        hold_velocity_into(asm, cb, v, sr.rule)
    if not emit(out, np.int64(0), asm, cb, q, v, t, acc, sr):  # (a literal 0 would compile emit twice)
        return Result(codes.FULL, 0, 0, -1, np.nan)
    if lost >= 0:
        return Result(codes.CONTACT_LOST, 1, 0, lost, 0.0)
    i, nsw, zeros, next_t = np.int64(1), np.int64(0), 0, dense_dt  # (literals: to_event, record_switches twice)
    floor = 1e-13 * t_end  # (an absolute floor of 1e-13 took a femtosecond structure's phases for no time at all)
    while True:
        tau, slot, lost, i, next_t, ok = to_event(asm, cb, t, t_end - t, floor, dense_dt, next_t, out, i, acc, scr)
        if not ok:
            return Result(codes.FULL, i, nsw, -1, np.nan)
        t = t_end if slot < 0 else t + tau
        if slot < 0:
            if not emit(out, i, asm, cb, q, v, t, acc, sr):
                return Result(codes.FULL, i, nsw, -1, np.nan)
            return Result(codes.OK, i + 1, nsw, -1, np.nan)
        if lost >= 0:
            ok = emit(out, i, asm, cb, q, v, t, acc, sr)
            return Result(codes.CONTACT_LOST if ok else codes.FULL, i + 1, nsw, lost, t)
        sp = decide_in(asm, minv, q, v, t, new, leaving, cache, sr, True)
        nsw = record_switches(events, nsw, t, cb.modes, new)
        j = find(cache.keys, cache.used, new)  # met before: no call taking the records (each of their arrays counted)
        if j >= 0:
            cb = cache.combos[j]
        elif same_modes(sp.modes, new):  # new: built from the stick rule's split
            cb = keep(cache, build_from(asm, minv, sp, cache.eigs))
        else:
            cb = lookup(cache, asm, minv, new)
        hold_velocity_into(asm, cb, v, sr.rule)
        zeros = zeros + 1 if tau <= floor else 0
        if zeros > MAX_ZERO + k:
            return Result(codes.STUCK, i, nsw, -1, np.nan)
        if not emit(out, i, asm, cb, q, v, t, acc, sr):
            return Result(codes.FULL, i, nsw, -1, np.nan)
        i += 1


@njit(cache=True)
def advance(asm, minv, modes, q, v, t0, tau, n_work):
    """(q, q', work over the stretch) ``tau`` after (q, q') at ``t0`` in the modes ``modes`` (no switch between)."""
    cb = build(asm, minv, modes)
    ph = start(cb, asm, q, v, t0)
    acc = np.zeros(n_work)
    integrate(asm, cb, ph, asm.force_omega, 0.0, tau, acc)
    q1, v1 = state_at(cb, ph, asm.force_omega, tau)
    return q1, v1, acc
