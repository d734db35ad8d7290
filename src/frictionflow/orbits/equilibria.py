"""The sliding equilibrium along a parameter, and its Hopf points.

At X' = 0 the mass slides at V_r = V_b and rests at X* = F(V_b).  Its
Jacobian, the slip vector field's at that point (the same matrix the
variational equations of :mod:`.flow_smooth` use),

    A = [[0, 1], [-1, -(2 zeta + F'(V_b))]]

has det A = 1 > 0, so the equilibrium can only lose stability through a
pair of complex eigenvalues crossing the imaginary axis -- a Hopf point,
where trace A = -(2 zeta + F'(V_b)) changes sign.  No fold of equilibria is
possible either, so the branch is the graph X*(lambda) and is sampled
directly rather than continued.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .flow_smooth import slip_curve
from .parameters import with_param


@dataclass(frozen=True)
class Equilibrium:
    """The sliding equilibrium at one parameter value."""

    value: float
    x: float
    jacobian: np.ndarray

    @property
    def eigenvalues(self) -> np.ndarray:
        return np.linalg.eigvals(self.jacobian)

    @property
    def stability(self) -> str:
        tr = float(np.trace(self.jacobian))
        return "stable" if tr < 0 else ("unstable" if tr > 0 else "neutral")


def slope_at_belt_speed(model: BeltOscillator, law: FrictionLaw) -> float:
    """F'(|V_b|) of the slip curve (0 for piecewise-constant laws)."""
    if law.piecewise_constant:
        return 0.0
    _, dF = slip_curve(law)
    return dF(abs(model.vb))


def equilibrium(model: BeltOscillator, law: FrictionLaw, value: float = math.nan) -> Equilibrium | None:
    """The sliding equilibrium, or None where there is none (V_b = 0, or inside Karnopp's band)."""
    x = float(law.sliding_equilibrium(model.vb))
    if model.vb == 0.0 or not math.isfinite(x):
        return None
    c = 2.0 * model.zeta + slope_at_belt_speed(model, law)
    return Equilibrium(value, x, np.array([[0.0, 1.0], [-1.0, -c]]))


def equilibrium_branch(model: BeltOscillator, law: FrictionLaw, param: str, values: np.ndarray) -> list[Equilibrium]:
    """The equilibrium at each value of ``param`` (values without one are skipped)."""
    out = []
    for lam in values:
        eq = equilibrium(*with_param(model, law, param, float(lam)), float(lam))
        if eq is not None:
            out.append(eq)
    return out


def hopf_points(model: BeltOscillator, law: FrictionLaw, param: str, values: np.ndarray) -> list[float]:
    """Parameter values in the span of ``values`` where trace A changes sign, refined by brentq."""

    def trace(lam: float) -> float:
        eq = equilibrium(*with_param(model, law, param, lam), lam)
        return math.nan if eq is None else float(np.trace(eq.jacobian))

    tr = [trace(float(lam)) for lam in values]
    found = []
    for a, b, ta, tb in zip(values[:-1], values[1:], tr[:-1], tr[1:], strict=True):
        if math.isfinite(ta) and math.isfinite(tb) and ta * tb < 0:
            found.append(float(brentq(trace, float(a), float(b), xtol=1e-14 * max(abs(a), abs(b), 1.0), rtol=4 * np.finfo(float).eps)))
    return found
