"""The physical rules of friction as compiled scalar functions, written once for every kernel.

* :func:`slip_magnitude` / :func:`slip_slope` / :func:`slip_partial`: |F|,
  dF/d|V_r| and dF/d(a parameter) of the law
  with code ``law`` while slipping, dispatched to each law's own compiled
  functions (in its module in :mod:`frictionflow.friction`).
* :func:`held_force` / :func:`stick_friction`: the force the interface must
  hold, F_e - f, and the friction force while sticking, X + 2 zeta V_b - f;
  :func:`stick_duration`: how long an unforced stick lasts (closed form; a
  forced one: :mod:`.stick`).
* :func:`holds_within` / :func:`holds`: Coulomb's stick rule for one contact,
  stated once (within the limit, or on it and moving inwards); every engine's
  stick decision calls it (:func:`rest_mode`, the exact kernel's
  :func:`~.exact.consistent`, the structure's active set).
* :func:`rest_mode`: Coulomb's set-valued stick rule at V_r = 0 with the slip
  direction (used by the adaptive kernel and the Python orbit flows).
* :func:`band_force` / :func:`band_mode` / :func:`band_side`: Karnopp's stick
  band |V_r| <= V_d (fixed-step RK4; the exact kernel's fallback
  :func:`~.exact.region_mode`), the law's parameters as one record (:func:`band_law`);
  for a law with Coulomb's rule the band holds the whole resultant (:func:`band_hold`).
* :func:`external_force`: the harmonic force f(tau) = F_ex cos(Omega tau + phi);
  :func:`belt_speed` and its rates, the belt's V_b(tau) = V_b + A sin(Omega_b tau + phi_b);
  :func:`stick_load`: f - V_b', the external force as the stick rules see it (a belt
  that accelerates must take the sticking mass with it).

Every rule that decides sticking takes ``fext``, the external force at that
instant: the interface holds what the spring, the damper and the external
force leave, F_e - f(tau).

A law's parameters arrive as plain floats in the layout of :mod:`.layout`
(re-exported here).  A new law with a compiled slip force adds its code to
:mod:`.layout`, its curve as a ``curve_*`` module here and one line to each
of the dispatchers below.
"""

from __future__ import annotations

import math
import types

from numba import njit

from . import curve_cubic as cubic
from . import curve_stribeck as stribeck
from .layout import (  # noqa: F401  (re-exported: the kernels import the layout from here)
    BAND_LAWS, COULOMB, CUBIC, FD, FEX, FS, KARNOPP, LAW, LAW_A, LAW_B, LAW_C, N_PARAMS, N_WORK, OMEGA, PHI, RESULTANT, SLIP_NEG,
    SLIP_POS, SMOOTH_LAWS, STICK, STRIBECK, VB_AMP, VB_OMEGA, VB_PHI, VD,
)

#: fused multiply-add allowed in the fixed-step kernels (the stick band and RK4): shorter
#: dependency chains, and the single and batched kernels share it so that they round alike.
#: Every function they call apart (``forceinline``) carries it too: flags are per compiled function.
FASTMATH = {"contract"}


@njit(cache=True, inline="always")
def slip_magnitude(law, fd, fs, a, b, c, speed):
    """|F| while slipping at relative speed ``speed`` >= 0 (a, b, c: the law's own parameters)."""
    if law == STRIBECK:
        return stribeck.magnitude(fd, fs, a, b, c, speed)
    if law == CUBIC:
        return cubic.magnitude(fd, fs, a, b, c, speed)
    return fd


@njit(cache=True, inline="always")
def slip_slope(law, fd, fs, a, b, c, speed):
    """d|F|/d|V_r| at ``speed`` > 0 (at 0: the limit from above)."""
    if law == STRIBECK:
        return stribeck.slope(fd, fs, a, b, c, speed)
    if law == CUBIC:
        return cubic.slope(fd, fs, a, b, c, speed)
    return 0.0


@njit(cache=True, inline="always")
def slip_partial(law, fd, fs, a, b, c, speed, slot):
    """d|F|/d(the parameter in kernel slot ``slot``) while slipping at ``speed`` >= 0 (constant laws: 1 for F_d)."""
    if law == STRIBECK:
        return stribeck.partial(fd, fs, a, b, c, speed, slot)
    if law == CUBIC:
        return cubic.partial(fd, fs, a, b, c, speed, slot)
    return 1.0 if slot == FD else 0.0


@njit(cache=True)
def slip_magnitude_of(p, speed):
    """:func:`slip_magnitude` of the law whose kernel parameters are ``p``."""
    return slip_magnitude(int(p[LAW]), p[FD], p[FS], p[LAW_A], p[LAW_B], p[LAW_C], speed)


@njit(cache=True, inline="always")
def slip_terms_of(p, speed, slot):
    """(|F|, dF/d|V_r|, dF/d(slot parameter)) at ``speed`` > 0, for the orbit engine (Stribeck: one exp for all three)."""
    law = int(p[LAW])
    if law == STRIBECK:
        return stribeck.terms(p[FD], p[FS], p[LAW_A], p[LAW_B], p[LAW_C], speed, slot)
    return slip_magnitude_of(p, speed), slip_slope_of(p, speed), slip_partial_of(p, speed, slot)


@njit(cache=True)
def slip_partial_of(p, speed, slot):
    """:func:`slip_partial` of the law whose kernel parameters are ``p``."""
    return slip_partial(int(p[LAW]), p[FD], p[FS], p[LAW_A], p[LAW_B], p[LAW_C], speed, slot)


@njit(cache=True)
def slip_slope_of(p, speed):
    """:func:`slip_slope` of the law whose kernel parameters are ``p``."""
    return slip_slope(int(p[LAW]), p[FD], p[FS], p[LAW_A], p[LAW_B], p[LAW_C], speed)


def _twin(fn, name):
    """A copy of the compiled ``fn``'s Python function named ``name``, to be compiled with other flags.

    Its own qualified name gives it its own cache file and symbol: numba's
    cache index does not tell flags apart, so two dispatchers of one
    function would load each other's machine code.
    """
    code = fn.py_func
    twin = types.FunctionType(code.__code__, code.__globals__, name, code.__defaults__)
    twin.__qualname__ = name
    return twin


@njit(cache=True, forceinline=True)
def stick_friction(x, zeta, vb, f):
    """F_c while sticking (X' = V_b, X'' = 0): X + 2 zeta V_b - f, what the spring, the damper and f leave.

    The friction force whatever ``stick_force`` says (that choice only
    decides when sticking ends: :func:`held_force`).
    """
    return x + 2.0 * zeta * vb - f


@njit(cache=True, forceinline=True)
def held_force(x, zeta, v, resultant, f):
    """F_e - f: the force the interface must hold at (x, v) with the external force f there.

    F_e = X + 2 zeta X' (``resultant``) or X (the spring alone, the paper's
    choice); X' = V_b while sticking.  Compared with F_s by every stick rule.
    """
    return (x + 2.0 * zeta * v if resultant else x) - f


@njit(cache=True, forceinline=True)
def stick_duration(x, zeta, vb, fs, resultant):
    """How long an unforced stick from X = ``x`` lasts: until |F_e| reaches F_s (inf when V_b = 0).

    F_e moves at the rate V_b, towards the limit on V_b's side; 0 when it is
    there or beyond already.  (A forced stick has no closed form: its end is
    searched on the held force along the phase, :mod:`.stick`.)
    """
    if vb == 0.0:
        return math.inf
    return max(0.0, (math.copysign(fs, vb) - held_force(x, zeta, vb, resultant, 0.0)) / vb)


#: :func:`held_force` with ``FASTMATH``, for the stick band of the fixed-step kernels (flags are per
#: compiled function: the band's callers contract it, the event-driven kernels must not)
held_force_fm = njit(cache=True, fastmath=FASTMATH, forceinline=True)(_twin(held_force, "held_force_fm"))


@njit(cache=True, inline="always")
def external_force(p, t):
    """f(tau) = F_ex cos(Omega tau + phi) of the force record ``p`` (0.0 unforced, without a cosine)."""
    fex = p[FEX]
    if fex == 0.0:
        return 0.0
    return fex * math.cos(p[OMEGA] * t + p[PHI])


@njit(cache=True, inline="always")
def external_force_rate(p, t):
    """f'(tau) = -F_ex Omega sin(Omega tau + phi) (0.0 unforced)."""
    fex = p[FEX]
    if fex == 0.0:
        return 0.0
    return -fex * p[OMEGA] * math.sin(p[OMEGA] * t + p[PHI])


@njit(cache=True, inline="always")
def belt_speed(p, vb, t):
    """V_b(tau) = V_b + A sin(Omega_b tau + phi_b) of the force record ``p`` (``vb`` itself when A = 0,
    without a sine: a constant belt stays bit for bit what it was)."""
    amp = p[VB_AMP]
    if amp == 0.0:
        return vb
    return vb + amp * math.sin(p[VB_OMEGA] * t + p[VB_PHI])


@njit(cache=True, inline="always")
def belt_accel(p, t):
    """V_b'(tau) = A Omega_b cos(Omega_b tau + phi_b) (0.0 for a belt at constant speed)."""
    amp = p[VB_AMP]
    if amp == 0.0:
        return 0.0
    return amp * p[VB_OMEGA] * math.cos(p[VB_OMEGA] * t + p[VB_PHI])


@njit(cache=True, inline="always")
def belt_jerk(p, t):
    """V_b''(tau) = -A Omega_b^2 sin(Omega_b tau + phi_b) (0.0 for a belt at constant speed)."""
    amp = p[VB_AMP]
    if amp == 0.0:
        return 0.0
    return -amp * p[VB_OMEGA] * p[VB_OMEGA] * math.sin(p[VB_OMEGA] * t + p[VB_PHI])


@njit(cache=True, inline="always")
def stick_load(p, t):
    """f(tau) - V_b'(tau): what every stick rule takes as its external force.

    While sticking X'' = V_b', so the interface holds F_e + V_b' - f: the
    belt's acceleration acts on the stick rule as an external force -V_b'
    (f itself when the belt's speed is constant, to the bit).
    """
    return external_force(p, t) - belt_accel(p, t)


@njit(cache=True, inline="always")
def stick_load_rate(p, t, zeta, resultant):
    """The rate :func:`rest_mode` takes as f': the held force F_e + V_b' - f changes at V_b - (this) while sticking,
    so this is f' - V_b'' less, when F_e = X + 2 zeta X' (``resultant``), the damper's 2 zeta V_b'."""
    rate = external_force_rate(p, t)
    if p[VB_AMP] == 0.0:
        return rate
    rate -= belt_jerk(p, t)
    return rate - 2.0 * zeta * belt_accel(p, t) if resultant else rate


#: a held force this close to its limit, relative, counts as on it (the rule's tolerance with no rounding
#: estimate of its own: the single mass's kernels and the structure's contacts)
ON_LIMIT = 1e-14


@njit(cache=True, forceinline=True)
def holds_within(held, rate, curv, inner, outer, rate_tol):
    """Coulomb's stick rule for one contact: does the interface keep holding the force ``held``?

    The rule, stated once: it holds while |held| is within its limit, or on
    the limit while sticking moves the held force back inwards.  ``inner``
    and ``outer`` bound "on the limit" (|held| < ``inner``: within, holds;
    |held| > ``outer``: beyond, releases); on it the held force's ``rate``
    decides (|rate| <= ``rate_tol`` counts as 0), then its ``curv`` (its
    second rate); a held force that neither moves nor curves inwards counts
    as moving outwards and releases.  The tolerances are the caller's: the
    exact kernel knows the rounding of each term (:func:`~.exact.consistent`),
    the others use :func:`holds`.
    """
    size = abs(held)
    if size < inner:
        return True
    if size > outer:
        return False
    out = rate if held >= 0.0 else -rate  # the rate away from 0, towards the limit
    if out < -rate_tol:
        return True
    if out > rate_tol:
        return False
    return (curv if held >= 0.0 else -curv) < 0.0


@njit(cache=True, forceinline=True)
def holds(held, limit, rate):
    """:func:`holds_within` with the shared tolerances: on the limit within ``ON_LIMIT`` of it (below only), the
    rate's sign exact, no curvature (a ``rate`` of 0 counts as outwards)."""
    return holds_within(held, rate, 0.0, limit * (1.0 - ON_LIMIT), limit, 0.0)


@njit(cache=True, forceinline=True)
def limit_ratio(held, limit):
    """|held| / limit, how far over its limit a held force is (inf when the limit is 0 or below): among the
    contacts that do not hold, the one to release first is the one with the largest."""
    return abs(held) / limit if limit > 0.0 else math.inf


@njit(cache=True)
def rest_mode(x, zeta, vb, fs, resultant, f0, fext, dfext):
    """Coulomb's stick rule at V_r = 0: 0 to stick, or the slip direction +-1.

    The mass sticks while the force the interface must hold, |F_e - f| with
    F_e = X + 2 zeta V_b (``resultant``) or X and f = ``fext`` the external
    force, is below F_s -- or on F_s while sticking would move it back
    inwards (while sticking it changes at the rate V_b - f', ``dfext`` = f').
    Otherwise it slips in the direction d whose slip force d F(0+) = d ``f0``
    drives V_r away from 0.
    """
    fe = held_force(x, zeta, vb, resultant, fext)
    rate = vb - dfext
    if holds(fe, fs, rate):
        return 0
    tol = 1e-12 * (abs(f0) + abs(x) + 2.0 * zeta * abs(vb) + abs(fext))
    first = 1.0 if fe > 0.0 else -1.0
    for d in (first, -first):
        a = d * f0 + fext - x - 2.0 * zeta * vb
        # slip+ means X' falls below V_b: needs X'' < 0 (or ~0, with X''' = f' - V_b < 0)
        if d * a < -tol or (abs(a) <= tol and d * rate > 0.0):
            return int(d)
    return 0


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def band_law(law, p):
    """The band record of the force record ``p``: (law, F_d, F_s, V_d, resultant, a, b, c, switch), built once per run.

    ``switch``: the law has Coulomb's stick rule (its band stands in for
    V_r = 0; Coulomb runs with Karnopp's ``law`` code, their slip forces
    being the same), so the band holds the whole resultant (:func:`band_hold`).

    ``law`` is passed apart (the kernels give ``code + 0``, a constant to LLVM,
    so that the other laws' branches fold away); a tuple of scalars costs
    nothing once inlined.
    """
    return law, p[FD], p[FS], p[VD], p[RESULTANT] != 0.0, p[LAW_A], p[LAW_B], p[LAW_C], int(p[LAW]) not in BAND_LAWS


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def band_side(fe, fs):
    """Inside the stick band, the side of the static bound the held force ``fe`` (:func:`held_force`) is on.

    +1 when F_e - f >= F_s (the band saturates at +F_s), -1 when <= -F_s,
    0 when the interface holds it (|F_e - f| < F_s).
    """
    if fe >= fs:
        return 1
    if fe <= -fs:
        return -1
    return 0


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def band_force(lw, x, v, zeta, vb, fext):
    """Friction force of a law with a stick band |V_r| <= V_d (Karnopp's scheme); ``lw``: its :func:`band_law`.

    Branches, for one trajectory at a time: they are predicted well and keep
    the untaken side off the chain of dependent operations.
    """
    law, fd, fs, vd, resultant, a, b, c, switch = lw
    vr = vb - v
    if vr > vd:
        return slip_magnitude(law, fd, fs, a, b, c, vr)
    if vr < -vd:
        return -slip_magnitude(law, fd, fs, a, b, c, -vr)
    fe = held_force_fm(x, zeta, v, resultant, fext)
    side = band_side(fe, fs)
    if side > 0:
        return fs
    if side < 0:
        return -fs
    return band_hold(switch, fe, x, v, zeta, fext)


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def band_hold(switch, fe, x, v, zeta, fext):
    """The friction force while the band holds: the held force ``fe`` for Karnopp's law, whose stick is the band
    itself (with the spring rule the damper's force is left over, as in the paper), and the whole resultant for a
    law with Coulomb's stick rule, whose band stands in for the constraint V_r = 0 that the rule holds (the spring
    rule only decides when)."""
    return held_force_fm(x, zeta, v, switch, fext) if switch else fe  # (switch, True there: a literal compiles twice)


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def band_force_select(lw, x, v, zeta, vb, fext):
    """:func:`band_force` computing both sides and selecting one: for loops over many lanes, which it lets vectorise."""
    law, fd, fs, vd, resultant, a, b, c, switch = lw
    vr = vb - v
    speed = abs(vr)
    mag = slip_magnitude(law, fd, fs, a, b, c, speed)
    slip = mag if vr > 0.0 else -mag
    fe = held_force_fm(x, zeta, v, resultant, fext)
    held = band_hold(switch, fe, x, v, zeta, fext)
    hold = held if abs(fe) < fs else math.copysign(fs, fe)  # F_s sgn(F_e) once |F_e| >= F_s
    return slip if speed > vd else hold


@njit(cache=True, inline="always")
def band_mode(v, vb, vd):
    """Friction mode -1/0/+1 (slip-/stick/slip+) of a law with a stick band."""
    vr = vb - v
    if vr > vd:
        return 1
    if vr < -vd:
        return -1
    return 0
