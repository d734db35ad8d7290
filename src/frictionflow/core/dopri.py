"""Adaptive Dormand-Prince 5(4) with dense output, for smooth nonlinear slip laws.

Slip phases are integrated with the embedded pair (the coefficients of
Dormand & Prince 1980, dense output of Shampine 1986 as in SciPy's RK45);
every switch (V_r = 0) is located on the dense output to machine precision
and the integration restarts there in the mode the stick rule selects.
There is no sign() inside the integrator: within a slip phase the slip
direction is fixed, so the right-hand side is smooth and nothing chatters.
Stick phases (X' = V_b) are closed forms.

The state is augmented with the running integrals of 2 zeta X'^2, of
P_f = X' F_c (signed; split into in/out at the zeros of X', which are
located as well) and of the interface heat F_c V_r.

With an external force f(tau) = F_ex cos(Omega tau + phi) (``p[FEX]`` > 0)
the right-hand side gets + f at each stage's own time, the state a sixth
integral W_ex = int X' f, and the run a sample at every tau_k = k 2 pi / Omega
(the stroboscopic section).  A stick phase then holds F_e - f(tau), which
varies: it is walked through the monotone pieces of that force, whose ends
(the zeros of its rate V_b - f') are known in closed form, so that no
excursion beyond F_s is missed however short (:func:`.stick.exit_time`).  The
forced and unforced runs are two specialisations of one body (:func:`_run`,
``forced`` a constant in each): the unforced one computes what this kernel
computed before forcing existed, to the bit.

A belt whose speed varies (``p[VB_AMP]`` > 0) runs in a third specialisation of the forced one:
every stage and event reads V_b(tau), a stick phase follows the belt
(X = X0 + int V_b, :func:`.stick.stick_x`) and holds F_e + V_b' - f (the
belt's acceleration is a load on the stick rule, :func:`.friction.stick_load`),
its works by quadrature, and the section is sampled every 2 pi / Omega_b
when there is no external force.

``slip_force(p, speed)`` is a module global: for a user-defined slip law the
kernel is rebuilt around the user's function (see
:func:`frictionflow.solvers.adaptive.kernel_for`).
"""

from __future__ import annotations


import math
from collections import namedtuple

import numpy as np
from numba import njit

from . import codes
from .friction import (FD, FEX, FS, LAW, LAW_A, LAW_B, LAW_C, OMEGA, PHI, RESULTANT, VB_AMP, VB_OMEGA, belt_speed,
                       external_force, rest_mode, slip_magnitude, stick_duration, stick_friction, stick_load,
                       stick_load_rate)
from . import sections as sec
from .layout import N_WORK
from .records import (DENSE_DT, MAX_STEPS, MIN_PERIODS, ODE_ATOL, ODE_RTOL, R_CERT, STOP_RTOL, T_END, T_TAIL, V0, VB, X0, X_EQ,
                      ZETA, record_switch)
from .samples import emit
# the forced stick's walk and the stick on a moving belt, stated once
from .stick import belt_stick_work, belt_zero, exit_time as _stick_exit, friction_zero as _friction_zero, stick_x

A21 = 1 / 5
A31, A32 = 3 / 40, 9 / 40
A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9
A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
E1, E3, E4, E5, E6, E7 = -71 / 57600, 71 / 16695, -71 / 1920, 17253 / 339200, -22 / 525, 1 / 40
P = np.array([
    [1, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
    [0, 0, 0, 0],
    [0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
    [0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
    [0, 127303824393 / 49829197408, -318862633887 / 49829197408, 701980252875 / 199316789632],
    [0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
    [0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
])
C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9  # the stages' times (the last two at 1)
NY = 5  # X, X', W_dv, W_f (signed), W_heat
NY_FORCED = 6  # ... and W_ex
H_MAX = 0.25  # about 1/25 of the natural period
#: a sample within this (relative) of a stroboscopic time is put on it: no second sample a rounding apart
STROBE_TOL = 1e-12
#: a forced slip phase shorter than this (relative) is no slip: F_s was touched, not crossed
NO_SLIP = 1e-12
OK, STEP_CAP, TINY_STEP, FULL = codes.OK, codes.STEP_CAP, codes.TINY_STEP, codes.FULL
EPS = 2.220446049250313e-16
#: the functions that read the slip force, themselves or through a callee here, callees first: a user's law
#: runs copies of them whose ``slip_force`` is the user's (:func:`frictionflow.solvers.adaptive.kernel_for`)
KERNEL_FUNCS = ("slip_force_at", "rhs", "at_rest", "_g", "dense", "_events_at", "_gd", "_root",
                "first_sample", "after_stick", "_slip_start", "_first_event", "_at_section",
                "_slip", "_switch", "slip_end", "_run", "run_unforced", "run_forced", "run_moving")
#: ``forced`` of the variant on a moving belt (:func:`run_moving`): true as a flag, and where the step reads the
#: belt's speed a constant apart from True, so that the other two variants compute no belt speed there
MOVING = 2


# Inlined by numba (inline="always") where every step calls it (rhs and the step's sample): a call
# costs two atomic reference-count updates of p, which LLVM's inlining keeps -- a fifth of the
# basins benchmark.  Elsewhere it is called (:func:`slip_force_at`): inlining there costs compile time.
@njit(cache=True, inline="always")
def slip_force(p, speed):
    """Friction magnitude while slipping at ``speed`` (a built-in law)."""
    return slip_magnitude(int(p[LAW]), p[FD], p[FS], p[LAW_A], p[LAW_B], p[LAW_C], speed)


@njit(cache=True)
def slip_force_at(p, speed):
    """:func:`slip_force`, called: for the sites outside the step."""
    return slip_force(p, speed)


@njit(cache=True)
def rhs(y, t, d, zeta, vb, p, out, forced):
    """Slip in direction d: X'' = d F(|V_r|) + f(t) - X - 2 zeta X', with the work integrands.

    ``forced`` (a constant where the kernel is specialised): whether f acts;
    then ``out[5]`` is W_ex's integrand X' f; :data:`MOVING`: the belt's speed varies too.
    """
    x = y[0]
    v = y[1]
    vr = (belt_speed(p, vb, t) if forced == MOVING else vb) - v
    f = d * slip_force(p, abs(vr))
    out[0] = v
    if forced:
        fx = external_force(p, t)
        out[1] = f + fx - x - 2.0 * zeta * v
        out[5] = v * fx
    else:
        out[1] = f - x - 2.0 * zeta * v
    out[2] = 2.0 * zeta * v * v
    out[3] = v * f
    out[4] = f * vr


@njit(cache=True)
def dense(y0, K, h, theta, out, ny):
    """The continuous extension at y0 + theta h (its first ``ny`` components)."""
    q1 = theta
    q2 = theta * theta
    q3 = q2 * theta
    q4 = q3 * theta
    for i in range(ny):
        acc = 0.0
        for s in range(7):
            acc += K[s, i] * (P[s, 0] * q1 + P[s, 1] * q2 + P[s, 2] * q3 + P[s, 3] * q4)
        out[i] = y0[i] + h * acc


@njit(cache=True)
def at_rest(x, zeta, vb, fs, res, p, t):
    """Mode at V_r = 0 at time t by Coulomb's stick rule (:func:`~frictionflow.core.friction.rest_mode`), with the belt's
    speed at t and its acceleration in the load (:func:`~frictionflow.core.friction.stick_load`)."""
    return rest_mode(x, zeta, belt_speed(p, vb, t), fs, res, slip_force_at(p, 0.0), stick_load(p, t),
                     stick_load_rate(p, t, zeta, res))


@njit(cache=True)
def _g(kind, y, a, zeta, vb, d):
    """Event functions: 0 the switch d (V_b - X') (> 0 inside; ``vb`` the belt's speed there), 1 X', 2 X'', 3 X' + 2 zeta X''."""
    if kind == 0:
        return d * (vb - y[1])
    if kind == 1:
        return y[1]
    if kind == 2:
        return a
    return y[1] + 2.0 * zeta * a


@njit(cache=True)
def run(run, p, samples, events):
    """Integrate to ``t_end``; returns (k, ne, status, t, h): the numbers of samples and of switches, t, h where it stopped.

    ``run`` is the run record (:mod:`.records`, :func:`.records.run_record`):
    x0, v0, t_end, zeta, vb, the tolerances ``ode_rtol``, ``ode_atol`` and
    the step cap ``max_steps``, ``dense_dt`` (also sample every ``dense_dt``;
    0: not), ``t_tail`` (the start of the tail sampled for the analysis) and
    the early stop.  ``p`` is the force record (:mod:`.layout`); the samples
    go to the arrays of the record ``samples`` = (t, x, v, fc, mode, work)
    and the switches to those of ``events`` = (t, mode, contact) (:mod:`.records`,
    :func:`frictionflow.solvers.base.output_buffers`), as many as fit (all
    are counted).

    The slots ``stop_rtol``, ``min_periods``, ``r_cert``, ``x_eq`` let a run
    whose end is already known stop early, at a section X' = 0 (sweeps;
    ``stop_rtol`` and ``r_cert`` zero: off): when it is inside the certified
    disc of radius ``r_cert`` about ``x_eq`` (:mod:`.certificate`), or when
    its last ``min_periods + 1`` maxima and minima of X and their periods
    repeat to ``stop_rtol`` of the amplitude.  A forced run (``p[FEX]`` > 0)
    ignores them (X' = 0 is no section of a time-dependent flow) and also
    samples every tau_k = k 2 pi / Omega.
    """
    if p[VB_AMP] != 0.0:
        return run_moving(run, p, samples, events)
    if p[FEX] != 0.0:
        return run_forced(run, p, samples, events)
    return run_unforced(run, p, samples, events)


@njit(cache=True)
def run_unforced(run, p, samples, events):
    """:func:`run` without an external force (compiled without its code)."""
    return _run(False, run, p, samples, events)


@njit(cache=True)
def run_forced(run, p, samples, events):
    """:func:`run` with the external force of ``p``."""
    return _run(True, run, p, samples, events)


@njit(cache=True)
def run_moving(run, p, samples, events):
    """:func:`run` on the moving belt of ``p`` (with its external force, if any): the forced variant reading V_b(tau)."""
    return _run(MOVING, run, p, samples, events)


#: a run's settings, unpacked once (numba keeps a named tuple of scalars in registers); ``forced`` not a literal:
#: the parts called once a phase read it and compile once for both variants
Setup = namedtuple("Setup", "t_end zeta vb rtol atol max_steps dense_dt t_tail stop_rtol r_cert x_eq res h_max period forced")
#: the sample grid: whether the tail's start is sampled, the next dense-grid time, the next stroboscopic index
Cursor = namedtuple("Cursor", "tail_done next_dense n_strobe")
#: a phase function's status when the run goes on (never a kernel's status code)
GO = -1


@njit(cache=True, inline="always")
def _run(forced, run, p, samples, events):
    """:func:`run`'s body; ``forced`` is a constant at each of its two call sites (two specialisations).

    A loop over phases -- stick (:func:`_stick`, :func:`forced_stick`), slip (:func:`_slip`) -- each a compiled
    function called once per phase that returns where it ended; the switches are written here (the stick
    rule: :func:`after_stick`, :func:`_switch`).  The run's arrays are made here once, and are passed on
    to as few calls as can be (each passing costs reference counting): the samples ``outs``, the works since
    the last sample ``w`` (W_dv, W_fin, W_fout, W_heat, W_ex), the step's scratch, the ring of the last maxima
    and minima.

    Inlined by numba into :func:`run_unforced` and :func:`run_forced`, not compiled on its own: every compiled
    function's machine code includes what it calls (optimised and generated again), so a level of its own would
    compile the whole kernel once more.  For the same reason the parts are few and shallow, and those called
    once a phase (not ``_slip``'s step) read ``s.forced`` rather than taking the literal: compiled once, not twice.
    """
    # the forced step cap: the same fraction of the forcing period as H_MAX is of the natural one,
    # as the event search sees signs only at step ends and f oscillates at Omega inside X''
    h_max, period = drive_limits(p) if forced else (H_MAX, np.inf)
    s = Setup(run[T_END], run[ZETA], run[VB], run[ODE_RTOL], run[ODE_ATOL], int(run[MAX_STEPS]), run[DENSE_DT], run[T_TAIL],
              run[STOP_RTOL], run[R_CERT], run[X_EQ], p[RESULTANT] != 0.0, h_max, period, np.bool_(forced))
    outs, w = (samples[0], samples[1], samples[2], samples[3], samples[4]), np.zeros(N_WORK)
    scr = (np.zeros((7, NY_FORCED)), np.zeros(NY_FORCED), np.zeros(NY_FORCED), np.zeros(NY_FORCED), np.zeros(NY_FORCED))
    ring = np.full((4, int(run[MIN_PERIODS]) + 2), np.nan)  # X and times of the last maxima, then minima
    t, x, v, h, fs = 0.0, run[X0], run[V0], 0.0, p[FS]
    # Counters and flags start as np.int64 / np.bool_, not bare constants: a constant reaching a compiled
    # callee has a literal type, for which numba would compile that callee once more.
    k, ne, steps, n_max, n_min = np.int64(0), np.int64(0), np.int64(0), np.int64(0), np.int64(0)
    hold = np.bool_(False)  # a forced stick that met F_s and held: its first monotone piece does not end it again
    cur = Cursor(s.t_tail <= 0.0, s.dense_dt if s.dense_dt > 0.0 else np.inf, np.int64(1))  # (k = 0 is the first sample)
    if len(samples[0]) < 2:
        return 0, 0, FULL, t, h
    mode = first_sample(s, p, (x, v, fs), outs, w)
    k += 1
    while t < s.t_end:
        if mode != 0:
            t_phase = t
            status, at, switched, cur = _slip(forced, s, p, (t, x, v, mode, h, k, steps, n_max, n_min), cur, scr, ring, outs, w)
            t, x, v, h, k, steps, n_max, n_min = at
            if switched:
                mode, hold, ne = slip_end(s, p, fs, (t, t_phase, x, k), events, ne, outs)
        else:
            if forced:
                status, t, x, k, cur = forced_stick(s, p, fs, (t, x, hold, k), cur, outs, w)
            else:
                status, t, x, k, cur = _stick(s, p, fs, (t, x, k), cur, outs, w)
            v = belt_speed(p, s.vb, t) if forced else s.vb
            if status == GO and t < s.t_end:
                mode, tt, fc, cur = after_stick(s, p, fs, (t, x), cur)
                hold = mode == 0  # on F_s but held (moving back inwards, or no consistent slip): on from here
                if mode == 0 and not forced:
                    fs = np.inf  # (possible with F_e = X when zeta V_b is large): the interface holds for good
                elif mode != 0:
                    ne = record_switch(events, ne, t, mode)
                    if not emit(outs, k, tt, x, v, fc, mode, w):
                        return k, ne, FULL, t, h
                    k += 1
        if status != GO:
            return k, ne, status, t, h
    k, status = finish_run(s, p, (t, x, v, k), cur, outs, w)
    return k, ne, status, t, h


@njit(cache=True)
def drive_limits(p):
    """(the step cap, the stroboscopic period) of a time-dependent run: the cap the same fraction of the fastest drive's
    period as H_MAX is of the natural one (the event search sees signs only at step ends); the period the external
    force's, else the moving belt's."""
    om = p[OMEGA] if p[FEX] != 0.0 else 0.0
    if p[VB_AMP] != 0.0:
        om = max(om, p[VB_OMEGA])
    period = 2.0 * math.pi / p[OMEGA] if p[FEX] != 0.0 else 2.0 * math.pi / p[VB_OMEGA]
    return H_MAX / max(1.0, om), period


@njit(cache=True)
def first_sample(s, p, start, outs, w):
    """The mode at the start ``start`` = (x, v, F_s) -- the stick rule's if V_r = 0 -- and its sample at t = 0."""
    x, v, fs = start
    vb = belt_speed(p, s.vb, 0.0)
    if v == vb:
        mode = at_rest(x, s.zeta, s.vb, fs, s.res, p, 0.0)
    else:
        mode = 1 if vb - v > 0.0 else -1
    fc0 = stick_friction(x, s.zeta, vb, stick_load(p, 0.0) if s.forced else 0.0)
    emit(outs, np.int64(0), 0.0, x, v, fc0 if mode == 0 else mode * slip_force_at(p, abs(vb - v)), mode, w)
    return mode


@njit(cache=True)
def after_stick(s, p, fs, where, cur):
    """A stick phase reached |F_e| = F_s at ``where`` = (t, x): the mode the stick rule selects (0: no slip direction
    is consistent) and, if it slips, its sample's time (forced: on the stroboscopic time if within rounding) and
    friction.  Returns (mode, time, friction, cur)."""
    t, x = where
    mode = at_rest(x, s.zeta, s.vb, fs, s.res, p, t)
    if mode == 0 or not s.forced:
        return mode, t, mode * slip_force_at(p, 0.0), cur
    tt, n_strobe = strobe_sample(t, cur.n_strobe, s.period)
    return mode, tt, mode * slip_force_at(p, 0.0), Cursor(cur.tail_done, cur.next_dense, n_strobe)


@njit(cache=True)
def _stick(s, p, fs, at, cur, outs, w):
    """An unforced stick phase from ``at`` = (t, x, k): X' = V_b until |F_e| = F_s or t_end (closed forms).

    Samples at the zero of F_c (where the friction work is split into in and
    out), the tail's start and the dense grid.  Returns (status, t, x, k, cur)
    at its end.
    """
    t, x, k = at
    zeta, vb = s.zeta, s.vb
    tail_done, next_dense = cur.tail_done, cur.next_dense
    stick_mode = np.int64(0)  # (not a literal 0: emit compiles once)
    T = min(s.t_end - t, stick_duration(x, zeta, vb, fs, s.res))
    fcz = -stick_friction(x, zeta, vb, 0.0) / vb if vb != 0.0 else -1.0
    ta = 0.0
    while True:
        tb, tag = T, 0  # the piece's end: the phase's, the zero of F_c, the tail's start or the dense grid's next point
        if ta < fcz < tb:
            tb = fcz
        if not tail_done and ta < s.t_tail - t < tb:
            tb, tag = s.t_tail - t, 1
        if next_dense - t < tb and next_dense - t > ta:
            tb, tag = next_dense - t, 2
        L = tb - ta
        xa = x + vb * ta
        w[0] += 2.0 * zeta * vb * vb * L
        pf = vb * (stick_friction(xa, zeta, vb, 0.0) * L + 0.5 * vb * L * L)
        if pf > 0.0:
            w[1] += pf
        else:
            w[2] -= pf
        ta = tb
        if tag == 1:
            tail_done = True
        if tag == 2:
            next_dense += s.dense_dt
        if ta >= T:
            break
        if not emit(outs, k, t + ta, x + vb * ta, vb, stick_friction(x + vb * ta, zeta, vb, 0.0), stick_mode, w):
            return FULL, t, x, k, Cursor(tail_done, next_dense, cur.n_strobe)
        k += 1
    return GO, t + T, x + vb * T, k, Cursor(tail_done, next_dense, cur.n_strobe)


@njit(cache=True, forceinline=True)
def _slip(forced, s, p, at, cur, scr, ring, outs, w):
    """A slip phase from ``at`` = (t, x, v, mode, h, k, steps, n_max, n_min): Dormand-Prince with the direction fixed.

    Each accepted step is sampled at its events on its dense output, in time order, and at its end (or switch).
    The step and sample loops stay here: an inlined part that takes arrays and calls or makes views keeps their
    reference counting.  Inlined by LLVM into the variant, where :func:`rhs` is inlined in turn (called, the step
    is slower).  Returns (status, at, switched, cur) where it ended.
    """
    (t, x, v, mode, h, k, steps, n_max, n_min), (K, y, yn, ys, tmp) = at, scr
    zeta, vb, d, rtol, atol = s.zeta, s.vb, float(mode), s.rtol, s.atol
    ny, ph = (NY_FORCED if forced else NY), (zeta, vb, d)  # ny a constant: the loops over the state unrolled
    h = _slip_start(y, K, (t, x, v, h), ph, p, forced)
    last, switched = (0.0, 0.0, 0.0, 0.0), False  # the phase's integrals W_dv, W_f, W_heat, W_ex (from ys) at the last sample
    while t < s.t_end and not switched:
        steps += 1
        status = STEP_CAP if steps > s.max_steps else (TINY_STEP if h < 1e-14 * (1.0 + abs(t)) else GO)
        if status != GO:
            return status, (t, x, v, h, k, steps, n_max, n_min), False, cur
        h = min(h, s.h_max, s.t_end - t)  # at most h_max: the event search looks at signs at step ends only
        for i in range(ny):
            tmp[i] = y[i] + h * A21 * K[0, i]
        rhs(tmp, t + C2 * h, d, zeta, vb, p, K[1], forced)
        for i in range(ny):
            tmp[i] = y[i] + h * (A31 * K[0, i] + A32 * K[1, i])
        rhs(tmp, t + C3 * h, d, zeta, vb, p, K[2], forced)
        for i in range(ny):
            tmp[i] = y[i] + h * (A41 * K[0, i] + A42 * K[1, i] + A43 * K[2, i])
        rhs(tmp, t + C4 * h, d, zeta, vb, p, K[3], forced)
        for i in range(ny):
            tmp[i] = y[i] + h * (A51 * K[0, i] + A52 * K[1, i] + A53 * K[2, i] + A54 * K[3, i])
        rhs(tmp, t + C5 * h, d, zeta, vb, p, K[4], forced)
        for i in range(ny):
            tmp[i] = y[i] + h * (A61 * K[0, i] + A62 * K[1, i] + A63 * K[2, i] + A64 * K[3, i] + A65 * K[4, i])
        rhs(tmp, t + h, d, zeta, vb, p, K[5], forced)
        for i in range(ny):
            yn[i] = y[i] + h * (B1 * K[0, i] + B3 * K[2, i] + B4 * K[3, i] + B5 * K[4, i] + B6 * K[5, i])
        rhs(yn, t + h, d, zeta, vb, p, K[6], forced)
        err = _error(h, K, y, yn, (rtol, atol), ny)
        if err > 1.0:
            h *= max(0.2, 0.9 * err ** -0.2)
            continue
        # accepted: events on the dense output, in time order, up to the switch if the step crosses V_r = 0
        switched = _g(np.int64(0), yn, K[6, 1], zeta, belt_speed(p, vb, t + h) if forced == MOVING else vb, d) <= 0.0
        theta_end = _root(np.int64(0), y, K, (t, h), ph, p, forced) if switched else 1.0
        th = 0.0
        # the sample events at the step's end: one dense output and X'' for all three
        gb = _events_at(y, K, (t, h), theta_end, ph, p, ys, tmp, forced)
        while True:
            # at the step's start the dense output is y itself, with X'' = K[0]: no evaluation
            ga = (y[1], K[0, 1], y[1] + 2.0 * zeta * K[0, 1]) if th == 0.0 else _events_at(y, K, (t, h), th, ph, p, ys, tmp, forced)
            best, kind = theta_end, np.int64(-1)  # (a literal -1 would compile _next_sample once more)
            if ga[0] * gb[0] < 0.0 or ga[1] * gb[1] < 0.0 or ga[2] * gb[2] < 0.0:
                best, kind = _first_event((ga, gb), y, K, (t, h), (th, theta_end), ph, p, ys, tmp, forced)
            best, kind, tt, cur = _next_sample(best, kind, (t, h), s, cur)
            if 0 < kind < 4 and tt <= outs[0][k - 1]:  # at the last sample's time (X'' ~ 0 where a slip starts at F_s)
                th = best  # that sample holds the event: a second row would repeat its time
                continue
            dense(y, K, h, best, ys, ny)
            vbt = belt_speed(p, vb, t + best * h) if forced == MOVING else vb
            if kind == 1 or (switched and kind == -1):
                ys[1] = 0.0 if kind == 1 else vbt  # exactly: the section crossing is a sample; the switch
            last = _add_works(w, ys, last, s.forced)  # the works since the phase began, split at the zeros of X'
            if not emit(outs, k, tt, ys[0], ys[1], d * slip_force(p, abs(vbt - ys[1])), mode, w):
                return FULL, (t, x, v, h, k, steps, n_max, n_min), False, cur
            k += 1
            if kind == 1 and not forced and (s.stop_rtol > 0.0 or s.r_cert > 0.0):
                n_max, n_min, stop = _at_section(ring, (n_max, n_min), (tt, ys[0], mode), s, p)
                if stop:
                    return OK, (tt, x, v, h, k, steps, n_max, n_min), False, cur
            th = best
            if kind == -1:
                break
        t += theta_end * h
        if not switched:
            for i in range(NY_FORCED):  # the state and FSAL (a loop: array slice assignment costs compile time)
                y[i] = yn[i]
                K[0, i] = K[6, i]
            h *= min(5.0, max(0.2, 0.9 * max(err, 1e-10) ** -0.2))
        x, v = (ys[0], belt_speed(p, vb, t) if forced == MOVING else vb) if switched else (y[0], y[1])
    return GO, (t, x, v, h, k, steps, n_max, n_min), switched, cur


@njit(cache=True, forceinline=True)
def _local(h, K, i):
    """Component ``i`` of the step's local error estimate: the 5th-order solution less the embedded 4th-order one."""
    return h * (E1 * K[0, i] + E3 * K[2, i] + E4 * K[3, i] + E5 * K[4, i] + E6 * K[5, i] + E7 * K[6, i])


@njit(cache=True, forceinline=True)
def _error(h, K, y, yn, tol, ny):
    """The step's error norm (above 1: rejected) with ``tol`` = (rtol, atol), over the first ``ny`` components: the
    work integrals too, their dense output is what the samples see.  (No call, no view: nothing to count references of.)"""
    rtol, atol = tol
    err = 0.0
    for i in range(ny):
        sc = atol + rtol * max(abs(y[i]), abs(yn[i]))
        err = max(err, abs(_local(h, K, i)) / sc)
    return err


@njit(cache=True, forceinline=True)
def _error_each(h, K, y, yn, rtol, atol):
    """:func:`_error` with an absolute tolerance per component (``atol``, one entry per component of y): a
    structure's positions, velocities and works each in their own units."""
    err = 0.0
    for i in range(len(atol)):
        sc = atol[i] + rtol * max(abs(y[i]), abs(yn[i]))
        err = max(err, abs(_local(h, K, i)) / sc)
    return err


@njit(cache=True)
def _slip_start(y, K, start, ph, p, forced):
    """A slip phase's start ``start`` = (t, x, v, h) into y (the integrals from zero) and its slope into K[0].

    Returns the step to try: h, or a first one from the scales of X, X' and X''.
    """
    t, x, v, h = start
    zeta, vb, d = ph
    y[0], y[1], y[2], y[3], y[4] = x, v, 0.0, 0.0, 0.0
    if forced:
        y[5] = 0.0
    rhs(y, t, d, zeta, vb, p, K[0], forced)
    if h <= 0.0:
        h = 0.01 * max(1e-3, min(1.0, (abs(x) + abs(v) + 1e-6) / (abs(K[0, 1]) + 1e-12)))
    return h


@njit(cache=True)
def _first_event(signs, y, K, step, span, ph, p, ys, tmp, forced):
    """The first of the sample events 1, 2, 3 whose sign changes over theta in ``span`` = (lo, hi] (``signs`` = (ga, gb)
    at its ends): (theta, kind), each located by bisection on the dense output (:func:`_gd`); (hi, -1) if none."""
    ga, gb = signs
    best, kind = span[1], -1
    for kk in range(1, 4):
        if ga[kk - 1] * gb[kk - 1] < 0.0:
            lo, hi = span
            glo = _gd(kk, y, K, step, lo, ph, p, ys, tmp, forced)
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                if mid <= lo or mid >= hi:
                    break
                gm = _gd(kk, y, K, step, mid, ph, p, ys, tmp, forced)
                if gm * glo > 0.0:
                    lo = mid
                    glo = gm
                else:
                    hi = mid
            if hi < best:
                best, kind = hi, kk
    return best, kind


@njit(cache=True, forceinline=True)
def _add_works(w, ys, last, forced):
    """Add the works since the last sample to ``w``, from the phase's integrals ``ys`` now and ``last`` = (W_dv,
    W_f, W_heat, W_ex) then; the friction work split into in and out at the zeros of X'.  Returns the new ``last``."""
    dwf = ys[3] - last[1]
    if dwf > 0.0:
        w[1] += dwf
    else:
        w[2] -= dwf
    w[0] += ys[2] - last[0]
    w[3] += ys[4] - last[2]
    if forced:
        w[4] += ys[5] - last[3]
    return (ys[2], ys[3], ys[4], ys[5] if forced else 0.0)


@njit(cache=True, forceinline=True)
def _next_sample(best, kind, step, s, cur):
    """The first sample in the step ``step`` = (t, h): an event of ``kind`` at theta ``best`` (-1: the step's end), or
    the grid's next point before it -- the tail's start (4), the dense grid (5), a stroboscopic time (6).

    Returns (theta, kind, its time, the :data:`Cursor` past it); forced, a time within rounding of a stroboscopic
    one is put on it (:func:`strobe_sample`).
    """
    t, h = step
    tt = t + best * h
    if not cur.tail_done and s.t_tail <= tt:
        best = (s.t_tail - t) / h
        kind = 4
        tt = s.t_tail
    if cur.next_dense <= tt:
        best = (cur.next_dense - t) / h
        kind = 5
        tt = cur.next_dense
    n_strobe = cur.n_strobe
    if s.forced:
        if n_strobe * s.period < tt - STROBE_TOL * (1.0 + tt):
            tt = n_strobe * s.period
            best = (tt - t) / h
            kind = 6
        tt, n_strobe = strobe_sample(tt, n_strobe, s.period)
    return best, kind, tt, Cursor(cur.tail_done or kind == 4, cur.next_dense + s.dense_dt if kind == 5 else cur.next_dense,
                                  n_strobe)


@njit(cache=True)
def _at_section(ring, counts, sample, s, p):
    """A sample ``sample`` = (t, X, mode) on the section X' = 0 of an unforced slip: pushed to the maxima or minima.

    ``counts`` = (n_max, n_min) pushed so far.  Returns (n_max, n_min, stop): whether the run's end is known --
    inside the certified disc, or its maxima and minima repeating (see :func:`run`).
    """
    n_max, n_min = counts
    tt, x, mode = sample
    falling = float(mode) * slip_force_at(p, abs(s.vb)) - x < 0.0  # X'' at X' = 0
    if falling:
        sec.push_section(ring[0], ring[1], x, tt)
        n_max += 1
    else:
        sec.push_section(ring[2], ring[3], x, tt)
        n_min += 1
    if s.r_cert > 0.0 and mode * s.vb > 0.0 and (x - s.x_eq) ** 2 <= s.r_cert * s.r_cert:
        return n_max, n_min, True  # inside the certified disc
    if s.stop_rtol <= 0.0 or n_min == 0:
        return n_max, n_min, False
    m = ring.shape[1]
    tol = s.stop_rtol * (ring[0, m - 1] - ring[2, m - 1])
    return n_max, n_min, (sec.ring_repeats(ring[0], ring[1], n_max, tol, s.stop_rtol)
                          and sec.ring_repeats(ring[2], ring[3], n_min, tol, s.stop_rtol))


@njit(cache=True)
def _switch(s, p, fs, where):
    """A slip phase from t_phase ended on V_r = 0 at ``where`` = (t, t_phase, x): (the mode that continues, hold, the
    friction force then) -- the switch's, which its sample (the phase's last) is given."""
    t, t_phase, x = where
    mode = at_rest(x, s.zeta, s.vb, fs, s.res, p, t)
    hold = False
    if s.forced and t - t_phase <= NO_SLIP * (1.0 + abs(t)):
        # F_s met at a rounding-level tangency (the held force touching F_s): the slip the
        # rule chose ends as it starts, and would again -- held, past this monotone piece
        mode = 0
        hold = True
    if mode != 0:
        return mode, hold, mode * slip_force_at(p, 0.0)
    return mode, hold, stick_friction(x, s.zeta, belt_speed(p, s.vb, t), stick_load(p, t) if s.forced else 0.0)


@njit(cache=True)
def slip_end(s, p, fs, where, events, ne, outs):
    """A slip phase from t_phase ended on V_r = 0 at ``where`` = (t, t_phase, x, k): the mode that continues and
    hold (:func:`_switch`), the switch recorded (its count after it returned), and the phase's last sample
    (k - 1), the switch's, given its mode and friction force."""
    t, t_phase, x, k = where
    mode, hold, fc = _switch(s, p, fs, (t, t_phase, x))
    ne = record_switch(events, ne, t, mode)
    outs[3][0, k - 1] = mode
    outs[2][0, k - 1] = fc
    return mode, hold, ne


@njit(cache=True)
def finish_run(s, p, end, cur, outs, w):
    """The run's end at ``end`` = (t, x, v, k): a run that ends sticking gets its last sample at t_end (forced: unless
    one is there within rounding, the stroboscopic one).  Returns (k, status)."""
    t, x, v, k = end
    tt, f, before = s.t_end, 0.0, s.t_end
    if s.forced:
        tt, _ = strobe_sample(s.t_end, cur.n_strobe, s.period)
        f, before = stick_load(p, s.t_end), s.t_end - STROBE_TOL * (1.0 + s.t_end)
    if outs[0][k - 1] < before:
        if not emit(outs, k, tt, x, v, stick_friction(x, s.zeta, belt_speed(p, s.vb, s.t_end), f), np.int64(0), w):
            return k, FULL
        k += 1
    return k, OK


@njit(cache=True)
def _events_at(y, K, step, theta, ph, p, ys, tmp, forced):
    """The sample events 1, 2, 3 on the dense output of the step ``step`` = (t, h) at theta: the values :func:`_gd`
    gives each, from one evaluation of the dense output and X'' (the three read the same two).

    ``ph`` = (zeta, V_b, d) is the slip phase's; ``ys``, ``tmp`` scratch.
    """
    t, h = step
    zeta, vb, d = ph
    dense(y, K, h, theta, ys, np.int64(2))
    rhs(ys, t + theta * h, d, zeta, vb, p, tmp, forced)
    return ys[1], tmp[1], ys[1] + 2.0 * zeta * tmp[1]


@njit(cache=True)
def _gd(kind, y, K, step, theta, ph, p, ys, tmp, forced):
    """Event function ``kind`` on the dense output of the step ``step`` = (t, h) at theta (``ph``: :func:`_events_at`)."""
    t, h = step
    zeta, vb, d = ph
    dense(y, K, h, theta, ys, np.int64(2))  # X and X' are all the event functions read
    rhs(ys, t + theta * h, d, zeta, vb, p, tmp, forced)
    return _g(kind, ys, tmp[1], zeta, belt_speed(p, vb, t + theta * h) if forced == MOVING else vb, d)


@njit(cache=True)
def _root(kind, y, K, step, ph, p, forced):
    """The switch: first theta in (0, 1] where d (V_b - X') <= 0 on the dense output (:func:`_gd`)."""
    ys = np.zeros(NY_FORCED)
    tmp = np.zeros(NY_FORCED)
    lo, hi = 0.0, 1.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _gd(kind, y, K, step, mid, ph, p, ys, tmp, forced) > 0.0:
            lo = mid
        else:
            hi = mid
    return hi


# -- the stroboscopic samples and the forced stick phase -----------------------------------------------

@njit(cache=True, forceinline=True)
def strobe_sample(tt, n, period):
    """A sample at ``tt``: (its time, the next stroboscopic index).

    A sample within rounding of the next stroboscopic time n 2 pi / Omega is
    put on it exactly and stands for it; the index moves past ``tt``.
    """
    tol = STROBE_TOL * (1.0 + abs(tt))
    if abs(tt - n * period) <= tol:
        tt = n * period
    while n * period <= tt + tol:
        n += 1
    return tt, n


@njit(cache=True)
def _stick_work(xs, ts, ta, tb, zeta, vb, p, w):
    """Add the works of stick over [ta, tb] (F_c of one sign there) to ``w``: closed forms.

    X' = V_b, F_c = X + 2 zeta V_b - f: P_f = V_b F_c, W_ex = V_b int f, no heat.  On a moving belt (V_b of one
    sign there too) by quadrature (:func:`.stick.belt_stick_work`).
    """
    if p[VB_AMP] != 0.0:
        dv, pf, ex = belt_stick_work(xs, ts, ta, tb, zeta, vb, p)
        w[0] += dv
        if pf > 0.0:
            w[1] += pf
        else:
            w[2] -= pf
        w[4] += ex
        return
    L = tb - ta
    xa = xs + vb * (ta - ts)
    om, ph = p[OMEGA], p[PHI]
    # int f over [ta, tb] = F_ex / Omega (sin(Omega tb + phi) - sin(Omega ta + phi)), without the cancellation
    fint = 2.0 * p[FEX] / om * math.cos(om * 0.5 * (ta + tb) + ph) * math.sin(0.5 * om * L)
    w[0] += 2.0 * zeta * vb * vb * L
    pf = vb * (stick_friction(xa, zeta, vb, 0.0) * L + 0.5 * vb * L * L - fint)
    if pf > 0.0:
        w[1] += pf
    else:
        w[2] -= pf
    w[4] += vb * fint


@njit(cache=True)
def forced_stick(s, p, fs, at, cur, outs, w):
    """A forced stick phase from ``at`` = (t, x, hold, k): the held force F_e - f(tau) varies; to where it leaves
    the static bound (:func:`_stick_exit`) or t_end.  Returns (status, t, x, k, cur) at its end.

    Samples at the zeros of F_c (where the friction work is split into in and out), the tail's start, the dense
    grid and the stroboscopic times (``cur``, a :data:`Cursor`); not at its end (the caller's sample).
    """
    ts, xs, hold, k = at
    zeta, vb = s.zeta, s.vb
    te = _stick_exit(xs, ts, s.t_end, hold, zeta, vb, fs, s.res, p)
    tail_done, next_dense, n_strobe = cur
    ta = ts
    stick_mode = np.int64(0)  # (not a literal 0: emit compiles once)
    while True:
        tb = te
        tag = 0
        if not tail_done and ta < s.t_tail < tb:
            tb = s.t_tail
            tag = 1
        if ta < next_dense < tb:
            tb = next_dense
            tag = 2
        ns = n_strobe * s.period
        if ns < tb - STROBE_TOL * (1.0 + tb):
            tb = max(ns, ta)  # (a time held on the bound may have passed it by rounding)
            tag = 3
        moving = p[VB_AMP] != 0.0
        z = _friction_zero(xs, ts, ta, tb, zeta, vb, s.res, p) if vb != 0.0 or moving else np.inf  # (V_b = 0: no work)
        if moving:  # P_f = V_b F_c changes sign where V_b does too
            z = min(z, belt_zero(ta, vb, p))
        if z < tb:
            tb = z
            tag = 4
        _stick_work(xs, ts, ta, tb, zeta, vb, p, w)
        ta = tb
        if tag == 0:
            return GO, te, stick_x(xs, ts, te, vb, p), k, Cursor(tail_done, next_dense, n_strobe)
        if tag == 1:
            tail_done = True
        if tag == 2:
            next_dense += s.dense_dt
        tt, n_strobe = strobe_sample(tb, n_strobe, s.period)
        xb = stick_x(xs, ts, tb, vb, p)
        vbb = belt_speed(p, vb, tb)
        if not emit(outs, k, tt, xb, vbb, stick_friction(xb, zeta, vbb, stick_load(p, tb)), stick_mode, w):
            return FULL, ts, xs, k, Cursor(tail_done, next_dense, n_strobe)
        k += 1
