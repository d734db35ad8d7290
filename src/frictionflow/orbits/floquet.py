"""Floquet multipliers of a periodic orbit and what they say about its stability.

The monodromy matrix M maps a perturbation at a point of the orbit to the
perturbation one period later.  Perturbing along the flow only shifts the
phase, so one multiplier is always 1 (the trivial one); in this plane system
the other one, mu, decides stability: |mu| < 1 stable, > 1 unstable.  It is
also the slope of the Poincare map, and det M = mu.

A stick phase (X' = V_b held) forgets perturbations of X', and the remaining
perturbation of X only shifts when the stick phase ends -- a shift in time.
So an orbit with a stick phase has mu = 0 exactly: it is superstable, every
nearby motion lands on it within one period.

mu is never negative here: inside a phase det Phi = exp(int div f) > 0, and
a switch that both vector fields cross the same way has
det S = (grad h . f+) / (grad h . f-) > 0 (0 into stick).  A plane flow
cannot flip orientation, so there is no period doubling (mu = -1) to find;
stability is lost at mu = 1 (folds) or where an orbit ceases to exist.
"""

from __future__ import annotations

import numpy as np

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..simulate import simulate
from ..solvers.base import Solver

#: |mu| within this of 1 is reported as neutral (a family of orbits, as the undamped slip circles)
NEUTRAL_TOL = 1e-7


class MultiplierStability:
    """Mixin of orbits with several multipliers: needs ``multipliers`` (largest modulus first) and
    ``autonomous`` (an unforced orbit has the trivial multiplier 1, the one nearest 1, dropped)."""

    __slots__ = ()
    multipliers: np.ndarray
    autonomous: bool

    @property
    def nontrivial(self) -> np.ndarray:
        """The multipliers without the trivial one (the one closest to 1; none when forced), largest modulus first."""
        mu = self.multipliers
        return np.delete(mu, int(np.argmin(np.abs(mu - 1.0)))) if self.autonomous else mu

    @property
    def multiplier(self) -> complex:
        """The nontrivial multiplier of largest modulus (it decides stability)."""
        return complex(self.nontrivial[0])

    @property
    def stability(self) -> str:
        """``stable``, ``unstable`` or ``neutral`` (``classify``)."""
        return classify(self.multiplier)

    @property
    def stable(self) -> bool:
        return self.stability == "stable"


def multipliers(monodromy: np.ndarray) -> np.ndarray:
    """All Floquet multipliers (eigenvalues of M), largest modulus first.

    Parameters
    ----------
    monodromy:
        The monodromy matrix M (square, finite real entries; a ValueError names it otherwise).
    """
    mu = np.linalg.eigvals(_monodromy(monodromy)).astype(complex)
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def _monodromy(monodromy: object) -> np.ndarray:
    """``monodromy`` as a float array; a ValueError naming it unless it is a square matrix of finite numbers."""
    allowed = "a square matrix (n x n, n >= 1) of finite real numbers"
    try:
        m = np.asarray(monodromy, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"monodromy must be {allowed}, got {monodromy!r}") from None
    if m.ndim != 2 or m.shape[0] != m.shape[1] or m.shape[0] < 1:
        raise ValueError(f"monodromy must be {allowed}, got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise ValueError(f"monodromy must be {allowed}, got non-finite entries")
    return m


def nontrivial(monodromy: np.ndarray) -> complex:
    """The multiplier that is not the trivial 1 (the one farther from 1)."""
    mu = multipliers(monodromy)
    return complex(mu[int(np.argmax(np.abs(mu - 1.0)))])


def classify(mu: complex, tol: float = NEUTRAL_TOL) -> str:
    """``stable``, ``unstable`` or ``neutral`` from the nontrivial multiplier."""
    r = abs(mu)
    if r < 1.0 - tol:
        return "stable"
    if r > 1.0 + tol:
        return "unstable"
    return "neutral"


def fd_monodromy(
    model: BeltOscillator,
    friction: FrictionLaw,
    state: tuple[float, float],
    period: float,
    *,
    eps: float | None = None,
    solver: Solver | None = None,
) -> np.ndarray:
    """M by central differences of the time-``period`` map, integrated by :func:`frictionflow.simulate`.

    Independent of the phase Jacobians and saltation matrices: a check on
    them.

    Parameters
    ----------
    model, friction:
        The oscillator and its law.
    state:
        (X, X') on the orbit.
    period:
        The orbit's period: the time the map integrates over.
    eps:
        The difference step (default 1e-6 of the orbit's scale).
    solver:
        The solver of the perturbed runs (default: the law's).
    """

    scale = max(abs(state[0]), abs(model.vb), friction.fs, 1e-12)
    h = 1e-6 * scale if eps is None else eps
    cols = []
    for e in (np.array([1.0, 0.0]), np.array([0.0, 1.0])):
        ends = []
        for sign in (1.0, -1.0):
            x0, v0 = np.asarray(state, dtype=float) + sign * h * e
            traj = simulate(model, friction, solver, t_end=period, x0=float(x0), v0=float(v0))
            ends.append(np.array([traj.x[-1], traj.v[-1]]))
        cols.append((ends[0] - ends[1]) / (2.0 * h))
    return np.column_stack(cols)
