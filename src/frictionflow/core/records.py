"""The records the single-run kernels take: their output buffers and their run settings.

Module-level named tuples (numba types them as records, and a kernel that
takes them can still be cached): a kernel unpacks them once at its top.

==============  ==========================================================
``Samples``     the arrays a run writes its samples into, one row per
                sample: tau, X, X', F_c, the friction mode (int8) and the
                work integrals since the previous sample (``(cap, N_WORK)``)
``Events``      the arrays of the switches: tau and the mode entered
                (int64); a run counts every switch but writes only as
                many as fit
==============  ==========================================================

The run record: the scalar settings of one run, a float64 array of
``N_RUN`` named slots (the pattern of the force record ``p``,
:mod:`.layout`), filled by :func:`run_record` only.  Flags are stored as
1.0 / 0.0 (a kernel reads ``!= 0.0``), counts as floats (read ``int(...)``).

=================  =======================================================
``X0``, ``V0``     the initial state (X, X') at tau = 0
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

Samples = namedtuple("Samples", "t x v fc mode work")
Events = namedtuple("Events", "t mode")

# The run record's slots (see the table above); numba reads them as constants.
(
    X0, V0, T_END, ZETA, VB, DENSE_DT, T_TAIL, ODE_RTOL, ODE_ATOL, MAX_STEPS,
    STOP_PERIODIC, STOP_TERMINAL, STOP_RTOL, MIN_PERIODS, R_CERT, X_EQ,
) = range(16)
N_RUN = 16


@njit(cache=True)
def run_record(x0, v0, t_end, zeta, vb, t_tail, dense_dt=0.0, ode_rtol=0.0, ode_atol=0.0, max_steps=0,
               stop_periodic=False, stop_terminal=False, stop_rtol=0.0, min_periods=3, r_cert=0.0, x_eq=0.0):
    """The run record (a float64 array of ``N_RUN`` slots) of one run's settings: the one place that fills it.

    From Python as from compiled code.  What a kernel does not read keeps
    its default: no dense grid, no early stop (``min_periods`` 3 sizes the
    adaptive kernel's ring all the same).  Callers on a hot path pass every
    argument positionally (numba folds keywords and omitted arguments in
    Python, and each set of omitted ones is a signature of its own).
    """
    r = np.empty(N_RUN)
    r[X0] = x0
    r[V0] = v0
    r[T_END] = t_end
    r[ZETA] = zeta
    r[VB] = vb
    r[DENSE_DT] = dense_dt
    r[T_TAIL] = t_tail
    r[ODE_RTOL] = ode_rtol
    r[ODE_ATOL] = ode_atol
    r[MAX_STEPS] = max_steps
    r[STOP_PERIODIC] = 1.0 if stop_periodic else 0.0
    r[STOP_TERMINAL] = 1.0 if stop_terminal else 0.0
    r[STOP_RTOL] = stop_rtol
    r[MIN_PERIODS] = min_periods
    r[R_CERT] = r_cert
    r[X_EQ] = x_eq
    return r
