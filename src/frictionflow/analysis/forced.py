"""Steady states of the forced oscillator, read on the stroboscopic section.

With an external force F_ex cos(Omega tau + phi) the state space is (X, X',
phase): a steady state is judged on the states P_k = (X, X')(tau_k) at the
stroboscopic times tau_k = k 2 pi / Omega, which every solver samples when
forced.  The kinds:

``periodic``
    The section repeats after m forcing periods, P_k = P_{k-m} to within
    ``rtol`` of the motion's scale for the last ``min_periods`` whole
    repetitions, with the smallest such m <= :data:`MAX_MULTIPLE` (m = 1: a
    harmonic response, m > 1: subharmonic of order m).  The period is
    m 2 pi / Omega.  An m whose last repetition repeats after a divisor d of
    m to a hundred times ``rtol`` is a d-cycle still converging (a multiplier
    near a root of unity: P_{k+m} - P_k shrinks below ``rtol`` first), not
    an m-cycle: ``not_settled`` then.
``chaotic``
    No repetition, and the largest Lyapunov exponent of the non-smooth flow
    (saltation matrices at every switch: :mod:`frictionflow.analysis.lyapunov`)
    is positive beyond its finite-time uncertainty: nearby states separate
    exponentially.
``quasi_periodic``
    No repetition, a largest exponent indistinguishable from 0, and a section
    that has stopped drifting: the points fill a closed curve (an invariant
    torus of the flow), which the second half of the tail revisits (each of
    its points lies close to a point of the first half), without closing in
    on a point or a cycle of up to 1024 points (the extents, or the m-step
    differences, of the tail's quarters falling: a slowly attracting cycle,
    whose exponent is within its uncertainty of 0 too).
``not_settled``
    None of these: still converging (a negative exponent: the run is too
    short for the repetition to show), or drifting.

A fixed-step run through a stick band (RK4) leaves the band up to a step
late, differently in each period: its section repeats only to a few steps'
travel, which the tolerance then allows.  The discrete run may still repeat
exactly after several periods (the step grid's own cycle: 9 forcing periods
for a harmonic orbit, QA); the smallest m within that travel is the one taken.

The window is a whole number of forcing periods ending at the last section
sample: m periods repeated ``n_periods`` times when periodic, else the tail
(the last half of the section samples), so that averages are over whole
periods of the forcing.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..core.sections import _stationary
# the test's constants, shared with its compiled port (the batched forced sweep)
from ..core import strobe
from ..core.strobe import (LYAPUNOV_PERIODS, LYAPUNOV_SPREAD_FLOOR, LYAPUNOV_STEPS, LYAPUNOV_STOP, LYAPUNOV_TRANSIENT,
                           MAX_MULTIPLE, REVISIT_SHARE, SUBCYCLE_SPREAD)
from ..trajectory import Trajectory
from .lyapunov import lyapunov_exponents

#: repetitions a fixed-step run's jittering section needs (as the autonomous classifier's 8 periods)
JITTER_REPEATS = 8


def section_indices(traj: Trajectory) -> np.ndarray:
    """Indices of the samples at the stroboscopic times k 2 pi / Omega (k = 0, 1, ...; a moving belt alone:
    2 pi / Omega_b) (:func:`frictionflow.core.strobe.section_indices`); RuntimeError where one has no sample."""
    period = float(traj.model.drive_period)
    idx = strobe.section_indices(np.ascontiguousarray(traj.t, dtype=float), len(traj.t), period)
    if len(idx) < strobe.section_count(float(traj.t[-1]), period):
        raise RuntimeError(f"solver={traj.solver.get('name')} did not sample the stroboscopic section at "
                           f"tau={len(idx) * period:.10g} (forced runs must sample every k 2 pi / Omega)")
    return idx


def section_scale(x: np.ndarray, v: np.ndarray, traj: Trajectory) -> float:
    """The motion's scale on the section: range of X and X', forcing amplitude, V_b, F_d."""
    return float(max(np.ptp(x), np.ptp(v), traj.model.fex, abs(traj.vb) + traj.model.vb_amplitude, traj.friction.fd, 1e-300))


def repeat_multiple(x: np.ndarray, v: np.ndarray, tol: float, min_periods: int,
                    max_multiple: int = MAX_MULTIPLE) -> tuple[int, int]:
    """(m, repetitions): the smallest m <= ``max_multiple`` whose last ``min_periods`` repetitions match to
    ``tol``; (0, 0) if none.  Repetitions count back from the end while P_k = P_{k-m} holds, up to the whole
    sequence.  The compiled test the batched sweeps run (:func:`frictionflow.core.strobe.repeat_multiple`)."""
    return strobe.repeat_multiple(np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(v, dtype=float),
                                  float(tol), int(min_periods), int(max_multiple))


def internal_scaled(traj: Trajectory) -> np.ndarray:
    """The internal states in the units of X: each over its ``internal_scale`` (the size at which it carries
    F_s) times F_s, so that a section judges them with the tolerance of X."""
    scale = np.asarray(traj.friction.internal_scale(), dtype=float)
    return traj.internal / scale[:, None] * traj.friction.fs


def state_repeat_multiple(cols: np.ndarray, tol: float, min_periods: int,
                          max_multiple: int = MAX_MULTIPLE) -> tuple[int, int]:
    """:func:`repeat_multiple` on the whole state: ``cols`` (one row per coordinate, one column per
    section sample) repeats after m samples when every coordinate does."""
    n = cols.shape[1]
    for m in range(1, max_multiple + 1):
        if n < (min_periods + 1) * m:
            break
        same = ~np.any(np.abs(cols[:, m:] - cols[:, :-m]) > tol, axis=0)  # P_{i+m} = P_i, i = 0 .. n-m-1 (as strobe's)
        run = n - m if same.all() else n - m - 1 - int(np.flatnonzero(~same)[-1])
        if run >= min_periods * m:
            return (0, 0) if state_subcycle(cols, m, SUBCYCLE_SPREAD * tol) else (m, run // m)
    return 0, 0


def state_subcycle(cols: np.ndarray, m: int, tol: float) -> bool:
    """:func:`frictionflow.core.strobe.converging_subcycle` on the whole state: whether the last ``m`` columns of
    ``cols`` (one row per coordinate, one column per section sample) repeat after a divisor of ``m`` to ``tol`` (a
    cycle of that divisor still converging, not an m-cycle; the structures' section uses it too)."""
    last = cols[:, cols.shape[1] - m:]
    return any(not np.any(np.abs(last[:, d:] - last[:, :-d]) > tol) for d in range(1, m) if m % d == 0)


def revisits(x: np.ndarray, v: np.ndarray, tol: float) -> bool:
    """Whether every point of the second half lies within ``tol`` of some point of the first half
    (:func:`frictionflow.core.strobe.revisits`)."""
    return bool(strobe.revisits(np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(v, dtype=float), float(tol)))


def closing_in(x: np.ndarray, v: np.ndarray) -> bool:
    """Whether the section (X, X') closes in on a point or a cycle (:func:`frictionflow.core.strobe.closing_in`)."""
    return bool(strobe.closing_in(np.ascontiguousarray(np.vstack([x, v]), dtype=float)))


def _step_jitter(traj: Trajectory, i0: int) -> float:
    """How far a fixed-step run's section may wander: a few steps' travel at the tail's largest speed.

    A fixed step leaves a stick band up to one step late, differently in each
    period; the state on the section then differs by up to h max|X'| in X and
    h max|X''| in X' from period to period.  0 for event-located solvers, and
    where nothing is held (no stick, or no friction to hold with).
    """
    h = traj.solver.get("dt")
    if h is None or traj.friction.fs <= 0.0 or not np.any(traj.mode[i0:] == 0):
        return 0.0
    return 4.0 * float(h) * float(max(np.max(np.abs(traj.v[i0:])), np.max(np.abs(traj.acceleration[i0:]))))


def jittered_multiple(x: np.ndarray, v: np.ndarray, jitter: float, max_multiple: int = MAX_MULTIPLE) -> int:
    """The smallest m whose last :data:`JITTER_REPEATS` repetitions agree to ``jitter`` without a trend; 0 if none.

    A transient converges: at each of the m phases its section values drift
    one way, a trend a t-test finds; a fixed step's jitter does not.
    """
    n = len(x)
    for m in range(1, max_multiple + 1):
        if n < JITTER_REPEATS * m:
            break
        last_x, last_v = x[n - JITTER_REPEATS * m:], v[n - JITTER_REPEATS * m:]
        phases = [(last_x[j::m], last_v[j::m]) for j in range(m)]
        if all(np.ptp(a) <= jitter and np.ptp(b) <= jitter and _stationary(a) and _stationary(b) for a, b in phases):
            return m
    return 0


def classify_forced(traj: Trajectory, rtol: float, min_periods: int = 3, noise: float = 0.0,
                    lyapunov: Callable[[Trajectory], tuple[float, float] | None] | None = None) -> dict:
    """Kind, window and details of the forced run ``traj`` (see the module docstring).

    ``lyapunov(traj)`` returns (largest exponent, its uncertainty), or None
    where it cannot, and is called only when the section does not repeat;
    without it such runs are ``not_settled``.  ``noise``: the solver's relative error on the section.
    """
    idx = section_indices(traj)
    tail = idx[len(idx) // 2:]
    xs, vs = traj.x[tail], traj.v[tail]
    scale = section_scale(xs, vs, traj)
    if traj.internal is None:
        m, reps = repeat_multiple(xs, vs, max(rtol, noise) * scale, min_periods)
    else:  # the internal states are part of the state the section repeats
        m, reps = state_repeat_multiple(np.vstack([xs, vs, internal_scaled(traj)[:, tail]]),
                                        max(rtol, noise) * scale, min_periods)
    jitter = _step_jitter(traj, tail[0])
    if jitter:  # a fixed step through a stick band: its own exact cycle may be a multiple of the motion's
        found = jittered_multiple(xs, vs, jitter)
        if found and (not m or found < m):
            m, reps = found, JITTER_REPEATS - 1
        elif m:
            jitter = 0.0  # the exact repetition is the smallest
    period = traj.model.drive_period
    out = {"multiple": None, "lyapunov": None, "n_periods": 0, "jitter": None}
    if len(tail) < 2:  # shorter than two forcing periods: no section to judge; the run itself is the window
        out.update(kind="not_settled", period=None, window=(float(traj.t[0]), float(traj.t[-1])))
        return out
    if m:
        if jitter:  # the relative spread over the repetitions, as the autonomous classifier reports it
            k = JITTER_REPEATS * m
            out["jitter"] = max(max(np.ptp(xs[-k:][j::m]), np.ptp(vs[-k:][j::m])) for j in range(m)) / scale
        last = idx[-1]
        first = idx[len(idx) - 1 - m * reps]
        out.update(kind="periodic", multiple=m, period=m * period, n_periods=reps,
                   window=(float(traj.t[first]), float(traj.t[last])))
        return out
    out["window"] = (float(traj.t[tail[0]]), float(traj.t[tail[-1]]))
    out["period"] = None
    if lyapunov is None:
        out["kind"] = "not_settled"
        return out
    found = lyapunov(traj)
    if found is None:
        out["kind"] = "not_settled"
        return out
    lam, spread = found
    out["lyapunov"] = lam
    if lam > spread:
        out["kind"] = "chaotic"
    elif abs(lam) <= spread and revisits(xs, vs, REVISIT_SHARE * scale) and not closing_in(xs, vs):
        out["kind"] = "quasi_periodic"
    else:
        out["kind"] = "not_settled"
    return out


def largest_exponent(traj: Trajectory) -> tuple[float, float] | None:
    """(largest Lyapunov exponent, its uncertainty) of the motion from the run's last section state; None if unavailable.

    Computed by :func:`frictionflow.analysis.lyapunov.lyapunov_exponents`
    (saltation matrices at every switch) from the state at the last
    stroboscopic time, which has the drive's phase of tau = 0 (the forcing's, or a moving belt's).  Laws without
    Coulomb's stick rule (Karnopp's band) and user-defined laws have no
    tangent kernel: None, and the run stays ``not_settled``.  The uncertainty
    is the spread of the running estimate over the second half of the
    averaging (at least 1e-4: a finite run cannot tell smaller exponents from 0).
    The averaging ends early once the exponent is below -2 times that
    uncertainty, checked after 60, 80, ... periods (:data:`~frictionflow.core.strobe.LYAPUNOV_STOP`):
    the kind is then ``not_settled`` whatever the remaining periods give,
    and the value is that of the periods averaged.
    """
    law = traj.friction
    if not law.has_tangent_kernel:
        return None
    i = section_indices(traj)[-1]
    period = traj.model.drive_period
    try:
        r = lyapunov_exponents(traj.model, law, float(traj.x[i]), float(traj.v[i]), t_transient=LYAPUNOV_TRANSIENT * period,
                               t_end=(LYAPUNOV_TRANSIENT + LYAPUNOV_PERIODS) * period, steps_per_block=LYAPUNOV_STEPS,
                               stop=LYAPUNOV_STOP)
    except RuntimeError:  # a grazing switch the tangent map cannot cross
        return None
    return float(r.exponents[0]), max(float(r.spread[0]), LYAPUNOV_SPREAD_FLOOR)
