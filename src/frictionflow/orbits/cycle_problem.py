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

:class:`CycleProblem` is a :class:`~.tracing.ContinuationProblem` in the one
unknown xi: the tracer (:class:`~.tracing.Tracer`) follows its branches; the
problem adds the cycles' own stop rules (back onto the equilibrium, period
blow-up), events (grazing, switching, smooth and non-smooth folds, refined
by Newton on the compiled engine) and the step over a grazing corner.
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
from .tracing import ContinuationProblem, Corrector, Crossing, Event, Step, Stop, Tracer


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


class CycleProblem(ContinuationProblem):
    """H(xi, lambda) = 0 for orbits of (model, law) with parameter ``param`` in [lo, hi].

    A branch ends where its period exceeds ``max_period`` or it runs back
    onto the sliding equilibrium (xi below ``xi_min``, default 1e-4 s_x).
    """

    #: H is one cheap map run (dH/dlambda exact, or one more run as a chord); Newton gives up after 2 slow iterations
    corrector = Corrector(max_iter=8, stall_after=2, chord_every=0, fresh_lambda=False)

    def __init__(self, model: BeltOscillator, law: FrictionLaw, param: str, lo: float, hi: float, *, returns: int = 1,
                 tol: float | None = None, max_period: float = 500.0, xi_min: float | None = None) -> None:
        self.model, self.law, self.param = model, law, param
        self.lo, self.hi = min(lo, hi), max(lo, hi)
        self.returns = returns
        self.sx = max(law.fs, abs(model.vb), 1e-12)
        self.sl = self.hi - self.lo
        self.scale = np.array([self.sx, self.sl])
        self.tol_abs = (default_tol(law) if tol is None else tol) * self.sx
        self.dlam = 1e-6 * self.sl
        self.max_period = max_period
        self.xi_min = 1e-4 * self.sx if xi_min is None else xi_min

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

    def at(self, xi: float, lam: float) -> Solution:
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

    def dH_dlambda(self, s: Solution) -> float:
        """dH/dlambda: exact on the compiled engine, else a forward difference (towards the inside of the interval)."""
        if math.isfinite(s.dHl):
            return s.dHl
        h = self.dlam if s.lam + self.dlam <= self.hi else -self.dlam
        return (self.at(s.xi, s.lam + h).H - s.H) / h

    def converged(self, s: Solution) -> bool:
        """The orbit's X is within tol_abs: |G| / |1 - mu| (its error, Newton's next step) and H are small."""
        return abs(s.G) <= self.tol_abs * contraction(s.mu) and abs(s.H) <= H_TOL

    def near(self, s: Solution) -> bool:
        """|G| within tol_abs: where rounding stops Newton short of :meth:`converged` (mu near 1), the best there is."""
        return abs(s.G) <= self.tol_abs and abs(s.H) <= H_TOL

    def solve_at(self, lam: float, xi_guess: float | np.ndarray) -> Solution:
        """The orbit at fixed lambda near xi_guess (Newton on P, deflated); raises on failure."""
        xi_guess = float(np.reshape(xi_guess, -1)[0])  # the tracer's guess is the vector of unknowns
        model, law, x_ref = self.system(lam)
        deflate = math.isfinite(x_ref)
        ref = x_ref if deflate else 0.0
        flow = self.flow(model, law)
        x, _, _, it = newton(flow, ref + xi_guess, x_star=x_ref, returns=self.returns, tol_abs=self.tol_abs, max_iter=12)
        s = self.at(x - ref, lam)
        s.iterations = it
        s.dHl = self.dH_dlambda(s)
        return s

    # -- the continuation protocol (:class:`~.tracing.ContinuationProblem`), unknowns u = (xi, lambda) -------------
    def evaluate(self, u: np.ndarray) -> Solution:
        return self.at(float(u[0]), float(u[1]))

    def unknowns(self, s: Solution) -> np.ndarray:
        return np.array([s.xi, s.lam])

    def residual(self, s: Solution) -> np.ndarray:
        return np.array([s.H])

    def jacobian(self, s: Solution) -> np.ndarray:
        return np.array([[s.dH, s.dHl]])

    def d_lambda(self, s: Solution) -> np.ndarray:
        return np.array([self.dH_dlambda(s)])

    def set_d_lambda(self, s: Solution, column: np.ndarray) -> None:
        s.dHl = float(column[0])

    def tests(self, s: Solution) -> dict[str, float]:
        """mu - 1: it changes sign at a smooth fold (no period doubling: mu is never negative, see :mod:`.floquet`)."""
        return {"fold": s.mu - 1.0}

    def admissible(self, u: np.ndarray) -> bool:
        return u[0] > 0.0  # xi > 0: the deflated H has no other zeros

    def corner(self, a: Solution, b: Solution) -> bool:
        return a.seg.modes != b.seg.modes  # the phase sequence changed: the branch may turn sharply there

    def stop(self, s: Solution) -> Stop | None:
        if math.isfinite(s.x_ref) and s.xi < self.xi_min:
            return Stop("hopf", keep=False)  # back onto the sliding equilibrium
        if s.period > self.max_period:
            return Stop("period blowup", True, [Event("period_blowup", s.lam, {"period": s.period})])
        return None

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

    # -- events, and where the corrector fails ---------------------------------------------------------------------
    def events(self, tracer: Tracer, step: Step) -> list[Event]:
        """Grazing (a stick phase appears or vanishes), switching (the slip sequence changes) and folds between a and b.

        A fold is smooth where mu - 1 changes sign on one regime (located by
        secant on it, then by Newton on the compiled engine), else it is the
        corner's (a non-smooth fold, at the grazing found).
        """
        a, b, out = step.a, step.b, []
        if a.has_stick != b.has_stick:
            lam = _middle(tracer.bisect(step, lambda s: s.has_stick == a.has_stick, max_iter=12))
            exact = self.refine_grazing(a, b, lam)
            detail = {"stick_phase": "appears" if b.has_stick else "vanishes", "refined": exact is not None}
            out.append(Event("grazing", lam if exact is None else exact, detail))
        elif a.slip_modes != b.slip_modes:
            lam = _middle(tracer.bisect(step, lambda s: s.slip_modes == a.slip_modes, max_iter=12))
            out.append(Event("switching", lam, {"before": list(a.seg.modes), "after": list(b.seg.modes)}))
        if step.ta[1] * step.tb[1] < 0:
            fa, fb = self.tests(a)["fold"], self.tests(b)["fold"]
            if a.has_stick == b.has_stick and fa * fb < 0:
                s = tracer.secant(step, lambda s: self.tests(s)["fold"], fa, fb, xtol=1e-9 * step.h, ftol=1e-9, max_iter=10)
                exact = self.refine_fold(s if s is not None else a)
                lam = exact if exact is not None else (s.lam if s else 0.5 * (a.lam + b.lam))
                out.append(Event("fold", lam, {"smooth": True, "multiplier": s.mu if s else None, "refined": s is not None or exact is not None}))
            else:
                out.append(Event("fold", out[-1].value if out else 0.5 * (a.lam + b.lam), {"smooth": False}))
        return out

    def dead_end(self, tracer: Tracer, solutions: list[Solution], t: np.ndarray) -> Crossing | Stop:
        """Past a grazing corner (:meth:`cross_corner`), else why the branch ends (:meth:`diagnose`)."""
        crossed = self.cross_corner(tracer, solutions[-1], t, solutions[:-1])
        return crossed if crossed is not None else self.diagnose(solutions[-1], t)

    def cross_corner(self, tracer: Tracer, a: Solution, t: np.ndarray, earlier: list[Solution]) -> Crossing | None:
        """Step over a grazing corner, where the branch has no tangent.

        Where a slip-only cycle touches X' = V_b it meets the stick-slip
        branch at an angle (the multiplier jumps to 0), and it may turn back
        there (a non-smooth fold: both cycles exist on one side only).  Next
        to the corner, at lambda a little before or beyond a's, look for a
        solution in the other regime (stick vs none) by Newton from probes
        on that side, and leave along its branch, away from a.
        """
        for size in (1e-5, 1e-4, 1e-3):
            for direction in (-1.0, 1.0):  # back (a fold) first, then on
                lam = a.lam + direction * math.copysign(size * self.sl, t[1])
                if not (self.lo <= lam <= self.hi):
                    continue
                for k in (1.0, -1.0, 3.0, -3.0, 10.0, -10.0):
                    s = self._other_regime(a, lam, a.xi + k * size * self.sx)
                    if s is None:
                        continue
                    away = tracer.w(s) - tracer.w(a)
                    if any(e.has_stick == s.has_stick and np.linalg.norm(tracer.w(s) - tracer.w(e)) < np.linalg.norm(away) for e in earlier[-8:]):
                        continue  # back onto the piece of branch just traced
                    t_new = tracer.tangent(s, away / np.linalg.norm(away))
                    exact = self.refine_grazing(a, s, a.lam)
                    lam_g = a.lam if exact is None else exact
                    found = [Event("grazing", lam_g, {"stick_phase": "appears" if s.has_stick else "vanishes", "corner": True,
                                                      "refined": exact is not None})]
                    if t_new[1] * t[1] < 0:
                        found.append(Event("fold", lam_g, {"smooth": False, "at": "grazing"}))
                    return Crossing(s, t_new, found)
        return None

    def _other_regime(self, a: Solution, lam: float, xi: float) -> Solution | None:
        """The orbit at lambda from the probe xi if the probe and the orbit are in the other regime than a (stick vs none)."""
        try:
            if xi <= 0 or self.at(xi, lam).has_stick == a.has_stick:
                return None
            s = self.solve_at(lam, xi)
        except (RuntimeError, ValueError):
            return None
        return None if s.has_stick == a.has_stick else s

    def diagnose(self, a: Solution, t: np.ndarray) -> Stop:
        """Why the branch could not be continued past a (direction t): a switch turning tangential, or unknown."""
        tr = min((sw.transversality for sw in a.seg.switches), default=1.0)
        if tr < 1e-2:
            # a stick-slip cycle ends where its slip excursion touches V_r = 0: the root of that margin past a
            direction = math.copysign(1.0, t[1]) if t[1] != 0 else 1.0
            exact = self.refine_stick_slip_end(a, direction, 1e-3 * self.sl)
            return Stop("grazing", True, [Event("grazing", a.lam if exact is None else exact,
                                                {"ends_branch": True, "transversality": tr, "refined": exact is not None})])
        return Stop("branch end", True, [Event("branch_end", a.lam, {"reason": "the corrector fails beyond this point"})])


def _middle(found: tuple[Solution, Solution | None]) -> float:
    """lambda between the last solution like a and the first unlike it (the last like a if none was found)."""
    last_a, first_b = found
    return 0.5 * (last_a.lam + first_b.lam) if first_b is not None else last_a.lam
