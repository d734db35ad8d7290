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

``slip_force(p, speed)`` is a module global: for a user-defined slip law the
kernel is rebuilt around the user's function (see
:func:`frictionflow.solvers.adaptive.kernel_for`).
"""

from __future__ import annotations


import numpy as np
from numba import njit

from .friction import FS, RESULTANT, rest_mode, slip_magnitude_of
from . import sections as sec
from .layout import N_WORK
from .samples import emit

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
NY = 5  # X, X', W_dv, W_f (signed), W_heat
H_MAX = 0.25  # about 1/25 of the natural period
OK, STEP_CAP, TINY_STEP, FULL = 0, 1, 2, 3
EPS = 2.220446049250313e-16


@njit(cache=True)
def slip_force(p, speed):
    """Friction magnitude while slipping at ``speed`` (a built-in law)."""
    return slip_magnitude_of(p, speed)


@njit(cache=True)
def rhs(y, d, zeta, vb, p, out):
    """Slip in direction d: X'' = d F(|V_r|) - X - 2 zeta X', with the work integrands."""
    x = y[0]
    v = y[1]
    vr = vb - v
    f = d * slip_force(p, abs(vr))
    out[0] = v
    out[1] = f - x - 2.0 * zeta * v
    out[2] = 2.0 * zeta * v * v
    out[3] = v * f
    out[4] = f * vr


@njit(cache=True)
def dense(y0, K, h, theta, out):
    """The continuous extension at y0 + theta h."""
    q1 = theta
    q2 = theta * theta
    q3 = q2 * theta
    q4 = q3 * theta
    for i in range(NY):
        acc = 0.0
        for s in range(7):
            acc += K[s, i] * (P[s, 0] * q1 + P[s, 1] * q2 + P[s, 2] * q3 + P[s, 3] * q4)
        out[i] = y0[i] + h * acc


@njit(cache=True)
def at_rest(x, zeta, vb, fs, res, p):
    """Mode at V_r = 0 by Coulomb's stick rule (:func:`~frictionflow.core.friction.rest_mode`)."""
    return rest_mode(x, zeta, vb, fs, res, slip_force(p, 0.0), 0.0, 0.0)


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
def run(x0, v0, t_end, zeta, vb, p, rtol, atol, max_steps, dense_dt, t_tail, stop,
        out_t, out_x, out_v, out_fc, out_mode, out_w, ev_t, ev_mode):
    """Integrate to ``t_end``; returns (samples, events, status, t, h) -- t, h where it stopped.

    ``stop`` = (stop_rtol, min_periods, r_cert, x_eq) lets a run whose end is
    already known stop early, at a section X' = 0 (sweeps; zeros: off): when it
    is inside the certified disc of radius ``r_cert`` about ``x_eq``
    (:mod:`.certificate`), or when its last ``min_periods + 1`` maxima and
    minima of X and their periods repeat to ``stop_rtol`` of the amplitude.
    """
    fs = p[FS]
    res = p[RESULTANT] != 0.0
    K = np.empty((7, NY))
    y = np.zeros(NY)
    yn = np.empty(NY)
    ys = np.empty(NY)
    tmp = np.empty(NY)
    w = np.zeros(N_WORK)  # W_dv, W_fin, W_fout, W_heat, W_ex since the last sample
    wf_last = 0.0
    t = 0.0
    x, v = x0, v0
    if v0 == vb:
        mode = at_rest(x0, zeta, vb, fs, res, p)
    else:
        mode = 1 if vb - v0 > 0.0 else -1
    k = 0
    ne = 0
    steps = 0
    h = 0.0
    stop_rtol, min_periods, r_cert, x_eq = stop
    ring = np.full((4, int(min_periods) + 2), np.nan)  # X and times of the last maxima, then minima
    n_max = 0
    n_min = 0
    outs = (out_t, out_x, out_v, out_fc, out_mode, out_w)
    if len(out_t) < 2:
        return 0, 0, FULL, t, h
    emit(outs, 0, t, x, v, (x + 2.0 * zeta * vb) if mode == 0 else mode * slip_force(p, abs(vb - v)), mode, w)
    k = 1
    next_dense = dense_dt if dense_dt > 0.0 else np.inf
    tail_done = t_tail <= 0.0
    while t < t_end:
        if mode == 0:
            # stick: X' = V_b until |F_e| = F_s
            fe0 = x + 2.0 * zeta * vb if res else x
            T = t_end - t
            if vb > 0.0:
                T = min(T, (fs - fe0) / vb)
            elif vb < 0.0:
                T = min(T, (-fs - fe0) / vb)
            T = max(T, 0.0)
            fcz = -(x + 2.0 * zeta * vb) / vb if vb != 0.0 else -1.0
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
                pf = vb * ((xa + 2.0 * zeta * vb) * L + 0.5 * vb * L * L)
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
                if not emit(outs, k, t + ta, x + vb * ta, vb, x + vb * ta + 2.0 * zeta * vb, 0, w):
                    return k, ne, FULL, t, h
                k += 1
            t += T
            x += vb * T
            v = vb
            if t >= t_end:
                break
            mode = at_rest(x, zeta, vb, fs, res, p)
            if mode == 0:
                # |F_e| = F_s but neither slip direction is consistent (possible with
                # F_e = X when zeta V_b is large): the interface holds for good
                fs = np.inf
                continue
            if ne < len(ev_t):
                ev_t[ne] = t
                ev_mode[ne] = mode
            ne += 1
            if not emit(outs, k, t, x, v, mode * slip_force(p, 0.0), mode, w):
                return k, ne, FULL, t, h
            k += 1
        else:
            # slip: Dormand-Prince from (x, v) with the direction fixed
            d = float(mode)
            y[0], y[1], y[2], y[3], y[4] = x, v, 0.0, 0.0, 0.0
            wf_last = 0.0  # the phase's integrals (from ys) at the last sample
            wdv_last = 0.0
            wq_last = 0.0
            rhs(y, d, zeta, vb, p, K[0])
            if h <= 0.0:
                h = 0.01 * max(1e-3, min(1.0, (abs(x) + abs(v) + 1e-6) / (abs(K[0, 1]) + 1e-12)))
            switched = False
            while t < t_end and not switched:
                steps += 1
                if steps > max_steps:
                    return k, ne, STEP_CAP, t, h
                if h < 1e-14 * (1.0 + abs(t)):
                    return k, ne, TINY_STEP, t, h
                # at most H_MAX: the event search looks at signs at step ends only
                h = min(h, H_MAX, t_end - t)
                # the stages
                for i in range(NY):
                    tmp[i] = y[i] + h * A21 * K[0, i]
                rhs(tmp, d, zeta, vb, p, K[1])
                for i in range(NY):
                    tmp[i] = y[i] + h * (A31 * K[0, i] + A32 * K[1, i])
                rhs(tmp, d, zeta, vb, p, K[2])
                for i in range(NY):
                    tmp[i] = y[i] + h * (A41 * K[0, i] + A42 * K[1, i] + A43 * K[2, i])
                rhs(tmp, d, zeta, vb, p, K[3])
                for i in range(NY):
                    tmp[i] = y[i] + h * (A51 * K[0, i] + A52 * K[1, i] + A53 * K[2, i] + A54 * K[3, i])
                rhs(tmp, d, zeta, vb, p, K[4])
                for i in range(NY):
                    tmp[i] = y[i] + h * (A61 * K[0, i] + A62 * K[1, i] + A63 * K[2, i] + A64 * K[3, i] + A65 * K[4, i])
                rhs(tmp, d, zeta, vb, p, K[5])
                for i in range(NY):
                    yn[i] = y[i] + h * (B1 * K[0, i] + B3 * K[2, i] + B4 * K[3, i] + B5 * K[4, i] + B6 * K[5, i])
                rhs(yn, d, zeta, vb, p, K[6])
                err = 0.0
                for i in range(NY):  # the work integrals too: their dense output is what samples see
                    e = h * (E1 * K[0, i] + E3 * K[2, i] + E4 * K[3, i] + E5 * K[4, i] + E6 * K[5, i] + E7 * K[6, i])
                    sc = atol + rtol * max(abs(y[i]), abs(yn[i]))
                    err = max(err, abs(e) / sc)
                if err > 1.0:
                    h *= max(0.2, 0.9 * err ** -0.2)
                    continue
                # accepted: events on the dense output, in time order
                theta_end = 1.0
                g_sw = _g(0, yn, K[6, 1], zeta, vb, d)
                if g_sw <= 0.0:
                    theta_end = _root(0, y, K, h, zeta, vb, d, p)
                    switched = True
                th = 0.0
                while True:
                    # the earliest sample point in (th, theta_end]
                    best = theta_end
                    kind = -1
                    for kk in range(1, 4):
                        # at the step's start the dense output is y itself, with X'' = K[0]: no evaluation
                        ga = _g(kk, y, K[0, 1], zeta, vb, d) if th == 0.0 else _gd(kk, y, K, h, th, zeta, vb, d, p, ys, tmp)
                        gb = _gd(kk, y, K, h, theta_end, zeta, vb, d, p, ys, tmp)
                        if ga * gb < 0.0:
                            r = _root_between(kk, y, K, h, th, theta_end, zeta, vb, d, p, ys, tmp)
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
                    dense(y, K, h, best, ys)
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
                    if kind == 4:
                        tail_done = True
                    if kind == 5:
                        next_dense += dense_dt
                    if switched and kind == -1:
                        ys[1] = vb  # exactly at the switch
                    if not emit(outs, k, tt, ys[0], ys[1], d * slip_force(p, abs(vb - ys[1])), mode, w):
                        return k, ne, FULL, t, h
                    k += 1
                    if kind == 1 and (stop_rtol > 0.0 or r_cert > 0.0):
                        falling = d * slip_force(p, abs(vb)) - ys[0] < 0.0  # X'' at X' = 0
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
                    for i in range(NY):
                        y[i] = yn[i]
                    K[0, :] = K[6, :]
                    x, v = y[0], y[1]
                    h *= min(5.0, max(0.2, 0.9 * max(err, 1e-10) ** -0.2))
            if switched:
                new = at_rest(x, zeta, vb, fs, res, p)
                if ne < len(ev_t):
                    ev_t[ne] = t
                    ev_mode[ne] = new
                ne += 1
                mode = new
                out_mode[k - 1] = mode
                out_fc[k - 1] = (x + 2.0 * zeta * vb) if mode == 0 else mode * slip_force(p, 0.0)
    if out_t[k - 1] < t_end:  # a run that ends sticking
        if not emit(outs, k, t_end, x, v, x + 2.0 * zeta * vb, 0, w):
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


@njit(cache=True)
def _gd(kind, y, K, h, theta, zeta, vb, d, p, ys, tmp):
    dense(y, K, h, theta, ys)
    rhs(ys, d, zeta, vb, p, tmp)
    return _g(kind, ys, tmp[1], zeta, vb, d)


@njit(cache=True)
def _root_between(kind, y, K, h, lo, hi, zeta, vb, d, p, ys, tmp):
    """Bisection for a sign change of event ``kind`` on the dense output, theta in (lo, hi]."""
    glo = _gd(kind, y, K, h, lo, zeta, vb, d, p, ys, tmp)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        gm = _gd(kind, y, K, h, mid, zeta, vb, d, p, ys, tmp)
        if gm * glo > 0.0:
            lo = mid
            glo = gm
        else:
            hi = mid
    return hi


@njit(cache=True)
def _root(kind, y, K, h, zeta, vb, d, p):
    """The switch: first theta in (0, 1] where d (V_b - X') <= 0 on the dense output."""
    ys = np.empty(NY)
    tmp = np.empty(NY)
    lo, hi = 0.0, 1.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _gd(kind, y, K, h, mid, zeta, vb, d, p, ys, tmp) > 0.0:
            lo = mid
        else:
            hi = mid
    return hi
