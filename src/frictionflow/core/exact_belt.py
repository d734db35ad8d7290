"""The exact engine on a belt whose speed varies, V_b(tau) = V_b + A sin(Omega_b tau + phi_b): Coulomb's switch.

Slip keeps its closed form (the constant friction d F_d and the harmonic force, :func:`.closed_form.forced_phase`):
the belt does not enter X'' = d F_d + f - X - 2 zeta X'.  What it changes is the switch back to the belt,
V_r = V_b(tau) - X'(tau) = 0, now a difference of the closed form and the belt's sinusoid.  Its root is
walked as the forced engine walks its event functions (:func:`.exact.parabola_step`), with the bound on
|V_r''| <= |X'''| + A Omega_b^2 (:func:`.closed_form.bound_at` for X''', the belt's |V_b''| <= A Omega_b^2
added): no crossing, however short, is stepped over.  The zeros of X', X'' and X' + 2 zeta X'' inside a
slip are the forced engine's sample functions (:func:`.exact.next_root`); the slip's works are the forced
engine's closed forms except the heat, F_c V_r = F_c (V_b(tau) - X'), whose belt part d F_d int V_b is
closed too (:func:`.stick.stick_x`).

Stick phases are the ones the adaptive kernel runs on a moving belt, shared, not copied: X = X0 + int V_b,
the held force's exit by :func:`.stick.exit_time` (proven steps, :func:`.stick.belt_turn`), the works by
Gauss-Legendre (:func:`.stick.belt_stick_work`), and Coulomb's stick rule with the belt's acceleration as a
load (:func:`.dopri.at_rest`): :func:`.dopri.forced_stick`, :func:`.dopri.after_stick`,
:func:`.dopri.slip_end`.  So are the samples' clock (the tail, the dense grid, the stroboscopic times of the
force, else of the belt: :func:`.dopri.drive_limits`) and the run's end.  Karnopp's band on a moving belt is not
run here (the façade refuses it).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from . import closed_form as cf
from .codes import FULL
from .dopri import (GO, Cursor, Setup, after_stick, drive_limits, finish_run, first_sample, forced_stick,
                    slip_end, strobe_sample)
from .exact import (FC_CONST, ForcedPiece, bound_consts, crossed_sample, event_row, forced_piece_work, next_root,
                    sample_functions, parabola_step)
from .friction import FD, FEX, FS, OMEGA, PHI, RESULTANT, VB_AMP, VB_OMEGA, belt_accel, belt_speed
from .layout import N_WORK
from .records import DENSE_DT, T_END, T_TAIL, V0, VB, X0, ZETA, record_switch
from .samples import emit
from .stick import stick_x

EPS = 2.220446049250313e-16
#: no boundaries in a slip's table of sample functions (:func:`_sample_table`)
NO_BOUNDS = ((0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))


@njit(cache=True)
def _vr(ph, p, vb, d, t0, u):
    """d V_r and its rate at u into the slip ``ph`` that began at t0, with the motion there (cf.forced_eval)."""
    co, dyn, zeta, force, pz, fz, om = ph
    st = cf.forced_eval(co, dyn, zeta, force, pz, fz, om, u)
    return d * (belt_speed(p, vb, t0 + u) - st[1]), d * (belt_accel(p, t0 + u) - st[2]), st


@njit(cache=True)
def _refine_vr(ph, p, vb, d, t0, lo, hi, st_hi):
    """A time u in (lo, hi] where d V_r reaches 0, given d V_r > 0 at lo (or on it within the graze level) and
    <= 0 at hi (``st_hi``: the motion there); :func:`belt_return`'s last step, where V_r is monotone, holds
    the crossing.  Newton kept inside the bracket (else bisection); once its step is below rounding an
    iterate on the outside is the answer, one on the inside probes a few ulps on.  (u, the motion there)."""
    u = 0.5 * (lo + hi)
    for _ in range(200):
        g, dg, st = _vr(ph, p, vb, d, t0, u)
        if g > 0.0:
            lo = u
        else:
            hi, st_hi = u, st
        if hi - lo <= 4.0 * EPS * (1.0 + hi):
            break
        un = u - g / dg if dg != 0.0 else 0.5 * (lo + hi)
        if abs(un - u) <= 2.0 * EPS * (1.0 + u):  # converged to rounding
            if g <= 0.0:
                return u, st
            un = u + 4.0 * EPS * (1.0 + u)
        if not (lo < un < hi):
            un = 0.5 * (lo + hi)
        u = un
    return hi, st_hi


@njit(cache=True)
def belt_return(ph, p, vb, d, t0, horizon):
    """When the slip ``ph`` in direction d from t0 returns to the belt, d V_r = d (V_b(tau) - X') <= 0, in
    (0, horizon]: (u, switched, the motion there).

    From u, d V_r stays above -graze up to :func:`.exact.parabola_step` with the bound
    |V_r''| <= |X'''| + A Omega_b^2 (X''' by :func:`.closed_form.bound_at`, valid from u on): a
    crossing is never stepped over; once below -graze it is refined in (the last step on the inside, u].
    """
    co, dyn, zeta, force, pz, fz, om = ph
    st = cf.forced_eval(co, dyn, zeta, force, pz, fz, om, 0.0)
    K1, K2, Kp, graze = bound_consts(ph, st[0], st[1], (0.0, 1.0, 0.0, 0.0, 0.0))
    amp, omb = p[VB_AMP], p[VB_OMEGA]
    graze += 1e-12 * (abs(vb) + amp)
    belt2 = amp * omb * omb  # |V_b''|
    u = last = 0.0
    while True:
        g, dg, st = _vr(ph, p, vb, d, t0, u)
        if g > 0.0:
            last = u
        elif g < -graze:
            uc, stc = _refine_vr(ph, p, vb, d, t0, last, u, st)
            return uc, True, stc
        if u >= horizon:
            return horizon, False, st
        step = parabola_step(g + graze, dg, cf.bound_at(co, dyn, K1, K2, Kp, u, st[6], st[7]) + belt2)
        un = min(u + step, horizon)
        u = un if un > u else min(np.nextafter(u, np.inf), horizon)


@njit(cache=True)
def _known(s, cur, t):
    """(u, tag): the next of the cursor's sample times (a :data:`.dopri.Cursor`) after t, from t: 1 the tail's
    start, 2 the dense grid, 3 the stroboscopic time (inf, 0: none)."""
    u, tag = np.inf, 0
    if not cur.tail_done and s.t_tail > t:
        u, tag = s.t_tail - t, 1
    if cur.next_dense - t < u:
        u, tag = cur.next_dense - t, 2
    ns = cur.n_strobe * s.period - t
    if ns < u:
        u, tag = ns, 3
    return u, tag


@njit(cache=True)
def _advance(s, cur, tag, tt):
    """The cursor past a sample at ``tt`` (``tag``: the known time it stands for, :func:`_known`; 0 none) and
    the sample's time: on the stroboscopic time if within rounding of it (:func:`.dopri.strobe_sample`)."""
    tt, n_strobe = strobe_sample(tt, cur.n_strobe, s.period)
    return Cursor(cur.tail_done or tag == 1, cur.next_dense + s.dense_dt if tag == 2 else cur.next_dense, n_strobe), tt


@njit(cache=True)
def _sample_table(ph, x, v):
    """The event table (:func:`.exact.next_root`) of a slip's sample functions: zeros of X', X'', X' + 2 zeta X''."""
    m, sf = sample_functions(ph[1], FC_CONST, ph[2])
    fns = (m, 0, NO_BOUNDS, sf)
    tab = (event_row(ph, x, v, fns, 0), event_row(ph, x, v, fns, 1), event_row(ph, x, v, fns, 2),
           event_row(ph, x, v, fns, 3), event_row(ph, x, v, fns, 4), event_row(ph, x, v, fns, 5))
    return tab, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0), m, 0


@njit(cache=True)
def _slip_work(pc, wr, a, b, span, p, vb):
    """The works of the slip piece from ``a`` to ``b`` = (motion, X, X') over ``span`` = (ta, tb) (absolute):
    the forced engine's closed forms (:func:`.exact.forced_piece_work`, with the belt at rest), the heat
    F_c V_r with the belt's part F_c int V_b added in closed form."""
    ta, tb = span
    dw = forced_piece_work(pc, wr, a, b, tb - ta, pc.om * ta + p[PHI])
    return dw[0], dw[1], dw[2], dw[3] + pc.force * (stick_x(0.0, ta, tb, vb, p)), dw[4]


@njit(cache=True)
def _slip(s, p, fo, at, cur, outs, w):
    """A slip phase from ``at`` = (t, x, v, mode, k) to its return to the belt (:func:`belt_return`) or t_end.

    Samples at the zeros of X', X'', X' + 2 zeta X'' and the cursor's times (``cur``), each with the works
    since the last, and at its end (the switch's sample, whose mode and friction the caller sets).
    Returns (status, (t, x, v, k), switched, cur) at its end.
    """
    t, x, v, mode, k = at
    fex, om, phi = fo
    force = float(mode) * p[FD]
    co, pz, fz = cf.forced_phase(cf.OSC, s.zeta, force, x, v, fex, om, om * t + phi)
    ph = (co, cf.OSC, s.zeta, force, pz, fz, om)
    T, switched, ste = belt_return(ph, p, s.vb, float(mode), t, s.t_end - t)
    table = _sample_table(ph, x, v)
    pc = ForcedPiece(cf.OSC, FC_CONST, s.zeta, 0.0, force, fex, om, mode)
    wr = (co[0] == cf.UNDER, cf.work_rep(co, cf.OSC, s.zeta, pz, fz, om))
    ta, xa, va, sta = 0.0, x, v, cf.forced_eval(co, cf.OSC, s.zeta, force, pz, fz, om, 0.0)
    while True:
        tk, tag = _known(s, cur, t)
        i, tb, stb, sides = next_root(ph, table, ta, sta, min(tk, T))
        table = (table[0], sides, table[2], table[3])
        xb, vb_ = stb[0], stb[1]
        if i >= 0:
            table, vb_ = crossed_sample(table, i, vb_)
            tag = 0
        elif tk >= T:
            break
        else:
            tb = tk
        cur, tt = _advance(s, cur, tag, t + tb)
        if tb <= ta:
            continue  # the same time from another source
        dw = _slip_work(pc, wr, (sta, xa, va), (stb, xb, vb_), (t + ta, t + tb), p, s.vb)
        for q in range(N_WORK):
            w[q] += dw[q]
        if not emit(outs, k, tt, xb, vb_, force, mode, w):
            return FULL, (t + ta, xa, va, k), False, cur
        k += 1
        ta, xa, va, sta = tb, xb, vb_, stb
    xe, ve = ste[0], (belt_speed(p, s.vb, t + T) if switched else ste[1])
    dw = _slip_work(pc, wr, (sta, xa, va), (ste, xe, ste[1]), (t + ta, t + T), p, s.vb)
    for q in range(N_WORK):
        w[q] += dw[q]
    cur, tt = _advance(s, cur, 0, t + T)
    if not emit(outs, k, tt, xe, ve, force, mode, w):
        return FULL, (t + ta, xa, va, k), False, cur
    return GO, (t + T, xe, ve, k + 1), switched, cur


@njit(cache=True)
def run_moving(run, p, samples, events):
    """Integrate from (x0, v0) at t = 0 to t_end on the moving belt of ``p`` (Coulomb's switch), phase by phase.

    ``run``, ``p``, ``samples``, ``events`` as for :func:`.exact.run`.  Returns (k, ne, status, -1, t):
    the numbers of samples and switches, the status (FULL: an output array was too short), no final phase
    certified (the belt drives for ever), where it stopped.
    """
    h_max, period = drive_limits(p)
    s = Setup(run[T_END], run[ZETA], run[VB], 0.0, 0.0, np.int64(0), run[DENSE_DT], run[T_TAIL], 0.0, 0.0, 0.0,
              p[RESULTANT] != 0.0, h_max, period, np.bool_(True))
    # without an external force any frequency off resonance gives the particular solution 0
    fo = (p[FEX], p[OMEGA] if p[FEX] != 0.0 else 2.0, p[PHI])
    outs, w = (samples[0], samples[1], samples[2], samples[3], samples[4]), np.zeros(N_WORK)
    t, x, v, fs = 0.0, run[X0], run[V0], p[FS]
    k, ne, hold, status = np.int64(0), np.int64(0), np.bool_(False), GO
    cur = Cursor(s.t_tail <= 0.0, s.dense_dt if s.dense_dt > 0.0 else np.inf, np.int64(1))
    if len(samples[0]) < 2:
        return 0, 0, FULL, -1.0, t
    mode = first_sample(s, p, (x, v, fs), outs, w)
    k += 1
    while t < s.t_end:
        if mode != 0:
            t_phase = t
            status, (t, x, v, k), switched, cur = _slip(s, p, fo, (t, x, v, mode, k), cur, outs, w)
            if switched:
                mode, hold, ne = slip_end(s, p, fs, (t, t_phase, x, k), events, ne, outs)
        else:
            status, t, x, k, cur = forced_stick(s, p, fs, (t, x, hold, k), cur, outs, w)
            v = belt_speed(p, s.vb, t)
            if status == GO and t < s.t_end:
                mode, tt, fc, cur = after_stick(s, p, fs, (t, x), cur)
                hold = mode == 0  # on F_s but held: on from here
                if mode != 0:
                    ne = record_switch(events, ne, t, mode)
                    if not emit(outs, k, tt, x, v, fc, mode, w):
                        return k, ne, FULL, -1.0, t
                    k += 1
        if status != GO:
            return k, ne, status, -1.0, t
    k, status = finish_run(s, p, (t, x, v, k), cur, outs, w)
    return k, ne, status, -1.0, t
