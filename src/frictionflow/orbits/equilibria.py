"""The sliding equilibrium along a parameter, and its Hopf points.

The equilibrium itself -- X* = F(V_b), its Jacobian
A = [[0, 1], [-1, -(2 zeta + F'(V_b))]] and its stability -- is
:class:`frictionflow.SlidingEquilibrium` (:mod:`frictionflow.analysis.equilibrium`),
the same one :func:`frictionflow.analyze` reports.  det A = 1 > 0, so the
equilibrium can only lose stability through a pair of complex eigenvalues
crossing the imaginary axis -- a Hopf point, where trace A changes sign.  No
fold of equilibria is possible either, so the branch is the graph
X*(lambda) and is sampled directly rather than continued.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from .._lazy import lazy_module
from ..analysis.equilibrium import SlidingEquilibrium, sliding_equilibrium
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .parameters import with_param

optimize = lazy_module("scipy.optimize")  # loaded on first use: importing the CLI stays quick

#: the orbits' name for the sliding equilibrium (kept for compatibility)
Equilibrium = SlidingEquilibrium


def slope_at_belt_speed(model: BeltOscillator, law: FrictionLaw) -> float:
    """F'(|V_b|) of the slip law (0 for piecewise-constant laws)."""
    return law.slip_slope(abs(model.vb))


def equilibrium(model: BeltOscillator, law: FrictionLaw, value: float = math.nan) -> SlidingEquilibrium | None:
    """The sliding equilibrium, or None where there is none (V_b = 0, or inside Karnopp's band)."""
    model.refuse_moving_belt("the sliding equilibrium")
    model.refuse_forcing("the sliding equilibrium")
    if model.vb == 0.0:
        return None
    eq = sliding_equilibrium(model, law, value)
    return eq if math.isfinite(eq.x) else None


def equilibrium_branch(model: BeltOscillator, law: FrictionLaw, param: str, values: np.ndarray,
                       at: Callable[..., Any] | None = None) -> list[Any]:
    """The equilibrium at each value of ``param`` (values without one are skipped).

    ``at(model, law, value)``: the equilibrium or None (default :func:`equilibrium`; steady sliding on the
    whole state for laws with internal state, :func:`~.stateful_equilibria.state_equilibrium`).
    """
    at = equilibrium if at is None else at
    out = []
    for lam in values:
        eq = at(*with_param(model, law, param, float(lam)), float(lam))
        if eq is not None:
            out.append(eq)
    return out


def hopf_points(model: BeltOscillator, law: FrictionLaw, param: str, values: np.ndarray) -> list[float]:
    """Parameter values in the span of ``values`` where trace A changes sign, refined by brentq."""

    def trace(lam: float) -> float:
        eq = equilibrium(*with_param(model, law, param, lam), lam)
        return math.nan if eq is None else -eq.damping

    tr = [trace(float(lam)) for lam in values]
    found = []
    for a, b, ta, tb in zip(values[:-1], values[1:], tr[:-1], tr[1:], strict=True):
        if math.isfinite(ta) and math.isfinite(tb) and ta * tb < 0:
            found.append(float(optimize.brentq(trace, float(a), float(b), xtol=1e-14 * max(abs(a), abs(b), 1.0), rtol=4 * np.finfo(float).eps)))
    return found
