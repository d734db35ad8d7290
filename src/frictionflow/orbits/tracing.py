"""Pseudo-arclength continuation of F(x, lambda) = 0, x in R^n, for any problem that can evaluate F.

A continuation problem (:class:`ContinuationProblem`) says what its unknowns
are and how to evaluate F with its Jacobian; :class:`Tracer` follows one
branch of zeros for any n.  Steps are taken along the branch's tangent in
the scaled coordinates w = u / scale, u = (x, lambda), and corrected by
Newton on the hyperplane normal to it (Keller's pseudo-arclength), so folds
are passed without special care.  Between accepted points the problem's
:meth:`~ContinuationProblem.events` looks for special points and refines
them along the arc with :meth:`Tracer.secant` (a sign change of a test
function) or :meth:`Tracer.bisect` (a change of a discrete label).

The problems:
:class:`~.cycle_problem.CycleProblem` (autonomous limit cycles, n = 1: the
deflated Poincare-map residual on the section) and the forced stroboscopic
map's fixed points (:mod:`.forced`, n = 2).  They step differently -- the
forced map's dF/dlambda is a difference of two map runs, the autonomous
one's exact or one run -- and keep those differences as data
(:class:`Corrector` on the problem, :class:`StepControl` on the tracer),
not as code.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Protocol

import numpy as np

from .._progress import progress_bar
from ..core import roots

#: more unknowns than this: the tangent by SVD, not by cofactors (whose cost grows as n!)
COFACTOR_MAX = 4


# -- records ------------------------------------------------------------------------------------------------------
@dataclass
class Event:
    """A special point found between two accepted solutions (``value``: its lambda)."""

    type: str
    value: float
    detail: dict[str, Any] = field(default_factory=dict)


@dataclass
class Trace:
    """What one run of the tracer found: the accepted solutions, the events between them, why it stopped."""

    solutions: list[Any]
    events: list[Any]
    end: str


@dataclass(frozen=True)
class Step:
    """Two consecutive accepted solutions, their tangents and the scaled arclength between them (b = a + h ta, corrected)."""

    a: Any
    b: Any
    ta: np.ndarray
    tb: np.ndarray
    h: float


@dataclass(frozen=True)
class Crossing:
    """The branch continued past a point where the corrector failed (a corner): the solution beyond, its tangent, events."""

    solution: Any
    tangent: np.ndarray
    events: list[Any] = field(default_factory=list)


@dataclass(frozen=True)
class Stop:
    """The branch ends (``keep``: with the solution that ended it among the branch's points)."""

    reason: str
    keep: bool = True
    events: list[Any] = field(default_factory=list)


@dataclass(frozen=True)
class Corrector:
    """How Newton corrects a predictor: a property of the problem (how dear and how smooth its evaluation is).

    ``stall_after``: from this iteration on, a residual that does not halve
    means no convergence (the caller shortens the step).  ``chord_every``: a
    dF/dlambda that is a difference (not exact from the evaluation) is taken
    again every this many iterations (0: once, a chord).  ``fresh_lambda``:
    take it again at the accepted point for the tangent (else the chord's).
    """

    max_iter: int = 8
    stall_after: int = 2
    chord_every: int = 0
    fresh_lambda: bool = False
    plane_tol: float = 1e-9  # |t . (w - w_pred)| at acceptance
    max_step: float = 0.5  # a scaled Newton step longer than this diverges


@dataclass(frozen=True)
class StepControl:
    """Step sizes (scaled arclength) and the rules that shorten them.

    A step is halved where the corrector fails, where the tangent turns by
    more than arccos(``min_cos``) (unless the step is already within
    ``turn_guard`` h_min, or the problem says a corner is expected: there,
    where the parameter's direction turns back), or where
    the corrected point lies farther than ``jump`` h from the last (another
    branch).  After ``fast`` Newton iterations or fewer the step grows by
    ``grow``, else shrinks by ``shrink``.
    """

    h0: float = 0.02
    h_max: float = 0.1
    h_min: float = 1e-5
    max_points: int = 300
    grow: float = 1.5
    shrink: float = 0.7
    fast: int = 3
    min_cos: float = 0.5
    turn_guard: float = 8.0
    jump: float = math.inf
    detect: bool = True  # look for events between points


# -- the protocol -------------------------------------------------------------------------------------------------
class ContinuationProblem(Protocol):
    """What the tracer needs of a problem F(x, lambda) = 0 with n unknowns x (u = (x, lambda), n + 1 numbers).

    Solutions are the problem's own records with attributes ``lam`` and a
    writable ``iterations``.  Evaluations raise RuntimeError or ValueError
    where F is undefined.  Subclass this class to inherit the defaults of
    the optional hooks (below :meth:`tests`).
    """

    scale: np.ndarray  # (n + 1,) the unknowns' and lambda's sizes: w = u / scale is what steps are measured in
    lo: float  # the interval of lambda
    hi: float
    corrector: Corrector

    def evaluate(self, u: np.ndarray) -> Any:
        """The solution record at u (F and dF/dx; dF/dlambda too where the evaluation gives it exactly)."""
        ...

    def unknowns(self, s: Any) -> np.ndarray:
        """u = (x, lambda) of a solution (it may differ from the u evaluated at: the problem may snap it)."""
        ...

    def residual(self, s: Any) -> np.ndarray:
        """F (n,), the residual Newton drives to 0 (its largest modulus must halve between iterations)."""
        ...

    def jacobian(self, s: Any) -> np.ndarray:
        """[dF/dx | dF/dlambda] (n, n + 1); the last column NaN where it is not known exactly (see :meth:`d_lambda`)."""
        ...

    def d_lambda(self, s: Any) -> np.ndarray:
        """dF/dlambda (n,) at s, by differences where the evaluation does not give it."""
        ...

    def set_d_lambda(self, s: Any, column: np.ndarray) -> None:
        """Keep dF/dlambda on s (its tangent is taken from :meth:`jacobian`)."""
        ...

    def converged(self, s: Any) -> bool:
        """Is s a solution to the problem's tolerance?"""
        ...

    def solve_at(self, lam: float, x: np.ndarray) -> Any:
        """The solution at fixed lambda from the guess x (Newton in x alone); raises RuntimeError/ValueError on failure."""
        ...

    def tests(self, s: Any) -> dict[str, float]:
        """Test functions whose sign changes between two solutions mark events (named by their keys)."""
        ...

    # -- optional hooks (defaults for subclasses) --------------------------------------------------------------------
    def admissible(self, u: np.ndarray) -> bool:
        """Is u inside the problem's domain (evaluations outside it are not tried)?"""
        return True

    def near(self, s: Any) -> bool:
        """Accept s when Newton stalls (at the rounding floor) though not :meth:`converged`?"""
        return False

    def corner(self, a: Any, b: Any) -> bool:
        """Is a sharp turn of the tangent between a and b expected (a corner), not a sign of too long a step?"""
        return False

    def stop(self, s: Any) -> Stop | None:
        """A reason to end the branch at s (a stop rule of the problem), or None."""
        return None

    def events(self, tracer: Tracer, step: Step) -> list[Any]:
        """Special points between step.a and step.b: folds, and sign changes of :meth:`tests`, located by secant."""
        return default_events(self, tracer, step)

    def dead_end(self, tracer: Tracer, solutions: list[Any], t: np.ndarray) -> Crossing | Stop:
        """The step shrank below h_min beyond solutions[-1] (direction t): cross a corner, or stop."""
        return Stop("branch end", True, [Event("branch_end", solutions[-1].lam, {"reason": "the corrector fails beyond this point"})])


def default_events(problem: ContinuationProblem, tracer: Tracer, step: Step) -> list[Event]:
    """Folds (lambda's tangent component changes sign) and sign changes of the test functions, each located by secant."""
    out = []
    xtol = 1e-10 * step.h  # in arclength, not lambda: at a fold lambda is flat (both sides of it alike)
    if step.ta[-1] * step.tb[-1] < 0.0:
        s = tracer.secant(step, lambda s: tracer.tangent(s, step.ta)[-1], step.ta[-1], step.tb[-1], xtol=xtol)
        out.append(Event("fold", (s or step.b).lam, {"refined": s is not None}))
    fa, fb = problem.tests(step.a), problem.tests(step.b)
    for name, va in fa.items():
        if va * fb[name] < 0.0:
            s = tracer.secant(step, lambda s, name=name: problem.tests(s)[name], va, fb[name], xtol=xtol)
            out.append(Event(name, (s or step.b).lam, {"refined": s is not None}))
    return out


# -- linear algebra for n unknowns ----------------------------------------------------------------------------------
def _det(m: np.ndarray) -> float:
    """Determinant by Laplace expansion along the first row (exact as written for 1 x 1, a d - b c for 2 x 2)."""
    if len(m) == 1:
        return float(m[0, 0])
    total = 0.0
    for j in range(len(m)):
        term = float(m[0, j]) * _det(np.delete(m[1:], j, axis=1))
        total = total + term if j % 2 == 0 else total - term
    return total


def null_vector(a: np.ndarray) -> np.ndarray:
    """A vector orthogonal to the n rows of a (n x (n + 1)), not normalised: the generalised cross product.

    t_i = (-1)^i det(a without column i): (a_1, -a_0) for n = 1, the cross
    product for n = 2 (the tracers' former formulas, rounding for rounding),
    a null vector of full-rank a for any n.  Beyond :data:`COFACTOR_MAX`
    unknowns the cofactors cost too much: the last right singular vector.
    """
    n = a.shape[0]
    if n > COFACTOR_MAX:
        return np.linalg.svd(a)[2][-1]
    return np.array([(-1.0) ** i * _det(np.delete(a, i, axis=1)) for i in range(n + 1)])


# -- the tracer ---------------------------------------------------------------------------------------------------
class Tracer:
    """Follows one branch of a :class:`ContinuationProblem` with adaptive steps."""

    def __init__(self, problem: ContinuationProblem, steps: StepControl | None = None, progress: bool = False) -> None:
        self.p = problem
        self.steps = StepControl() if steps is None else steps
        self.progress = progress  # a bar on stderr per branch: its points of at most max_points

    def w(self, s: Any) -> np.ndarray:
        """Scaled coordinates of a solution."""
        return self.p.unknowns(s) / self.p.scale

    def tangent(self, s: Any, previous: np.ndarray | None) -> np.ndarray:
        """Unit tangent of the branch at s (scaled), pointing the way ``previous`` did (if given).

        Where the Jacobian has no null direction of its own (zero or not
        finite) the previous direction is kept.
        """
        p = self.p
        j = p.jacobian(s)
        if not np.all(np.isfinite(j[:, -1])):
            j[:, -1] = p.d_lambda(s)
        t = null_vector(j * p.scale)
        n = float(np.linalg.norm(t))
        if not math.isfinite(n) or n == 0.0:
            if previous is not None:
                return previous
            t, n = np.linalg.svd(j * p.scale)[2][-1], 1.0
        t = t / n
        return -t if previous is not None and float(t @ previous) < 0.0 else t

    def start(self, s: Any, toward: float) -> np.ndarray:
        """The tangent at s pointing toward lambda = ``toward``."""
        t = self.tangent(s, None)
        return -t if (toward - s.lam) * t[-1] < 0 else t

    # -- one step ---------------------------------------------------------------------------------------------------
    def correct(self, w_pred: np.ndarray, t: np.ndarray) -> Any | None:
        """Newton on (F = 0, t . (w - w_pred) = 0) from w_pred; None where it does not converge.

        Gives up early when |F| stops halving (a corner, or no solution near
        the predictor): the caller then shortens the step.  A stall within
        the problem's :meth:`~ContinuationProblem.near` is accepted (the
        rounding floor of a barely contracting map).
        """
        p, c = self.p, self.p.corrector
        u = w_pred * p.scale
        chord = None  # dF/dlambda where the evaluation does not give it
        last = math.inf
        for k in range(c.max_iter):
            if not (np.all(np.isfinite(u)) and p.admissible(u)):
                return None
            try:
                s = p.evaluate(u)
                u = p.unknowns(s)
                r2 = float(t @ (u / p.scale - w_pred))
                f = p.residual(s)
                size = float(np.max(np.abs(f)))
                stalled = k >= c.stall_after and size > 0.5 * last
                if abs(r2) < c.plane_tol and (p.converged(s) or (stalled and p.near(s))):
                    return self._accept(s, k, chord)
                if stalled:
                    return None
                last = size
                j = p.jacobian(s)
                if np.all(np.isfinite(j[:, -1])):
                    chord = j[:, -1]  # exact: Newton rather than a chord
                elif chord is None or (c.chord_every and k % c.chord_every == 0):
                    chord = p.d_lambda(s)
            except (RuntimeError, ValueError):
                return None
            j[:, -1] = chord
            try:
                dw = np.linalg.solve(np.vstack([j * p.scale, t]), -np.append(f, r2))
            except np.linalg.LinAlgError:
                return None
            if not np.all(np.isfinite(dw)) or float(np.linalg.norm(dw)) > c.max_step:
                return None
            u = u + dw * p.scale
        return None

    def _accept(self, s: Any, k: int, chord: np.ndarray | None) -> Any:
        """s with its iterations and a dF/dlambda for its tangent (exact, the chord, or differenced again)."""
        p = self.p
        s.iterations = k
        if not np.all(np.isfinite(p.jacobian(s)[:, -1])):
            p.set_d_lambda(s, p.d_lambda(s) if chord is None or p.corrector.fresh_lambda else chord)
        return s

    def along(self, a: Any, t: np.ndarray, h: float) -> Any | None:
        """The solution at scaled arclength h from a along t."""
        return self.correct(self.w(a) + h * t, t)

    # -- the branch -------------------------------------------------------------------------------------------------
    def trace(self, first: Any, t: np.ndarray) -> Trace:
        """Follow the branch from ``first`` in direction ``t`` until it ends, leaves [lo, hi] or has max_points."""
        with progress_bar("branch", self.steps.max_points, enabled=self.progress, unit="points") as advance:
            return self._trace(first, t, advance)

    def _trace(self, first: Any, t: np.ndarray, advance: Callable[[float], None]) -> Trace:
        p, c = self.p, self.steps
        sols, events = [first], []
        h, end = c.h0, "max_points"
        while len(sols) < c.max_points:
            a = sols[-1]
            s = self.along(a, t, h)
            t_new = self.tangent(s, t) if s is not None else t
            if s is None or self._too_far(a, s, t, t_new, h):
                h *= 0.5
                if h >= c.h_min:
                    continue
                way = p.dead_end(self, sols, t)
                events += way.events
                if isinstance(way, Stop):
                    end = way.reason
                    break
                sols.append(way.solution)
                advance(1)
                t, h = way.tangent, c.h0
                continue
            outside = not (p.lo <= s.lam <= p.hi)
            if outside:
                s = self._at_boundary(a, s)
                if s is None:
                    end = "interval end"
                    break
                t_new = self.tangent(s, t)
            halt = p.stop(s)
            if halt is not None and not halt.keep and not outside:
                end = halt.reason
                break
            if c.detect:
                events += p.events(self, Step(a, s, t, t_new, h))
            sols.append(s)
            advance(1)
            if halt is not None and halt.keep:
                events += halt.events
                end = halt.reason
                break
            if outside:
                end = "interval end"
                break
            t = t_new
            h = min(c.grow * h, c.h_max) if s.iterations <= c.fast else max(c.shrink * h, c.h_min)
        return Trace(sols, events, end)

    def _too_far(self, a: Any, s: Any, t: np.ndarray, t_new: np.ndarray, h: float) -> bool:
        """Was the step too long: the corrector jumped to another branch, or the tangent turned sharply?"""
        c = self.steps
        if float(np.linalg.norm(self.w(s) - self.w(a))) > c.jump * h:
            return True
        if h <= c.turn_guard * c.h_min:
            return False
        if self.p.corner(a, s):  # a corner may turn the branch sharply, but lambda's direction turning there is
            # resolved with short steps: a grazing and a smooth fold within one step read as a fold at the grazing
            return float(t_new[-1] * t[-1]) < 0.0
        return float(t_new @ t) < c.min_cos

    def _at_boundary(self, a: Any, s: Any) -> Any | None:
        """The solution at the interval's end between a (inside) and s (outside), from the chord's guess."""
        p = self.p
        b = p.hi if s.lam > p.hi else p.lo
        ua, us = p.unknowns(a)[:-1], p.unknowns(s)[:-1]
        frac = (b - a.lam) / (s.lam - a.lam)
        try:
            return p.solve_at(b, ua + frac * (us - ua))
        except (RuntimeError, ValueError):
            return None

    # -- locating events along the arc ------------------------------------------------------------------------------
    def secant(self, step: Step, f: Callable[[Any], float], fa: float, fb: float, *, xtol: float = 0.0,
               ftol: float = 0.0, max_iter: int = 40, lam_tol: float = 0.0) -> Any | None:
        """The solution along the arc from step.a (direction step.ta) where f changes sign (:mod:`..core.roots` on arclength).

        Stops at ``xtol`` in arclength, |f| <= ``ftol``, or once the
        solutions on both sides are within ``lam_tol`` in lambda; None if no
        point could be corrected.
        """
        a, t = step.a, step.ta
        b = roots.bracket(0.0, step.h, fa, fb, xtol, 0.0, ftol, max_iter)
        lam_lo, lam_hi = a.lam, math.inf
        best = None
        while b.status == roots.RUNNING:
            s = self.along(a, t, b.x)
            if s is None:
                break
            best = s
            b = roots.update(b, b.x, f(s))
            if b.side > 0:
                lam_hi = s.lam
            else:
                lam_lo = s.lam
            if abs(lam_hi - lam_lo) < lam_tol:
                break
        return best

    def bisect(self, step: Step, like_a: Callable[[Any], bool], *, max_iter: int,
               lam_tol: float = 0.0) -> tuple[Any, Any | None]:
        """Bisection on arclength for where ``like_a`` turns False: (last solution like a, first not like it or None).

        Stops after ``max_iter`` points or once the two are within ``lam_tol`` in lambda.
        """
        lo, hi = 0.0, step.h
        last_a, first_b = step.a, None
        for _ in range(max_iter):
            if first_b is not None and abs(first_b.lam - last_a.lam) < lam_tol:
                break
            mid = 0.5 * (lo + hi)
            s = self.along(step.a, step.ta, mid)
            if s is None:
                break
            if like_a(s):
                lo, last_a = mid, s
            else:
                hi, first_b = mid, s
        return last_a, first_b
