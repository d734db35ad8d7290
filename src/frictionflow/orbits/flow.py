"""Choosing the flow-map engine for a friction law."""

from __future__ import annotations

import math
from typing import Callable, Protocol

from .._display import spoken
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
    if engine != "auto" and engine not in ENGINES:
        raise ValueError(f"engine must be {spoken(('auto', *ENGINES))}, got {engine!r}")
    return ENGINES[auto_engine(model, law) if engine == "auto" else engine](model, law, rtol, param)


def auto_engine(model: BeltOscillator, law: FrictionLaw) -> str:
    """The engine ``auto`` picks, from what the law declares."""
    if law.piecewise_constant:
        return "exact"
    if supports(law) and not model.forced:  # law.has_tangent_kernel: the compiled slip curve
        return "compiled"
    return "smooth"


#: the engines by name: each builds its flow from (model, law, rtol, param)
ENGINES: dict[str, Callable[[BeltOscillator, FrictionLaw, float, "str | None"], Flow]] = {
    "exact": lambda model, law, rtol, param: ExactFlow(model, law),
    "compiled": lambda model, law, rtol, param: CompiledFlow(model, law, param=param, rtol=rtol),
    "smooth": lambda model, law, rtol, param: SmoothFlow(model, law, rtol=rtol),
}
