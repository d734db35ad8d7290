"""Held forces and the stick rule of every contact, with the whole structure's constraint forces.

Stuck contacts S hold lambda_S = G E_S M^-1 (C q' + K_eff q - f0 - forces(t))
(:mod:`.combo`); a contact with ``stick_force`` "spring" compares the same
expression without the dampers' term with F_s N_j.  The rule per contact is
the single mass's, stated once in :func:`frictionflow.core.friction.holds`
(with its tolerance): a contact keeps sticking while its held force is within
F_s N_j; otherwise it slips in the direction of its held force, provided
that direction makes V_r leave 0 on the right side (else the other one; if
neither, it sticks).  Several contacts at once: an active-set loop releases
the contact most over its limit and computes the others' held forces again,
until every stuck contact holds.  A flip or a stick of the direction check
moves the others' held forces and directions: the modes it ends with are
checked, and where they do not hold, the modes that do and change the fewest
contacts are searched among the contacts at V_r = 0
(:func:`nearest_consistent`).

A held force within ``ON_LIMIT`` of F_s N_j is on the limit: then its rate
decides (:func:`held_rates`, lambda_S' from the combination's matrices and
q'' of the candidate stuck set, relative to the limit's own rate F_s n_j . q'),
as for the single mass; it is computed only then.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ..friction import ON_LIMIT, holds, limit_ratio
from ..layout import FD, FS, RESULTANT, STICK
from ..products import matvec
from ..options import NO_RUNTIME
from .combo import Split, contacts_of, slip_into, split

#: a relative rate this close to 0 counts as 0
RATE_TOL = 1e-12
#: contacts at V_r = 0 beyond which no consistent modes are searched (3^n candidates)
SEARCH_MAX = 6


#: the stick rule's room, made once per run (:func:`new_room`): the forces on the structure, a product, the forces'
#: rate and q'' (n each); per stuck contact its held force as its rule reads it, its friction force, the "spring"
#: rule's rate and the rates (k each: the first entries, one per stuck contact)
Room = namedtuple("Room", "f tmp d acc rule fr spring rates")


@njit(cache=True)
def new_room(n, k):
    """A :data:`Room` for ``n`` coordinates and ``k`` contacts."""
    return Room(np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(k), np.empty(k), np.empty(k),
                np.empty(k))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def rest_into(asm, cb, q, v, t, damped, f, tmp):
    """:func:`rest` into ``f`` (``tmp``: room for a product)."""
    matvec(cb.keff, q, tmp)
    for a in range(len(f)):
        f[a] = cb.f0[a] - tmp[a]
    if damped:
        matvec(asm.damping, v, tmp)
        for a in range(len(f)):
            f[a] -= tmp[a]
    for i in range(len(asm.force_amp)):
        c = asm.force_amp[i] * math.cos(asm.force_omega[i] * t + asm.force_phi[i])
        for a in range(len(f)):
            f[a] += asm.force_dir[i, a] * c


@njit(cache=True)
def rest(asm, cb, q, v, t, damped):
    """All forces on the structure but the stuck contacts' (``damped``: with the dampers' term)."""
    f = np.empty(len(q))
    rest_into(asm, cb, q, v, t, damped, f, np.empty(len(q)))
    return f


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def held_into(asm, cb, q, v, t, room):
    """:func:`held` into the first entries of ``room.rule`` and ``room.fr`` (``room``: a :data:`Room`)."""
    ns = len(cb.stuck)
    rule, fr = room.rule[:ns], room.fr[:ns]
    rest_into(asm, cb, q, v, t, np.bool_(True), room.f, room.tmp)
    matvec(cb.HE, room.f, fr)
    spring = False  # the spring rule's force only where some stuck contact reads it
    for i in range(ns):
        fr[i] = -fr[i]
        spring = spring or asm.law[cb.stuck[i], RESULTANT] == 0.0
    if spring:
        rest_into(asm, cb, q, v, t, np.bool_(False), room.f, room.tmp)
        matvec(cb.HE, room.f, rule)
    for i in range(ns):
        rule[i] = -rule[i] if spring and asm.law[cb.stuck[i], RESULTANT] == 0.0 else fr[i]


@njit(cache=True)
def held(asm, cb, q, v, t):
    """(rule, friction): each stuck contact's held force as its stick rule reads it, and its friction force."""
    room = new_room(len(q), len(cb.stuck))
    held_into(asm, cb, q, v, t, room)
    return room.rule, room.fr


@njit(cache=True, inline="always")
def normal_load(asm, j, q):
    """N_j = P_j + n_j . q."""
    return asm.normal[j, 0] + asm.normal[j, 1:] @ q


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def friction_forces_into(asm, cb, q, v, t, out, room):
    """The friction force of every contact on the structure into ``out``: +-F_d N_j slipping, the held force stuck
    (``room``: a :data:`Room`)."""
    if len(cb.stuck):
        held_into(asm, cb, q, v, t, room)
        for i in range(len(cb.stuck)):
            out[cb.stuck[i]] = room.fr[i]
    for j in range(len(cb.modes)):
        if cb.modes[j] != STICK:
            out[j] = cb.modes[j] * asm.law[j, FD] * normal_load(asm, j, q)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def constrained(asm, cb, a0):
    """``a0`` (M^-1 times the forces) less its part along the stuck directions, in place: q'' in ``cb``."""
    for i in range(len(cb.stuck)):
        s = asm.contact_dir[cb.stuck[i]] @ a0
        for a in range(len(a0)):
            a0[a] -= cb.R[a, i] * s


@njit(cache=True)
def acceleration(asm, cb, q, v, t):
    """q'' in the combination ``cb``: M^-1 rest minus its part along the stuck directions."""
    a0 = np.linalg.solve(asm.mass, rest(asm, cb, q, v, t, True))
    constrained(asm, cb, a0)
    return a0


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def acceleration_into(asm, cb, minv, q, v, t, room):
    """:func:`acceleration` into ``room.acc`` with M^-1 given (``minv``): a product instead of a solve."""
    rest_into(asm, cb, q, v, t, np.bool_(True), room.f, room.tmp)
    matvec(minv, room.f, room.acc)
    constrained(asm, cb, room.acc)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def held_rates(asm, cb, minv, q, v, t, room):
    """d/dt of each stuck contact's held force as its stick rule reads it (:func:`held`), with q'' of ``cb``,
    into the first entries of ``room.rates`` (``room``: a :data:`Room`).

    lambda_S = G E_S M^-1 (C q' + K_eff q - f0 - forces(t)) with G E_S M^-1
    and K_eff constant in the combination: lambda_S' = G E_S M^-1 (C q'' +
    K_eff q' - forces'(t)); the "spring" rule leaves C q'' out.
    """
    ns = len(cb.stuck)
    d, spring, rate = room.d, room.spring[:ns], room.rates[:ns]
    matvec(cb.keff, v, d)
    for i in range(len(asm.force_amp)):
        w = asm.force_omega[i] * t + asm.force_phi[i]
        c = asm.force_amp[i] * asm.force_omega[i] * math.sin(w)
        for a in range(len(d)):
            d[a] += asm.force_dir[i, a] * c
    matvec(cb.HE, d, spring)
    acceleration_into(asm, cb, minv, q, v, t, room)
    matvec(asm.damping, room.acc, room.tmp)
    for a in range(len(d)):
        room.f[a] = d[a] + room.tmp[a]
    matvec(cb.HE, room.f, rate)
    for i in range(ns):
        if asm.law[cb.stuck[i], RESULTANT] == 0.0:
            rate[i] = spring[i]


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def cached(keys, used, modes):
    """(i, same modes): the row of ``keys`` (a :data:`~.combo.Cache`'s, the first ``used[0]``) with the stuck set of
    ``modes``, the one of the same modes first (-1: none).  Entries compared in place: a row taken as a view would
    be reference-counted at every row of the scan."""
    found = -1
    for i in range(used[0]):
        stuck_same, modes_same = True, True
        for j in range(len(modes)):
            if (keys[i, j] == STICK) != (modes[j] == STICK):
                stuck_same = False
                break
            modes_same = modes_same and keys[i, j] == modes[j]
        if stuck_same and modes_same:
            return i, True
        if stuck_same and found < 0:
            found = i
    return found, False


@njit(cache=True)
def candidate(ct, minv, modes, cache):
    """The :data:`~.combo.Split` of ``modes``: from a combination of the run's :data:`~.combo.Cache` ``cache`` (or
    None) with the same stuck set when there is one (its R and HE are the split's numbers, and its K_eff and f0
    with the same modes), else made (:func:`~.combo.split`; ``ct``: the :data:`~.combo.Contacts`)."""
    if cache is not None:
        i, same_modes = cached(cache.keys, cache.used, modes)
        if i >= 0:
            cb = cache.splits[i]
            if same_modes:
                return cb
            keff, f0 = ct.stiffness.copy(), np.zeros(minv.shape[0])
            slip_into(ct, modes, keff, f0)
            return Split(modes.copy(), cb.stuck, cb.R, cb.HE, keff, f0)
    return split(ct, minv, modes)


@njit(cache=True)
def release_over_limit(asm, minv, q, v, t, modes, released):
    """The active-set loop: release the stuck contact most over F_s N_j until none is (``released`` marks them).

    Returns the :data:`Split` of the modes it ends with (:func:`decide_in`).
    """
    return decide_in(asm, minv, q, v, t, modes, released, None, new_room(len(q), len(modes)), np.bool_(False))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def released_one(asm, cb, minv, q, v, t, modes, released, room):
    """One pass of the active-set loop (:func:`decide_in`) with the :data:`Split` ``cb`` of ``modes``: the stuck
    contact most over F_s N_j released in ``modes`` (slipping along its held force) and marked in ``released``;
    whether there was one."""
    worst = most_over(asm, cb, minv, q, v, t, room)
    if worst < 0:
        return False
    j = cb.stuck[worst]
    modes[j] = 1 if room.rule[worst] > 0.0 else -1
    released[j] = True
    return True


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def most_over(asm, cb, minv, q, v, t, room):
    """The stuck contact (its index in ``cb.stuck``) most over F_s N_j, -1 when each holds; its held forces stay in
    ``room.rule``."""
    held_into(asm, cb, q, v, t, room)
    rule, rates = room.rule, room.rates
    worst, wr, have_rates = -1, -1.0, False
    for i in range(len(cb.stuck)):
        j = cb.stuck[i]
        lim = asm.law[j, FS] * normal_load(asm, j, q)
        rate = 0.0
        if lim > 0.0 and abs(rule[i]) >= lim * (1.0 - ON_LIMIT):  # on the limit: its rate decides
            if not have_rates:
                held_rates(asm, cb, minv, q, v, t, room)
                have_rates = True
            # relative to the limit F_s N_j(q), which moves at F_s n_j . q'
            rate = rates[i] - math.copysign(asm.law[j, FS] * (asm.normal[j, 1:] @ v), rule[i])
        if holds(rule[i], lim, rate):
            continue
        ratio = limit_ratio(rule[i], lim)
        if ratio >= wr:
            worst, wr = i, ratio
    return worst


@njit(cache=True, inline="always")
def abs_max(a):
    """max |a_i| over a vector's entries (no temporary array)."""
    m = 0.0
    for i in range(len(a)):
        m = max(m, abs(a[i]))
    return m


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def any_slipping(modes, leaving):
    """Some contact leaving V_r = 0 slips."""
    for j in range(len(modes)):
        if leaving[j] and modes[j] != STICK:
            return True
    return False


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def flip(asm, cb, minv, q, v, t, modes, leaving, attempt, room):
    """One pass of :func:`decide_in`'s direction check with q'' of ``cb``: flip (``attempt`` 0) or stick (1) each
    contact leaving V_r = 0 the wrong way; whether one was."""
    tol = acceleration_and_tol(asm, cb, minv, (q, v, t), room)
    changed = False
    for j in range(len(modes)):
        if leaving[j] and wrong_way(asm, room.acc, j, modes[j], tol):
            modes[j] = -modes[j] if attempt == 0 else STICK
            changed = True
    return changed


@njit(cache=True, inline="always")
def acceleration_and_tol(asm, cb, minv, state, room):
    """q'' of ``cb`` at ``state`` = (q, q', t) into ``room.acc``, and the tolerance below which a contact's V_r' counts
    as 0 (:data:`RATE_TOL` of q'' and of M^-1 f0's size)."""
    q, v, t = state
    acceleration_into(asm, cb, minv, q, v, t, room)
    mi = 0.0
    for a in range(minv.shape[0]):
        mi = max(mi, abs_max(minv[a]))
    return RATE_TOL * (abs_max(room.acc) + mi * abs_max(cb.f0) + 1e-300)


@njit(cache=True, inline="always")
def wrong_way(asm, acc, j, mode, tol):
    """Contact ``j`` slipping in ``mode`` with q'' ``acc`` drives V_r back towards 0 (beyond ``tol``)."""
    return mode != STICK and -mode * (asm.contact_dir[j] @ acc) < -tol


@njit(cache=True)
def decide_in(asm, minv, q, v, t, modes, leaving, cache, room, directions):
    """:func:`decide` with the run's :data:`~.combo.Cache` ``cache`` (or None: every split made) and a :data:`Room`;
    the active-set loop alone (:func:`release_over_limit`) when not ``directions``.  Returns the :data:`Split` of the
    modes the loop ends with; when it ran out first, the split of the modes it reached (never None: a split that may
    be None would compile every function it is passed to once more).  The directions may change the modes after it:
    a caller compares its modes with theirs.

    After that loop each contact leaving V_r = 0 must see sigma V_r' >= 0: flip it once, then stick it (then the
    modes are checked: :func:`nearest_consistent`).  Both loops
    are written here and run their passes in kernels without numba's runtime: each call of a function with the
    runtime (or inlined in one) counts references to every array of the records it takes.
    """
    ct = contacts_of(asm)  # candidate takes 4 of the Assembly's arrays, not its 17
    first = candidate(ct, minv, modes, cache)  # always the split of the current modes
    for _ in range(len(modes) + 1):
        if len(first.stuck) == 0 or not released_one(asm, first, minv, q, v, t, modes, leaving, room):
            break
        first = candidate(ct, minv, modes, cache)
    if not directions or not any_slipping(modes, leaving):  # no direction to check: no acceleration to compute
        return first
    changed = False
    for attempt in range(2):
        cb = first if attempt == 0 else candidate(ct, minv, modes, cache)
        if not flip(asm, cb, minv, q, v, t, modes, leaving, attempt, room):
            break
        changed = True
    if changed:  # a flip or a stick changes the others' held forces and directions: checked, and searched if wrong
        nearest_consistent(asm, ct, minv, (q, v, t), modes, leaving, cache, room)
    return first


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def consistent(asm, cb, minv, state, free, room):
    """Whether the modes of the :data:`Split` ``cb`` hold at ``state`` = (q, q', t): every stuck contact within its
    limit (:func:`most_over`), every slipping contact marked in ``free`` leaving V_r = 0 the way it slips."""
    q, v, t = state
    if len(cb.stuck) and most_over(asm, cb, minv, q, v, t, room) >= 0:
        return False
    tol = acceleration_and_tol(asm, cb, minv, state, room)
    for j in range(len(cb.modes)):
        if free[j] and wrong_way(asm, room.acc, j, cb.modes[j], tol):
            return False
    return True


@njit(cache=True)
def nearest_consistent(asm, ct, minv, state, modes, leaving, cache, room):
    """``modes`` as they are when they hold (:func:`consistent`), else the modes that hold nearest to them (fewest
    contacts changed; the first in a fixed order among as near), each contact at V_r = 0 (stuck or ``leaving``) free
    to stick or slip either way; as they are when none holds or more than :data:`SEARCH_MAX` are free.

    The direction check sticks every contact it cannot flip, at once: two contacts each stuck because of the
    other's slip can hold forces far over their limits while one of them stuck alone lets the other slip (a
    zero-length phase, then the next, until the run stops)."""
    free = leaving.copy()
    for j in range(len(modes)):
        free[j] = free[j] or modes[j] == STICK
    if consistent(asm, candidate(ct, minv, modes, cache), minv, state, free, room):
        return
    index = np.flatnonzero(free)
    m = len(index)
    if m > SEARCH_MAX:
        return
    trial, best, near = modes.copy(), modes.copy(), m + 1
    for code in range(3 ** m):
        c, changed = code, 0
        for i in range(m):
            trial[index[i]] = c % 3 - 1  # -1, 0 (STICK), +1
            changed += trial[index[i]] != modes[index[i]]
            c //= 3
        if changed < near and consistent(asm, candidate(ct, minv, trial, cache), minv, state, free, room):
            best[:], near = trial, changed
    modes[:] = best


@njit(cache=True)
def decide(asm, minv, q, v, t, modes, leaving):
    """The contact modes after an event at (q, q', t), in place; ``leaving``: the contacts slipping from V_r = 0.

    ``modes`` holds 0 for every contact at V_r = 0 that may stick and the
    forced direction of those released (their held force reached F_s N).
    """
    # np.bool_: as release_over_limit's, so that both compile one decide_in (a literal is a type of its own)
    decide_in(asm, minv, q, v, t, modes, leaving, None, new_room(len(q), len(modes)), np.bool_(True))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def hold_velocity_into(asm, cb, v, s):
    """:func:`hold_velocity` in place (``s``: room for the stuck contacts' corrections)."""
    for i in range(len(cb.stuck)):
        j = cb.stuck[i]
        s[i] = asm.belt[j] - asm.contact_dir[j] @ v
    for i in range(len(cb.stuck)):
        for a in range(len(v)):
            v[a] += cb.R[a, i] * s[i]


@njit(cache=True)
def hold_velocity(asm, cb, v):
    """q' with every stuck contact's e_j . q' = b_j exactly (the M-orthogonal correction)."""
    out = v.copy()
    hold_velocity_into(asm, cb, out, np.empty(len(cb.stuck)))
    return out
