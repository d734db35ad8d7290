"""The exact state at many times at once, from a run's samples (no work integrals: the state alone).

Between two samples no switch lies, so the state at t is the closed form of
the phase that starts at the last sample at or before t, in that sample's
modes.  Times are visited in ascending order, so each sample's phase is set
up once however many times fall after it.
"""

from __future__ import annotations

from numba import njit

from .combo import build_from, new_eigs, split
from .phase import start, state_at


@njit(cache=True, nogil=True)  # evaluated by a model sweep's threads at once
def states(asm, minv, t, state, modes, times, out):
    """Fill ``out[:, m]`` with (q, q') at ``times[m]``; ``times`` ascending, within [t[0], t[-1]].

    ``t``, ``state`` (2n, T), ``modes`` (k, T): a run's samples.  Returns the
    number of times filled (fewer when one lies outside the run).
    """
    n = asm.mass.shape[0]
    i, eigs = 0, new_eigs()  # the samples' combinations share their symmetric blocks' decompositions
    cb = build_from(asm, minv, split(asm, minv, modes[:, 0].copy()), eigs)
    ph = start(cb, asm, state[:n, 0].copy(), state[n:, 0].copy(), t[0])
    for m in range(len(times)):
        tm = times[m]
        if tm < t[0] or tm > t[-1]:
            return m
        j = i
        while j + 1 < len(t) and t[j + 1] <= tm:
            j += 1
        if j != i or m == 0:
            i = j
            cb = build_from(asm, minv, split(asm, minv, modes[:, i].copy()), eigs)
            ph = start(cb, asm, state[:n, i].copy(), state[n:, i].copy(), t[i])
        if tm == t[i]:
            out[:, m] = state[:, i]
            continue
        q, v = state_at(cb, ph, asm.force_omega, tm - t[i])
        out[:n, m] = q
        out[n:, m] = v
    return len(times)
