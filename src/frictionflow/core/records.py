"""The records the single-run kernels take: their output buffers and their run settings.

Module-level named tuples (numba types them as records, and a kernel that
takes them can still be cached): a kernel unpacks them once at its top.

==============  ==========================================================
``Samples``     the arrays a run writes its samples into, ``cap`` samples:
                ``t`` (cap,) the times; ``y`` (n, cap) the state, one row
                per component (the single mass: X, X'); ``fc`` (k, cap)
                and ``mode`` (k, cap, int8) each contact's friction force
                and mode; ``work`` (cap, N_WORK) the work integrals since
                the previous sample.  Blocks of n and k rows, so that the
                record does not assume one mass or one contact; a block's
                rows are contiguous (``y[0]`` is a plain 1-D array).
                The single-mass kernels and the structure engine
                (:mod:`.structure.run`: y = (q, q'), one ``fc``/``mode``
                row per contact, one ``work`` column per channel) write it
``Events``      the arrays of the switches: tau, the mode entered and the
                contact that switched (both int64; the single mass's
                kernels write contact 0); a run counts every switch but
                writes only as many as fit
``Derivatives`` the slopes at both ends of each sample's interval, for a
                cubic Hermite interpolant between samples (the structure's
                adaptive kernel, :mod:`.structure.adaptive`): ``accel``
                (2n, cap) the acceleration just after each sample (rows
                0..n-1) and the one the next sample is reached with (rows
                n..2n-1); ``power`` (2W, cap) each work channel's power
                likewise
==============  ==========================================================

The run record: the settings of one run and its initial state, a float64
array of ``N_SETTINGS`` named slots followed by the state's n components
(the pattern of the force record ``p``, :mod:`.layout`), filled by
:func:`run_record` only.  Flags are stored as 1.0 / 0.0 (a kernel reads
``!= 0.0``), counts as floats (read ``int(...)``).

=================  =======================================================
``Y0`` ...         the initial state at tau = 0, ``run[Y0 + i]`` (the
                   single mass: ``X0``, ``V0`` = X, X')
``T_END``          the end of the run
``ZETA``, ``VB``   the damping ratio and the belt speed
``DENSE_DT``       also sample every ``DENSE_DT`` (0: no dense grid)
``T_TAIL``         the start of the tail sampled for the analysis
``ODE_RTOL``       adaptive: the step's relative error tolerance
``ODE_ATOL``       adaptive: the step's absolute error tolerance
``MAX_STEPS``      adaptive: the step cap
``STOP_PERIODIC``  exact: stop once the section values repeat (flag)
``STOP_TERMINAL``  exact: stop once the final phase is reached (flag)
``STOP_RTOL``      the early stop's tolerance on the repeating sections
                   (adaptive: 0 turns that stop off)
``MIN_PERIODS``    how many periods must repeat for the early stop
``R_CERT``         adaptive: the certified disc's radius about ``X_EQ``
                   (:mod:`.certificate`; 0: off)
``X_EQ``           adaptive: the sliding equilibrium X* = F(V_b)
=================  =======================================================

A named tuple passed from Python costs the call about 0.5 us more than its
fields would (numba types a named tuple in Python, arrays and floats in C);
a float array costs no more than one argument, so the settings are one.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

from .layout import N_WORK

Samples = namedtuple("Samples", "t y fc mode work")
Events = namedtuple("Events", "t mode contact")
Derivatives = namedtuple("Derivatives", "accel power")

# The run record's slots (see the table above); numba reads them as constants.
(
    T_END, ZETA, VB, DENSE_DT, T_TAIL, ODE_RTOL, ODE_ATOL, MAX_STEPS,
    STOP_PERIODIC, STOP_TERMINAL, STOP_RTOL, MIN_PERIODS, R_CERT, X_EQ,
) = range(14)
N_SETTINGS = 14
#: the initial state's first slot; the single mass's X(0) and X'(0)
Y0 = N_SETTINGS
X0, V0 = Y0, Y0 + 1


#: the single mass on the belt: the state (X, X'), one contact
N_STATE, N_CONTACTS = 2, 1


def empty_samples(cap, n_state, n_contacts, n_work=N_WORK):
    """Empty :data:`Samples` with room for ``cap`` samples of ``n_state`` components, ``n_contacts`` contacts and
    ``n_work`` work channels (the single mass's ``N_WORK``).

    Python callers use this one: numpy gives large arrays transparent huge
    pages, and a long run's first touch of its buffers costs a quarter of
    the time with 4 KiB pages (numba's allocator does not ask for them).
    """
    return Samples(np.empty(cap), np.empty((n_state, cap)), np.empty((n_contacts, cap)),
                   np.empty((n_contacts, cap), dtype=np.int8), np.empty((cap, n_work)))


def empty_events(cap):
    """Empty :data:`Events` with room for ``cap`` switches."""
    return Events(np.empty(cap), np.empty(cap, dtype=np.int64), np.empty(cap, dtype=np.int64))


def empty_derivatives(cap, n, n_work):
    """Empty :data:`Derivatives` for ``cap`` samples of ``n`` coordinates and ``n_work`` work channels."""
    return Derivatives(np.empty((2 * n, cap)), np.empty((2 * n_work, cap)))


@njit(cache=True, inline="always")
def record_switch(events, ne, t, mode):
    """Count the single mass's switch at ``t`` into ``mode``, writing it into the :data:`Events` ``events`` while it
    fits (contact 0: its one contact); the count after it (a run counts every switch)."""
    ev_t, ev_mode, ev_contact = events
    if ne < len(ev_t):
        ev_t[ne] = t
        ev_mode[ne] = mode
        ev_contact[ne] = 0
    return ne + 1


#: :func:`empty_samples` compiled, for kernels that allocate their own (small) buffers
new_samples = njit(cache=True)(empty_samples)
#: :func:`empty_events` compiled
new_events = njit(cache=True)(empty_events)


@njit(cache=True)
def run_record(y0, t_end, zeta, vb, t_tail, dense_dt, ode, stop, cert):
    """The run record (a float64 array: ``N_SETTINGS`` slots, then ``y0``) of one run: the one place that fills it.

    From Python as from compiled code.  ``y0``: the initial state (a tuple
    or array of n floats); ``ode`` = (rtol, atol, max_steps) of the
    adaptive step (zeros where unused); ``stop`` = (periodic, terminal,
    rtol, min_periods) of the early stops (``min_periods`` 3 sizes the
    adaptive kernel's ring even with no stop); ``cert`` = (radius, X*) of
    the adaptive solver's certified equilibrium (zeros: off).  Callers pass
    every argument positionally, with the same types from every call site
    (each set of types is a compiled builder of its own).
    """
    r = np.empty(N_SETTINGS + len(y0))
    for i in range(len(y0)):
        r[Y0 + i] = y0[i]
    r[T_END] = t_end
    r[ZETA] = zeta
    r[VB] = vb
    r[DENSE_DT] = dense_dt
    r[T_TAIL] = t_tail
    r[ODE_RTOL], r[ODE_ATOL], r[MAX_STEPS] = ode[0], ode[1], ode[2]
    r[STOP_PERIODIC] = 1.0 if stop[0] else 0.0
    r[STOP_TERMINAL] = 1.0 if stop[1] else 0.0
    r[STOP_RTOL] = stop[2]
    r[MIN_PERIODS] = stop[3]
    r[R_CERT], r[X_EQ] = cert[0], cert[1]
    return r
