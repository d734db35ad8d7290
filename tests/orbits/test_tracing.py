"""The one continuation tracer on problems written here, with closed-form branches: 1 and 3 unknowns, through a fold."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from frictionflow.orbits.tracing import COFACTOR_MAX, ContinuationProblem, Corrector, Tracer, StepControl, null_vector


@dataclass
class Point:
    u: np.ndarray  # (x, lambda)
    dl: np.ndarray  # dF/dlambda (NaN until differenced)
    iterations: int = 0

    @property
    def lam(self) -> float:
        return float(self.u[-1])


class Equations(ContinuationProblem):
    """F(u) = 0 from ``f`` and its Jacobian ``jac`` in u = (x, lambda); ``exact``: else dF/dlambda by central differences."""

    def __init__(self, f, jac, n, interval, scale, tests, *, exact=True, corrector=Corrector()):
        self.f, self.jac, self.n, self.exact, self._tests = f, jac, n, exact, tests
        self.lo, self.hi = interval
        self.scale = np.asarray(scale, dtype=float)
        self.corrector = corrector

    def evaluate(self, u):
        return Point(u.copy(), self.jac(u)[:, -1] if self.exact else np.full(self.n, math.nan))

    def unknowns(self, s):
        return s.u

    def residual(self, s):
        return self.f(s.u)

    def jacobian(self, s):
        return np.column_stack([self.jac(s.u)[:, :-1], s.dl])

    def d_lambda(self, s):
        d = 1e-6
        up, dn = s.u.copy(), s.u.copy()
        up[-1] += d
        dn[-1] -= d
        return (self.f(up) - self.f(dn)) / (2 * d)

    def set_d_lambda(self, s, column):
        s.dl = column

    def converged(self, s):
        return float(np.max(np.abs(self.f(s.u)))) <= 1e-13

    def solve_at(self, lam, x):
        u = np.append(np.asarray(x, dtype=float), lam)
        for _ in range(30):
            if float(np.max(np.abs(self.f(u)))) <= 1e-13:
                return self.evaluate(u)
            u[:-1] -= np.linalg.solve(self.jac(u)[:, :-1], self.f(u))
        raise RuntimeError("no solution at this lambda")

    def tests(self, s):
        return {name: g(s.u) for name, g in self._tests.items()}


def circle(exact=True):
    """x^2 + lambda^2 = 1 (1 unknown): a fold at lambda = 1; the test x - 1/2 changes sign at lambda = sqrt(3)/2."""
    return Equations(lambda u: np.array([u[0] ** 2 + u[1] ** 2 - 1.0]), lambda u: np.array([[2 * u[0], 2 * u[1]]]),
                     1, (-0.5, 1.5), [1.0, 1.0], {"x_half": lambda u: u[0] - 0.5}, exact=exact)


def twisted(exact=True):
    """3 unknowns: x1^2 + lambda^2 = 1, x2 = x1 lambda, exp(x3) = 2 + x1 -- the branch
    (cos th, sin th cos th, log(2 + cos th), sin th); a fold at lambda = 1, x3 = log 2.5 at lambda = sqrt(3)/2."""

    def f(u):
        x1, x2, x3, lam = u
        return np.array([x1 * x1 + lam * lam - 1.0, x2 - x1 * lam, math.exp(x3) - 2.0 - x1])

    def jac(u):
        x1, _, x3, lam = u
        return np.array([[2 * x1, 0.0, 0.0, 2 * lam], [-lam, 1.0, 0.0, -x1], [-1.0, 0.0, math.exp(x3), 0.0]])

    return Equations(f, jac, 3, (-0.5, 1.5), [1.0, 0.5, 2.0, 2.0], {"x3": lambda u: u[2] - math.log(2.5)}, exact=exact,
                     corrector=Corrector(max_iter=10, stall_after=3, chord_every=3, fresh_lambda=True))


def on_branch(u):
    """Distance of u from the closed-form branch at its own angle."""
    th = math.atan2(u[-1], u[0])
    exact = [math.sin(th) * math.cos(th), math.log(2 + math.cos(th))]  # x2, x3 (3 unknowns)
    return max([abs(math.hypot(u[0], u[-1]) - 1.0), *(abs(a - b) for a, b in zip(u[1:-1], exact))])


@pytest.mark.parametrize("make", [circle, twisted], ids=["1 unknown", "3 unknowns"])
@pytest.mark.parametrize("exact", [True, False], ids=["exact", "differenced"])
def test_tracer_follows_the_branch_through_its_fold_and_locates_the_events(make, exact):
    pb = make(exact)
    tracer = Tracer(pb, StepControl(h0=0.02, h_max=0.1, h_min=1e-6))
    first = pb.solve_at(0.0, [1.0, 0.0, math.log(3.0)][:pb.n])
    trace = tracer.trace(first, tracer.start(first, pb.hi))
    # round the fold at lambda = 1 and back down to the interval's lower end on the other side (x1 < 0)
    assert trace.end == "interval end"
    last = trace.solutions[-1]
    assert last.lam == pytest.approx(-0.5, abs=1e-12) and last.u[0] < 0
    assert max(s.lam for s in trace.solutions) < 1.0 + 1e-12
    assert max(on_branch(s.u) for s in trace.solutions) < 1e-10
    lams = [s.lam for s in trace.solutions]
    assert all(lam <= pb.hi for lam in lams) and len(trace.solutions) > 20
    folds = [e for e in trace.events if e.type == "fold"]
    assert len(folds) == 1 and abs(folds[0].value - 1.0) < 1e-12, trace.events
    # the test function's one sign change (x1 = 1/2), located to the tolerance on the arc
    crossings = [e for e in trace.events if e.type in ("x_half", "x3")]
    assert len(crossings) == 1 and abs(crossings[0].value - math.sqrt(0.75)) < 1e-9, trace.events


def test_tangent_is_the_null_direction_for_any_number_of_unknowns():
    rng = np.random.default_rng(3)
    for n in range(1, COFACTOR_MAX + 3):  # cofactors, then the SVD
        a = rng.standard_normal((n, n + 1))
        t = null_vector(a)
        assert np.max(np.abs(a @ t)) < 1e-12 * np.linalg.norm(t) * np.linalg.norm(a)
    # n = 1: (a1, -a0) exactly; n = 2: the cross product
    assert list(null_vector(np.array([[3.0, 5.0]]))) == [5.0, -3.0]
    a = rng.standard_normal((2, 3))
    assert np.array_equal(null_vector(a), np.cross(a[0], a[1]))
