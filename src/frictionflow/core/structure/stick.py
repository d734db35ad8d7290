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
until every stuck contact holds.

A held force within ``ON_LIMIT`` of F_s N_j is on the limit: then its rate
decides (:func:`held_rates`, lambda_S' from the combination's matrices and
q'' of the candidate stuck set, relative to the limit's own rate F_s n_j . q'),
as for the single mass; it is computed only then.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..friction import ON_LIMIT, holds, limit_ratio
from ..layout import FD, FS, RESULTANT, STICK
from .combo import split

#: a relative rate this close to 0 counts as 0
RATE_TOL = 1e-12


@njit(cache=True)
def rest(asm, cb, q, v, t, damped):
    """All forces on the structure but the stuck contacts' (``damped``: with the dampers' term)."""
    f = cb.f0 - cb.keff @ q
    if damped:
        f -= asm.damping @ v
    for i in range(len(asm.force_amp)):
        f += asm.force_dir[i] * (asm.force_amp[i] * math.cos(asm.force_omega[i] * t + asm.force_phi[i]))
    return f


@njit(cache=True)
def held(asm, cb, q, v, t):
    """(rule, friction): each stuck contact's held force as its stick rule reads it, and its friction force."""
    fr = -(cb.HE @ rest(asm, cb, q, v, t, True))
    rule = fr.copy()
    spring = False  # the spring rule's force only where some stuck contact reads it
    for i in range(len(cb.stuck)):
        spring = spring or asm.law[cb.stuck[i], RESULTANT] == 0.0
    if spring:
        fs = -(cb.HE @ rest(asm, cb, q, v, t, False))
        for i in range(len(cb.stuck)):
            if asm.law[cb.stuck[i], RESULTANT] == 0.0:
                rule[i] = fs[i]
    return rule, fr


@njit(cache=True)
def normal_load(asm, j, q):
    """N_j = P_j + n_j . q."""
    return asm.normal[j, 0] + asm.normal[j, 1:] @ q


@njit(cache=True)
def friction_forces(asm, cb, q, v, t):
    """The friction force of every contact on the structure: +-F_d N_j slipping, the held force stuck."""
    k = len(cb.modes)
    out = np.empty(k)
    _, fr = held(asm, cb, q, v, t) if len(cb.stuck) else (np.zeros(0), np.zeros(0))
    for j in range(k):
        if cb.modes[j] != STICK:
            out[j] = cb.modes[j] * asm.law[j, FD] * normal_load(asm, j, q)
    for i in range(len(cb.stuck)):
        out[cb.stuck[i]] = fr[i]
    return out


@njit(cache=True)
def acceleration(asm, cb, q, v, t):
    """q'' in the combination ``cb``: M^-1 rest minus its part along the stuck directions."""
    a0 = np.linalg.solve(asm.mass, rest(asm, cb, q, v, t, True))
    for i in range(len(cb.stuck)):
        s = asm.contact_dir[cb.stuck[i]] @ a0
        a0 -= cb.R[:, i] * s
    return a0


@njit(cache=True)
def held_rates(asm, cb, q, v, t):
    """d/dt of each stuck contact's held force as its stick rule reads it (:func:`held`), with q'' of ``cb``.

    lambda_S = G E_S M^-1 (C q' + K_eff q - f0 - forces(t)) with G E_S M^-1
    and K_eff constant in the combination: lambda_S' = G E_S M^-1 (C q'' +
    K_eff q' - forces'(t)); the "spring" rule leaves C q'' out.
    """
    d = cb.keff @ v
    for i in range(len(asm.force_amp)):
        w = asm.force_omega[i] * t + asm.force_phi[i]
        d += asm.force_dir[i] * (asm.force_amp[i] * asm.force_omega[i] * math.sin(w))
    spring = cb.HE @ d
    rate = cb.HE @ (d + asm.damping @ acceleration(asm, cb, q, v, t))
    for i in range(len(cb.stuck)):
        if asm.law[cb.stuck[i], RESULTANT] == 0.0:
            rate[i] = spring[i]
    return rate


@njit(cache=True)
def release_over_limit(asm, minv, q, v, t, modes, released):
    """The active-set loop: release the stuck contact most over F_s N_j until none is (``released`` marks them).

    Returns the :data:`Split` of the final modes (None when the loop ran out first).
    """
    for _ in range(len(modes) + 1):
        cb = split(asm, minv, modes)
        if len(cb.stuck) == 0:
            return cb
        rule, _ = held(asm, cb, q, v, t)
        worst, wr = -1, -1.0
        rates = np.zeros(0)
        for i in range(len(cb.stuck)):
            j = cb.stuck[i]
            lim = asm.law[j, FS] * normal_load(asm, j, q)
            rate = 0.0
            if lim > 0.0 and abs(rule[i]) >= lim * (1.0 - ON_LIMIT):  # on the limit: its rate decides
                if len(rates) == 0:
                    rates = held_rates(asm, cb, q, v, t)
                # relative to the limit F_s N_j(q), which moves at F_s n_j . q'
                rate = rates[i] - math.copysign(asm.law[j, FS] * (asm.normal[j, 1:] @ v), rule[i])
            if holds(rule[i], lim, rate):
                continue
            ratio = limit_ratio(rule[i], lim)
            if ratio >= wr:
                worst, wr = i, ratio
        if worst < 0:
            return cb
        j = cb.stuck[worst]
        modes[j] = 1 if rule[worst] > 0.0 else -1
        released[j] = True
    return None


@njit(cache=True)
def any_slipping(modes, leaving):
    """Some contact leaving V_r = 0 slips."""
    for j in range(len(modes)):
        if leaving[j] and modes[j] != STICK:
            return True
    return False


@njit(cache=True)
def check_directions(asm, minv, q, v, t, modes, leaving, first):
    """Each contact leaving V_r = 0 must see sigma V_r' >= 0: flip it once, then stick it (``leaving``: those).

    ``first``: the :data:`Split` of ``modes`` as they come (None: made here).
    """
    if not any_slipping(modes, leaving):  # no direction to check: no acceleration to compute
        return
    for attempt in range(2):
        cb = first if attempt == 0 and first is not None else split(asm, minv, modes)
        acc = acceleration(asm, cb, q, v, t)
        tol = RATE_TOL * (np.abs(acc).max() + np.abs(minv).max() * np.abs(cb.f0).max() + 1e-300)
        changed = False
        for j in range(len(modes)):
            if leaving[j] and modes[j] != STICK and -modes[j] * (asm.contact_dir[j] @ acc) < -tol:
                modes[j] = -modes[j] if attempt == 0 else STICK
                changed = True
        if not changed:
            return


@njit(cache=True)
def decide(asm, minv, q, v, t, modes, leaving):
    """The contact modes after an event at (q, q', t), in place; ``leaving``: the contacts slipping from V_r = 0.

    ``modes`` holds 0 for every contact at V_r = 0 that may stick and the
    forced direction of those released (their held force reached F_s N).
    """
    check_directions(asm, minv, q, v, t, modes, leaving, release_over_limit(asm, minv, q, v, t, modes, leaving))


@njit(cache=True)
def hold_velocity(asm, cb, v):
    """q' with every stuck contact's e_j . q' = b_j exactly (the M-orthogonal correction)."""
    out = v.copy()
    for i in range(len(cb.stuck)):
        j = cb.stuck[i]
        s = asm.belt[j] - asm.contact_dir[j] @ v
        out += cb.R[:, i] * s
    return out
