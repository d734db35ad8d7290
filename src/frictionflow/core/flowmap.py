"""Compiled flow maps of the autonomous belt oscillator with their first derivatives.

For laws with Coulomb's stick rule and a compiled slip curve (Coulomb,
Stribeck, cubic), :func:`flow_map` integrates

    X'' = d F(d (V_b - X')) - X - 2 zeta X'      (slip in direction d)

from (X0, V0) to the ``returns``-th crossing of the section X' = 0 (X'' < 0)
or for a fixed time, and returns, besides the end state,

* the monodromy (d y1 / d y0 at fixed time, saltation matrices included),
* xi = d y1 / d lambda, the derivative with respect to one parameter lambda
  (V_b, zeta, F_d, F_s or one of the law's own parameters),
* the work integrals W_dv = int 2 zeta X'^2 and W_fin = int max(X' F_c, 0)
  with their derivatives with respect to X0, V0 and lambda,
* the smallest X at an upward crossing of X' = 0 with its derivatives,
* every phase (mode, times, end states, its own Jacobian) and switch.

Slip phases are integrated by the 8th-order Dormand-Prince pair DOP853 (the
coefficients of SciPy's ``solve_ivp``) with the tangent vectors and the
quadratures; the error is controlled on the state and the monodromy only,
so the steps (and the map) do not depend on which parameter is
differentiated.  Every switch V_r = 0 and every zero of X' is a root of the
scheme's own solution: the step is retaken from its start with lengths theta
found by Newton (:mod:`.roots`' false position as a fallback) on the event function of the
step of length theta (as in :mod:`.tangent`); a cubic Hermite sketch of the
step flags a dip that may touch zero inside it, whose bottom is then located
on the scheme's own steps (Newton on X'' = 0).  Stick phases (X' = V_b while |F_e| < F_s) are closed forms.

Derivatives across switches
---------------------------
Treat lambda as a state with lambda' = 0.  A switch surface h(y, lambda) = 0
with n = dh/dy, crossed from field f- to f+, maps a tangent column delta
(and the parameter column, for which h_lambda enters) by

    delta+ = delta- + (f+ - f-) (n . delta- + h_lambda) / (n . f-),

and a work integral of integrand q jumps by (q- - q+) dt with the switch
time's shift dt = -(n . delta- + h_lambda) / (n . f-).  Stick onset and
slip reversal: h = d (V_b - X'), n = (0, -d), h_lambda = d dV_b/dlambda.
Slip onset on the side s: h = s F_e - F_s with F_e = X + 2 zeta V_b
(resultant) or X, n = (s, 0), h_lambda = s dF_e/dlambda - dF_s/dlambda.

Inside a phase the columns follow delta' = A delta (+ df/dlambda for the
parameter column), A = [[0, 1], [-1, -(2 zeta + F'(|V_r|))]] and

    df/dlambda = (0, F'(|V_r|) dV_b/dlambda + d dF/dtheta - 2 X' dzeta/dlambda).

Every slip phase is cut at the zeros of X', where the integrand X' F_c of
W_fin changes sign, so its indicator is constant on each piece (and the
integrands vanish at the cuts: no jump terms there).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from scipy.integrate._ivp import dop853_coefficients as _dop

from . import codes
from .friction import (FD, FS, LAW_A, LAW_B, LAW_C, RESULTANT, rest_mode, slip_partial_of, slip_terms_of,
                       stick_duration, stick_friction)
from .hermite import hermite, hermite_min
from .roots import RUNNING, bracket, steer, tolerance, update
from .tangent import slip_force, slip_slope

# -- DOP853 coefficients (Hairer's, as SciPy stores them) --------------------------
N_STAGES = 12
A = np.ascontiguousarray(_dop.A[:N_STAGES, :N_STAGES])
B = np.ascontiguousarray(_dop.B)
C = np.ascontiguousarray(_dop.C[:N_STAGES])
E3 = np.ascontiguousarray(_dop.E3)
E5 = np.ascontiguousarray(_dop.E5)

#: parameter codes (which lambda the parameter column differentiates by)
P_NONE, P_VB, P_ZETA, P_FD, P_FS, P_A, P_B, P_C = range(8)

#: the integrated vector of a slip piece: state, phase Jacobian columns, xi, two quadratures x 4
IX, IV, J00, J10, J01, J11, XIX, XIV = range(8)
QDV = 8  # W_dv, then d/dX0, d/dV0, d/dlambda of the piece
QFIN = 12  # W_fin, the same
NY = 16
N_MAP = 8  # the state, the monodromy and xi: what the map and its derivatives need
N_ERR = 6  # components under error control: the state and the monodromy (the steps do not depend on lambda's choice)

#: ``tot`` layout (the run's summary)
(T_NPH, T_NSW, T_RET, T_TIME, T_X, T_V, T_FX, T_FV, T_M00, T_M01, T_M02, T_M10, T_M11, T_M12,
 T_WDV, T_DWDV0, T_DWDV1, T_DWDV2, T_WFIN, T_DWFIN0, T_DWFIN1, T_DWFIN2, T_XMIN, T_DXMIN0, T_DXMIN1,
 T_DXMIN2, T_STICK, T_GRAZE, T_VRMIN, T_VRX, T_DVR0, T_DVR1, T_DVR2) = range(33)
N_TOT = 33
#: phase record: mode, t0, duration, x0, v0, x1, v1, J00, J01, J10, J11
N_PH = 11
#: switch record: t, x, v, from, to, n0, n1, fb0, fb1, fa0, fa1
N_SW = 11

OK, NO_RETURN, FULL, ZERO_PHASES, STEP_FAIL, NOT_FINITE = (codes.OK, codes.NO_RETURN, codes.FULL, codes.STUCK,
                                                         codes.STEP_FAIL, codes.NOT_FINITE)
MAX_ZERO_PHASES = 8
EPS = 2.220446049250313e-16
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0


# -- parameter partials ------------------------------------------------------------
#: the kernel slot of each law-parameter code (the law's own module gives the derivative)
_SLOT = (-1, -1, -1, FD, FS, LAW_A, LAW_B, LAW_C)


@njit(cache=True)
def slip_partial(p, s, code):
    """dF/dtheta at slip speed s >= 0 for the parameter ``code`` (0 for V_b, zeta: no law parameter)."""
    slot = np.int64(_SLOT[code])  # (a plain int: a constant slot would compile slip_partial_of again)
    return slip_partial_of(p, max(s, 0.0), slot) if slot >= 0 else 0.0


@njit(cache=True)
def dvb(code):
    return 1.0 if code == P_VB else 0.0


@njit(cache=True)
def dzeta(code):
    return 1.0 if code == P_ZETA else 0.0


@njit(cache=True)
def dfs(code):
    return 1.0 if code == P_FS else 0.0


# -- the slip field ------------------------------------------------------------------
@njit(cache=True)
def law_terms(p, s, code):
    """(F, F', dF/dtheta) at slip speed s; below 0 (a stage overshooting a switch) the linear extension."""
    slot = np.int64(_SLOT[code])
    if s > 0.0 and slot >= 0:
        return slip_terms_of(p, s, slot)
    if s > 0.0:
        f, fp, _ = slip_terms_of(p, s, np.int64(FD))  # a model parameter: no derivative of the law itself
        return f, fp, 0.0
    return slip_force(p, s), slip_slope(p, s), slip_partial(p, s, code)


@njit(cache=True)
def rhs(y, d, ind, zeta, vb, p, code, out):
    """The slip field of the state, the tangents, xi and the two quadratures with their derivatives."""
    x = y[IX]
    v = y[IV]
    s = d * (vb - v)
    F, Fp, Ft = law_terms(p, s, code)
    damp = 2.0 * zeta + Fp
    dz = 2.0 if code == P_ZETA else 0.0
    fvb = Fp if code == P_VB else 0.0
    out[IX] = v
    out[IV] = d * F - x - 2.0 * zeta * v
    out[J00] = y[J10]
    out[J10] = -y[J00] - damp * y[J10]
    out[J01] = y[J11]
    out[J11] = -y[J01] - damp * y[J11]
    flam = fvb + d * Ft  # d(d F)/dlambda
    out[XIX] = y[XIV]
    out[XIV] = -y[XIX] - damp * y[XIV] + flam - dz * v
    # W_dv: q = 2 zeta v^2, q_v = 4 zeta v, q_lambda = 2 v^2 dzeta
    qv = 4.0 * zeta * v
    out[QDV] = 2.0 * zeta * v * v
    out[QDV + 1] = qv * y[J10]
    out[QDV + 2] = qv * y[J11]
    out[QDV + 3] = qv * y[XIV] + dz * v * v
    # W_fin on a piece where X' F_c > 0 (ind = 1): q = v d F, q_v = d F - v F', q_lambda = v d(d F)/dlambda
    if ind != 0.0:
        qv = d * F - v * Fp
        out[QFIN] = v * d * F
        out[QFIN + 1] = qv * y[J10]
        out[QFIN + 2] = qv * y[J11]
        out[QFIN + 3] = qv * y[XIV] + v * flam
    else:
        out[QFIN] = 0.0
        out[QFIN + 1] = 0.0
        out[QFIN + 2] = 0.0
        out[QFIN + 3] = 0.0


@njit(cache=True)
def accel(d, x, v, zeta, vb, p):
    """X'' slipping in direction d."""
    return d * slip_force(p, d * (vb - v)) - x - 2.0 * zeta * v


@njit(cache=True)
def dop_step(y, h, d, ind, zeta, vb, p, code, K, tmp, out):
    """One DOP853 step of length h from y into ``out`` (stages in K; K[0] must hold the slope at y).

    Only the first ``int(y[NY])`` components are advanced (the quadratures are
    left out while only the map and its Jacobian are wanted).
    """
    n = int(y[NY])
    for s in range(1, N_STAGES):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += A[s, j] * K[j, i]
            tmp[i] = y[i] + h * acc
        rhs(tmp, d, ind, zeta, vb, p, code, K[s])
    for i in range(n):
        acc = 0.0
        for j in range(N_STAGES):
            acc += B[j] * K[j, i]
        out[i] = y[i] + h * acc


@njit(cache=True)
def error_norm(y, ynew, h, K, rtol, atol_x, d, ind, zeta, vb, p, code):
    """SciPy's DOP853 error norm on the first :data:`N_ERR` components."""
    rhs(ynew, d, ind, zeta, vb, p, code, K[N_STAGES])
    e5 = 0.0
    e3 = 0.0
    for i in range(N_ERR):
        atol = atol_x if i < 2 else rtol
        sc = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        a5 = 0.0
        a3 = 0.0
        for j in range(N_STAGES + 1):
            a5 += E5[j] * K[j, i]
            a3 += E3[j] * K[j, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    den = e5 + 0.01 * e3
    return abs(h) * e5 / math.sqrt(den * N_ERR)


# -- events in a slip piece ------------------------------------------------------------
@njit(cache=True)
def _g(y, kind, d, sig, vb):
    """Event function: kind 0 the switch d (V_b - X'), kind 1 the zero of X' (sig X')."""
    return d * (vb - y[IV]) if kind == 0 else sig * y[IV]


@njit(cache=True)
def _g_rate(a, kind, d, sig):
    return -d * a if kind == 0 else sig * a


@njit(cache=True)
def _event_root(y, lo, hi, glo, ghi, theta, kind, d, sig, ind, zeta, vb, p, code, K, tmp, out, t):
    """theta with g(theta) = 0 (g(lo) > 0 >= g(hi)), from the guess ``theta``; the state there in ``out``.

    Newton with the slope of g at the step's end (the scheme's d/dtheta up to
    its own error), kept inside the bracket; the bracket's own next point
    (:mod:`.roots`) where Newton would leave it.
    """
    b = bracket(lo, hi, glo, ghi, 4.0 * EPS * abs(t), 4.0 * EPS, 0.0, 100)
    while b.status == RUNNING:
        dop_step(y, theta, d, ind, zeta, vb, p, code, K, tmp, out)
        gm = _g(out, kind, d, sig, vb)
        if gm == 0.0:
            return theta
        b = update(b, theta, gm)
        rate = _g_rate(accel(d, out[IX], out[IV], zeta, vb, p), kind, d, sig)
        step = -gm / rate if rate != 0.0 else math.inf
        if abs(step) <= tolerance(b, theta):
            return theta
        theta = steer(b, theta + step).x
    dop_step(y, b.hi, d, ind, zeta, vb, p, code, K, tmp, out)
    return b.hi


@njit(cache=True)
def _hermite_root(g0, g1, m0, m1, lo, hi):
    """A root of the Hermite cubic in [lo, hi] (fractions of the step) by bisection: the first guess."""
    a, b = lo, hi
    ga = hermite(g0, g1, m0, m1, a)
    for _ in range(40):
        m = 0.5 * (a + b)
        gm = hermite(g0, g1, m0, m1, m)
        if (gm > 0.0) == (ga > 0.0):
            a, ga = m, gm
        else:
            b = m
    return 0.5 * (a + b)


@njit(cache=True)
def _noise(v, vb):
    return 16.0 * EPS * (abs(v) + abs(vb))


@njit(cache=True)
def _extremum_theta(y, h, th, d, ind, zeta, vb, p, code, K, tmp, out, t):
    """theta in (0, h) where X'' = 0 on the step from y (an extreme of X'), by Newton from ``th``; state in ``out``.

    d X''/dtau = -X' - (2 zeta + F') X''.
    """
    for _ in range(20):
        dop_step(y, th, d, ind, zeta, vb, p, code, K, tmp, out)
        a = accel(d, out[IX], out[IV], zeta, vb, p)
        ad = -out[IV] - (2.0 * zeta + slip_slope(p, d * (vb - out[IV]))) * a
        if ad == 0.0:
            break
        step = -a / ad
        nxt = min(max(th + step, 0.0), h)
        if abs(nxt - th) <= 4.0 * EPS * (abs(t) + h):
            th = nxt
            break
        th = nxt
    dop_step(y, th, d, ind, zeta, vb, p, code, K, tmp, out)
    return th


@njit(cache=True)
def _first_root(y, h, kind, d, sig, fresh, ind, zeta, vb, p, code, K, tmp, out, y1, t):
    """theta in (0, h] where event ``kind`` first happens in the step to y1 (-1: none)."""
    g0 = _g(y, kind, d, sig, vb)
    g1 = _g(y1, kind, d, sig, vb)
    noise = _noise(y1[IV], vb)
    if fresh and abs(g1) <= noise:
        return -1.0
    m0 = _g_rate(accel(d, y[IX], y[IV], zeta, vb, p), kind, d, sig) * h
    m1 = _g_rate(accel(d, y1[IX], y1[IV], zeta, vb, p), kind, d, sig) * h
    if g1 > 0.0:
        s, val = hermite_min(g0, g1, m0, m1)
        # no interior dip that could reach 0 (a phase just leaving the surface: only a clear one)
        if s < 0.0 or val >= (-noise if fresh else 0.05 * min(g0, g1) + noise):
            return -1.0
        # the dip's bottom on the scheme's own steps (the cubic is only a sketch of it)
        th = _extremum_theta(y, h, s * h, d, ind, zeta, vb, p, code, K, tmp, out, t)
        if th <= 0.0 or th >= h:
            return -1.0  # the lowest point is an end of the step: no dip inside
        gm = _g(out, kind, d, sig, vb)
        if gm > 0.0:
            return -1.0  # a near miss of the scheme's own solution
        hi, ghi = th, gm
    else:
        hi, ghi = h, g1
    lo, glo = 0.0, g0
    if glo <= 0.0 or fresh:
        lo = hi
        glo = 0.0
        for _ in range(60):
            lo *= 0.5
            dop_step(y, lo, d, ind, zeta, vb, p, code, K, tmp, out)
            glo = _g(out, kind, d, sig, vb)
            if glo > 0.0:
                break
        if not glo > 0.0:
            return 0.0
    guess = h * _hermite_root(g0, g1, m0, m1, lo / h, hi / h)
    if not (lo < guess < hi):
        guess = 0.5 * (lo + hi)
    return _event_root(y, lo, hi, glo, ghi, guess, kind, d, sig, ind, zeta, vb, p, code, K, tmp, out, t)


@njit(cache=True)
def _track_min(y, y1, h, d, ind, zeta, vb, p, code, K, tmp, out, M, tot, t):
    """The smallest V_r = d (V_b - X') inside the step y -> y1 (a maximum of d X'), kept if below the record.

    Located by Newton on theta for X''(theta) = 0 on the scheme's own steps
    (d X''/dtau = -X' - (2 zeta + F') X''); its derivatives are the tangent
    columns' V components there (at an extremum a time shift moves nothing).
    """
    g0 = d * (vb - y[IV])
    g1 = d * (vb - y1[IV])
    a0 = accel(d, y[IX], y[IV], zeta, vb, p)
    a1 = accel(d, y1[IX], y1[IV], zeta, vb, p)
    s, val = hermite_min(g0, g1, -d * a0 * h, -d * a1 * h)
    if s < 0.0 or val > tot[T_VRMIN] + 1e-3 * (abs(vb) + abs(y[IV])):
        return
    th = _extremum_theta(y, h, s * h, d, ind, zeta, vb, p, code, K, tmp, out, t)
    if th <= 0.0 or th >= h:
        return  # the smallest value is at an end of the step: no interior extremum (a tangential start)
    vr = d * (vb - out[IV])
    if not vr < min(g0, g1) - _noise(out[IV], vb):
        return  # no lower than the ends: a touch at a phase start, not an excursion's extremum
    if vr < tot[T_VRMIN]:
        tot[T_VRMIN] = vr
        tot[T_VRX] = out[IX]
        for c in range(3):
            dv = out[J10] * M[0, c] + out[J11] * M[1, c] + (out[XIV] if c == 2 else 0.0)
            tot[T_DVR0 + c] = -d * dv + (d * dvb(code) if c == 2 else 0.0)  # g = d (V_b - X')


# -- bookkeeping ----------------------------------------------------------------------------
@njit(cache=True)
def _close_piece(y, M, tot, Jph):
    """Fold a slip piece (integrated from the identity) into the run's columns, totals and the phase Jacobian."""
    for c in range(3):
        m0 = M[0, c]
        m1 = M[1, c]
        tot[T_DWDV0 + c] += y[QDV + 1] * m0 + y[QDV + 2] * m1 + (y[QDV + 3] if c == 2 else 0.0)
        tot[T_DWFIN0 + c] += y[QFIN + 1] * m0 + y[QFIN + 2] * m1 + (y[QFIN + 3] if c == 2 else 0.0)
        M[0, c] = y[J00] * m0 + y[J01] * m1 + (y[XIX] if c == 2 else 0.0)
        M[1, c] = y[J10] * m0 + y[J11] * m1 + (y[XIV] if c == 2 else 0.0)
    tot[T_WDV] += y[QDV]
    tot[T_WFIN] += y[QFIN]
    a00 = y[J00] * Jph[0, 0] + y[J01] * Jph[1, 0]
    a01 = y[J00] * Jph[0, 1] + y[J01] * Jph[1, 1]
    a10 = y[J10] * Jph[0, 0] + y[J11] * Jph[1, 0]
    a11 = y[J10] * Jph[0, 1] + y[J11] * Jph[1, 1]
    Jph[0, 0], Jph[0, 1], Jph[1, 0], Jph[1, 1] = a00, a01, a10, a11


@njit(cache=True)
def _reset_piece(y):
    for i in range(2, NY):
        y[i] = 0.0
    y[J00] = 1.0
    y[J11] = 1.0


@njit(cache=True)
def _switch(M, tot, n0, n1, hl, fb0, fb1, fa0, fa1, qfin_b, qfin_a):
    """Saltation of the three columns and the jump of W_fin at a switch (W_dv's integrand is continuous)."""
    den = n0 * fb0 + n1 * fb1
    for c in range(3):
        w = n0 * M[0, c] + n1 * M[1, c] + (hl if c == 2 else 0.0)
        M[0, c] += (fa0 - fb0) * w / den
        M[1, c] += (fa1 - fb1) * w / den
        tot[T_DWFIN0 + c] += -(qfin_b - qfin_a) * w / den


@njit(cache=True)
def _record_phase(ph, k, mode, t0, dur, x0, v0, x1, v1, Jph):
    ph[k, 0] = mode
    ph[k, 1] = t0
    ph[k, 2] = dur
    ph[k, 3] = x0
    ph[k, 4] = v0
    ph[k, 5] = x1
    ph[k, 6] = v1
    ph[k, 7] = Jph[0, 0]
    ph[k, 8] = Jph[0, 1]
    ph[k, 9] = Jph[1, 0]
    ph[k, 10] = Jph[1, 1]


@njit(cache=True)
def _stick_quads(M, tot, xs, T, zeta, vb, code):
    """The work integrals of a stick phase of length T from X = xs, with derivatives (closed forms).

    While sticking X' = V_b and F_c = X + 2 zeta V_b (the interface holds the
    spring and the damper): q_dv = 2 zeta V_b^2, q_f = V_b (X + 2 zeta V_b),
    counted in W_fin where positive.  The columns move as X = X_s + tau dV_s.
    """
    dz = dzeta(code)
    dv = dvb(code)
    tot[T_WDV] += 2.0 * zeta * vb * vb * T
    for c in range(3):
        tot[T_DWDV0 + c] += (4.0 * zeta * vb * M[1, c] + (2.0 * dz * vb * vb if c == 2 else 0.0)) * T
    f0 = stick_friction(xs, zeta, vb, 0.0)
    if vb == 0.0:
        return
    # q_f = vb f0 + vb^2 tau grows with tau whatever the sign of V_b: positive past tau = -f0 / vb
    lo = min(max(-f0 / vb, 0.0), T)
    hi = T
    if hi <= lo:
        return
    L = hi - lo
    L2 = 0.5 * (hi * hi - lo * lo)
    tot[T_WFIN] += vb * f0 * L + vb * vb * L2
    kl = 2.0 * (dz * vb + zeta * dv)
    for c in range(3):
        alpha = vb * M[0, c] + ((dv * f0 + vb * kl) if c == 2 else 0.0)
        beta = vb * M[1, c] + ((dv * vb) if c == 2 else 0.0)
        tot[T_DWFIN0 + c] += alpha * L + beta * L2


# -- the run ---------------------------------------------------------------------------------
@njit(cache=True)
def flow_map(x0, v0, zeta, vb, p, code, returns, horizon, rtol, quads, virtual, ph, sw, tot):
    """Flow from (x0, v0) to the ``returns``-th section crossing (returns = 0: for ``horizon``).

    Fills ``ph`` (phases), ``sw`` (switches) and ``tot`` (layout ``T_*``);
    ``quads`` False leaves the work integrals out (zeros) and the smallest
    V_r inside slip unrecorded.  ``virtual``: slip on through V_r = 0 in the
    same direction (the slip field continued: no switches), for grazing
    functions that stay smooth on both sides of a touch.  Returns a status (``OK``, ``NO_RETURN``: the horizon came first, ``FULL``:
    more phases than rows, ``ZERO_PHASES``, ``STEP_FAIL``, ``NOT_FINITE``).
    """
    res = p[RESULTANT] != 0.0
    fs = p[FS]
    f0 = slip_force(p, 0.0)
    scale = max(abs(fs), abs(vb), 1e-12)
    atol_x = rtol * scale
    y = np.zeros(NY + 1)
    y1 = np.zeros(NY + 1)
    out = np.zeros(NY + 1)
    tmp = np.zeros(NY + 1)
    n_act = NY if quads else N_MAP
    y[NY] = y1[NY] = out[NY] = tmp[NY] = n_act
    K = np.empty((N_STAGES + 1, NY))
    M = np.zeros((2, 3))
    M[0, 0] = 1.0
    M[1, 1] = 1.0
    Jph = np.eye(2)
    for i in range(N_TOT):
        tot[i] = 0.0
    tot[T_XMIN] = math.inf
    tot[T_VRMIN] = math.inf
    x, v = x0, v0
    t = 0.0
    if v == vb:
        mode = rest_mode(x, zeta, vb, fs, res, f0, 0.0, 0.0)
    else:
        mode = 1 if vb - v > 0.0 else -1
    armed = v > 0.0
    fresh = v == vb
    nph = np.int64(0)  # (not a literal: _record_phase compiles once)
    nsw = 0
    count = 0
    zero_run = 0
    h = 0.0
    tph = 0.0
    xph, vph = x, v
    while True:
        if nph >= ph.shape[0] or nsw >= sw.shape[0]:
            return FULL
        if mode == 0:
            # stick: X' = V_b until |F_e| reaches F_s on the side V_b drives it to
            T = stick_duration(x, zeta, vb, fs, res)
            if T < math.inf and rest_mode(x + vb * T, zeta, vb, fs, res, f0, 0.0, 0.0) == 0:
                T = math.inf
            ends = t + T < horizon
            if not ends:
                T = horizon - t
            Jph[0, 0], Jph[0, 1], Jph[1, 0], Jph[1, 1] = 1.0, T, 0.0, 1.0
            _stick_quads(M, tot, x, T, zeta, vb, code)
            for c in range(3):
                M[0, c] += T * M[1, c]
            tot[T_STICK] += T
            x1 = x + vb * T
            _record_phase(ph, nph, np.int64(0), tph, T, xph, vph, x1, vb, Jph)
            nph += 1
            t += T
            x = x1
            v = vb
            armed = armed or vb > 0.0
            if not ends:
                break
            new = rest_mode(x, zeta, vb, fs, res, f0, 0.0, 0.0)
            side = 1.0 if vb > 0.0 else -1.0
            fa1 = new * f0 - x - 2.0 * zeta * vb
            hl = side * 2.0 * (dzeta(code) * vb + zeta * dvb(code)) * (1.0 if res else 0.0) - dfs(code)
            qb = vb * stick_friction(x, zeta, vb, 0.0)
            qb = qb if qb > 0.0 else 0.0
            qa = vb * new * f0
            qa = qa if qa > 0.0 else 0.0
            _switch(M, tot, side, 0.0, hl, vb, 0.0, vb, fa1, qb, qa)
            sw[nsw, 0] = t
            sw[nsw, 1] = x
            sw[nsw, 2] = vb
            sw[nsw, 3] = 0
            sw[nsw, 4] = new
            sw[nsw, 5] = side
            sw[nsw, 6] = 0.0
            sw[nsw, 7] = vb
            sw[nsw, 8] = 0.0
            sw[nsw, 9] = vb
            sw[nsw, 10] = fa1
            nsw += 1
            mode = new
            fresh = True
            Jph = np.eye(2)
            tph, xph, vph = t, x, v
            continue
        # slip in direction d, cut at the zeros of X'
        d = float(mode)
        y[IX] = x
        y[IV] = v
        _reset_piece(y)
        a0 = accel(d, x, v, zeta, vb, p)
        sig = (1.0 if v > 0.0 else -1.0) if v != 0.0 else (1.0 if a0 > 0.0 else -1.0)
        ind = 1.0 if sig * d > 0.0 else 0.0
        zfresh = v == 0.0
        rhs(y, d, ind, zeta, vb, p, code, K[0])
        if h <= 0.0:
            h = min(0.1, 0.01 * max(horizon - t, 1e-3))
        ended = 0  # 0 running, 1 switch V_r = 0, 2 zero of X', 3 horizon
        nsteps = 0
        while ended == 0:
            nsteps += 1
            if nsteps > 1000000:
                return STEP_FAIL
            hh = min(h, horizon - t)
            last = hh >= horizon - t
            dop_step(y, hh, d, ind, zeta, vb, p, code, K, tmp, y1)
            err = error_norm(y, y1, hh, K, rtol, atol_x, d, ind, zeta, vb, p, code)
            if not math.isfinite(err):
                h = 0.5 * hh
                if h < 1e-14 * (1.0 + abs(t)):
                    return NOT_FINITE
                continue
            if err > 1.0:
                h = hh * max(MIN_FACTOR, SAFETY * err ** (-1.0 / 8.0))
                if h < 1e-14 * (1.0 + abs(t)):
                    return STEP_FAIL
                continue
            # accepted: the first event inside it
            # (np.int64: a literal event kind would compile the root finders once per kind)
            th_sw = -1.0 if virtual else _first_root(y, hh, np.int64(0), d, sig, fresh, ind, zeta, vb, p, code, K, tmp, out, y1,
                                                     t)
            th_z = _first_root(y, hh, np.int64(1), d, sig, zfresh, ind, zeta, vb, p, code, K, tmp, out, y1, t)
            kind = -1
            th = hh
            if th_sw >= 0.0:
                kind, th = 0, th_sw
            if th_z >= 0.0 and (kind < 0 or th_z < th):
                kind, th = 1, th_z
            if kind >= 0:
                dop_step(y, th, d, ind, zeta, vb, p, code, K, tmp, y1)
                hh = th
            if quads:
                _track_min(y, y1, hh, d, ind, zeta, vb, p, code, K, tmp, out, M, tot, t)
            for i in range(n_act):
                y[i] = y1[i]
            t += hh
            vr = d * (vb - y[IV])
            fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** (-1.0 / 8.0))
            if kind < 0:
                for i in range(n_act):
                    K[0, i] = K[N_STAGES, i]  # first same as last
                h = hh * fac
                fresh = fresh and not vr > _noise(y[IV], vb)
                zfresh = zfresh and not sig * y[IV] > _noise(y[IV], 0.0)
                if last:
                    ended = 3
                continue
            ended = 1 if kind == 0 else 2
        x, v = y[IX], y[IV]
        if ended == 1:
            v = vb
            y[IV] = vb
        elif ended == 2:
            v = 0.0
            y[IV] = 0.0
        _close_piece(y, M, tot, Jph)
        zero_run = zero_run + 1 if (ended != 3 and t - tph <= 4.0 * EPS * (1.0 + abs(t))) else 0
        if zero_run > MAX_ZERO_PHASES:
            return ZERO_PHASES
        if ended == 3:
            _record_phase(ph, nph, mode, tph, t - tph, xph, vph, x, v, Jph)
            nph += 1
            break
        if ended == 2:
            # a zero of X': a minimum of X (arms the section) or a maximum (the section)
            fresh = False
            if sig < 0.0:
                armed = True
                if x < tot[T_XMIN]:
                    tot[T_XMIN] = x
                    for c in range(3):
                        tot[T_DXMIN0 + c] = M[0, c]
                continue
            if armed and returns > 0:
                count += 1
                armed = False
                if count == returns:
                    _record_phase(ph, nph, mode, tph, t - tph, xph, vph, x, v, Jph)
                    nph += 1
                    break
            continue
        # a switch on V_r = 0
        new = rest_mode(x, zeta, vb, fs, res, f0, 0.0, 0.0)
        ab = d * f0 - x - 2.0 * zeta * vb
        if new == mode:
            tot[T_GRAZE] += 1
            fresh = True
            continue
        _record_phase(ph, nph, mode, tph, t - tph, xph, vph, x, v, Jph)
        nph += 1
        fa1 = 0.0 if new == 0 else new * f0 - x - 2.0 * zeta * vb
        qb = vb * d * f0
        qb = qb if qb > 0.0 else 0.0
        if new == 0:
            qa = vb * stick_friction(x, zeta, vb, 0.0)
            qa = qa if qa > 0.0 else 0.0
        else:
            qa = vb * new * f0
            qa = qa if qa > 0.0 else 0.0
        _switch(M, tot, 0.0, -d, d * dvb(code), vb, ab, vb, fa1, qb, qa)
        sw[nsw, 0] = t
        sw[nsw, 1] = x
        sw[nsw, 2] = vb
        sw[nsw, 3] = mode
        sw[nsw, 4] = new
        sw[nsw, 5] = 0.0
        sw[nsw, 6] = 1.0
        sw[nsw, 7] = vb
        sw[nsw, 8] = ab
        sw[nsw, 9] = vb
        sw[nsw, 10] = fa1
        nsw += 1
        mode = new
        fresh = True
        Jph = np.eye(2)
        tph, xph, vph = t, x, v
    tot[T_NPH] = nph
    tot[T_NSW] = nsw
    tot[T_RET] = count
    tot[T_TIME] = t
    tot[T_X] = x
    tot[T_V] = v
    tot[T_FX] = v if mode != 0 else vb
    tot[T_FV] = accel(float(mode), x, v, zeta, vb, p) if mode != 0 else 0.0
    tot[T_M00], tot[T_M01], tot[T_M02] = M[0, 0], M[0, 1], M[0, 2]
    tot[T_M10], tot[T_M11], tot[T_M12] = M[1, 0], M[1, 1], M[1, 2]
    if returns > 0 and count < returns:
        return NO_RETURN
    return OK
