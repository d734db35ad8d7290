"""Branches of cycles of laws with internal state, traced by the pseudo-arclength tracer (:mod:`.tracing`).

A cycle is described on the section X' = 0 relative to steady sliding
y*(lambda) (:mod:`.stateful_equilibria`):

    y0 = y* + xi (1, 0, w),   xi = X - X* > 0,

with the unknowns (xi, w_1 .. w_m, T) and the parameter lambda.  Dividing
the return by xi,

    H = [phi_T(y0) - y0] / xi   (rows scaled by the states' sizes),

removes the equilibrium (any T, xi = 0) from the solutions, as the section
map's deflation does (:mod:`.cycle_problem`): at xi -> 0, H = 0 says that
(1, 0, w) is a real eigenvector of exp(A T) for the multiplier 1, i.e. that
lambda is a Hopf point and T = 2 pi / omega.  So a branch born at a Hopf point
starts regularly at (0, w_H, 2 pi / omega, lambda_H) and its amplitude xi
vanishes there.  dH/d(xi, w, T) come from the monodromy and the field at the
end; dH/dlambda is a forward difference (one more flow).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .errors import ShootingError
from .flow_stiff import FlowEnd, StiffFlow
from .parameters import with_param
from .stateful import STATE_TOL
from .stateful_equilibria import StateEquilibrium, state_equilibrium
from .tracing import ContinuationProblem, Corrector, Event, Stop, StepControl, Trace, Tracer


@dataclass
class CycleSolution:
    """A solved point (xi, w, T, lambda) with its flow's end and what its events are judged on."""

    lam: float
    u: np.ndarray  # (xi, w ..., T)
    H: np.ndarray
    dH: np.ndarray  # dH / d(xi, w, T)
    y0: np.ndarray
    end: FlowEnd
    eq: StateEquilibrium
    dHl: np.ndarray = field(default_factory=lambda: np.full(0, math.nan))
    iterations: int = 0

    @property
    def xi(self) -> float:
        return float(self.u[0])

    @property
    def period(self) -> float:
        return float(self.u[-1])

    @property
    def multipliers(self) -> np.ndarray:
        """The nontrivial Floquet multipliers (the trivial 1, the one nearest 1, dropped), largest modulus first."""
        mu = np.linalg.eigvals(self.end.jacobian).astype(complex)
        mu = np.delete(mu, int(np.argmin(np.abs(mu - 1.0))))
        return mu[np.argsort(-np.abs(mu), kind="stable")]

    @property
    def stable(self) -> bool:
        return bool(abs(self.multipliers[0]) < 1.0)


class StateCycleProblem(ContinuationProblem):
    """H(xi, w, T; lambda) = 0 for cycles of (model, law) in ``param`` on [lo, hi] (module docstring).

    A branch ends where its period exceeds ``max_period`` or it runs back onto steady sliding
    (xi below ``xi_min``, default 1e-4 s_x: a Hopf point).
    """

    corrector = Corrector(max_iter=10, stall_after=3, chord_every=0, fresh_lambda=True)

    def __init__(self, model: BeltOscillator, law: FrictionLaw, param: str, lo: float, hi: float, *,
                 tol: float | None = None, max_period: float = 500.0, xi_min: float | None = None) -> None:
        self.model, self.law, self.param = model, law, param
        self.lo, self.hi = min(lo, hi), max(lo, hi)
        self.sx = max(law.fs, abs(model.vb), 1e-12)
        self.rows = np.concatenate([[1.0, 1.0], law.internal_scale() / self.sx])  # H's rows, each of order 1
        self.sl = self.hi - self.lo
        self.scale = np.concatenate([[self.sx], self.rows[2:], [2.0 * math.pi, self.sl]])
        self.tol = STATE_TOL if tol is None else tol
        self.dlam = 1e-6 * self.sl
        self.max_period = max_period
        self.xi_min = 1e-4 * self.sx if xi_min is None else xi_min

    def system(self, lam: float) -> tuple[StiffFlow, StateEquilibrium]:
        """The flow and steady sliding at lambda; ValueError where there is none."""
        model, law = with_param(self.model, self.law, self.param, lam)
        eq = state_equilibrium(model, law, lam)
        if eq is None:
            raise ValueError(f"no steady sliding at {self.param}={lam!r}")
        return StiffFlow(model, law), eq

    def at(self, u: np.ndarray, lam: float) -> CycleSolution:
        """H and dH/d(xi, w, T) at (u, lambda); RuntimeError/ValueError where undefined."""
        flow, eq = self.system(lam)
        xi, period = float(u[0]), float(u[-1])
        e = np.concatenate([[1.0, 0.0], u[1:-1]])
        y0 = eq.state + xi * e
        end = flow.run(y0, period)
        g = (end.y - y0) / self.rows
        H = g / xi
        m = end.jacobian - np.eye(flow.n)
        d_xi = (m @ e / self.rows - H) / xi
        d_w = m[:, 2:] / self.rows[:, None]
        d_t = end.field / self.rows / xi
        return CycleSolution(lam, np.asarray(u, dtype=float).copy(), H, np.column_stack([d_xi, d_w, d_t]), y0, end, eq)

    def d_lambda(self, s: CycleSolution) -> np.ndarray:
        if np.all(np.isfinite(s.dHl)) and len(s.dHl):
            return s.dHl
        h = self.dlam if s.lam + self.dlam <= self.hi else -self.dlam
        return (self.at(s.u, s.lam + h).H - s.H) / h

    def solve_at(self, lam: float, x: np.ndarray) -> CycleSolution:
        """The cycle at fixed lambda near the unknowns x (Newton in them); ShootingError on failure."""
        u = np.asarray(x, dtype=float)
        for it in range(20):
            s = self.at(u, lam)
            if self.converged(s):
                s.iterations = it
                s.dHl = self.d_lambda(s)
                return s
            u = u - np.linalg.solve(s.dH, s.H)
            if not self.admissible(np.append(u, lam)):
                break
        raise ShootingError(f"no cycle near xi={x[0]:.6g} at {self.param}={lam:.10g}")

    # -- the continuation protocol ---------------------------------------------------------------------------------
    def evaluate(self, u: np.ndarray) -> CycleSolution:
        return self.at(u[:-1], float(u[-1]))

    def unknowns(self, s: CycleSolution) -> np.ndarray:
        return np.append(s.u, s.lam)

    def residual(self, s: CycleSolution) -> np.ndarray:
        return s.H

    def jacobian(self, s: CycleSolution) -> np.ndarray:
        last = s.dHl if len(s.dHl) else np.full(len(s.H), math.nan)
        return np.column_stack([s.dH, last])

    def set_d_lambda(self, s: CycleSolution, column: np.ndarray) -> None:
        s.dHl = np.asarray(column, dtype=float)

    def converged(self, s: CycleSolution) -> bool:
        """The return misses y0 by at most tol of each state's scale."""
        return float(np.max(np.abs(s.H))) * s.xi <= self.tol * self.sx

    def tests(self, s: CycleSolution) -> dict[str, float]:
        """|mu|_max - 1: it changes sign where the cycle loses or gains stability (fold, flip or torus)."""
        return {"stability": float(abs(s.multipliers[0])) - 1.0}

    def admissible(self, u: np.ndarray) -> bool:
        return bool(u[0] > 0.0 and u[-2] > 0.0)  # xi > 0 and T > 0

    def stop(self, s: CycleSolution) -> Stop | None:
        if s.xi < self.xi_min:
            return Stop("hopf", keep=False)  # back onto steady sliding
        if s.period > self.max_period:
            return Stop("period blowup", True, [Event("period_blowup", s.lam, {"period": s.period})])
        return None


def hopf_start(eq: StateEquilibrium) -> tuple[np.ndarray, float]:
    """(w, T) of the cycle born at the Hopf point ``eq``: the critical eigenvector on the section, 2 pi / omega."""
    lam, vecs = np.linalg.eig(eq.jacobian)
    pair = np.flatnonzero(lam.imag > 0.0)
    if not len(pair):
        raise ValueError("steady sliding has no complex pair of eigenvalues here: no Hopf point")
    k = pair[int(np.argmin(np.abs(lam[pair].real)))]
    v = vecs[:, k]
    c = 1j * np.conj(v[1]) / abs(v[1])  # Re(c v) has X' = 0 and X' falling: the section's point
    e = (c * v).real
    return e[2:] / e[0], float(2.0 * math.pi / lam[k].imag)


def branch_from_hopf(problem: StateCycleProblem, lam_h: float, xi0: float, steps: StepControl | None = None) -> Trace:
    """The branch of cycles born at the Hopf point lambda_H, from its first cycle at amplitude xi0."""
    tracer = Tracer(problem, steps)
    _, eq = problem.system(lam_h)
    w, period = hopf_start(eq)
    t0 = np.zeros(len(problem.scale))
    t0[0] = 1.0
    first = tracer.correct(np.concatenate([[xi0], w, [period, lam_h]]) / problem.scale, t0)
    if first is None:
        raise ShootingError(f"no cycle of amplitude xi={xi0:.6g} near the Hopf point {problem.param}={lam_h:.10g}")
    return tracer.trace(first, tracer.tangent(first, t0))


def branch_from_orbit(problem: StateCycleProblem, lam: float, y0: np.ndarray, period: float, toward: float,
                      steps: StepControl | None = None) -> Trace:
    """The branch through the orbit (y0 on X' = 0, period) at lambda, traced toward lambda = ``toward``."""
    tracer = Tracer(problem, steps)
    _, eq = problem.system(lam)
    xi = float(y0[0] - eq.state[0])
    if not xi > 0.0:
        raise ValueError(f"the orbit's X={y0[0]:.10g} is not beyond steady sliding's X*={eq.state[0]:.10g}")
    first = problem.solve_at(lam, np.concatenate([[xi], (np.asarray(y0[2:]) - eq.state[2:]) / xi, [period]]))
    return tracer.trace(first, tracer.start(first, toward))
