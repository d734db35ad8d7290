r"""Closed-form steady responses of the harmonically forced oscillator, for the tests.

Derived here independently of frictionflow's solvers (numpy/scipy only).
The model, with time tau in units of 1/omega0::

    X'' + 2 zeta X' + X = F_c + F cos(Omega tau + phi)

1. Linear oscillator (F_c = 0)
------------------------------
Trying X = A cos(Omega tau + phi - delta) gives

    A = F / sqrt((1 - Omega^2)^2 + (2 zeta Omega)^2),   delta = atan2(2 zeta Omega, 1 - Omega^2),

``delta`` in [0, pi) is the lag of the displacement behind the force.  Over
one period the damper takes (1/T) int 2 zeta X'^2 = 2 zeta Omega^2 A^2 / 2,
so ``P_dv = zeta Omega^2 A^2``; the force gives (1/T) int X' F cos =
F A Omega sin(delta) / 2 and sin(delta) = 2 zeta Omega A / F makes that the
same number: P_ex = P_dv over every steady period.

2. Den Hartog (1931): Coulomb (+ viscous) friction on a fixed surface
---------------------------------------------------------------------
Belt at rest (V_b = 0), so V_r = -X' and, while slipping,
F_c = -F_d sgn(X'); the interface holds up to F_s >= F_d while X' = 0.
We look for the *non-stop* harmonic response: period T = 2 pi / Omega,
half-period antisymmetric, X(tau + h) = -X(tau) with h = pi / Omega, one
turning point per half period and no stick.

Put tau = 0 at a displacement minimum (X(0) = -A, X'(0) = 0), with X' > 0 on
(0, h), so F_c = -F_d on the whole half period, and write the force as
F cos(Omega tau + psi), psi unknown (the forcing phase at the minimum).  The
equation is linear on (0, h), so X = P + Y with

* P = a cos(Omega tau + theta), a = A_lin above, theta = psi - delta: the
  steady response to the force alone (antiperiodic over h by itself);
* Y = -F_d + e^{-zeta tau} (D1 cos w tau + D2 sin w tau), w = sqrt(1 - zeta^2):
  the response to the square wave -F_d sgn(X'), made antiperiodic,
  Y(h) = -Y(0), Y'(h) = -Y'(0).  With E = e^{-zeta h}, c = cos wh, s = sin wh
  that is the 2x2 linear system::

      (1 + E c) D1 + E s D2                                   = 2 F_d
      (-zeta - E (zeta c + w s)) D1 + (w + E (w c - zeta s)) D2 = 0

  (singular only for zeta = 0 at Omega = 1/(2k+1), where a free antiperiodic
  oscillation exists).  Y0 = Y(0) = D1 - F_d, Y0' = Y'(0) = w D2 - zeta D1.

P + Y is then antiperiodic over h and continuous with its derivative at the
switch (both are), so only the turning point remains to impose:

    X'(0) = 0:   -a Omega sin(theta) + Y0' = 0   =>  sin(theta) = sigma = Y0' / (a Omega),
    X(0) = -A:   A = -a cos(theta) - Y0,

and for a minimum cos(theta) < 0, so theta = pi - arcsin(sigma),
A = a sqrt(1 - sigma^2) - Y0.  The displacement maximum is at tau = h, where
the forcing phase is Omega h + psi = pi + theta + delta: the **phase lag**
(forcing phase at the displacement maximum, as delta in the linear case) is

    lag = delta - arcsin(sigma)   (mod 2 pi).

For zeta = 0 this is Den Hartog's: D1 = F_d, D2 = F_d tan(h/2), Y0 = 0,
Y0' = F_d tan(pi / (2 Omega)), so with r = F_d / F and
U = tan(pi/(2 Omega)) / Omega = sin(pi/Omega) / (Omega (1 + cos(pi/Omega))),

    A / F = sqrt(1 / (1 - Omega^2)^2 - (r U)^2).

Where it stops holding (stops)
------------------------------
At the turning point X' = 0 and the mass stays stuck if the interface can
hold what the others apply, |X(0) - f(0)| <= F_s (F_e = X: V_b = 0).  The
non-stop motion needs it to leave in the assumed direction:
X''(0+) = f(0) - X(0) - F_d > 0 and f(0) - X(0) > F_s, i.e. the **stop margin**

    m = f(0) - X(0) - F_s = F cos(theta + delta) + A - F_s > 0.

(By antisymmetry the other turning point gives the same condition.)  For
zeta = 0 and Omega < 1 the margin is Omega^2 A - F_s, Den Hartog's boundary
A Omega^2 = F_d.  Everything is homogeneous of degree one in (F, F_d, F_s, X),
so for a fixed F_s / F_d the boundary is a ratio r* = F_d / F, found by
root finding on m(r) = 0.  The margin is necessary, not sufficient: X' > 0
inside (0, h) is checked separately on the closed form
(:attr:`NonStop.interior_ok`).  At low frequencies (Omega ~ 0.3-0.45 for
small zeta) X' first touches zero in mid-stroke, before the margin vanishes:
there that tangency (X' = X'' = 0, so f - X = F_d) is the boundary.  A cross-check of the derivation is the
friction work over one period: the mass travels 4A against F_d, so
W_friction = 4 F_d A, and W_ex = W_dv + 4 F_d A.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar


def wrap(angle: float) -> float:
    """``angle`` mod 2 pi in (-pi, pi]."""
    return math.pi - (math.pi - angle) % (2.0 * math.pi)


def linear_response(fex: float, omega: float, zeta: float) -> tuple[float, float]:
    """(A, delta): steady amplitude and lag of X'' + 2 zeta X' + X = F cos(Omega tau + phi)."""
    amplitude = fex / math.hypot(1.0 - omega * omega, 2.0 * zeta * omega)
    return amplitude, math.atan2(2.0 * zeta * omega, 1.0 - omega * omega)


def linear_damper_power(amplitude: float, omega: float, zeta: float) -> float:
    """P_dv = zeta Omega^2 A^2, the damper's (and the force's) mean power in the steady state."""
    return zeta * omega * omega * amplitude * amplitude


def square_wave_coefficients(fd: float, omega: float, zeta: float) -> tuple[float, float]:
    """(D1, D2) of the antiperiodic response Y to -F_d on (0, h), +F_d on (h, 2h) (underdamped, zeta < 1)."""
    w = math.sqrt(1.0 - zeta * zeta)
    h = math.pi / omega
    e, c, s = math.exp(-zeta * h), math.cos(w * h), math.sin(w * h)
    m = np.array([[1.0 + e * c, e * s], [-zeta - e * (zeta * c + w * s), w + e * (w * c - zeta * s)]])
    d1, d2 = np.linalg.solve(m, [2.0 * fd, 0.0])
    return float(d1), float(d2)


@dataclass(frozen=True)
class NonStop:
    """Den Hartog's non-stop steady response (tau = 0 at a displacement minimum).

    ``exists`` is False when |sigma| > 1 (no such solution); ``amplitude``,
    ``lag`` and ``margin`` are then NaN.
    """

    fex: float
    omega: float
    zeta: float
    fd: float
    fs: float
    a: float        # amplitude of the forced part P
    delta: float    # lag of P
    d1: float
    d2: float
    sigma: float    # sin(theta)

    @property
    def exists(self) -> bool:
        return abs(self.sigma) <= 1.0

    @property
    def theta(self) -> float:
        return math.pi - math.asin(self.sigma) if self.exists else math.nan

    @property
    def amplitude(self) -> float:
        return self.a * math.sqrt(1.0 - self.sigma**2) - (self.d1 - self.fd) if self.exists else math.nan

    @property
    def lag(self) -> float:
        """Forcing phase at the displacement maximum, in (-pi, pi]."""
        return wrap(self.delta - math.asin(self.sigma)) if self.exists else math.nan

    @property
    def margin(self) -> float:
        """f(0) - X(0) - F_s: > 0 leaves the turning point without a stop."""
        return self.fex * math.cos(self.theta + self.delta) + self.amplitude - self.fs

    def state(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(X, X') on the first half period 0 <= tau <= h."""
        tau = np.asarray(tau, dtype=float)
        w = math.sqrt(1.0 - self.zeta**2)
        ph = self.omega * tau + self.theta
        e, c, s = np.exp(-self.zeta * tau), np.cos(w * tau), np.sin(w * tau)
        x = self.a * np.cos(ph) - self.fd + e * (self.d1 * c + self.d2 * s)
        v = -self.a * self.omega * np.sin(ph) + e * ((w * self.d2 - self.zeta * self.d1) * c - (w * self.d1 + self.zeta * self.d2) * s)
        return x, v

    def least_interior_velocity(self) -> float:
        """min X' over the inside of the half period, away from its ends (where X' -> 0 as it should).

        The least of a grid, refined by a bounded minimisation between its neighbours.
        """
        h = math.pi / self.omega
        grid = np.linspace(0.0, h, 2001)
        v = self.state(grid)[1][1:-1]
        i = int(np.argmin(v)) + 1
        if i in (1, len(grid) - 2):  # no interior minimum: X' rises from 0 and falls back to 0
            return math.inf
        best = minimize_scalar(lambda t: float(self.state(t)[1]), bounds=(grid[i - 1], grid[i + 1]), method="bounded",
                               options={"xatol": 1e-12 * h})
        return float(min(best.fun, v[i - 1]))

    @property
    def interior_ok(self) -> bool:
        """X' > 0 strictly inside the half period (one turning point per half period)."""
        return self.least_interior_velocity() > 0.0

    @property
    def failure(self) -> str:
        """Why the closed form is not the motion ('' when it is)."""
        if not self.exists:
            return "no solution"
        if self.margin <= 0.0:
            return "stops at the turning point"
        return "" if self.interior_ok else "reverses mid-stroke"

    @property
    def valid(self) -> bool:
        """The non-stop closed form is the motion: it exists, leaves each turning point, and turns only there."""
        return self.exists and self.margin > 0.0 and self.interior_ok

    def damper_work(self) -> float:
        """W_dv = int 2 zeta X'^2 over one forcing period (quadrature of the closed form)."""
        h = math.pi / self.omega
        half, _ = quad(lambda t: 2.0 * self.zeta * float(self.state(t)[1]) ** 2, 0.0, h, epsabs=1e-14, epsrel=1e-12)
        return 2.0 * half

    def friction_work(self) -> float:
        """4 F_d A: the work friction takes over one period (two strokes of 2A each)."""
        return 4.0 * self.fd * self.amplitude


def non_stop(fex: float, omega: float, zeta: float, fd: float, fs: float | None = None) -> NonStop:
    """Den Hartog's non-stop response of X'' + 2 zeta X' + X = -F_d sgn X' + F cos(Omega tau + phi)."""
    fs = fd if fs is None else fs
    a, delta = linear_response(fex, omega, zeta)
    d1, d2 = square_wave_coefficients(fd, omega, zeta)
    w = math.sqrt(1.0 - zeta * zeta)
    sigma = (w * d2 - zeta * d1) / (a * omega)
    return NonStop(fex, omega, zeta, fd, fs, a, delta, d1, d2, sigma)


def den_hartog_undamped_amplitude(fex: float, omega: float, fd: float) -> float:
    """Den Hartog's published zeta = 0 amplitude, F sqrt(1/(1-Omega^2)^2 - (r U)^2)."""
    u = math.sin(math.pi / omega) / (omega * (1.0 + math.cos(math.pi / omega)))
    return fex * math.sqrt(1.0 / (1.0 - omega * omega) ** 2 - (fd / fex * u) ** 2)


def stop_boundary(omega: float, zeta: float, fs_over_fd: float = 1.0, points: int = 400) -> float:
    """r* = F_d / F_ex at which the non-stop response first stops holding (:attr:`NonStop.valid` fails).

    Scans r upwards from 0 (where the response is the linear one, valid) and
    refines the first failure: by root finding on the margin when the mass
    would stop at the turning point (Den Hartog's boundary), by bisection when
    X' first reaches zero inside the half period (at low Omega this comes
    first: :attr:`NonStop.failure` tells which).
    """

    def at(r: float) -> NonStop:
        return non_stop(1.0, omega, zeta, r, r * fs_over_fd)

    r_max = 1.0
    while at(r_max).valid:  # the boundary lies beyond: widen
        r_max *= 2.0
    grid = np.linspace(0.0, r_max, points + 1)[1:]
    i = next(i for i, r in enumerate(grid) if not at(r).valid)
    lo, hi = (grid[i - 1] if i else 1e-12), grid[i]
    if at(hi).exists and at(hi).interior_ok:  # the margin changed sign
        return brentq(lambda r: at(r).margin, lo, hi, xtol=1e-14, rtol=1e-13)
    if at(lo).margin > 0.0 and at(hi).exists and at(hi).margin > 0.0:  # mid-stroke: the least velocity changes sign
        return brentq(lambda r: at(r).least_interior_velocity(), lo, hi, xtol=1e-14, rtol=1e-13)
    while hi - lo > 1e-13 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if at(mid).valid else (lo, mid)
    return lo
