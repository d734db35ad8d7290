"""Choosing the flow-map engine for a friction law."""

from __future__ import annotations

import math
from typing import Protocol

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .flow_compiled import CompiledFlow, supports
from .flow_exact import ExactFlow
from .flow_smooth import SmoothFlow
from .hybrid import Segment


class Flow(Protocol):
    """What shooting and continuation need from an engine."""

    def run(self, y0: tuple[float, float], *, duration: float = math.inf, returns: int = 0, max_time: float = 1e4) -> Segment:
        """Flow from ``y0`` for ``duration`` or to the ``returns``-th section crossing."""
        ...


def make_flow(model: BeltOscillator, law: FrictionLaw, *, rtol: float = 1e-11, engine: str = "auto", param: str | None = None) -> Flow:
    """The closed-form engine for piecewise-constant laws, the compiled DOP853 engine for smooth ones.

    ``engine``: ``auto``; ``exact`` (closed forms); ``compiled``
    (:mod:`.flow_compiled`: Coulomb, Stribeck, cubic, with the derivative
    with respect to ``param``); ``smooth`` (scipy's solve_ivp, for user laws
    and as an independent check).  ``auto`` picks exact for piecewise-constant
    laws, compiled where the law has a compiled slip curve, else smooth.
    """
    if engine not in ("auto", "exact", "smooth", "compiled"):
        raise ValueError(f"engine must be auto, exact, compiled or smooth, got {engine!r}")
    if engine == "exact" or (engine == "auto" and law.piecewise_constant):
        return ExactFlow(model, law)
    if engine == "compiled" or (engine == "auto" and supports(law) and not model.forced):
        return CompiledFlow(model, law, param=param, rtol=rtol)
    return SmoothFlow(model, law, rtol=rtol)
