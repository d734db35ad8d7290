"""Choosing the flow-map engine for a friction law."""

from __future__ import annotations

import math
from typing import Protocol

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .flow_exact import ExactFlow
from .flow_smooth import SmoothFlow
from .hybrid import Segment


class Flow(Protocol):
    """What shooting and continuation need from an engine."""

    def run(self, y0: tuple[float, float], *, duration: float = math.inf, returns: int = 0, max_time: float = 1e4) -> Segment:
        """Flow from ``y0`` for ``duration`` or to the ``returns``-th section crossing."""
        ...


def make_flow(model: BeltOscillator, law: FrictionLaw, *, rtol: float = 1e-11, engine: str = "auto") -> Flow:
    """The closed-form engine for piecewise-constant laws, solve_ivp for smooth slip curves.

    ``engine="smooth"`` forces the solve_ivp engine (Coulomb only among the
    piecewise-constant laws: Karnopp's band has no slip curve).
    """
    if engine not in ("auto", "exact", "smooth"):
        raise ValueError(f"engine must be auto, exact or smooth, got {engine!r}")
    if engine == "exact" or (engine == "auto" and law.piecewise_constant):
        return ExactFlow(model, law)
    return SmoothFlow(model, law, rtol=rtol)
