"""The stiff engine: Rodas4, an L-stable Rosenbrock method, for laws with internal state.

The state is y = (X, X', z_1 .. z_m): the mass and the law's internal states
(LuGre's bristle deflection z).  With V_r = V_b - X' the equations are

    X'  = X'
    X'' = -X - 2 zeta X' + F(V_r, z) + f(tau)
    z'  = r(V_r, z)

and a law gives F, r, their exact derivatives in V_r and z, and the gradient
and (diagonal) curvature of its stored energy E(z).  Rosenbrock methods need
the exact Jacobian for their order: it is assembled here from those
derivatives, never differenced.

Rodas4 (Hairer & Wanner, Solving ODEs II, sec. IV.7; coefficients of their
``rodas.f``) is stiffly accurate and L-stable, of order 4 with an embedded
order-3 estimate (the last stage).  The error is controlled on the whole state
(X, X' and every internal state, each with its own absolute scale).  The work
integrals ride along as quadrature components: their Jacobian rows are exact
too and their columns are zero, so each step solves the n x n block and the
quadratures by substitution, starting from zero each step (the increments,
not running totals, as every solver keeps them).  They are not in the error
norm: the state's error bounds theirs.

The belt's speed may vary, V_b(tau) (:func:`.friction.belt_speed`): every stage
takes V_r at its own time, and the method's time derivative (df/dtau at fixed
y) carries the belt's acceleration through V_r: dF/dV_r V_b' in X'', dr/dV_r V_b'
in z', and its terms in the work integrands (the belt's input F V_b(tau) too).

The right-hand side is Lipschitz (|V_r| has a kink, no switch), so breakaway
and re-stick are crossed by the step-size control alone, with nothing to
chatter; after a rejected step the step does not grow (Hairer's rule).

The force record ``q`` is the kernels' record (:mod:`.layout`, with the
external force) followed by the law's own parameters from :data:`Q_LAW`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .friction import belt_accel, belt_speed, external_force, external_force_rate
from .layout import LAW, N_PARAMS
from .options import NO_RUNTIME
from .roots import EPS, RUNNING, bracket, update

#: codes of the laws with internal state (the stiff engine's dispatch)
LUGRE = 100
DAHL = 101
ELASTOPLASTIC = 102
RATE_STATE = 103
#: where a stateful law's own parameters start in ``q``
Q_LAW = N_PARAMS
#: work channels the engine integrates: damper, friction in, friction out, interface heat, external force, belt input
N_CHANNELS = 6
W_BELT = 5
#: the functions whose zeros end a step, a sample there (:func:`marks_of`): X' (the turns of X; downwards, the
#: section) and P_f = X' F (the kinks of max(P_f, 0), the friction work's split into input and output).  (The turns
#: of X' and of the transmitted force, which the adaptive solver samples, measured 1.25x the run's time at
#: Canudas' rtol 1e-6: the extremes of X' and TR_B are the steps'.)
N_MARKS = 2
#: a function this small against its value at the step's end starts on the zero the last step ended on
MARK_FLOOR = 1e-9
#: P_f's zero is located to this fraction of its values at the step's ends (well below MARK_FLOOR: the next step
#: starts on it; an error delta in its time moves the work across the kink by only ~P_f' delta^2)
MARK_TOL = 1e-11
#: how a run ended
DONE, FULL, STEP_CAP, TINY_STEP = 0, 1, 2, 3

# Rodas4 (Hairer & Wanner, rodas.f)
GAMMA = 0.25
A21 = 1.544
A31, A32 = 0.9466785280815826, 0.2557011698983284
A41, A42, A43 = 3.314825187068521, 2.896124015972201, 0.9986419139977817
A51, A52, A53, A54 = 1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950
C21 = -5.6688
C31, C32 = -2.430093356833875, -0.2063599157091915
C41, C42, C43 = -0.1073529058151375, -9.594562251023355, -20.47028614809616
C51, C52, C53, C54 = 7.496443313967647, -10.24680431464352, -33.99990352819905, 11.70890893206160
C61, C62, C63, C64, C65 = 8.083246795921522, -7.981132988064893, -31.52159432874371, 16.31930543123136, -6.058818238834054
CC2, CC3, CC4 = 0.386, 0.21, 0.63
D1, D2, D3, D4 = 0.25, -0.1043, 0.1035, -0.0362


@njit(cache=True, forceinline=True)
def lugre_stribeck(q, speed):
    """g(|V_r|) = F_C + (F_S - F_C) exp(-(|V_r|/v_s)^delta) and dg/d|V_r|."""
    fc, fs, vs, delta = q[Q_LAW], q[Q_LAW + 1], q[Q_LAW + 2], q[Q_LAW + 3]
    u = speed / vs
    up = u if delta == 2.0 else u ** (delta - 1.0)  # one power (none for the Gaussian, the usual choice)
    e = math.exp(-up * u)
    dg = 0.0 if speed == 0.0 else -(fs - fc) * e * delta * up / vs
    return fc + (fs - fc) * e, dg


#: columns of a law's derivative record ``d`` (m rows, one per internal state): its rate r, dr/dV_r, dF/dz,
#: E's gradient and (diagonal) curvature, then dr/dz (m columns)
D_RATE, D_RS, D_FZ, D_EZ, D_EZZ, D_RZ = range(6)


@njit(cache=True, forceinline=True)
def bristle_force(q, s, zz, d):
    """F = sigma0 z + sigma1 z' + sigma2 V_r of the bristle laws (LuGre, elasto-plastic), from the rate and
    its derivatives in ``d``; fills dF/dz and the stored energy's terms (sigma0 z^2 / 2), returns (F, dF/dV_r)."""
    s0, s1, s2 = q[Q_LAW + 4], q[Q_LAW + 5], q[Q_LAW + 6]
    d[0, D_FZ] = s0 + s1 * d[0, D_RZ]
    d[0, D_EZ] = s0 * zz
    d[0, D_EZZ] = s0
    return s0 * zz + s1 * d[0, D_RATE] + s2 * s, s1 * d[0, D_RS] + s2


@njit(cache=True, forceinline=True)
def lugre(q, s, z, d):
    """LuGre (Canudas de Wit et al. 1995) at V_r = ``s``, bristle deflection z[0]; returns (F, dF/dV_r).

    z' = V_r - sigma0 |V_r| z / g(V_r), F = sigma0 z + sigma1 z' + sigma2 V_r,
    E = sigma0 z^2 / 2.  Fills the derivative record ``d`` (:data:`D_RATE` ...).
    """
    s0 = q[Q_LAW + 4]
    g, dg = lugre_stribeck(q, abs(s))
    sgn = 1.0 if s > 0.0 else (-1.0 if s < 0.0 else 0.0)
    zz = z[0]
    d[0, D_RATE] = s - s0 * abs(s) * zz / g
    d[0, D_RZ] = -s0 * abs(s) / g
    d[0, D_RS] = 1.0 - s0 * zz * sgn * (g - abs(s) * dg) / (g * g)
    return bristle_force(q, s, zz, d)


@njit(cache=True, forceinline=True)
def dahl(q, s, z, d):
    """Dahl (1968) at V_r = ``s``, deflection z[0]; returns (F, dF/dV_r).

    F = sigma0 z, z' = V_r phi(u) with u = 1 - sigma0 z sgn(V_r) / F_C and
    phi(u) = |u|^alpha sgn(u) (alpha >= 1: a bounded Jacobian where u = 0,
    steady sliding); E = sigma0 z^2 / 2.
    """
    fc, s0, alpha = q[Q_LAW], q[Q_LAW + 1], q[Q_LAW + 2]
    sgn = 1.0 if s > 0.0 else (-1.0 if s < 0.0 else 0.0)
    zz = z[0]
    u = 1.0 - s0 * zz * sgn / fc
    au = abs(u)
    pw = 1.0 if alpha == 1.0 else au ** (alpha - 1.0)  # |u|^(alpha - 1)
    phi = pw * u
    d[0, D_RATE] = s * phi
    d[0, D_RZ] = -alpha * pw * s0 * abs(s) / fc
    d[0, D_RS] = phi  # sgn(V_r) jumps at 0, where V_r multiplies it: no term
    d[0, D_FZ] = s0
    d[0, D_EZ] = s0 * zz
    d[0, D_EZZ] = s0
    return s0 * zz, 0.0


@njit(cache=True, forceinline=True)
def plastic_fraction(zz, s, zss, z_ba):
    """alpha(z, V_r) of the elasto-plastic law and its derivatives in z and in z_ss: 0 (elastic) while
    |z| <= z_ba or z and V_r disagree in sign, 1 from |z| >= z_ss, a half sine between."""
    az = abs(zz)
    if zz * s <= 0.0 or az <= z_ba:
        return 0.0, 0.0, 0.0
    if az >= zss:
        return 1.0, 0.0, 0.0
    w = zss - z_ba
    theta = math.pi * (az - 0.5 * (zss + z_ba)) / w
    c = 0.5 * math.cos(theta)
    return 0.5 * math.sin(theta) + 0.5, c * math.pi / w * (1.0 if zz > 0.0 else -1.0), -c * math.pi * (az - z_ba) / (w * w)


@njit(cache=True, forceinline=True)
def elastoplastic(q, s, z, d):
    """The elasto-plastic law (Dupont et al. 2002) at V_r = ``s``, deflection z[0]; returns (F, dF/dV_r).

    z' = V_r - alpha(z, V_r) |V_r| z / z_ss(V_r), z_ss = g(V_r) / sigma0 (LuGre's g),
    F = sigma0 z + sigma1 z' + sigma2 V_r, E = sigma0 z^2 / 2; below the break-away
    deflection z_ba the contact is purely elastic (alpha = 0: true stiction).
    """
    s0, z_ba = q[Q_LAW + 4], q[Q_LAW + 7]
    g, dg = lugre_stribeck(q, abs(s))
    sgn = 1.0 if s > 0.0 else (-1.0 if s < 0.0 else 0.0)
    zss, dzss = g / s0, dg * sgn / s0  # z_ss and dz_ss/dV_r
    zz = z[0]
    a, da_dz, da_dzss = plastic_fraction(zz, s, zss, z_ba)
    d[0, D_RATE] = s - a * abs(s) * zz / zss
    d[0, D_RZ] = -abs(s) / zss * (a + zz * da_dz)
    d[0, D_RS] = 1.0 - zz / zss * (a * sgn + abs(s) * da_dzss * dzss) + a * abs(s) * zz * dzss / (zss * zss)
    return bristle_force(q, s, zz, d)


@njit(cache=True, forceinline=True)
def rate_state(q, s, z, d):
    """Rate-and-state friction (Dieterich, Ruina) at V_r = ``s``, state z[0] = psi = ln(V_0 theta / D_c);
    returns (F, dF/dV_r).

    F = N a asinh(V_r / (2 V_0) e^Omega), Omega = (mu0 + b psi) / a (the regularised form: defined at
    V_r = 0); the aging law psi' = (V_0 / D_c) e^(-psi) - |V_r| / D_c, the slip law
    psi' = -(|V_r| / D_c)(ln(|V_r| / V_0) + psi) (theta' / theta of the usual forms: theta stays > 0).
    No stored energy.  Above |x| = 1 the asinh is taken from ln|x| (e^Omega alone may overflow).
    """
    nrm, mu0, a, b, dc, v0, slip = q[Q_LAW], q[Q_LAW + 1], q[Q_LAW + 2], q[Q_LAW + 3], q[Q_LAW + 4], q[Q_LAW + 5], q[Q_LAW + 6]
    psi = z[0]
    sp = abs(s)
    sgn = 1.0 if s > 0.0 else (-1.0 if s < 0.0 else 0.0)
    om = (mu0 + b * psi) / a
    lx = math.log(sp / (2.0 * v0)) + om if sp > 0.0 else -math.inf  # ln|x|, x = V_r e^Omega / (2 V_0)
    if lx > 0.0:
        w = math.exp(-lx)  # 1 / |x|
        r1 = math.sqrt(1.0 + w * w)
        f, df_ds, df_dpsi = sgn * nrm * a * (lx + math.log(1.0 + r1)), nrm * a / (sp * r1), sgn * nrm * b / r1
    else:
        kk = math.exp(om) / (2.0 * v0)
        x = s * kk
        r1 = math.sqrt(1.0 + x * x)
        f, df_ds, df_dpsi = nrm * a * math.asinh(x), nrm * a * kk / r1, nrm * b * x / r1
    if slip != 0.0:
        lg = math.log(sp / v0) + psi if sp > 0.0 else 0.0  # |V_r| ln|V_r| -> 0: rate 0 at rest
        d[0, D_RATE], d[0, D_RS], d[0, D_RZ] = -sp * lg / dc, (-sgn * (lg + 1.0) / dc if sp > 0.0 else 0.0), -sp / dc
    else:
        e = v0 * math.exp(-psi) / dc
        d[0, D_RATE], d[0, D_RS], d[0, D_RZ] = e - sp / dc, -sgn / dc, -e
    d[0, D_FZ] = df_dpsi
    d[0, D_EZ] = 0.0
    d[0, D_EZZ] = 0.0
    return f, df_ds


@njit(cache=True, forceinline=True)
def law_eval(q, s, z, d):
    """The stateful law of ``q[LAW]`` (one line per law); returns (F, dF/dV_r) and fills ``d``."""
    # every other code is refused before a kernel runs (solvers.stiff: the law's own capability)
    if q[LAW] == DAHL:
        return dahl(q, s, z, d)
    if q[LAW] == ELASTOPLASTIC:
        return elastoplastic(q, s, z, d)
    if q[LAW] == RATE_STATE:
        return rate_state(q, s, z, d)
    return lugre(q, s, z, d)


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def work_of(q, zeta, vb, t, v, s, f, d, w, m):
    """The work integrands at one state: 2 zeta X'^2, max(P_f, 0), max(-P_f, 0), the interface heat
    F V_r - dE/dtau, X' f(tau) and the belt's input F V_b (P_f = X' F); ``m`` internal states."""
    pf = v * f
    store = 0.0
    for i in range(m):
        store += d[i, D_EZ] * d[i, D_RATE]
    w[0] = 2.0 * zeta * v * v
    w[1] = max(pf, 0.0)
    w[2] = max(-pf, 0.0)
    w[3] = f * s - store
    w[4] = v * external_force(q, t)
    w[5] = f * vb


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def evaluate(q, zeta, vb, t, y, dy, dw, jac, jw, ft, want_jac, d):
    """dy/dtau and the work integrands at (t, y); with ``want_jac`` also the state's Jacobian ``jac``
    (n x n), the integrands' gradients ``jw`` (N_CHANNELS x n) and the time rates at fixed y (``ft``: n,
    then N_CHANNELS).  ``vb``: the belt's mean speed.  ``d``: room for the law's derivative record."""
    evaluate_n(q, zeta, vb, t, y, dy, dw, (jac, jw, ft, d), want_jac, len(y))


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def evaluate_n(q, zeta, vb, t, y, dy, dw, jd, want_jac, n):
    """:func:`evaluate` for a state of ``n`` components (a constant where the caller specialises on it);
    ``jd``: (jac, jw, ft, d)."""
    jac, jw, ft, d = jd
    m = n - 2
    x, v = y[0], y[1]
    vbt = belt_speed(q, vb, t)
    s = vbt - v
    f, df_ds = law_eval(q, s, y[2:], d)
    dy[0] = v
    dy[1] = -x - 2.0 * zeta * v + f + external_force(q, t)
    for i in range(m):
        dy[2 + i] = d[i, D_RATE]
    work_of(q, zeta, vbt, t, v, s, f, d, dw, m)
    if want_jac:
        side = input_side(v, f, dy[1])
        _jacobian(zeta, vbt, v, s, (f, df_ds, side), d, jac, jw, n)
        jw[4, 1] = external_force(q, t)
        _time_rates(q, t, v, vbt, (f, df_ds, side), d, jw, ft, n)


@njit(cache=True, inline="always")
def input_side(v, f, acc):
    """1 where the friction power P_f = X' F feeds the mass (the integrand max(P_f, 0) is P_f there), else 0; on
    P_f = 0 -- a step that starts on a turn of X', where the run sets X' to 0 -- the side the step goes into,
    by P_f' = X'' F (``acc`` = X''): the stages' linearisation must be that side's."""
    pf = v * f
    if pf != 0.0:
        return 1.0 if pf > 0.0 else 0.0
    return 1.0 if acc * f > 0.0 else 0.0


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def _time_rates(q, t, v, vbt, force, d, jw, ft, n):
    """d/dtau at fixed y of the state's rates (``ft[:n]``) and of the work integrands (``ft[n:]``): the
    external force's rate, and the belt's acceleration V_b' through V_r (d/dV_r = -d/dX'); ``force``: (F,
    dF/dV_r, :func:`input_side`)."""
    f, df_ds, side = force
    fr = external_force_rate(q, t)
    for i in range(n + N_CHANNELS):
        ft[i] = 0.0
    ft[1] = fr
    ft[n + 4] = v * fr
    ab = belt_accel(q, t)
    if ab == 0.0:  # a belt at constant speed: nothing more (and bit for bit the constant belt's step)
        return
    ft[1] += df_ds * ab
    for i in range(n - 2):
        ft[2 + i] = d[i, D_RS] * ab
    ft[n + 1] = side * v * df_ds * ab
    ft[n + 2] = (side - 1.0) * v * df_ds * ab
    ft[n + 3] = -jw[3, 1] * ab
    ft[n + 5] = (df_ds * vbt + f) * ab


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def _jacobian(zeta, vb, v, s, force, d, jac, jw, n):
    """The exact Jacobian of the state and of the work integrands (d/dX' = -d/dV_r), ``n`` components;
    ``force``: (F, dF/dV_r, :func:`input_side`)."""
    f, df_ds, side = force
    m = n - 2
    for i in range(n):
        for j in range(n):
            jac[i, j] = 0.0
        for c in range(N_CHANNELS):
            jw[c, i] = 0.0
    jac[0, 1] = 1.0
    jac[1, 0] = -1.0
    jac[1, 1] = -2.0 * zeta - df_ds
    for i in range(m):
        jac[1, 2 + i] = d[i, D_FZ]
        jac[2 + i, 1] = -d[i, D_RS]
        for j in range(m):
            jac[2 + i, 2 + j] = d[i, D_RZ + j]
    dpf_dv = f - v * df_ds
    jw[0, 1] = 4.0 * zeta * v
    jw[1, 1], jw[2, 1] = side * dpf_dv, (side - 1.0) * dpf_dv
    # heat: F V_r - sum e_i r_i
    dstore_ds = 0.0
    for i in range(m):
        dstore_ds += d[i, D_EZ] * d[i, D_RS]
    jw[3, 1] = -(df_ds * s + f - dstore_ds)
    jw[5, 1] = -df_ds * vb
    for j in range(m):
        dstore = d[j, D_EZZ] * d[j, D_RATE]
        for i in range(m):
            dstore += d[i, D_EZ] * d[i, D_RZ + j]
        jw[1, 2 + j], jw[2, 2 + j] = side * v * d[j, D_FZ], (side - 1.0) * v * d[j, D_FZ]
        jw[3, 2 + j] = d[j, D_FZ] * s - dstore
        jw[5, 2 + j] = d[j, D_FZ] * vb


#: Rodas4 as a loop: stage i evaluates at t + C_NODE[i] h and y + sum_j A_TAB[i, j] K_j, adds
#: sum_j C_TAB[i, j] K_j / h and h D_TAB[i] df/dtau; the new state is row 5 of A_TAB plus K_5
C_NODE = np.array([0.0, CC2, CC3, CC4, 1.0, 1.0])
D_TAB = np.array([D1, D2, D3, D4, 0.0, 0.0])
A_TAB = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [A21, 0.0, 0.0, 0.0, 0.0, 0.0],
    [A31, A32, 0.0, 0.0, 0.0, 0.0],
    [A41, A42, A43, 0.0, 0.0, 0.0],
    [A51, A52, A53, A54, 0.0, 0.0],
    [A51, A52, A53, A54, 1.0, 0.0],
])
C_TAB = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [C21, 0.0, 0.0, 0.0, 0.0, 0.0],
    [C31, C32, 0.0, 0.0, 0.0, 0.0],
    [C41, C42, C43, 0.0, 0.0, 0.0],
    [C51, C52, C53, C54, 0.0, 0.0],
    [C61, C62, C63, C64, C65, 0.0],
])


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def lu_factor(a, piv):
    """LU with partial pivoting in place (a small dense n x n); False if singular."""
    return lu_factor_n(a, piv, a.shape[0])


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def lu_factor_n(a, piv, n):
    """:func:`lu_factor` of the leading ``n`` x ``n`` block (a constant where the caller specialises on it)."""
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(a[i, k]) > abs(a[p, k]):
                p = i
        piv[k] = p
        if a[p, k] == 0.0:
            return False
        if p != k:
            for j in range(n):
                a[k, j], a[p, j] = a[p, j], a[k, j]
        for i in range(k + 1, n):
            a[i, k] /= a[k, k]
            for j in range(k + 1, n):
                a[i, j] -= a[i, k] * a[k, j]
    return True


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def lu_solve(a, piv, b, r):
    """Solve for row ``r`` of ``b`` in place with the factors of :func:`lu_factor` (a row index, not a
    view: a view costs two atomic reference counts in the step loop)."""
    lu_solve_n(a, piv, b, r, a.shape[0])


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def lu_solve_n(a, piv, b, r, n):
    """:func:`lu_solve` with the leading ``n`` x ``n`` factors (a constant where the caller specialises on it)."""
    for k in range(n):
        p = piv[k]
        if p != k:
            b[r, k], b[r, p] = b[r, p], b[r, k]
    for i in range(n):
        for j in range(i):
            b[r, i] -= a[i, j] * b[r, j]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            b[r, i] -= a[i, j] * b[r, j]
        b[r, i] /= a[i, i]


@njit(cache=True)
def scratch(n):
    """The arrays a step works in, allocated once per run: (dy, dw, jac, jw, LU factors, pivots, K, KW,
    stage state, the law's derivative record, the time rates, then dy and dw at the step's start)."""
    return (np.empty(n), np.empty(N_CHANNELS), np.empty((n, n)), np.empty((N_CHANNELS, n)), np.empty((n, n)),
            np.empty(n, dtype=np.int64), np.zeros((6, n)), np.zeros((6, N_CHANNELS)), np.empty(n),
            np.empty((n - 2, D_RZ + n - 2)), np.empty(n + N_CHANNELS), np.empty(n), np.empty(N_CHANNELS))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: without the runtime, no atomic reference counts
def rodas_step(q, zeta, vb, t, y, h, ynew, wnew, tol, ws):
    """One Rodas4 step of length ``h`` from (t, y): the new state in ``ynew``, the work increments in
    ``wnew``; returns the error norm: the rms of the last stage, component c over
    ``tol[c] + tol[n] max(|y_c|, |ynew_c|)`` (absolute scales, then rtol); inf if the step failed.
    ``ws``: the arrays of :func:`scratch`."""
    return step_from(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, np.bool_(True))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: without the runtime, no atomic reference counts
def step_from(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, fresh):
    """:func:`rodas_step`; with ``fresh`` False the step starts where the last one in ``ws`` started (a
    retry after a rejection, the section search): the field, the Jacobian and the time rates there are
    kept, only the factors of W = I / (gamma h) - J are new (the same numbers as evaluating them again).

    Callers pass ``fresh`` as a bool value (``np.bool_(True)``, not ``True``): a literal compiles this step once
    more for each literal, about 20 s each on a first run."""
    if len(y) == 3:  # one internal state (every law today): loops of known length, which the compiler unrolls
        return _rodas(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, 3, fresh)
    return _rodas(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, len(y), fresh)


@njit(cache=True, inline="always")  # takes arrays in the step loop: numba inlines it (no reference counting)
def _rodas(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, n, fresh):
    """:func:`step_from` for a state of ``n`` components."""
    dy, dw, jac, jw, a, piv, k, kw, yi, d, ft, dy0, dw0 = ws
    for st in range(6):
        for c in range(n):
            acc = y[c]
            for j in range(st):
                acc += A_TAB[st, j] * k[j, c]
            yi[c] = acc  # (stage 0: y itself)
        # one call site, so that the law's code is compiled into the step once (a fifth less compiling); the
        # first stage's call also brings J, jw and ft, which the later stages keep (and a step that is not
        # ``fresh`` keeps from the last one)
        if st > 0 or fresh:
            first = st == 0
            evaluate_n(q, zeta, vb, t + C_NODE[st] * h, yi, dy0 if first else dy, dw0 if first else dw,
                       (jac, jw, ft, d), first, n)
        if st == 0:
            for i in range(n):
                dy[i] = dy0[i]
            for c in range(N_CHANNELS):
                dw[c] = dw0[c]
            for i in range(n):
                for j in range(n):
                    a[i, j] = -jac[i, j]  # jac stays for the quadratures
                a[i, i] += 1.0 / (GAMMA * h)
            if not lu_factor_n(a, piv, n):
                return np.inf
        hd = h * D_TAB[st]
        for c in range(n):
            acc = dy[c]
            for j in range(st):
                acc += C_TAB[st, j] * k[j, c] / h
            k[st, c] = acc + hd * ft[c]
        lu_solve_n(a, piv, k, st, n)
        for c in range(N_CHANNELS):
            acc = dw[c] + hd * ft[n + c]
            for j in range(st):
                acc += C_TAB[st, j] * kw[j, c] / h
            for j in range(n):
                acc += jw[c, j] * k[st, j]
            kw[st, c] = GAMMA * h * acc
    err = 0.0
    for c in range(n):
        ynew[c] = yi[c] + k[5, c]
        e = k[5, c] / (tol[c] + tol[n] * max(abs(y[c]), abs(ynew[c])))
        err += e * e
    for c in range(N_CHANNELS):
        wnew[c] = kw[4, c] + kw[5, c]
        for j in range(4):
            wnew[c] += A_TAB[4, j] * kw[j, c]
    err = math.sqrt(err / n)
    return err if err == err else np.inf


@njit(cache=True, inline="always")
def marks_of(y, dw, out):
    """The functions whose zeros end a step (:data:`N_MARKS`) into ``out``, from the state ``y`` and the work
    integrands ``dw`` there: X' and P_f = X' F (max(P_f, 0) - max(-P_f, 0))."""
    out[0] = y[1]
    out[1] = dw[1] - dw[2]


@njit(cache=True, inline="always")  # takes arrays in the search loop: inlined (no reference counting)
def marks_at(q, zeta, vb, t, y, ws, out):
    """:func:`marks_of` at (t, y), its rates and integrands evaluated into the stage arrays of ``ws``."""
    dy, dw, jac, jw, _, _, _, _, _, d, ft, _, _ = ws
    evaluate_n(q, zeta, vb, t, y, dy, dw, (jac, jw, ft, d), False, len(y))
    marks_of(y, dw, out)


@njit(cache=True, inline="always")
def earliest_mark(fa, fb, skip):
    """The function (not ``skip``) whose sign changes between ``fa`` and ``fb`` with the earliest chord root; -1:
    none.  A start within :data:`MARK_FLOOR` of 0 is the zero the last step ended on, not a new one (X' needs no
    floor: a located zero of it is set to 0 exactly)."""
    best, which = 2.0, np.int64(-1)  # (a literal -1 would compile to_mark once more for it)
    for i in range(N_MARKS):
        if i != skip and fa[i] * fb[i] < 0.0 and (i == 0 or abs(fa[i]) > MARK_FLOOR * abs(fb[i])):
            x = fa[i] / (fa[i] - fb[i])
            if x < best:
                best, which = x, i
    return which


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: no reference counting (see rodas_step)
def to_mark(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, which, marks):
    """The step from (t, y) that ends on the zero of function ``which`` (:func:`marks_of`) inside the step of
    length ``h`` (its state in ``ynew``, its functions in ``marks[1]``, the start's in ``marks[0]``): its length h'
    by Illinois on that function at t + h' of Rodas4 steps of length h', to 1e-13 of X''s scale (X' is then set to
    0) or :data:`MARK_TOL` of P_f's, or the step length at rounding.  ``ynew``, ``wnew``, ``marks[1]``: the located step's state, work increments and
    functions (a zero of X' ends with X' exactly 0: downwards, the section crossing of the other solvers); returns
    (h', its error norm).  ``ws`` holds a step from (t, y): its start's field and Jacobian serve every trial step
    (:func:`step_from`)."""
    fa, fb, trial = marks[0, which], marks[1, which], marks[2]
    # X' to 1e-13 of its scale: it is then set to 0, a change of the state
    tol_f = 1e-13 * max(abs(vb), abs(y[1])) if which == 0 else MARK_TOL * max(abs(fa), abs(fb))
    b = bracket(0.0, h, fa, fb, 0.0, 4.0 * EPS, tol_f, 100)
    err, x_last = 0.0, h
    while b.status == RUNNING:
        x_last = b.x
        err = step_from(q, zeta, vb, t, y, x_last, ynew, wnew, tol, ws, np.bool_(False))
        if err < np.inf:
            marks_at(q, zeta, vb, t + x_last, ynew, ws, trial)
        b = update(b, x_last, trial[which] if err < np.inf else -fa)
    if x_last != b.hi:  # the last point evaluated was not the end kept: the step to that end
        err = step_from(q, zeta, vb, t, y, b.hi, ynew, wnew, tol, ws, np.bool_(False))
    if which == 0:  # X' exactly 0 there, either way: the next step starts on the turn, not across it
        ynew[1] = 0.0
    marks_at(q, zeta, vb, t + b.hi, ynew, ws, marks[1])
    return b.hi, err


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: no reference counting (see rodas_step)
def to_first_mark(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, marks):
    """The accepted step of length ``h`` from (t, y) to ``ynew``, with a zero inside it of a function of
    :func:`marks_of` (their values at its ends in ``marks[0]`` and ``marks[1]``), shortened to the first such zero:
    (h', error norm).  Each located zero may hide an earlier one of another function: the shortened step is looked
    at again."""
    adv, err, skip = h, 0.0, -1
    for _ in range(N_MARKS):
        which = earliest_mark(marks[0], marks[1], skip)
        if which < 0:
            break
        adv, err = to_mark(q, zeta, vb, t, y, adv, ynew, wnew, tol, ws, which, marks)
        skip = which
    return adv, err


#: the run's position (``at`` of :func:`run`): samples written, steps attempted, next step, next sample's
#: period index, whether the last attempt was rejected
AT_COUNT, AT_TAKEN, AT_H, AT_K, AT_REJECTED = range(5)
N_AT = 5


@njit(cache=True)
def run(q, zeta, vb, y0, t_end, tol, steps, t_out, y_out, w_out, at):
    """Integrate from (0, y0) to ``t_end``, keeping every accepted step.

    ``tol``: the absolute scale of each state component, then rtol; ``steps``:
    (first step, largest step, step cap, sampling period): with a period
    (> 0, the forcing's or the belt's) a step ends on every k period, so that the
    stroboscopic section is sampled exactly as the other solvers sample it;
    without, each downward X' = 0 crossing is a sample; a step also ends on every zero of the functions of
    :func:`marks_of` (:func:`to_first_mark`).
    Writes the times, states and work increments (row 0 zero) and returns (samples, status, t reached, step):
    status :data:`DONE`, :data:`FULL` (buffers full: copy the samples into larger ones and call again with
    the same ``at``, the run goes on where it stopped), :data:`STEP_CAP` or :data:`TINY_STEP`.
    ``at``: the run's position (:data:`AT_COUNT` ...), AT_COUNT 0 to start.
    """
    n = len(y0)
    cap = len(t_out)
    h_max, max_steps, period = steps[1], int(steps[2]), steps[3]
    if at[AT_COUNT] == 0.0:
        t_out[0] = 0.0
        y_out[:, 0] = y0
        w_out[0, :] = 0.0
        at[:] = 0.0
        at[AT_COUNT], at[AT_H], at[AT_K] = 1.0, steps[0], 1.0
    count, taken, h, k_next, rejected = int(at[AT_COUNT]), int(at[AT_TAKEN]), at[AT_H], at[AT_K], at[AT_REJECTED] != 0.0
    t = t_out[count - 1]
    y, ynew, wnew = y_out[:, count - 1].copy(), np.empty(n), np.empty(N_CHANNELS)
    ws, marks = scratch(n), np.empty((3, N_MARKS))  # marks: the functions at a step's start, end and a trial point
    status, again = DONE, False
    while t < t_end:
        if taken >= max_steps:
            status = STEP_CAP
            break
        if h < 1e-14 * max(1.0, t):
            status = TINY_STEP
            break
        h = min(h, h_max)
        stop = min(t_end, k_next * period) if period > 0.0 else t_end  # the next time a sample must fall on
        last = t + h >= stop * (1.0 - 1e-14)
        hh = stop - t if last else h
        err = step_from(q, zeta, vb, t, y, hh, ynew, wnew, tol, ws, not again)
        again = True  # until the state moves on, the next attempt starts from the same (t, y)
        taken += 1
        fac = 0.2 if err == np.inf else min(6.0, max(0.2, 0.9 * err ** -0.25))
        if err > 1.0:
            h = hh * fac
            rejected = True
            continue
        if count == cap:
            status, taken = FULL, taken - 1  # this step is taken again, the same, on the next call
            break
        # adv: how far the sample lies (the first zero of a marked function); the next step follows the full one's error
        adv, err = hh, 0.0
        marks_of(y, ws[12], marks[0])  # the step's start: its field was evaluated there
        # the end: P_f from the last stage's integrands (at t + h, within the step's error of ynew), no evaluation;
        # a zero that error hides lies as near the end, where its kink costs ~nothing
        marks_of(ynew, ws[1], marks[1])
        if earliest_mark(marks[0], marks[1], -1) >= 0:  # the step ends on the first zero inside it (a sample)
            adv, err = to_first_mark(q, zeta, vb, t, y, hh, ynew, wnew, tol, ws, marks)
            last = last and adv == hh
        if err > 1.0:  # the shorter step from the same state failed its error test (hardly ever)
            h, rejected = adv * max(0.2, 0.9 * err ** -0.25), True
            continue
        t = stop if last else t + adv
        if last and period > 0.0 and stop < t_end:
            k_next += 1.0
        y[:] = ynew
        again = False
        t_out[count] = t
        y_out[:, count] = y
        w_out[count, :] = wnew
        count += 1
        h = hh * (min(fac, 1.0) if rejected else fac)  # no growth right after a rejection
        rejected = False
    at[AT_COUNT], at[AT_TAKEN], at[AT_H], at[AT_K], at[AT_REJECTED] = count, taken, h, k_next, 1.0 if rejected else 0.0
    return count, status, t, h
