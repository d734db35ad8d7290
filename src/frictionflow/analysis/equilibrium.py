"""The steady-sliding equilibrium and its linear stability.

Sliding at the belt speed, X' = 0 and X* = F(V_b).  Linearised about it,
with F'(V_b) the slope of the slip law, perturbations obey

    x'' + (2 zeta + F'(V_b)) x' + x = 0

so the equilibrium is stable when 2 zeta + F'(V_b) > 0 and loses stability
in a Hopf bifurcation where 2 zeta + F'(V_b) = 0 (a falling slip law,
F' < 0, feeds energy in: the negative-damping mechanism of friction-induced
vibration).
"""

from __future__ import annotations

import cmath
from dataclasses import dataclass

from ..friction.base import FrictionLaw
from ..params import BeltOscillator


@dataclass(frozen=True)
class SlidingEquilibrium:
    """X* = F(V_b), its effective damping 2 zeta + F'(V_b) and what follows from it."""

    x: float
    damping: float
    eigenvalues: tuple[complex, complex]

    @property
    def stability(self) -> str:
        if self.damping > 0:
            return "stable"
        if self.damping < 0:
            return "unstable"
        return "neutral"

    @property
    def decay_rate(self) -> float:
        """-max Re(lambda): how fast perturbations decay (negative: grow)."""
        return -max(l.real for l in self.eigenvalues)


def sliding_equilibrium(model: BeltOscillator, friction: FrictionLaw) -> SlidingEquilibrium:
    """The equilibrium of steady sliding at V_r = V_b and its linear stability."""
    c = 2.0 * model.zeta + friction.slip_slope(abs(model.vb))
    root = cmath.sqrt(c * c / 4.0 - 1.0)
    return SlidingEquilibrium(
        x=friction.sliding_equilibrium(model.vb),
        damping=c,
        eigenvalues=(-c / 2.0 + root, -c / 2.0 - root),
    )
