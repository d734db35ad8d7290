"""Choosing the flow-map engine for a friction law."""

from __future__ import annotations

import math
from typing import Callable, Protocol

from .._display import spoken
from ..estimate import SECONDS_PER
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .flow_compiled import CompiledFlow, flow_seconds, supports
from .flow_exact import ExactFlow
from .flow_smooth import SmoothFlow
from .hybrid import MAX_TIME, Segment


class Flow(Protocol):
    """What shooting and continuation need from an engine."""

    def run(self, y0: tuple[float, float], *, duration: float = math.inf, returns: int = 0, max_time: float = MAX_TIME) -> Segment:
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
    model.refuse_moving_belt("periodic orbits")
    model.refuse_forcing("periodic orbits on the section X' = 0")
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


#: each engine's class, for what it declares (its cost per time unit flowed)
ENGINE_CLASSES: dict[str, type] = {"exact": ExactFlow, "compiled": CompiledFlow, "smooth": SmoothFlow}


def flow_cost(model: BeltOscillator, law: FrictionLaw, span: float, engine: str = "auto") -> float:
    """CPU seconds of one flow of ``span`` time units (at most :data:`~.hybrid.MAX_TIME`, where every flow stops)
    on ``engine``, from its declared cost per time unit; a compiled flow of a law whose slip curve its steps cannot
    resolve is assumed to run to its step caps (:func:`~.flow_compiled.flow_seconds`)."""
    name = auto_engine(model, law) if engine == "auto" else engine
    seconds = SECONDS_PER["flow_start"] + min(span, MAX_TIME) * SECONDS_PER[ENGINE_CLASSES[name].time_cost]
    return max(seconds, flow_seconds(law)) if name == "compiled" and not law.resolvable() else seconds
