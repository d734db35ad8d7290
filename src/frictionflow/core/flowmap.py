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
from collections import namedtuple

import numpy as np
from numba import njit

from .._lazy import module_alone
from . import codes
from . import saltation as salt
from .friction import (FD, FS, LAW_A, LAW_B, LAW_C, RESULTANT, rest_mode, slip_partial_of, slip_terms_of,
                       stick_duration, stick_friction)
from .hermite import hermite, hermite_min
from .roots import RUNNING, bracket, steer, tolerance, update
from .tangent import slip_force, slip_slope

# -- DOP853 coefficients (Hairer's, as SciPy stores them) --------------------------
_dop = module_alone("scipy.integrate._ivp.dop853_coefficients")  # scipy.integrate's __init__ costs ~0.4 s
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

# -- records ------------------------------------------------------------------------------
# Module-level named tuples (numba types them as records; a kernel that takes them can still be
# cached): the kernels take these rather than long lists of scalars and buffers.

#: what a flow map is of (:func:`flow_map`'s argument): the model's zeta and V_b, the law's kernel
#: record p, the parameter code ``P_*``, DOP853's relative tolerance, and whether slip goes on
#: through V_r = 0 (``virtual``)
Flow = namedtuple("Flow", "zeta vb p code rtol virtual")
#: a run's settings: Flow's, then the law's F_s, resultant rule and F(0+), the state's absolute
#: tolerance, whether the quadratures are integrated, the end rule (returns, horizon) and how many
#: components a step advances
Run = namedtuple("Run", "zeta vb p code rtol virtual fs res f0 atol_x quads returns horizon n_act")
#: the slip field of a piece (what :func:`rhs` evaluates, with the law's record p): direction d, W_fin's
#: indicator (1.0 where X' F_c > 0 on the piece), zeta, V_b and the parameter code.  Scalars only: the
#: functions a step calls take their arrays one by one (p, the buffers), since taking an array out of a
#: record, or passing a record of arrays, counts the arrays' references at every call
Field = namedtuple("Field", "d ind zeta vb code")
#: a run's step buffers: the piece's vector y, the end y1 of the step being taken, the end ``out`` of a
#: trial step inside it, a stage's argument tmp (the last slot of each holds how many components a step
#: advances), the stages K; taken apart once per slip piece
Steps = namedtuple("Steps", "y y1 out tmp K")


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
def rhs(y, fl, p, out):
    """The slip field ``fl`` (:class:`Field`, law p) of the state, the tangents, xi and the quadratures with derivatives."""
    d, ind, zeta, vb, code = fl
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
def dop_step(y, h, fl, p, K, tmp, out):
    """One DOP853 step of length h of the field ``fl`` (law p) from y into ``out`` (stages in K; K[0]: the slope at y).

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
        rhs(tmp, fl, p, K[s])
    for i in range(n):
        acc = 0.0
        for j in range(N_STAGES):
            acc += B[j] * K[j, i]
        out[i] = y[i] + h * acc


@njit(cache=True)
def error_norm(y, ynew, h, K, rtol, atol_x, fl, p):
    """SciPy's DOP853 error norm on the first :data:`N_ERR` components (``fl``: the slip field)."""
    rhs(ynew, fl, p, K[N_STAGES])
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
# Every step calls these: they take their arrays one by one (see Field).  ``ev`` = (kind, sig)
# names the event: kind 0 the switch V_r = 0, kind 1 the zero of X' (sig: the sign of X' on the piece).
@njit(cache=True)
def _g(y, kind, d, sig, vb):
    """Event function: kind 0 the switch d (V_b - X'), kind 1 the zero of X' (sig X')."""
    return d * (vb - y[IV]) if kind == 0 else sig * y[IV]


@njit(cache=True)
def _g_rate(a, kind, d, sig):
    return -d * a if kind == 0 else sig * a


@njit(cache=True)
def _event_root(y, K, tmp, out, p, fl, b, theta, ev):
    """theta with g(theta) = 0 in the bracket ``b`` (:func:`.roots.bracket`, g(lo) > 0 >= g(hi)), from ``theta``.

    The step of the field ``fl`` from y; the state at the root in ``out``.
    Newton with the slope of g at the step's end (the scheme's d/dtheta up
    to its own error), kept inside the bracket; the bracket's own next point
    (:mod:`.roots`) where Newton would leave it.
    """
    kind, sig = ev
    while b.status == RUNNING:
        dop_step(y, theta, fl, p, K, tmp, out)
        gm = _g(out, kind, fl.d, sig, fl.vb)
        if gm == 0.0:
            return theta
        b = update(b, theta, gm)
        rate = _g_rate(accel(fl.d, out[IX], out[IV], fl.zeta, fl.vb, p), kind, fl.d, sig)
        step = -gm / rate if rate != 0.0 else math.inf
        if abs(step) <= tolerance(b, theta):
            return theta
        theta = steer(b, theta + step).x
    dop_step(y, b.hi, fl, p, K, tmp, out)
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
def _extremum_theta(y, K, tmp, out, p, fl, h, th, t):
    """theta in (0, h) where X'' = 0 on the step from y (an extreme of X'), by Newton from ``th``.

    The state there is left in ``out``.  d X''/dtau = -X' - (2 zeta + F') X''.
    """
    d, zeta, vb = fl.d, fl.zeta, fl.vb
    for _ in range(20):
        dop_step(y, th, fl, p, K, tmp, out)
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
    dop_step(y, th, fl, p, K, tmp, out)
    return th


@njit(cache=True)
def _dip_bottom(y, K, tmp, out, p, fl, h, s, ev, t):
    """The bottom of g's dip inside the step, from the Hermite sketch's minimum at the fraction ``s``.

    Returns (theta, g there), located on the scheme's own steps; theta -1:
    no dip below 0 inside.
    """
    th = _extremum_theta(y, K, tmp, out, p, fl, h, s * h, t)
    if th <= 0.0 or th >= h:
        return -1.0, 0.0  # the lowest point is an end of the step: no dip inside
    gm = _g(out, ev[0], fl.d, ev[1], fl.vb)
    if gm > 0.0:
        return -1.0, 0.0  # a near miss of the scheme's own solution
    return th, gm


@njit(cache=True)
def _positive_start(y, K, tmp, out, p, fl, hi, ev):
    """The largest of hi / 2, hi / 4, ... where g > 0, and g there (none found: g <= 0).

    The left end of a bracket when the step starts on the surface.
    """
    lo = hi
    glo = 0.0
    for _ in range(60):
        lo *= 0.5
        dop_step(y, lo, fl, p, K, tmp, out)
        glo = _g(out, ev[0], fl.d, ev[1], fl.vb)
        if glo > 0.0:
            break
    return lo, glo


@njit(cache=True)
def _first_root(y, y1, K, tmp, out, p, fl, h, ev, fresh, t):
    """theta in (0, h] where the event ``ev`` first happens in the step from y to y1 (-1: none)."""
    kind, sig = ev
    d, vb = fl.d, fl.vb
    g0 = _g(y, kind, d, sig, vb)
    g1 = _g(y1, kind, d, sig, vb)
    noise = _noise(y1[IV], vb)
    if fresh and abs(g1) <= noise:
        return -1.0
    m0 = _g_rate(accel(d, y[IX], y[IV], fl.zeta, vb, p), kind, d, sig) * h
    m1 = _g_rate(accel(d, y1[IX], y1[IV], fl.zeta, vb, p), kind, d, sig) * h
    if g1 > 0.0:
        s, val = hermite_min(g0, g1, m0, m1)
        # no interior dip that could reach 0 (a phase just leaving the surface: only a clear one)
        if s < 0.0 or val >= (-noise if fresh else 0.05 * min(g0, g1) + noise):
            return -1.0
        # the dip's bottom on the scheme's own steps (the cubic is only a sketch of it)
        hi, ghi = _dip_bottom(y, K, tmp, out, p, fl, h, s, ev, t)
        if hi < 0.0:
            return -1.0
    else:
        hi, ghi = h, g1
    lo, glo = 0.0, g0
    if glo <= 0.0 or fresh:
        lo, glo = _positive_start(y, K, tmp, out, p, fl, hi, ev)
        if not glo > 0.0:
            return 0.0
    guess = h * _hermite_root(g0, g1, m0, m1, lo / h, hi / h)
    if not (lo < guess < hi):
        guess = 0.5 * (lo + hi)
    b = bracket(lo, hi, glo, ghi, 4.0 * EPS * abs(t), 4.0 * EPS, 0.0, 100)
    return _event_root(y, K, tmp, out, p, fl, b, guess, ev)


@njit(cache=True)
def _track_min(y, y1, K, tmp, out, p, fl, h, M, tot, t):
    """The smallest V_r = d (V_b - X') inside the step y -> y1 (a maximum of d X'), if a record.

    Located by Newton on theta for X''(theta) = 0 on the scheme's own steps
    (d X''/dtau = -X' - (2 zeta + F') X''); its derivatives are the tangent
    columns' V components there (at an extremum a time shift moves nothing).
    """
    d, zeta, vb = fl.d, fl.zeta, fl.vb
    g0 = d * (vb - y[IV])
    g1 = d * (vb - y1[IV])
    a0 = accel(d, y[IX], y[IV], zeta, vb, p)
    a1 = accel(d, y1[IX], y1[IV], zeta, vb, p)
    s, val = hermite_min(g0, g1, -d * a0 * h, -d * a1 * h)
    if s < 0.0 or val > tot[T_VRMIN] + 1e-3 * (abs(vb) + abs(y[IV])):
        return
    th = _extremum_theta(y, K, tmp, out, p, fl, h, s * h, t)
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
            tot[T_DVR0 + c] = -d * dv + (d * dvb(fl.code) if c == 2 else 0.0)  # g = d (V_b - X')


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
    """Saltation (:mod:`.saltation`) of the three columns -- d/dx0, d/dv0, d/dlambda, the surface moving with
    lambda at the rate ``hl`` -- and the jump of W_fin's derivatives: W_fin is carried as a third state row
    whose integrand jumps from ``qfin_b`` to ``qfin_a`` and that the surface does not depend on (W_dv's
    integrand is continuous: no jump)."""
    cols = np.empty((3, 3))
    for c in range(3):
        cols[0, c], cols[1, c], cols[2, c] = M[0, c], M[1, c], tot[T_DWFIN0 + c]
    salt.apply(cols, (fb0, fb1, qfin_b), (fa0, fa1, qfin_a), (n0, n1, 0.0), 0.0, (0.0, 0.0, hl))
    for c in range(3):
        M[0, c], M[1, c], tot[T_DWFIN0 + c] = cols[0, c], cols[1, c], cols[2, c]


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


@njit(cache=True)
def _record_switch(row, t, x, vb, frm, to, n0, n1, fb1, fa1):
    """A switch's row of ``sw``: where (on X' = V_b), the modes, the surface's normal, X'' before and after."""
    row[0] = t
    row[1] = x
    row[2] = vb
    row[3] = frm
    row[4] = to
    row[5] = n0
    row[6] = n1
    row[7] = vb
    row[8] = fb1
    row[9] = vb
    row[10] = fa1


@njit(cache=True)
def _positive(q):
    return q if q > 0.0 else 0.0


# -- the phases ------------------------------------------------------------------------------
@njit(cache=True)
def _stick(run, x, t, M, tot):
    """A stick phase from X = x at t: X' = V_b until |F_e| reaches F_s on the side V_b drives it to.

    Returns (T, ends): its duration, cut at the horizon (ends False).  Folds
    the phase into the columns ``M`` and its work integrals into ``tot``.
    """
    zeta, vb, fs, res, f0 = run.zeta, run.vb, run.fs, run.res, run.f0
    T = stick_duration(x, zeta, vb, fs, res)
    if T < math.inf and rest_mode(x + vb * T, zeta, vb, fs, res, f0, 0.0, 0.0) == 0:
        T = math.inf
    ends = t + T < run.horizon
    if not ends:
        T = run.horizon - t
    _stick_quads(M, tot, x, T, zeta, vb, run.code)
    for c in range(3):
        M[0, c] += T * M[1, c]
    tot[T_STICK] += T
    return T, ends


@njit(cache=True)
def _stick_exit(run, x, t, M, tot, row):
    """The slip onset ending a stick phase at (x, V_b): saltation, W_fin's jump, the switch's ``row``; the new mode."""
    zeta, vb, f0, code = run.zeta, run.vb, run.f0, run.code
    new = rest_mode(x, zeta, vb, run.fs, run.res, f0, 0.0, 0.0)
    side = 1.0 if vb > 0.0 else -1.0
    fa1 = new * f0 - x - 2.0 * zeta * vb
    hl = side * 2.0 * (dzeta(code) * vb + zeta * dvb(code)) * (1.0 if run.res else 0.0) - dfs(code)
    qb = _positive(vb * stick_friction(x, zeta, vb, 0.0))
    qa = _positive(vb * new * f0)
    _switch(M, tot, side, 0.0, hl, vb, 0.0, vb, fa1, qb, qa)
    _record_switch(row, t, x, vb, np.int64(0), new, side, 0.0, 0.0, fa1)
    return new


@njit(cache=True)
def _slip_exit(run, mode, new, x, t, M, tot, row):
    """The switch on V_r = 0 ending a slip phase in direction ``mode`` at (x, V_b) into ``new`` (stick or reversal)."""
    zeta, vb, f0 = run.zeta, run.vb, run.f0
    d = float(mode)
    ab = d * f0 - x - 2.0 * zeta * vb
    fa1 = 0.0 if new == 0 else new * f0 - x - 2.0 * zeta * vb
    qb = _positive(vb * d * f0)
    if new == 0:
        qa = _positive(vb * stick_friction(x, zeta, vb, 0.0))
    else:
        qa = _positive(vb * new * f0)
    _switch(M, tot, 0.0, -d, d * dvb(run.code), vb, ab, vb, fa1, qb, qa)
    _record_switch(row, t, x, vb, mode, new, 0.0, 1.0, ab, fa1)


@njit(cache=True, inline="always")
def _slip_piece(run, st, mode, t, h, fresh, M, tot):
    """A slip piece from (X, X') in ``st.y[:2]`` at t, in direction ``mode``, to its first event; h: the next step.

    Returns (status, ended, t, h, fresh, sig): ``ended`` 1 the switch
    V_r = 0, 2 a zero of X', 3 the horizon; sig the sign of X' on the piece.
    The piece's vector (integrated from the identity) is left in ``st.y``.
    Inlined by numba into :func:`flow_map` (a call, once per piece, was
    measurably slower: the loop's array references are counted otherwise).
    """
    y, y1, out, tmp, K = st
    p, horizon = run.p, run.horizon
    d = float(mode)
    x, v = y[IX], y[IV]
    _reset_piece(y)
    a0 = accel(d, x, v, run.zeta, run.vb, p)
    sig = (1.0 if v > 0.0 else -1.0) if v != 0.0 else (1.0 if a0 > 0.0 else -1.0)
    fl = Field(d, 1.0 if sig * d > 0.0 else 0.0, run.zeta, run.vb, run.code)
    zfresh = v == 0.0
    rhs(y, fl, p, K[0])
    if h <= 0.0:
        h = min(0.1, 0.01 * max(horizon - t, 1e-3))
    for _ in range(1000000):
        hh = min(h, horizon - t)
        last = hh >= horizon - t
        dop_step(y, hh, fl, p, K, tmp, y1)
        err = error_norm(y, y1, hh, K, run.rtol, run.atol_x, fl, p)
        if not math.isfinite(err):
            h = 0.5 * hh
            if h < 1e-14 * (1.0 + abs(t)):
                return NOT_FINITE, 0, t, h, fresh, sig
            continue
        if err > 1.0:
            h = hh * max(MIN_FACTOR, SAFETY * err ** (-1.0 / 8.0))
            if h < 1e-14 * (1.0 + abs(t)):
                return STEP_FAIL, 0, t, h, fresh, sig
            continue
        # accepted: the first event inside it, the step retaken to it
        # (np.int64: a literal event kind would compile the root finders once per kind)
        th_sw = -1.0 if run.virtual else _first_root(y, y1, K, tmp, out, p, fl, hh, (np.int64(0), sig), fresh, t)
        th_z = _first_root(y, y1, K, tmp, out, p, fl, hh, (np.int64(1), sig), zfresh, t)
        kind = 0 if th_sw >= 0.0 else -1
        th = th_sw if th_sw >= 0.0 else hh
        if th_z >= 0.0 and (kind < 0 or th_z < th):
            kind, th = 1, th_z
        if kind >= 0:
            dop_step(y, th, fl, p, K, tmp, y1)
            hh = th
        if run.quads:
            _track_min(y, y1, K, tmp, out, p, fl, hh, M, tot, t)
        for i in range(run.n_act):
            y[i] = y1[i]
        t += hh
        if kind >= 0:
            return OK, 1 if kind == 0 else 2, t, h, fresh, sig
        for i in range(run.n_act):
            K[0, i] = K[N_STAGES, i]  # first same as last
        h = hh * (MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** (-1.0 / 8.0)))
        vr = d * (run.vb - y[IV])
        fresh = fresh and not vr > _noise(y[IV], run.vb)
        zfresh = zfresh and not sig * y[IV] > _noise(y[IV], 0.0)
        if last:
            return OK, 3, t, h, fresh, sig
    return STEP_FAIL, 0, t, h, fresh, sig


# -- the run ---------------------------------------------------------------------------------
@njit(cache=True)
def _settings(flow, returns, horizon, quads):
    """The :class:`Run` record of a run of ``flow`` (a :class:`Flow`)."""
    zeta, vb, p, code, rtol, virtual = flow
    fs = p[FS]
    atol_x = rtol * max(abs(fs), abs(vb), 1e-12)
    return Run(zeta, vb, p, code, rtol, virtual, fs, p[RESULTANT] != 0.0, slip_force(p, 0.0), atol_x, quads, returns,
               horizon, NY if quads else N_MAP)


@njit(cache=True)
def _steps(n_act):
    """The :class:`Steps` buffers of a run advancing ``n_act`` components."""
    st = Steps(np.zeros(NY + 1), np.zeros(NY + 1), np.zeros(NY + 1), np.zeros(NY + 1), np.empty((N_STAGES + 1, NY)))
    st.y[NY] = st.y1[NY] = st.out[NY] = st.tmp[NY] = n_act
    return st


@njit(cache=True)
def _start(run, x, v, tot):
    """Clear the summary ``tot``; returns the mode at (x, v): the slip direction, or the rest rule on V_r = 0."""
    for i in range(N_TOT):
        tot[i] = 0.0
    tot[T_XMIN] = math.inf
    tot[T_VRMIN] = math.inf
    if v == run.vb:
        return rest_mode(x, run.zeta, run.vb, run.fs, run.res, run.f0, 0.0, 0.0)
    return 1 if run.vb - v > 0.0 else -1


@njit(cache=True)
def _zero_of_v(sig, x, armed, count, returns, M, tot):
    """A zero of X' ending a piece: a minimum of X (sig < 0) arms the section, a maximum while armed is a return.

    Returns (armed, count, last): ``last``, the ``returns``-th return.  The
    smallest minimum of X, with its derivatives, goes into ``tot``.
    """
    if sig < 0.0:
        if x < tot[T_XMIN]:
            tot[T_XMIN] = x
            for c in range(3):
                tot[T_DXMIN0 + c] = M[0, c]
        return True, count, False
    if armed and returns > 0:
        count += 1
        return False, count, count == returns
    return armed, count, False


@njit(cache=True)
def _finish(run, tot, M, counts, end):
    """The run's summary into ``tot`` (``counts``: phases, switches, returns; ``end``: t, x, v, mode); returns the status."""
    nph, nsw, count = counts
    t, x, v, mode = end
    tot[T_NPH] = nph
    tot[T_NSW] = nsw
    tot[T_RET] = count
    tot[T_TIME] = t
    tot[T_X] = x
    tot[T_V] = v
    tot[T_FX] = v if mode != 0 else run.vb
    tot[T_FV] = accel(float(mode), x, v, run.zeta, run.vb, run.p) if mode != 0 else 0.0
    tot[T_M00], tot[T_M01], tot[T_M02] = M[0, 0], M[0, 1], M[0, 2]
    tot[T_M10], tot[T_M11], tot[T_M12] = M[1, 0], M[1, 1], M[1, 2]
    if run.returns > 0 and count < run.returns:
        return NO_RETURN
    return OK


@njit(cache=True)
def flow_map(x0, v0, flow, returns, horizon, quads, ph, sw, tot):
    """Flow from (x0, v0) to the ``returns``-th section crossing (returns = 0: for ``horizon``).

    ``flow``: the :class:`Flow` record (model, law, parameter, tolerance).
    Fills ``ph`` (phases), ``sw`` (switches) and ``tot`` (layout ``T_*``);
    ``quads`` False leaves the work integrals out (zeros) and the smallest
    V_r inside slip unrecorded.  ``flow.virtual``: slip on through V_r = 0 in
    the same direction (the slip field continued: no switches), for grazing
    functions that stay smooth on both sides of a touch.  Returns a status (``OK``, ``NO_RETURN``: the horizon came first, ``FULL``:
    more phases than rows, ``ZERO_PHASES``, ``STEP_FAIL``, ``NOT_FINITE``).
    """
    run = _settings(flow, returns, horizon, quads)
    st = _steps(run.n_act)
    y, vb = st.y, run.vb
    M = np.zeros((2, 3))
    M[0, 0] = M[1, 1] = 1.0
    Jph = np.eye(2)
    x, v, t = x0, v0, 0.0
    mode = _start(run, x, v, tot)
    armed, fresh = v > 0.0, v == vb
    # (not literals: _record_phase, _zero_of_v and _finish compile once)
    nph, nsw, count = np.int64(0), np.int64(0), np.int64(0)
    zero_run, new = 0, np.int64(0)  # (a literal 0: _slip_exit compiled once more)
    h = 0.0
    tph, xph, vph = t, x, v
    while True:
        if nph >= ph.shape[0] or nsw >= sw.shape[0]:
            return FULL
        if mode == 0:
            T, ends = _stick(run, x, t, M, tot)
            Jph[0, 0], Jph[0, 1], Jph[1, 0], Jph[1, 1] = 1.0, T, 0.0, 1.0
            x1 = x + vb * T
            _record_phase(ph, nph, np.int64(0), tph, T, xph, vph, x1, vb, Jph)
            nph += 1
            t, x, v = t + T, x1, vb
            armed = armed or vb > 0.0
            if not ends:
                break
            mode = _stick_exit(run, x, t, M, tot, sw[nsw])
            nsw += 1
        else:
            y[IX], y[IV] = x, v
            status, ended, t, h, fresh, sig = _slip_piece(run, st, mode, t, h, fresh, M, tot)
            if status != OK:
                return status
            x, v = y[IX], y[IV]
            if ended != 3:  # exactly on the surface it stopped at: V_r = 0 or X' = 0
                v = y[IV] = vb if ended == 1 else 0.0
            _close_piece(y, M, tot, Jph)
            zero_run = zero_run + 1 if (ended != 3 and t - tph <= 4.0 * EPS * (1.0 + abs(t))) else 0
            if zero_run > MAX_ZERO_PHASES:
                return ZERO_PHASES
            if ended == 2:
                fresh = False
                armed, count, last = _zero_of_v(sig, x, armed, count, returns, M, tot)
                if not last:
                    continue
            elif ended == 1:
                new = rest_mode(x, run.zeta, vb, run.fs, run.res, run.f0, 0.0, 0.0)
                if new == mode:
                    tot[T_GRAZE] += 1
                    fresh = True
                    continue
            _record_phase(ph, nph, mode, tph, t - tph, xph, vph, x, v, Jph)
            nph += 1
            if ended != 1:
                break  # the horizon, or the last return
            _slip_exit(run, mode, new, x, t, M, tot, sw[nsw])
            nsw += 1
            mode = new
        fresh = True
        Jph[0, 0], Jph[0, 1], Jph[1, 0], Jph[1, 1] = 1.0, 0.0, 0.0, 1.0
        tph, xph, vph = t, x, v
    return _finish(run, tot, M, (nph, nsw, count), (t, x, v, mode))
