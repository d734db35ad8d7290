"""Steady sliding of a law with internal state, its eigenvalues on the whole state, and its Hopf points.

At steady sliding X' = 0, the states rest where their rates vanish at
V_r = V_b, r(V_b, z*) = 0 (found by Newton with the law's exact dr/dz), and
X* = F(V_b, z*), computed once by
:func:`frictionflow.sliding_equilibrium`; the Jacobian there is the stiff
engine's exact one, n x n.  A Hopf point is where
a complex pair crosses the imaginary axis: there the product of all pairwise
sums of eigenvalues, prod_{i<j} (l_i + l_j) (the determinant of the
bialternate product, real and smooth in the parameter), changes sign; a sign
change without a complex pair on the axis (a neutral saddle) is no Hopf
point.  Steady sliding has no folds in V_b-like parameters for these laws,
so the branch is sampled on a grid, as for the static laws (:mod:`.equilibria`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as check
from .._lazy import lazy_module
from ..analysis.equilibrium import sliding_equilibrium
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .equilibria import equilibrium_branch
from .parameters import with_param

optimize = lazy_module("scipy.optimize")



@dataclass(frozen=True, eq=False)
class StateEquilibrium:
    """Steady sliding on the whole state: y* = (X*, 0, z*), its Jacobian and eigenvalues (largest real part first).

    Attributes
    ----------
    value:
        The continued parameter's value it was computed at (NaN: none).
    state:
        y* = (X*, 0, z*): the displacement X* = F(V_b, z*), X' = 0, and the
        law's internal states at rest; shape (2 + number of states,).
    jacobian:
        The whole state's Jacobian at y* (the stiff engine's exact one), n x n
        with n = 2 + the number of internal states, in the order of ``state``.
    eigenvalues:
        The eigenvalues of ``jacobian`` (complex, n of them), largest real
        part first.
    """

    value: float
    state: np.ndarray
    jacobian: np.ndarray
    eigenvalues: np.ndarray

    @property
    def x(self) -> float:
        return float(self.state[0])

    @property
    def stability(self) -> str:
        """``stable`` (every real part < 0), ``unstable`` (one > 0) or ``neutral``."""
        top = float(np.max(self.eigenvalues.real))
        tol = 1e-12 * max(1.0, float(np.max(np.abs(self.eigenvalues))))
        return "stable" if top < -tol else ("unstable" if top > tol else "neutral")

    @property
    def hopf_test(self) -> float:
        """The Hopf test function prod_{i<j} Re(l_i + l_j), zero where a complex pair has real part 0 (or a
        neutral saddle)."""
        lam = self.eigenvalues
        out = 1.0 + 0.0j
        for i in range(len(lam)):
            for j in range(i + 1, len(lam)):
                out *= lam[i] + lam[j]
        return float(out.real)


def state_equilibrium(model: BeltOscillator, law: FrictionLaw, value: float = math.nan) -> StateEquilibrium | None:
    """Steady sliding of (model, law), or None where there is none (V_b = 0, forced, or the states do not rest).

    The one computation of :func:`frictionflow.sliding_equilibrium` (the states at
    rest by Newton on the law's exact rates, the whole state's Jacobian), kept with the continued value.

    Parameters
    ----------
    model, law:
        The oscillator and a law with internal state.
    value:
        The continued parameter's value, kept on the result (a real number; NaN: none).
    """
    value = check.real("value", value, "a real number (NaN: none)")
    if model.vb == 0.0 or model.forced:
        return None
    eq = sliding_equilibrium(model, law, value)
    if not (math.isfinite(eq.x) and np.all(np.isfinite(eq.internal))):
        return None
    y = np.concatenate([[eq.x, 0.0], eq.internal])
    return StateEquilibrium(float(value), y, eq.matrix, np.array(eq.eigenvalues, dtype=complex))


def state_equilibrium_branch(model: BeltOscillator, law: FrictionLaw, param: str, values: np.ndarray) -> list[StateEquilibrium]:
    """Steady sliding at each value of ``param`` (values without it are skipped)."""
    return equilibrium_branch(model, law, param, values, at=state_equilibrium)


def state_hopf_points(model: BeltOscillator, law: FrictionLaw, param: str, values: np.ndarray) -> list[float]:
    """Parameter values in the span of ``values`` where steady sliding has a Hopf point, refined by brentq on
    :attr:`~frictionflow.orbits.stateful_equilibria.StateEquilibrium.hopf_test` (a sign change with a complex pair on the axis).

    Parameters
    ----------
    model, law:
        The oscillator and a law with internal state at the other parameters' values.
    param:
        The parameter varied (zeta, vb or one of the law's).
    values:
        The grid the test is evaluated on (a Hopf point between two of its values is found).
    """

    def test(lam: float) -> float:
        eq = state_equilibrium(*with_param(model, law, param, lam), lam)
        return math.nan if eq is None else eq.hopf_test

    values = [float(v) for v in values]
    tests = [test(v) for v in values]
    found = []
    for a, b, ta, tb in zip(values[:-1], values[1:], tests[:-1], tests[1:], strict=True):
        if not (math.isfinite(ta) and math.isfinite(tb) and ta * tb < 0.0):
            continue
        lam = float(optimize.brentq(test, a, b, xtol=1e-14 * max(abs(a), abs(b), 1.0), rtol=4 * np.finfo(float).eps))
        eq = state_equilibrium(*with_param(model, law, param, lam), lam)
        pair = eq.eigenvalues[np.abs(eq.eigenvalues.imag) > 0.0]
        if len(pair) and float(np.min(np.abs(pair.real))) <= 1e-6 * float(np.max(np.abs(pair))):
            found.append(lam)
    return found
