"""Pseudo-arclength continuation of periodic orbits in one parameter lambda.

Steps are taken along the tangent of the branch of zeros of H (see
:mod:`.cycle_problem`) in the scaled coordinates w = (xi / s_x,
lambda / s_lambda) and corrected on the hyperplane normal to it (Keller's
pseudo-arclength), so folds are passed without special care.  Between
accepted points the tracer looks for

* folds: the tangent's lambda component changes sign (mu crosses 1 on a
  smooth branch; at a grazing corner the turn is non-smooth);
* grazing: a stick phase appears or vanishes;
* other changes of the phase sequence ("switching", e.g. a slip reversal);

and refines each by solving again along the last tangent.  Where a slip-only
cycle touches X' = V_b the branch has a corner (the multiplier jumps to 0);
the tracer steps over it explicitly (:meth:`Tracer._cross_corner`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..core import roots
from .cycle_problem import CycleProblem, Solution


@dataclass
class Event:
    """A special point found between two accepted solutions."""

    type: str
    value: float
    detail: dict[str, Any] = field(default_factory=dict)


@dataclass
class Trace:
    """What one run of the tracer found."""

    solutions: list[Solution]
    events: list[Event]
    end: str


class Tracer:
    """Follows one branch of a :class:`CycleProblem` with adaptive steps."""

    def __init__(
        self,
        problem: CycleProblem,
        *,
        h0: float = 0.02,
        h_max: float = 0.1,
        h_min: float = 1e-5,
        max_points: int = 300,
        max_period: float = 500.0,
        xi_min: float | None = None,
    ) -> None:
        self.p = problem
        self.h0, self.h_max, self.h_min = h0, h_max, h_min
        self.max_points = max_points
        self.max_period = max_period
        self.xi_min = 1e-4 * problem.sx if xi_min is None else xi_min

    # -- one step ---------------------------------------------------------------
    def correct(self, w_pred: np.ndarray, t: np.ndarray, max_iter: int = 8) -> Solution | None:
        """Newton on (H = 0, t . (w - w_pred) = 0) from w_pred (chord in dH/dlambda).

        Gives up early when |H| stops falling fast (a corner or no solution
        near the predictor): the caller then shortens the step.
        """
        p = self.p
        xi, lam = float(w_pred[0] * p.sx), float(w_pred[1] * p.sl)
        dHl = math.nan
        last = math.inf
        for k in range(max_iter):
            if xi <= 0.0 or not math.isfinite(xi + lam):
                return None
            try:
                s = p.evaluate(xi, lam)
                r2 = float(t @ (p.w(s) - w_pred))
                stalled = k >= 2 and abs(s.H) > 0.5 * last
                # converged; or stalled within |G| <= tol_abs, at the rounding floor of a barely contracting map
                if abs(r2) < 1e-9 and (p.converged(s) or (stalled and p.near(s))):
                    s.iterations = k
                    if not math.isfinite(s.dHl):  # exact from the compiled engine, else the chord's
                        s.dHl = dHl if math.isfinite(dHl) else p.d_lambda(s)
                    return s
                if stalled:
                    return None
                last = abs(s.H)
                if math.isfinite(s.dHl):
                    dHl = s.dHl  # exact: Newton rather than a chord
                elif not math.isfinite(dHl):
                    dHl = p.d_lambda(s)
            except (RuntimeError, ValueError):
                return None
            J = np.array([[s.dH * p.sx, dHl * p.sl], [t[0], t[1]]])
            try:
                dw = np.linalg.solve(J, -np.array([s.H, r2]))
            except np.linalg.LinAlgError:
                return None
            if not np.all(np.isfinite(dw)) or float(np.linalg.norm(dw)) > 0.5:
                return None
            xi += float(dw[0] * p.sx)
            lam += float(dw[1] * p.sl)
        return None

    def along(self, a: Solution, t: np.ndarray, h: float) -> Solution | None:
        """The solution at scaled arclength h from a along t (for refining events)."""
        return self.correct(self.p.w(a) + h * t, t)

    # -- the branch ---------------------------------------------------------------
    def trace(self, first: Solution, t: np.ndarray) -> Trace:
        """Follow the branch from ``first`` in direction ``t`` until it ends or leaves [lo, hi]."""
        p = self.p
        sols, events = [first], []
        h = self.h0
        end = "max_points"
        while len(sols) < self.max_points:
            a = sols[-1]
            s = self.correct(p.w(a) + h * t, t)
            t_new = p.tangent(s, t) if s is not None else t
            sharp = s is not None and float(t_new @ t) < 0.5 and h > 8 * self.h_min and s.seg.modes == a.seg.modes
            if s is None or sharp:
                h *= 0.5
                self._last_t = t
                if h < self.h_min:
                    crossed = self._cross_corner(a, t, sols[:-1])
                    if crossed is None:
                        end = self._diagnose(a, events)
                        break
                    s, t_new, found = crossed
                    events += found
                    sols.append(s)
                    t, h = t_new, self.h0
                    continue
                continue
            outside = not (p.lo <= s.lam <= p.hi)
            if outside:
                s = self._at_boundary(a, s, p.hi if s.lam > p.hi else p.lo)
                if s is None:
                    end = "interval end"
                    break
                t_new = p.tangent(s, t)
            elif math.isfinite(s.x_ref) and s.xi < self.xi_min:
                end = "hopf"  # back onto the sliding equilibrium
                break
            events += self.events_between(a, s, t, t_new, h)
            sols.append(s)
            if s.period > self.max_period:
                events.append(Event("period_blowup", s.lam, {"period": s.period}))
                end = "period blowup"
                break
            if outside:
                end = "interval end"
                break
            t = t_new
            h = min(1.5 * h, self.h_max) if s.iterations <= 3 else max(0.7 * h, self.h_min)
        return Trace(sols, events, end)

    def _at_boundary(self, a: Solution, s: Solution, b: float) -> Solution | None:
        """The orbit at lambda = b, between a (inside) and s (outside)."""
        frac = (b - a.lam) / (s.lam - a.lam)
        try:
            return self.p.solve_at(b, a.xi + frac * (s.xi - a.xi))
        except (RuntimeError, ValueError):
            return None

    def _cross_corner(self, a: Solution, t: np.ndarray, earlier: list[Solution]) -> tuple[Solution, np.ndarray, list[Event]] | None:
        """Step over a grazing corner, where the branch has no tangent.

        Where a slip-only cycle touches X' = V_b it meets the stick-slip
        branch at an angle (the multiplier jumps to 0), and it may turn back
        there (a non-smooth fold: both cycles exist on one side only).  Next
        to the corner, at lambda a little before or beyond a's, look for a
        solution in the other regime (stick vs none) by Newton from probes
        on that side, and leave along its branch, away from a.
        """
        p = self.p
        for size in (1e-5, 1e-4, 1e-3):
            for direction in (-1.0, 1.0):  # back (a fold) first, then on
                lam = a.lam + direction * math.copysign(size * p.sl, t[1])
                if not (p.lo <= lam <= p.hi):
                    continue
                for k in (1.0, -1.0, 3.0, -3.0, 10.0, -10.0):
                    xi = a.xi + k * size * p.sx
                    try:
                        if xi <= 0 or p.evaluate(xi, lam).has_stick == a.has_stick:
                            continue
                        s = p.solve_at(lam, xi)
                    except (RuntimeError, ValueError):
                        continue
                    if s.has_stick == a.has_stick:
                        continue
                    away = p.w(s) - p.w(a)
                    if any(e.has_stick == s.has_stick and np.linalg.norm(p.w(s) - p.w(e)) < np.linalg.norm(away) for e in earlier[-8:]):
                        continue  # back onto the piece of branch just traced

                    t_new = p.tangent(s, away / np.linalg.norm(away))
                    exact = p.refine_grazing(a, s, a.lam)
                    lam_g = a.lam if exact is None else exact
                    found = [Event("grazing", lam_g, {"stick_phase": "appears" if s.has_stick else "vanishes", "corner": True,
                                                      "refined": exact is not None})]
                    if t_new[1] * t[1] < 0:
                        found.append(Event("fold", lam_g, {"smooth": False, "at": "grazing"}))
                    return s, t_new, found
        return None

    def _diagnose(self, a: Solution, events: list[Event]) -> str:
        """Why the branch could not be continued past a: a switch turning tangential, or unknown."""
        tr = min((sw.transversality for sw in a.seg.switches), default=1.0)
        if tr < 1e-2:
            # a stick-slip cycle ends where its slip excursion touches V_r = 0: the root of that margin past a
            t = getattr(self, "_last_t", None)
            direction = math.copysign(1.0, t[1]) if t is not None and t[1] != 0 else 1.0
            exact = self.p.refine_stick_slip_end(a, direction, 1e-3 * self.p.sl)
            events.append(Event("grazing", a.lam if exact is None else exact, {"ends_branch": True, "transversality": tr, "refined": exact is not None}))
            return "grazing"
        events.append(Event("branch_end", a.lam, {"reason": "the corrector fails beyond this point"}))
        return "branch end"

    # -- events -------------------------------------------------------------------
    def events_between(self, a: Solution, b: Solution, ta: np.ndarray, tb: np.ndarray, h: float) -> list[Event]:
        """Special points between consecutive solutions a and b (b = a + h ta, corrected).

        No period doubling is looked for: the multiplier of this plane system
        is never negative (see :mod:`.floquet`).
        """
        out = []
        if a.has_stick != b.has_stick:
            lam = self._bisect(a, ta, h, lambda s: s.has_stick == a.has_stick)
            exact = self.p.refine_grazing(a, b, lam)
            detail = {"stick_phase": "appears" if b.has_stick else "vanishes", "refined": exact is not None}
            out.append(Event("grazing", lam if exact is None else exact, detail))
        elif a.slip_modes != b.slip_modes:
            lam = self._bisect(a, ta, h, lambda s: s.slip_modes == a.slip_modes)
            out.append(Event("switching", lam, {"before": list(a.seg.modes), "after": list(b.seg.modes)}))
        if ta[1] * tb[1] < 0:
            smooth = a.has_stick == b.has_stick and (a.mu - 1.0) * (b.mu - 1.0) < 0
            if smooth:
                s = self._secant(a, ta, h, lambda s: s.mu - 1.0, a.mu - 1.0, b.mu - 1.0)
                exact = self.p.refine_fold(s if s is not None else a)
                lam = exact if exact is not None else (s.lam if s else 0.5 * (a.lam + b.lam))
                out.append(Event("fold", lam, {"smooth": True, "multiplier": s.mu if s else None, "refined": s is not None or exact is not None}))
            else:
                out.append(Event("fold", out[-1].value if out else 0.5 * (a.lam + b.lam), {"smooth": False}))
        return out

    def _bisect(self, a: Solution, t: np.ndarray, h: float, like_a, n: int = 12) -> float:
        """lambda where like_a turns False along the arc from a (bisection on arclength)."""
        lo, hi = 0.0, h
        lam_lo, lam_hi = a.lam, math.nan
        for _ in range(n):
            mid = 0.5 * (lo + hi)
            s = self.along(a, t, mid)
            if s is None:
                break
            if like_a(s):
                lo, lam_lo = mid, s.lam
            else:
                hi, lam_hi = mid, s.lam
        return 0.5 * (lam_lo + lam_hi) if math.isfinite(lam_hi) else lam_lo

    def _secant(self, a: Solution, t: np.ndarray, h: float, f, fa: float, fb: float, n: int = 10) -> Solution | None:
        """The solution along the arc where f = 0 (:mod:`..core.roots` on arclength), to 1e-9 in f or in h."""
        b = roots.bracket(0.0, h, fa, fb, 1e-9 * h, 0.0, 1e-9, n)
        best = None
        while b.status == roots.RUNNING:
            s = self.along(a, t, b.x)
            if s is None:
                break
            best = s
            b = roots.update(b, b.x, f(s))
        return best


def start_from_hopf(problem: CycleProblem, tracer: Tracer, lam_h: float, xi0: float) -> tuple[Solution, np.ndarray] | None:
    """The first orbit of the branch born at lambda_H, at amplitude xi0, and the branch's tangent.

    From the virtual point (0, lambda_H) the branch leaves along xi: correct
    (xi0, lambda_H) on the line xi = xi0.
    """
    t0 = np.array([1.0, 0.0])
    w_h = np.array([0.0, lam_h / problem.sl])
    s = tracer.correct(w_h + (xi0 / problem.sx) * t0, t0)
    if s is None:
        return None
    return s, problem.tangent(s, t0)


def start_from_orbit(problem: CycleProblem, lam: float, x: float, toward: float) -> tuple[Solution, np.ndarray]:
    """A solution at (lambda, X) and the tangent pointing toward lambda = ``toward``."""
    _, _, x_ref = problem.system(lam)
    s = problem.solve_at(lam, x - (x_ref if math.isfinite(x_ref) else 0.0))
    j = np.array([s.dH * problem.sx, s.dHl * problem.sl])
    t = np.array([j[1], -j[0]])
    t /= np.linalg.norm(t)
    if (toward - lam) * t[1] < 0:
        t = -t
    return s, t

