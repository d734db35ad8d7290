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

``slip_force(p, speed)`` is a module global: for a user-defined slip law the
kernel is rebuilt around the user's function (see
:func:`frictionflow.solvers.adaptive.kernel_for`).
"""

from __future__ import annotations


import math

import numpy as np
from numba import njit

from . import codes
from .friction import (FD, FEX, FS, LAW, LAW_A, LAW_B, LAW_C, OMEGA, PHI, RESULTANT, external_force, external_force_rate,
                       rest_mode, slip_magnitude, stick_duration, stick_friction)
from . import sections as sec
from .layout import N_WORK
from .records import (DENSE_DT, MAX_STEPS, MIN_PERIODS, ODE_ATOL, ODE_RTOL, R_CERT, STOP_RTOL, T_END, T_TAIL, V0, VB, X0, X_EQ,
                      ZETA)
from .samples import emit
from .stick import exit_time as _stick_exit, friction_zero as _friction_zero  # the forced stick's walk, stated once

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
    then ``out[5]`` is W_ex's integrand X' f.
    """
    x = y[0]
    v = y[1]
    vr = vb - v
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
    """Mode at V_r = 0 at time t by Coulomb's stick rule (:func:`~frictionflow.core.friction.rest_mode`)."""
    return rest_mode(x, zeta, vb, fs, res, slip_force_at(p, 0.0), external_force(p, t), external_force_rate(p, t))


@njit(cache=True)
def _g(kind, y, a, zeta, vb, d):
    """Event functions: 0 the switch d (V_b - X') (> 0 inside), 1 X', 2 X'', 3 X' + 2 zeta X''."""
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
    and the switches to those of ``events`` = (t, mode) (:mod:`.records`,
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


@njit(cache=True, forceinline=True)
def _run(forced, run, p, samples, events):
    """:func:`run`'s body; ``forced`` is a constant at each of its two call sites (two specialisations)."""
    x0, v0, t_end, zeta, vb = run[X0], run[V0], run[T_END], run[ZETA], run[VB]
    rtol, atol, max_steps = run[ODE_RTOL], run[ODE_ATOL], int(run[MAX_STEPS])
    dense_dt, t_tail = run[DENSE_DT], run[T_TAIL]
    stop_rtol, min_periods, r_cert, x_eq = run[STOP_RTOL], int(run[MIN_PERIODS]), run[R_CERT], run[X_EQ]
    out_t, out_y, out_fc, out_mode, out_w = samples
    ev_t, ev_mode = events
    fs = p[FS]
    res = p[RESULTANT] != 0.0
    ny = NY_FORCED if forced else NY
    # the forced step cap: the same fraction of the forcing period as H_MAX is of the natural one,
    # as the event search sees signs only at step ends and f oscillates at Omega inside X''
    h_max = H_MAX / max(1.0, p[OMEGA]) if forced else H_MAX
    period = 2.0 * math.pi / p[OMEGA] if forced else np.inf
    # Counters and flags start as np.int64 / np.bool_, not bare constants: a constant reaching a compiled
    # callee has a literal type, for which numba would compile that callee once more.
    n_strobe = np.int64(1)  # the next stroboscopic time is n_strobe * period (k = 0 is the first sample)
    hold = np.bool_(False)  # a forced stick that met F_s and held: its first monotone piece does not end it again
    stick_mode = np.int64(0)  # the stick mode, written with the samples
    K = np.zeros((7, NY_FORCED))
    y = np.zeros(NY_FORCED)
    yn = np.zeros(NY_FORCED)
    ys = np.zeros(NY_FORCED)
    tmp = np.zeros(NY_FORCED)
    w = np.zeros(N_WORK)  # W_dv, W_fin, W_fout, W_heat, W_ex since the last sample
    wf_last = 0.0
    t = 0.0
    x, v = x0, v0
    if v0 == vb:
        mode = at_rest(x0, zeta, vb, fs, res, p, 0.0)
    else:
        mode = 1 if vb - v0 > 0.0 else -1
    k = np.int64(0)
    ne = 0
    steps = 0
    h = 0.0
    ring = np.full((4, int(min_periods) + 2), np.nan)  # X and times of the last maxima, then minima
    n_max = 0
    n_min = 0
    outs = (out_t, out_y, out_fc, out_mode, out_w)
    if len(out_t) < 2:
        return 0, 0, FULL, t, h
    fc0 = stick_friction(x, zeta, vb, external_force(p, 0.0) if forced else 0.0)
    emit(outs, k, t, x, v, fc0 if mode == 0 else mode * slip_force_at(p, abs(vb - v)), mode, w)
    k += 1
    next_dense = dense_dt if dense_dt > 0.0 else np.inf
    tail_done = t_tail <= 0.0
    while t < t_end:
        if mode == 0 and forced:
            # stick with the held force F_e - f(tau) varying: to where it leaves the static bound
            te = _stick_exit(x, t, t_end, hold, zeta, vb, fs, res, p)
            k, tail_done, next_dense, n_strobe, room = _stick_walk(
                outs, k, w, x, t, te, zeta, vb, p, t_tail, tail_done, next_dense, dense_dt, n_strobe, period)
            if not room:
                return k, ne, FULL, t, h
            x += vb * (te - t)
            t = te
            v = vb
            if t >= t_end:
                break
            mode = at_rest(x, zeta, vb, fs, res, p, t)
            hold = mode == 0  # on F_s but held (moving back inwards, or no consistent slip): on from here
            if hold:
                continue
            if ne < len(ev_t):
                ev_t[ne] = t
                ev_mode[ne] = mode
            ne += 1
            tt, n_strobe = _strobe(t, n_strobe, period)
            if not emit(outs, k, tt, x, v, mode * slip_force_at(p, 0.0), mode, w):
                return k, ne, FULL, t, h
            k += 1
        elif mode == 0:
            # stick: X' = V_b until |F_e| = F_s
            T = min(t_end - t, stick_duration(x, zeta, vb, fs, res))
            fcz = -stick_friction(x, zeta, vb, 0.0) / vb if vb != 0.0 else -1.0
            ta = 0.0
            while True:
                tb = T
                tag = 0
                if ta < fcz < tb:
                    tb = fcz
                if not tail_done and ta < t_tail - t < tb:
                    tb = t_tail - t
                    tag = 1
                if next_dense - t < tb and next_dense - t > ta:
                    tb = next_dense - t
                    tag = 2
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
                    next_dense += dense_dt
                if ta >= T:
                    break
                if not emit(outs, k, t + ta, x + vb * ta, vb, stick_friction(x + vb * ta, zeta, vb, 0.0), stick_mode, w):
                    return k, ne, FULL, t, h
                k += 1
            t += T
            x += vb * T
            v = vb
            if t >= t_end:
                break
            mode = at_rest(x, zeta, vb, fs, res, p, t)
            if mode == 0:
                # |F_e| = F_s but neither slip direction is consistent (possible with
                # F_e = X when zeta V_b is large): the interface holds for good
                fs = np.inf
                continue
            if ne < len(ev_t):
                ev_t[ne] = t
                ev_mode[ne] = mode
            ne += 1
            if not emit(outs, k, t, x, v, mode * slip_force_at(p, 0.0), mode, w):
                return k, ne, FULL, t, h
            k += 1
        else:
            # slip: Dormand-Prince from (x, v) with the direction fixed
            d = float(mode)
            t_phase = t
            y[0], y[1], y[2], y[3], y[4] = x, v, 0.0, 0.0, 0.0
            if forced:
                y[5] = 0.0
            wf_last = 0.0  # the phase's integrals (from ys) at the last sample
            wdv_last = 0.0
            wq_last = 0.0
            wx_last = 0.0
            rhs(y, t, d, zeta, vb, p, K[0], forced)
            if h <= 0.0:
                h = 0.01 * max(1e-3, min(1.0, (abs(x) + abs(v) + 1e-6) / (abs(K[0, 1]) + 1e-12)))
            switched = False
            while t < t_end and not switched:
                steps += 1
                if steps > max_steps:
                    return k, ne, STEP_CAP, t, h
                if h < 1e-14 * (1.0 + abs(t)):
                    return k, ne, TINY_STEP, t, h
                # at most h_max: the event search looks at signs at step ends only
                h = min(h, h_max, t_end - t)
                # the stages, each at its own time
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
                err = 0.0
                for i in range(ny):  # the work integrals too: their dense output is what samples see
                    e = h * (E1 * K[0, i] + E3 * K[2, i] + E4 * K[3, i] + E5 * K[4, i] + E6 * K[5, i] + E7 * K[6, i])
                    sc = atol + rtol * max(abs(y[i]), abs(yn[i]))
                    err = max(err, abs(e) / sc)
                if err > 1.0:
                    h *= max(0.2, 0.9 * err ** -0.2)
                    continue
                # accepted: events on the dense output, in time order
                theta_end = 1.0
                g_sw = _g(np.int64(0), yn, K[6, 1], zeta, vb, d)
                if g_sw <= 0.0:
                    theta_end = _root(np.int64(0), y, K, t, h, zeta, vb, d, p, forced)
                    switched = True
                th = 0.0
                # the sample events at the step's end: one dense output and X'' for all three
                gb = _events_at(y, K, t, h, theta_end, zeta, vb, d, p, ys, tmp, forced)
                while True:
                    # the earliest sample point in (th, theta_end]
                    best = theta_end
                    kind = -1
                    # at the step's start the dense output is y itself, with X'' = K[0]: no evaluation
                    ga = _events_of(y, K[0, 1], zeta) if th == 0.0 else _events_at(y, K, t, h, th, zeta, vb, d, p, ys, tmp, forced)
                    for kk in range(1, 4):
                        if ga[kk - 1] * gb[kk - 1] < 0.0:
                            r = _root_between(kk, y, K, t, h, th, theta_end, zeta, vb, d, p, ys, tmp, forced)
                            if r < best:
                                best = r
                                kind = kk
                    tt = t + best * h
                    if not tail_done and t_tail <= tt:
                        best = (t_tail - t) / h
                        kind = 4
                        tt = t_tail
                    if next_dense <= tt:
                        best = (next_dense - t) / h
                        kind = 5
                        tt = next_dense
                    if forced and n_strobe * period < tt - STROBE_TOL * (1.0 + tt):
                        tt = n_strobe * period
                        best = (tt - t) / h
                        kind = 6
                    dense(y, K, h, best, ys, ny)
                    if kind == 1:
                        ys[1] = 0.0  # exactly: the section crossing is a sample
                    # works since the phase began, split at the zeros of X'
                    dwf = ys[3] - wf_last
                    if dwf > 0.0:
                        w[1] += dwf
                    else:
                        w[2] -= dwf
                    wf_last = ys[3]
                    w[0] += ys[2] - wdv_last
                    w[3] += ys[4] - wq_last
                    wdv_last = ys[2]
                    wq_last = ys[4]
                    if forced:
                        w[4] += ys[5] - wx_last
                        wx_last = ys[5]
                        tt, n_strobe = _strobe(tt, n_strobe, period)
                    if kind == 4:
                        tail_done = True
                    if kind == 5:
                        next_dense += dense_dt
                    if switched and kind == -1:
                        ys[1] = vb  # exactly at the switch
                    if not emit(outs, k, tt, ys[0], ys[1], d * slip_force(p, abs(vb - ys[1])), mode, w):
                        return k, ne, FULL, t, h
                    k += 1
                    if kind == 1 and not forced and (stop_rtol > 0.0 or r_cert > 0.0):
                        falling = d * slip_force_at(p, abs(vb)) - ys[0] < 0.0  # X'' at X' = 0
                        if falling:
                            sec.push_section(ring[0], ring[1], ys[0], tt)
                            n_max += 1
                        else:
                            sec.push_section(ring[2], ring[3], ys[0], tt)
                            n_min += 1
                        if _known_end(ring, n_max, n_min, ys[0], mode, vb, stop_rtol, r_cert, x_eq):
                            return k, ne, OK, tt, h
                    th = best
                    if kind == -1:
                        break
                t += theta_end * h
                if switched:
                    x, v = ys[0], vb
                else:
                    for i in range(ny):
                        y[i] = yn[i]
                    for i in range(K.shape[1]):  # FSAL (a loop: array slice assignment costs compile time)
                        K[0, i] = K[6, i]
                    x, v = y[0], y[1]
                    h *= min(5.0, max(0.2, 0.9 * max(err, 1e-10) ** -0.2))
            if switched:
                new = at_rest(x, zeta, vb, fs, res, p, t)
                hold = False
                if forced and t - t_phase <= NO_SLIP * (1.0 + abs(t)):
                    # F_s met at a rounding-level tangency (the held force touching F_s): the slip the
                    # rule chose ends as it starts, and would again -- held, past this monotone piece
                    new = 0
                    hold = True
                if ne < len(ev_t):
                    ev_t[ne] = t
                    ev_mode[ne] = new
                ne += 1
                mode = new
                out_mode[0, k - 1] = mode
                if mode != 0:
                    out_fc[0, k - 1] = mode * slip_force_at(p, 0.0)
                else:
                    out_fc[0, k - 1] = stick_friction(x, zeta, vb, external_force(p, t) if forced else 0.0)
    if forced:
        if out_t[k - 1] < t_end - STROBE_TOL * (1.0 + t_end):  # a run that ends sticking
            tt, n_strobe = _strobe(t_end, n_strobe, period)
            if not emit(outs, k, tt, x, v, stick_friction(x, zeta, vb, external_force(p, t_end)), stick_mode, w):
                return k, ne, FULL, t, h
            k += 1
    elif out_t[k - 1] < t_end:  # a run that ends sticking
        if not emit(outs, k, t_end, x, v, stick_friction(x, zeta, vb, 0.0), stick_mode, w):
            return k, ne, FULL, t, h
        k += 1
    return k, ne, OK, t, h


@njit(cache=True)
def _known_end(ring, n_max, n_min, x, mode, vb, stop_rtol, r_cert, x_eq):
    """At a section: inside the certified disc, or maxima and minima repeating (see :func:`run`)."""
    if r_cert > 0.0 and mode * vb > 0.0 and (x - x_eq) ** 2 <= r_cert * r_cert:
        return True
    if stop_rtol <= 0.0 or n_min == 0:
        return False
    m = ring.shape[1]
    tol = stop_rtol * (ring[0, m - 1] - ring[2, m - 1])
    return sec.ring_repeats(ring[0], ring[1], n_max, tol, stop_rtol) and sec.ring_repeats(ring[2], ring[3], n_min, tol, stop_rtol)


@njit(cache=True, forceinline=True)
def _events_of(y, a, zeta):
    """The sample events 1, 2, 3 of :func:`_g` at state ``y`` with X'' = ``a``."""
    return y[1], a, y[1] + 2.0 * zeta * a


@njit(cache=True)
def _events_at(y, K, t, h, theta, zeta, vb, d, p, ys, tmp, forced):
    """The sample events 1, 2, 3 on the dense output at theta: the values :func:`_gd` gives each, from one
    evaluation of the dense output and X'' (the three read the same two)."""
    dense(y, K, h, theta, ys, np.int64(2))
    rhs(ys, t + theta * h, d, zeta, vb, p, tmp, forced)
    return _events_of(ys, tmp[1], zeta)


@njit(cache=True)
def _gd(kind, y, K, t, h, theta, zeta, vb, d, p, ys, tmp, forced):
    """Event function ``kind`` on the dense output of the step [t, t + h] at theta."""
    dense(y, K, h, theta, ys, np.int64(2))  # X and X' are all the event functions read
    rhs(ys, t + theta * h, d, zeta, vb, p, tmp, forced)
    return _g(kind, ys, tmp[1], zeta, vb, d)


@njit(cache=True)
def _root_between(kind, y, K, t, h, lo, hi, zeta, vb, d, p, ys, tmp, forced):
    """Bisection for a sign change of event ``kind`` on the dense output, theta in (lo, hi]."""
    glo = _gd(kind, y, K, t, h, lo, zeta, vb, d, p, ys, tmp, forced)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        gm = _gd(kind, y, K, t, h, mid, zeta, vb, d, p, ys, tmp, forced)
        if gm * glo > 0.0:
            lo = mid
            glo = gm
        else:
            hi = mid
    return hi


@njit(cache=True)
def _root(kind, y, K, t, h, zeta, vb, d, p, forced):
    """The switch: first theta in (0, 1] where d (V_b - X') <= 0 on the dense output."""
    ys = np.zeros(NY_FORCED)
    tmp = np.zeros(NY_FORCED)
    lo, hi = 0.0, 1.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _gd(kind, y, K, t, h, mid, zeta, vb, d, p, ys, tmp, forced) > 0.0:
            lo = mid
        else:
            hi = mid
    return hi


# -- the stroboscopic samples and the forced stick phase -----------------------------------------------

@njit(cache=True, forceinline=True)
def _strobe(tt, n, period):
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

    X' = V_b, F_c = X + 2 zeta V_b - f: P_f = V_b F_c, W_ex = V_b int f, no heat.
    """
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
def _stick_walk(outs, k, w, xs, ts, te, zeta, vb, p, t_tail, tail_done, next_dense, dense_dt, n_strobe, period):
    """A forced stick phase's samples and works from (ts, xs) to its end ``te`` (excluded: the caller's sample).

    Samples at the zeros of F_c (where the friction work is split into in
    and out), the tail's start, the dense grid and the stroboscopic times.
    Returns (k, tail_done, next_dense, n_strobe, room).
    """
    ta = ts
    res = p[RESULTANT] != 0.0
    stick_mode = np.int64(0)  # (not a literal 0: emit compiles once)
    while True:
        tb = te
        tag = 0
        if not tail_done and ta < t_tail < tb:
            tb = t_tail
            tag = 1
        if ta < next_dense < tb:
            tb = next_dense
            tag = 2
        ns = n_strobe * period
        if ns < tb - STROBE_TOL * (1.0 + tb):
            tb = max(ns, ta)  # (a time held on the bound may have passed it by rounding)
            tag = 3
        z = _friction_zero(xs, ts, ta, tb, zeta, vb, res, p) if vb != 0.0 else np.inf  # (V_b = 0: no friction work)
        if z < tb:
            tb = z
            tag = 4
        _stick_work(xs, ts, ta, tb, zeta, vb, p, w)
        ta = tb
        if tag == 0:
            return k, tail_done, next_dense, n_strobe, True
        if tag == 1:
            tail_done = True
        if tag == 2:
            next_dense += dense_dt
        tt, n_strobe = _strobe(tb, n_strobe, period)
        xb = xs + vb * (tb - ts)
        if not emit(outs, k, tt, xb, vb, stick_friction(xb, zeta, vb, external_force(p, tb)), stick_mode, w):
            return k, tail_done, next_dense, n_strobe, False
        k += 1
