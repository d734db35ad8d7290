"""Periodic orbits as zeros of H(xi, lambda), the deflated Poincare-map residual.

An orbit is a fixed point of the Poincare map P_lambda on X' = 0.  It is
described by xi = X - X*(lambda) > 0, its distance from the sliding
equilibrium along the section, and solves

    H(xi, lambda) = [P_lambda(X* + xi) - X* - xi] / xi = 0 .

Dividing by xi removes the trivial solution xi = 0 (the equilibrium), so a
branch born at a Hopf point starts regularly at (0, lambda_H) and Newton
cannot slide onto the equilibrium.  dH/dxi = (P' - 1 - H) / xi comes from
the monodromy (P' is the nontrivial multiplier).  dH/dlambda: on the
compiled engine (smooth laws) exactly, from the parameter column of the
variational equations with its saltation terms (:mod:`frictionflow.core.flowmap`),

    dH/dlambda = [(P' - 1) dX*/dlambda + dP/dlambda] / xi ;

on the closed-form engine by a forward difference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .flow import make_flow
from .flow_compiled import CompiledFlow, equilibrium_slope, param_code, supports
from .hybrid import Segment
from .parameters import with_param
from .sensitivity import locate_fold, locate_grazing, stick_slip_grazing, stick_slip_margin
from .shooting import H_TOL, contraction, default_tol, newton


@dataclass
class Solution:
    """A solved point (xi, lambda) with what the events are judged on."""

    xi: float
    lam: float
    H: float
    dH: float  # dH / dxi
    seg: Segment
    model: BeltOscillator
    law: FrictionLaw
    x: float
    x_ref: float  # X* (NaN: no sliding equilibrium, no deflation)
    dHl: float = math.nan  # dH / dlambda
    iterations: int = 0

    @property
    def G(self) -> float:
        return float(self.seg.y1[0] - self.x)

    @property
    def mu(self) -> float:
        """The nontrivial multiplier: the slope of the Poincare map."""
        return float(self.seg.section_jacobian()[0, 0])

    @property
    def has_stick(self) -> bool:
        return self.seg.stick_time > 0.0

    @property
    def slip_modes(self) -> tuple[str, ...]:
        """The phase sequence with the stick phases left out (to tell switching from grazing)."""
        return tuple(m for m in self.seg.modes if m == "slip+" or m == "slip-")

    @property
    def period(self) -> float:
        return self.seg.duration


class CycleProblem:
    """H(xi, lambda) = 0 for orbits of (model, law) with parameter ``param`` in [lo, hi]."""

    def __init__(self, model: BeltOscillator, law: FrictionLaw, param: str, lo: float, hi: float, *, returns: int = 1, tol: float | None = None) -> None:
        self.model, self.law, self.param = model, law, param
        self.lo, self.hi = min(lo, hi), max(lo, hi)
        self.returns = returns
        self.sx = max(law.fs, abs(model.vb), 1e-12)
        self.sl = self.hi - self.lo
        self.tol_abs = (default_tol(law) if tol is None else tol) * self.sx
        self.dlam = 1e-6 * self.sl

    def system(self, lam: float) -> tuple[BeltOscillator, FrictionLaw, float]:
        """(model, law, X*) at lambda; X* is NaN where there is no sliding equilibrium (then xi = X, no deflation)."""
        model, law = with_param(self.model, self.law, self.param, lam)
        x_ref = float(law.sliding_equilibrium(model.vb))
        return model, law, x_ref

    @property
    def exact_lambda(self) -> bool:
        """Is dH/dlambda taken from the variational equations (compiled engine), not a difference?"""
        return supports(self.law) and not self.law.piecewise_constant and param_code(self.law, self.param) is not None

    def flow(self, model: BeltOscillator, law: FrictionLaw):
        """The flow engine at one parameter value (the compiled one differentiates by ``param``)."""
        if self.exact_lambda:
            return CompiledFlow(model, law, param=self.param)
        return make_flow(model, law)

    def evaluate(self, xi: float, lam: float) -> Solution:
        """H and dH/dxi at (xi, lambda) (and dH/dlambda where exact); raises RuntimeError/ValueError where undefined."""
        model, law, x_ref = self.system(lam)
        deflate = math.isfinite(x_ref)
        x = (x_ref if deflate else 0.0) + xi
        seg = self.flow(model, law).run((x, 0.0), returns=self.returns)
        G = float(seg.y1[0] - x)
        dp = float(seg.section_jacobian()[0, 0])
        if deflate:
            H = G / xi
            dH = (dp - 1.0 - H) / xi
        else:
            H, dH = G, dp - 1.0
        s = Solution(xi, lam, H, dH, seg, model, law, x, x_ref)
        if self.exact_lambda:
            dpl = float(seg.section_columns()[0, 2])
            if deflate:
                dxs = equilibrium_slope(model, law, self.param)
                s.dHl = ((dp - 1.0) * dxs + dpl) / xi
            else:
                s.dHl = dpl
        return s

    def d_lambda(self, s: Solution) -> float:
        """dH/dlambda: exact on the compiled engine, else a forward difference (towards the inside of the interval)."""
        if math.isfinite(s.dHl):
            return s.dHl
        h = self.dlam if s.lam + self.dlam <= self.hi else -self.dlam
        return (self.evaluate(s.xi, s.lam + h).H - s.H) / h

    def converged(self, s: Solution) -> bool:
        """The orbit's X is within tol_abs: |G| / |1 - mu| (its error, Newton's next step) and H are small."""
        return abs(s.G) <= self.tol_abs * contraction(s.mu) and abs(s.H) <= H_TOL

    def near(self, s: Solution) -> bool:
        """|G| within tol_abs: where rounding stops Newton short of :meth:`converged` (mu near 1), the best there is."""
        return abs(s.G) <= self.tol_abs and abs(s.H) <= H_TOL

    def solve_at(self, lam: float, xi_guess: float) -> Solution:
        """The orbit at fixed lambda near xi_guess (Newton on P, deflated); raises on failure."""
        model, law, x_ref = self.system(lam)
        deflate = math.isfinite(x_ref)
        ref = x_ref if deflate else 0.0
        flow = self.flow(model, law)
        x, _, _, it = newton(flow, ref + xi_guess, x_star=x_ref, returns=self.returns, tol_abs=self.tol_abs, max_iter=12)
        s = self.evaluate(x - ref, lam)
        s.iterations = it
        s.dHl = self.d_lambda(s)
        return s

    def w(self, s: Solution) -> np.ndarray:
        return np.array([s.xi / self.sx, s.lam / self.sl])

    def tangent(self, s: Solution, previous: np.ndarray) -> np.ndarray:
        """Unit tangent of the branch at s in w coordinates, pointing the way ``previous`` did."""
        j = np.array([s.dH * self.sx, s.dHl * self.sl])
        t = np.array([j[1], -j[0]])
        n = float(np.linalg.norm(t))
        if not math.isfinite(n) or n == 0.0:
            return previous
        t /= n
        return t if t @ previous >= 0 else -t

    # -- exact locations of events (compiled engine; None where it does not apply) ------------
    @property
    def locatable(self) -> bool:
        """Can grazing and fold points be located by Newton on the compiled engine?"""
        return supports(self.law) and param_code(self.law, self.param) is not None

    def refine_grazing(self, a: Solution, b: Solution, guess: float) -> float | None:
        """lambda of the grazing between a and b (one has a stick phase): Newton from the slip-only side."""
        if not self.locatable:
            return None

        s = b if a.has_stick else a
        try:
            _, lam = locate_grazing(self.model, self.law, self.param, s.x, guess, returns=self.returns)
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            return None
        span = abs(b.lam - a.lam) + 1e-9 * self.sl
        return lam if min(a.lam, b.lam) - span <= lam <= max(a.lam, b.lam) + span else None

    def refine_stick_slip_end(self, a: Solution, direction: float, step: float) -> float | None:
        """lambda beyond the stick-slip cycle a (going ``direction``) where it grazes and ceases to exist."""
        if not self.locatable or not a.has_stick:
            return None

        def g(lam: float) -> float:
            return stick_slip_margin(*with_param(self.model, self.law, self.param, lam), self.param)[0]

        try:
            if not g(a.lam) < 0.0:
                return None
            lo = a.lam
            for k in range(1, 40):
                hi = a.lam + direction * step * k
                if not (self.lo <= hi <= self.hi):
                    return None
                if g(hi) > 0.0:
                    return stick_slip_grazing(self.model, self.law, self.param, min(lo, hi), max(lo, hi))
                lo = hi
        except (RuntimeError, ValueError):
            return None
        return None

    def refine_fold(self, s: Solution) -> float | None:
        """lambda of the smooth fold of cycles near s (P = X, P' = 1 by Newton)."""
        if not self.locatable:
            return None

        try:
            _, lam = locate_fold(self.model, self.law, self.param, s.x, s.lam, returns=self.returns)
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            return None
        return lam if abs(lam - s.lam) <= 1e-3 * self.sl else None
