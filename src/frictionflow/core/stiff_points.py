"""The stiff engine at many points and at its fixed points: a run that releases the GIL, a law's steady
internal states, and the whole state's Jacobian there.

:func:`run_released` is :func:`frictionflow.core.stiff.run` compiled with
``nogil``: the sweeps run a chunk's points on numba's threads
(:func:`frictionflow.core.threads.over_points`) and the stiff solver's
façade runs through it too, so a swept point and ``simulate`` execute the
same compiled run.  :func:`steady_internal` serves the steady-sliding equilibrium of a law with internal state
(:func:`frictionflow.analysis.equilibrium.sliding_equilibrium`): its
states where their rates vanish (its linearisation is
:func:`frictionflow.core.stiff_flow.field_at`'s exact Jacobian).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from . import stiff

#: Newton steps for the steady internal states: a rate linear in the states (LuGre, the elasto-plastic law
#: beyond break-away, Dahl with alpha = 1) takes one, Dahl's rate with alpha > 1 converges linearly
NEWTON_STEPS = 200


@njit(cache=True, nogil=True)
def run_released(q, zeta, vb, y0, t_end, tol, steps, t_out, y_out, w_out, at):
    """:func:`frictionflow.core.stiff.run` with the GIL released (same arguments, same results)."""
    return stiff.run(q, zeta, vb, y0, t_end, tol, steps, t_out, y_out, w_out, at)


@njit(cache=True)
def steady_internal(q, vr, z):
    """The internal states whose rates vanish at relative velocity ``vr`` (sliding steadily), by Newton's
    method on the law's rates with their exact derivatives from the guess ``z`` (overwritten, returned).

    Stops when a step no longer changes the states, the rates are exactly 0, or the derivative matrix is
    singular (a rate that vanishes to higher order at its root, Dahl's with alpha > 1, is then at it).
    """
    m = len(z)
    d = np.empty((m, stiff.D_RZ + m))
    a = np.empty((m, m))
    piv = np.empty(m, dtype=np.int64)
    r = np.empty((1, m))  # the solver works on a row of a matrix
    for _ in range(NEWTON_STEPS):
        stiff.law_eval(q, vr, z, d)
        still = True
        for i in range(m):
            r[0, i] = -d[i, stiff.D_RATE]
            still = still and r[0, i] == 0.0
            for j in range(m):
                a[i, j] = d[i, stiff.D_RZ + j]
        if still or not stiff.lu_factor(a, piv):
            break
        stiff.lu_solve(a, piv, r, 0)
        moved = False
        for i in range(m):
            znew = z[i] + r[0, i]
            moved = moved or znew != z[i]
            z[i] = znew
        if not moved:
            break
    return z
