"""The state of the belt oscillator together with its tangent (variational) dynamics, switch by switch.

The flow is ``X'' + 2 zeta X' + X = F_c(V_r) + f(tau)``, ``V_r = V_b - X'``,
``f(tau) = F_ex cos(Omega tau + phi)``, for laws with Coulomb's stick rule
(``stick_rule == "switch"``: Coulomb, Stribeck, cubic).  It is smooth inside
each friction mode and switches between modes on surfaces ``h(X, X', tau) = 0``;
the kernel integrates every phase on its own and *locates* every switch
(no smoothed sign function), then carries two tangent vectors across it with
the saltation matrix.

On a belt whose speed varies (``p[VB_AMP]`` > 0), V_b is V_b(tau) =
V_b + A sin(Omega_b tau + phi_b) wherever it appears below (read from the
force record at each stage's and switch's time: :func:`~.friction.belt_speed`),
a stick phase follows the belt, and the surfaces move with it: see
"On a moving belt" at the end.  A belt at constant speed computes what it
computed before, to the bit (every belt term is V_b itself or 0 there).

Inside the phases
-----------------
*Slip in direction d* (d = sgn V_r = +-1, so |V_r| = d (V_b - X')):
``X'' = d F(d (V_b - X')) + f(tau) - X - 2 zeta X'`` with F = |F_c| the slip
curve.  Its Jacobian: dX''/dX = -1 and

    dX''/dX' = -2 zeta + d F'(|V_r|) d|V_r|/dX' = -2 zeta + d F'(|V_r|) (-d) = -2 zeta - F'(|V_r|),

the same in both directions (d^2 = 1), so the tangent dynamics are

    dx' = dv,        dv' = -dx - (2 zeta + F'(|V_r|)) dv.

Integrated with the state by classical RK4 (the 6-vector of X, X' and the two
tangent vectors), on a grid of steps that lands on every block end
tau_k = k T (T the forcing period when forced).

*Stick*: X' = V_b held, X = X_s + V_b (tau - tau_s) in closed form.  The
field (V_b, 0) is constant, its Jacobian is 0: the tangent vectors do not
change (and have dv = 0, see the stick onset).

The switches and their saltation matrices
-----------------------------------------
A perturbation dy (at fixed time) of a trajectory that crosses
``h(y, tau) = 0`` at tau* from field f- to field f+ crosses at
tau* + dtau with n.(dy + f- dtau) + h_tau dtau = 0 (n = grad_y h), and by the
common time it has followed f- for -dtau less, f+ for -dtau more:

    dy+ = S dy,     S = I + (f+ - f-) n^T / (n.f- + h_tau).

With a = X'' of a field at the switch state:

1. *Stick onset* (slip d -> stick): h = V_b - X', n = (0, -1), h_tau = 0,
   f- = (V_b, a-), f+ = (V_b, 0).  n.f- = -a-, (f+ - f-) n^T = [[0, 0], [0, a-]]:
   S = diag(1, 0).  dv -> 0: the stick phase forgets every perturbation of
   X', and the tangent map loses a dimension (det S = 0).  Two tangent
   vectors become parallel: the second Lyapunov exponent is -inf whenever
   the motion keeps sticking (the kernel records the collapse rather than
   read rounding noise as a finite exponent).
2. *Slip onset* (stick -> slip d): h = s (F_e - f(tau)) - F_s with s the side
   reached (F_e = X + 2 zeta V_b or X), n = (s, 0) (a v component of n
   would meet dv = 0), h_tau = -s f'(tau), f- = (V_b, 0), f+ = (V_b, a+),
   a+ = d F(0+) + f - X - 2 zeta V_b.  n.f- + h_tau = s (V_b - f'):

       S = [[1, 0], [a+ / (V_b - f'(tau)), 1]],

   a perturbation dx > 0 on the side s = +1 leaves dx / (V_b - f') earlier
   and has gained a+ dx / (V_b - f') of velocity by the common time.
   Unforced: a+ / V_b.
3. *Slip reversal* (slip d -> slip -d through V_r = 0 without sticking):
   h = V_b - X', n = (0, -1), f-+ = (V_b, a-+), a-+ = -+d F(0+) + f - X - 2 zeta V_b:

       S = diag(1, a+ / a-),

   the velocity perturbation scales with the ratio of the accelerations.

Switch location
---------------
Slip ends where g = d (V_b - X') reaches 0.  A step whose end has g <= 0
(or whose cubic Hermite interpolant of g dips below 0: two crossings inside
one step) is retaken from its start with lengths theta found by false
position (Illinois, :mod:`.roots`) on g(theta) = g(the RK4 step of length theta), to
|dtheta| ~ 1e-15 tau: the switch is a root of the scheme's own solution, and
the state and tangent vectors at the switch are one RK4 step of length theta.
A stick phase ends where |F_e - f(tau)| reaches F_s moving outwards: an
explicit function of tau, searched once per phase, off the grid, by the
adaptive kernel's rule (:func:`.stick.exit_time`: the held force walked
through its monotone pieces and bisected to the last bit; unforced, one
piece).  The mode after every switch is :func:`~.friction.rest_mode`
with the external force and its rate at that instant; where it holds the
interface at F_s (no slip direction is consistent) the stick goes on as a
new phase past the monotone piece it holds on.

On a moving belt
----------------
*Stick*: X' = V_b(tau), X = X_s + int V_b in closed form
(:func:`.stick.stick_x`): the field (V_b(tau), V_b'(tau)) does not depend on
the state, its Jacobian is 0, the tangent vectors do not change.  While
sticking X'' = V_b', so the interface holds F_e + V_b' - f
(:func:`~.friction.stick_load`), with the rate
V_b + [2 zeta V_b'] + V_b'' - f' (:func:`~.friction.stick_load_rate`; the
bracket when F_e = X + 2 zeta X').  With a = X'' of a field at the switch:

1. *Stick onset*: h = V_b(tau) - X', h_tau = V_b', f+ = (V_b, V_b'):
   n.f- + h_tau = V_b' - a-, (f+ - f-) n^T = [[0, 0], [0, a- - V_b']]:
   S = diag(1, 0) still.
2. *Slip onset*: h = s (F_e + V_b' - f) - F_s on the stick manifold; n.f- +
   h_tau = s (the held force's rate):
   S = [[1, 0], [(a+ - V_b') / (the held force's rate), 1]].
3. *Slip reversal*: h = V_b(tau) - X', h_tau = V_b':
   S = diag(1, (a+ - V_b') / (a- - V_b')).

The relative accelerations a - V_b' are :func:`_a_rest`'s (the belt's
acceleration enters as the stick rule's load); on a constant belt they are
the accelerations themselves.

Exponents
---------
Every block (from tau = 0, of length ``block``) ends with a QR (Gram-Schmidt)
renormalisation of the two tangent vectors u1, u2: r11 = |u1|,
q1 = u1 / r11, q2 = q1 turned by 90 degrees, r22 = q2.u2.  After the transient
blocks, the sums of log r11 and log |r22| over the averaged blocks divided by
their time are the exponents (log r22 = -inf in a block with a stick onset).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit
from numba.np.unsafe.ndarray import to_fixed_tuple

from . import codes
from .friction import (FS, RESULTANT, belt_accel, belt_speed, external_force, rest_mode, slip_magnitude_of,
                       slip_slope_of, stick_load, stick_load_rate)
from .hermite import hermite_min
from .layout import N_PARAMS
from .roots import RUNNING, bracket, update
from .stick import exit_time, stick_x

#: the 6-vector integrated in slip: X, X', then the tangent vectors u1 = (y2, y3), u2 = (y4, y5)
NY = 6
#: columns of a ``strobe`` row that also takes the tangent vectors (X, X', mode, u1, u2; else 3)
N_FRAME = 7
#: counts the kernel returns: stick onsets, slip onsets, slip reversals, held at F_s, grazing touches
N_COUNTS = 5
C_STICK, C_SLIP, C_REVERSAL, C_HELD, C_GRAZE = range(N_COUNTS)
#: status codes
OK, ZERO_PHASES, NOT_FINITE = codes.OK, codes.STUCK, codes.NOT_FINITE
#: consecutive phases shorter than a rounding unit before the kernel gives up
MAX_ZERO_PHASES = 16
EPS = 2.220446049250313e-16

#: the arrays one RK4 step of the 6-vector works in: its four stages, the stage argument and the step's end
#: (``out``: where :func:`rk4_step` and :func:`slip_until` leave the state); one record, not six arguments
Scratch = namedtuple("Scratch", "k1 k2 k3 k4 tmp out")


@njit(cache=True)
def slip_force(p, s):
    """|F| at the slip speed s = d (V_b - X'); for s < 0 (an RK stage overshooting a switch) its linear extension."""
    if s >= 0.0:
        return slip_magnitude_of(p, s)
    k = slip_slope_of(p, 0.0)
    f0 = slip_magnitude_of(p, 0.0)
    return f0 + s * k if math.isfinite(k) else f0


@njit(cache=True)
def slip_slope(p, s):
    """F'(s), continued as F'(0+) below 0 (see :func:`slip_force`)."""
    k = slip_slope_of(p, max(s, 0.0))
    return k if math.isfinite(k) else 0.0


@njit(cache=True)
def accel(d, x, v, t, zeta, vb, p):
    """X'' while slipping in direction d (``vb``: the record's V_b; the belt's speed at t is read from ``p``)."""
    return accel_with(d, x, v, external_force(p, t), zeta, belt_speed(p, vb, t), p)


@njit(cache=True, forceinline=True)
def accel_with(d, x, v, f, zeta, vb, p):
    """:func:`accel` given the external force f and the belt's speed ``vb`` there."""
    return d * slip_force(p, d * (vb - v)) + f - x - 2.0 * zeta * v


# The slip step works on tuples (the 6-vector and RK4's stages are values, not arrays): a call of a compiled
# function costs two atomic reference-count updates per array argument, and so does an array bound to
# another name (an inlined callee's argument) in a loop -- more than the step's arithmetic.
# :func:`slip_until` and :func:`rk4_step` keep their array form for callers outside the kernel.
@njit(cache=True, forceinline=True)
def _rhs(y, t, d, zeta, vb, p):
    """The slip field of the state and of both tangent vectors (``y``: the 6-vector as a tuple; ``vb``: the
    record's V_b, the belt's speed at t read from ``p``)."""
    return _rhs_f(y, external_force(p, t), d, zeta, belt_speed(p, vb, t), p)


@njit(cache=True, forceinline=True)
def _rhs_f(y, f, d, zeta, vb, p):
    """:func:`_rhs` given the external force f and the belt's speed ``vb`` there (RK4's two middle stages share
    them)."""
    x = y[0]
    v = y[1]
    acc = accel_with(d, x, v, f, zeta, vb, p)
    damp = 2.0 * zeta + slip_slope(p, d * (vb - v))
    return (v, acc, y[3], -y[2] - damp * y[3], y[5], -y[4] - damp * y[5])


@njit(cache=True, forceinline=True)
def _axpy(y, a, k):
    """y + a k, element by element (6-tuples)."""
    return (y[0] + a * k[0], y[1] + a * k[1], y[2] + a * k[2], y[3] + a * k[3], y[4] + a * k[4], y[5] + a * k[5])


@njit(cache=True, forceinline=True)
def _rk4(y, t, h, d, zeta, vb, p):
    """One classical RK4 step of length h from (y, t) (6-tuples): the state at its end."""
    return _rk4_from(y, t, h, d, zeta, vb, p, _rhs(y, t, d, zeta, vb, p))


@njit(cache=True, forceinline=True)
def _rk4_from(y, t, h, d, zeta, vb, p, k1):
    """:func:`_rk4` given its first stage ``k1`` (the field at (y, t))."""
    f_mid = external_force(p, t + 0.5 * h)
    vb_mid = belt_speed(p, vb, t + 0.5 * h)
    k2 = _rhs_f(_axpy(y, 0.5 * h, k1), f_mid, d, zeta, vb_mid, p)
    k3 = _rhs_f(_axpy(y, 0.5 * h, k2), f_mid, d, zeta, vb_mid, p)
    k4 = _rhs(_axpy(y, h, k3), t + h, d, zeta, vb, p)
    c = h / 6.0
    return (y[0] + c * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]), y[1] + c * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
            y[2] + c * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2]), y[3] + c * (k1[3] + 2.0 * k2[3] + 2.0 * k3[3] + k4[3]),
            y[4] + c * (k1[4] + 2.0 * k2[4] + 2.0 * k3[4] + k4[4]), y[5] + c * (k1[5] + 2.0 * k2[5] + 2.0 * k3[5] + k4[5]))


@njit(cache=True)
def scratch():
    """Fresh :class:`Scratch` for :func:`rk4_step` and :func:`slip_until` (every array of length :data:`NY`)."""
    return Scratch(np.empty(NY), np.empty(NY), np.empty(NY), np.empty(NY), np.empty(NY), np.empty(NY))


@njit(cache=True)
def rk4_step(y, t, h, d, zeta, vb, p, sc):
    """One classical RK4 step of length h from (y, t) into ``sc.out`` (``sc``: a :class:`Scratch`)."""
    out = sc.out
    out[0], out[1], out[2], out[3], out[4], out[5] = _rk4((y[0], y[1], y[2], y[3], y[4], y[5]), t, h, d, zeta, vb, p)


@njit(cache=True)
def _g_step(y, t, theta, d, zeta, vb, p):
    """(the switch function d (V_b - X'), the state) after an RK4 step of length theta."""
    out = _rk4(y, t, theta, d, zeta, vb, p)
    return d * (belt_speed(p, vb, t + theta) - out[1]), out


@njit(cache=True)
def _refine(y, t, lo, hi, glo, ghi, d, zeta, vb, p):
    """(theta, the state there): theta where g(theta) = 0, g(lo) > 0 >= g(hi), to a few units of tau (:mod:`.roots`)."""
    b = bracket(lo, hi, glo, ghi, 4.0 * EPS * abs(t), 4.0 * EPS, 0.0, 200)
    while b.status == RUNNING:
        b = update(b, b.x, _g_step(y, t, b.x, d, zeta, vb, p)[0])
    return b.hi, _g_step(y, t, b.hi, d, zeta, vb, p)[1]


@njit(cache=True)
def rounding_noise(v, vb):
    """The size below which d (V_b - X') is rounding: a few units of X' and V_b."""
    return 16.0 * EPS * (abs(v) + abs(vb))


@njit(cache=True)
def slip_until(y, t, h, d, zeta, vb, p, fresh, sc):
    """One slip step of at most h; returns (theta, switched): the step taken and whether it ends on V_r = 0.

    The state at its end in ``sc.out`` (``sc``: a :class:`Scratch`).  The
    array form of :func:`_slip_step`.
    """
    theta, switched, end, _ = _slip_step((y[0], y[1], y[2], y[3], y[4], y[5]), t, h, d, zeta, vb, p, fresh)
    out = sc.out
    out[0], out[1], out[2], out[3], out[4], out[5] = end
    return theta, switched


@njit(cache=True)
def _slip_step(y, t, h, d, zeta, vb, p, fresh):
    """One slip step of at most h from the 6-vector ``y`` (a tuple); returns (theta, switched, the state at
    its end, away): the step taken, whether it ends on V_r = 0, and (a whole step) whether its end is off
    V_r = 0 by more than rounding.

    ``fresh``: the phase began at t (g(0) = 0; the left end of a bracket is then looked for inside).
    """
    vb0 = belt_speed(p, vb, t)
    g0 = d * (vb0 - y[1])
    k1 = _rhs(y, t, d, zeta, vb, p)
    end = _rk4_from(y, t, h, d, zeta, vb, p, k1)
    vb1 = belt_speed(p, vb, t + h)
    g1 = d * (vb1 - end[1])
    a0 = k1[1]  # X'' at the start: the first stage's
    noise = rounding_noise(y[1], vb0)
    if fresh and abs(g1) <= noise:
        # leaving tangentially (Stribeck's a+ = 0), or a step too short to show it: the
        # stick rule chose a direction that leaves, so V_r = 0 is no switch yet
        return h, False, end, g1 > rounding_noise(end[1], vb1)
    if g1 > 0.0:
        # two crossings inside the step?  The Hermite cubic of g (g' = -d (X'' - V_b')) dips below 0
        a1 = accel(d, end[0], end[1], t + h, zeta, vb, p)
        s, val = hermite_min(g0, g1, -d * (a0 - belt_accel(p, t)) * h, -d * (a1 - belt_accel(p, t + h)) * h)
        if s < 0.0 or val >= -noise:
            return h, False, end, g1 > rounding_noise(end[1], vb1)
        gm = _g_step(y, t, s * h, d, zeta, vb, p)[0]
        if gm > 0.0:  # the scheme's own solution stays off the surface: a near miss
            return h, False, end, g1 > rounding_noise(end[1], vb1)
        hi, ghi = s * h, gm
    else:
        hi, ghi = h, g1
    lo, glo = 0.0, g0
    if glo <= 0.0 or fresh:
        # the phase starts on the surface: a left end inside (0, hi) where g > 0
        lo = hi
        glo = 0.0
        for _ in range(60):
            lo *= 0.5
            glo, end = _g_step(y, t, lo, d, zeta, vb, p)
            if glo > 0.0:
                break
        if not glo > 0.0:
            return 0.0, True, end, False  # leaves the surface the wrong way at once: a zero-length phase
    theta, end = _refine(y, t, lo, hi, glo, ghi, d, zeta, vb, p)
    return theta, True, end, False


@njit(cache=True)
def stick_phase(x_s, t_s, t_end, zeta, vb, p):
    """A stick phase from (x_s, t_s): (x_s, t_s, the time it leaves F_s, :func:`.stick.exit_time`; t_end if not before).

    Every stick phase begins where :func:`~.friction.rest_mode` has just
    chosen to stick (a stick onset, the start, or a hold at F_s), so it is
    searched as held (``hold``): if it begins on or past F_s moving outwards
    (no slip direction was consistent), the rule's answer there stands for
    that monotone piece instead of being asked again at the same instant.
    """
    return x_s, t_s, exit_time(x_s, t_s, t_end, True, zeta, vb, p[FS], p[RESULTANT] != 0.0, p)


@njit(cache=True)
def surface_mode(x, t, zeta, vb, p):
    """The mode the stick rule gives on V_r = 0 (X' = V_b(t)) at (x, t): 0 sticking, else the slip direction.

    The belt's acceleration is a load on the rule (:func:`~.friction.stick_load`, its rate
    :func:`~.friction.stick_load_rate`): the external force and its rate themselves on a constant belt.
    """
    res = p[RESULTANT] != 0.0
    return rest_mode(x, zeta, belt_speed(p, vb, t), p[FS], res, slip_force(p, 0.0), stick_load(p, t),
                     stick_load_rate(p, t, zeta, res))


@njit(cache=True)
def start_mode(x, v, t, zeta, vb, p):
    """The mode at (x, v, t): the slip direction sgn(V_r), or the stick rule on V_r = 0."""
    vbt = belt_speed(p, vb, t)
    if v != vbt:
        return 1 if vbt - v > 0.0 else -1
    return surface_mode(x, t, zeta, vb, p)


@njit(cache=True)
def _a_rest(d, x, t, zeta, vb, p):
    """X'' - V_b' at X' = V_b(t) slipping in direction d (the relative field on either side of a switch; X''
    itself on a constant belt)."""
    return d * slip_force(p, 0.0) + stick_load(p, t) - x - 2.0 * zeta * belt_speed(p, vb, t)


@njit(cache=True, inline="always")
def saltation_stick(y):
    """Stick onset, S = diag(1, 0), on both tangent vectors of ``y``: every dv is forgotten."""
    y[3] = 0.0
    y[5] = 0.0


@njit(cache=True, inline="always")
def saltation_slip(y, new, t, zeta, vb, p):
    """Slip onset into direction ``new``, S = [[1, 0], [(a+ - V_b') / (the held force's rate), 1]], on both
    tangent vectors (V_b - f' on a constant belt)."""
    rate = belt_speed(p, vb, t) - stick_load_rate(p, t, zeta, p[RESULTANT] != 0.0)
    c = _a_rest(float(new), y[0], t, zeta, vb, p) / rate
    y[3] += c * y[2]
    y[5] += c * y[4]


@njit(cache=True, inline="always")
def saltation_reversal(y, d, new, t, zeta, vb, p):
    """Slip reversal d -> ``new`` through V_r = 0, S = diag(1, (a+ - V_b') / (a- - V_b')), on both tangent vectors."""
    ratio = _a_rest(float(new), y[0], t, zeta, vb, p) / _a_rest(d, y[0], t, zeta, vb, p)
    y[3] *= ratio
    y[5] *= ratio


@njit(cache=True)
def _grid_time(j, n_sub, block, h):
    """The end of grid step j: whole blocks plus whole steps, without a running sum's drift."""
    return (j // n_sub) * block + (j % n_sub) * h


@njit(cache=True)
def _start(x0, v0, zeta, vb, p):
    """The 6-vector at tau = 0 (the state, u1 = (1, 0), u2 = (0, 1)) and the mode there.

    Sticking from the start: X' = V_b and the stick onset's dv -> 0.
    """
    y = np.zeros(NY)
    y[0], y[1] = x0, v0
    y[2], y[3], y[4], y[5] = 1.0, 0.0, 0.0, 1.0
    mode = start_mode(x0, v0, 0.0, zeta, vb, p)
    if mode == 0:
        y[1] = belt_speed(p, vb, 0.0)
        saltation_stick(y)
    return y, mode


@njit(cache=True)
def _stick_on(y, t, target, phase, t_end, zeta, vb, p, counts):
    """Stick from t toward ``target`` in the :func:`stick_phase` ``phase``; returns (t, mode, phase) where it stops.

    Mode 0: sticking on to ``target``, or held at F_s where
    :func:`~.friction.rest_mode` gives no slip direction (a new phase, on
    past the monotone piece it holds on); else the slip direction entered,
    its saltation applied to ``y``.
    """
    x_s, t_s, te = phase
    if te > target or te >= t_end:
        y[0] = stick_x(x_s, t_s, target, vb, p)
        y[1] = belt_speed(p, vb, target)
        return target, 0, phase
    y[0] = stick_x(x_s, t_s, te, vb, p)
    y[1] = belt_speed(p, vb, te)
    new = surface_mode(y[0], te, zeta, vb, p)
    if new == 0:
        counts[C_HELD] += 1
        return te, 0, stick_phase(y[0], te, t_end, zeta, vb, p)
    saltation_slip(y, new, te, zeta, vb, p)
    counts[C_SLIP] += 1
    return te, new, phase


@njit(cache=True)
def _slip_end(y, t, d, zeta, vb, p, counts):
    """The end of a slip phase in direction d on V_r = 0 at t: X' = V_b exactly, the switch's saltation; returns the mode.

    The same direction again is a grazing touch, no switch.
    """
    y[1] = belt_speed(p, vb, t)  # exactly on the switch
    new = surface_mode(y[0], t, zeta, vb, p)
    if new == 0:
        saltation_stick(y)
        counts[C_STICK] += 1
    elif new != d:
        saltation_reversal(y, d, new, t, zeta, vb, p)
        counts[C_REVERSAL] += 1
    else:
        counts[C_GRAZE] += 1  # touched V_r = 0 and slips on the same way: no switch
    return new


@njit(cache=True)
def _block_end(y, mode, row):
    """The block end: the stroboscopic sample (X, X', mode) into ``row``, the QR of the tangent vectors; returns (r11, r22).

    A row of :data:`N_FRAME` columns also gets both tangent vectors before
    the QR (u1, then u2).  A block that starts sticking then gets the stick
    onset's projection: the frame's dv components belong to no sticking
    motion (a perturbed X' slips back onto the belt at once).
    """
    row[0] = y[0]
    row[1] = y[1]
    row[2] = mode
    if len(row) >= N_FRAME:
        row[3], row[4], row[5], row[6] = y[2], y[3], y[4], y[5]
    r11, r22 = _qr(y)
    if mode == 0:
        saltation_stick(y)
    return r11, r22


@njit(cache=True)
def _average(s1, s2, r11, r22, collapsed, k, block, est):
    """The sums of log r11 and log|r22| with averaged block k's (log r22 = -inf in a block with a stick onset).

    Writes the running estimates after block k into ``est[k]``.
    """
    s1 += math.log(r11)
    s2 += -math.inf if (collapsed or r22 == 0.0) else math.log(abs(r22))
    elapsed = (k + 1) * block
    est[k, 0] = s1 / elapsed
    est[k, 1] = s2 / elapsed
    return s1, s2


@njit(cache=True)
def run(x0, v0, zeta, vb, p, block, n_sub, n_transient, n_blocks, strobe, est, counts):
    """Integrate n_transient + n_blocks blocks with the two tangent vectors; returns (status, sum log r11, sum log|r22|).

    Fills ``strobe`` (n_transient + n_blocks, 3: X, X', mode at each block
    end; with :data:`N_FRAME` columns, also the tangent vectors there before
    their renormalisation: over a single block from the identity, the
    columns of the flow's derivative d(X, X')/d(x0, v0)), ``est`` (n_blocks, 2: the running exponent estimates after each
    averaged block) and ``counts`` (:data:`N_COUNTS`, over the whole run).
    """
    never = (n_blocks + 1, n_blocks + 1, 0.0, 0.0)  # (from the arguments: int64, not a literal type per constant)
    status, s1, s2, _ = run_until(x0, v0, zeta, vb, p, block, n_sub, (n_transient, n_blocks), never, strobe, est, counts)
    return status, s1, s2


@njit(cache=True)
def _negative(est, n, stop):
    """Whether lambda_1's estimate after n averaged blocks (``est[n - 1, 0]``) is below -factor times its
    uncertainty, checked at n = first, first + every, ...; ``stop`` = (first, every, factor, floor).

    The uncertainty is the range of the running estimate over the second half
    of the n blocks, at least ``floor``; NaN (not finite) never stops.
    """
    first, every, factor, floor = stop
    if every <= 0 or n < first or (n - first) % every != 0:
        return False
    lo, hi = np.inf, -np.inf
    for i in range(n // 2, n):
        lo, hi = min(lo, est[i, 0]), max(hi, est[i, 0])
    spread = hi - lo
    return math.isfinite(spread) and est[n - 1, 0] < -factor * max(spread, floor)


@njit(cache=True)
def run_until(x0, v0, zeta, vb, p, block, n_sub, blocks, stop, strobe, est, counts):
    """:func:`run` of ``blocks`` = (n_transient, n_blocks), ended early once lambda_1 is negative beyond its
    uncertainty (:func:`_negative`, ``stop``); returns (status, s1, s2, averaged blocks done).

    A running estimate converging like C / n onto 0 has its range over the
    second half about equal to itself, so a ``factor`` of 2 does not end a
    run whose exponent is heading for 0.  Only negative exponents end the
    run: a positive one (chaos) is averaged over every block.
    """
    h = block / n_sub
    p = to_fixed_tuple(p, N_PARAMS)  # the force record as a tuple: calls taking it cost no reference counting
    for i in range(N_COUNTS):
        counts[i] = 0
    y, mode = _start(x0, v0, zeta, vb, p)
    t = 0.0
    fresh = v0 == belt_speed(p, vb, 0.0)
    n_transient, n_blocks = blocks
    t_end = _grid_time((n_transient + n_blocks) * n_sub, n_sub, block, h)
    phase = stick_phase(y[0], t, t_end, zeta, vb, p) if mode == 0 else (y[0], t, t_end)
    zero_run = 0
    s1 = 0.0
    s2 = 0.0
    collapsed = mode == 0
    j = np.int64(0)  # (a literal 0 would compile _grid_time once more for it)
    for blk in range(n_transient + n_blocks):
        for _ in range(n_sub):
            j += 1
            target = _grid_time(j, n_sub, block, h)
            while t < target:
                if mode == 0:
                    t, mode, phase = _stick_on(y, t, target, phase, t_end, zeta, vb, p, counts)
                    fresh = True  # read once slipping: a slip phase entered here starts on V_r = 0
                    continue
                d = float(mode)
                theta, switched, out, away = _slip_step((y[0], y[1], y[2], y[3], y[4], y[5]), t, target - t, d, zeta, vb, p, fresh)
                if not switched:
                    y[0], y[1], y[2], y[3], y[4], y[5] = out
                    t = target
                    zero_run = 0
                    # a phase that has not yet left V_r = 0 by more than rounding is still starting
                    fresh = fresh and not away
                    continue
                if theta > 0.0:
                    y[0], y[1], y[2], y[3], y[4], y[5] = out
                    t += theta
                zero_run = zero_run + 1 if theta <= 4.0 * EPS * (1.0 + abs(t)) else 0
                if zero_run > MAX_ZERO_PHASES:
                    return ZERO_PHASES, s1, s2, blk - n_transient
                mode = _slip_end(y, t, d, zeta, vb, p, counts)
                fresh = mode != 0  # a slip phase entered here starts on V_r = 0
                if mode == 0:
                    phase = stick_phase(y[0], t, t_end, zeta, vb, p)
                    collapsed = True
        r11, r22 = _block_end(y, mode, strobe[blk])
        if not (math.isfinite(r11) and math.isfinite(r22)):
            return NOT_FINITE, s1, s2, blk - n_transient
        if blk >= n_transient:
            s1, s2 = _average(s1, s2, r11, r22, collapsed, blk - n_transient, block, est)
            if _negative(est, blk - n_transient + 1, stop):
                return OK, s1, s2, blk - n_transient + 1
        collapsed = mode == 0
    return OK, s1, s2, n_blocks


@njit(cache=True)
def _qr(y):
    """Gram-Schmidt of the tangent vectors in y[2:6] in place; returns (r11, r22).

    q2 is q1 turned by 90 degrees, so a collapsed pair (u2 parallel to u1)
    still leaves an orthonormal frame.  A first vector killed by a stick
    onset (u1 along dv exactly) gives way to the second.
    """
    n1 = math.hypot(y[2], y[3])
    if n1 == 0.0:
        y[2], y[3], y[4], y[5] = y[4], y[5], y[2], y[3]
        n1 = math.hypot(y[2], y[3])
        if n1 == 0.0:
            return 0.0, 0.0
    q1x = y[2] / n1
    q1v = y[3] / n1
    q2x = -q1v
    q2v = q1x
    r22 = q2x * y[4] + q2v * y[5]
    y[2], y[3], y[4], y[5] = q1x, q1v, q2x, q2v
    return n1, r22
