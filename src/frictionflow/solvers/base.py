"""The contract every solver satisfies.

A solver is a small immutable strategy object: it validates its settings in
``__init__`` and its :meth:`Solver.solve` turns (model, friction law, initial
state, end time) into a :class:`~frictionflow.trajectory.Trajectory` whose
``work`` columns it integrated itself.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any, ClassVar, Mapping

import numpy as np

from ..friction.base import FrictionLaw
from ..parameters import Param, resolve
from ..modes import SwitchMode
from ..params import BeltOscillator
from ..trajectory import Trajectory
from .events import switch_modes


class CoarseStepWarning(UserWarning):
    """The fixed step is too coarse for the stick band or for RK4's stability."""


class Solver(ABC):
    """Base class of solvers."""

    name: str = "abstract"
    #: its settings, declared once (CLI options, config keys); ``keywords`` maps them to ``__init__``
    parameters: ClassVar[tuple[Param, ...]] = ()
    keywords: ClassVar[dict[str, str]] = {}

    @classmethod
    def from_values(cls, values: Mapping[str, Any]) -> "Solver":
        """Build from a mapping of parameter values (missing or None: the declared defaults)."""
        resolved = resolve(cls.parameters, values)
        return cls(**{cls.keywords.get(k, k): v for k, v in resolved.items()})

    @abstractmethod
    def solve(
        self,
        model: BeltOscillator,
        friction: FrictionLaw,
        x0: float,
        v0: float,
        t_end: float,
        progress: bool = False,
    ) -> Trajectory:
        """Integrate from (x0, v0) at tau = 0 to ``t_end``."""

    def supports(self, friction: FrictionLaw) -> bool:
        """Whether this solver can integrate ``friction``."""
        return True

    def describe(self) -> dict[str, Any]:
        """Name and settings, for reports and JSON."""
        return {"name": self.name}

    def __repr__(self) -> str:
        d = self.describe()
        args = ", ".join(f"{k}={v!r}" for k, v in d.items() if k != "name")
        return f"{type(self).__name__}({args})"


def output_buffers(cap: int) -> tuple[np.ndarray, ...]:
    """Arrays an event-driven kernel writes into: t, x, v, fc, mode, work, event times, event modes."""
    t, x, v, fc = (np.empty(cap) for _ in range(4))
    return t, x, v, fc, np.empty(cap, dtype=np.int8), np.empty((cap, 4)), np.empty(cap), np.empty(cap, dtype=np.int64)


def trajectory_from(
    buffers: tuple[np.ndarray, ...],
    n: int,
    n_events: int,
    model: BeltOscillator,
    friction: FrictionLaw,
    solver: dict[str, Any],
    extra: dict[str, Any] | None = None,
    *,
    event_modes: Mapping[int, SwitchMode],
) -> Trajectory:
    """A :class:`Trajectory` of the first ``n`` samples and ``n_events`` events in ``buffers``.

    ``event_modes`` is the solver's table from its kernel's mode codes to
    :class:`SwitchMode` (see :mod:`.events`): the events leave the solver in
    public values only.
    """
    t, x, v, fc, mode, work, ev_t, ev_mode = buffers
    return Trajectory(
        t=t[:n].copy(), x=x[:n].copy(), v=v[:n].copy(), fc=fc[:n].copy(), mode=mode[:n].copy(), dwork=work[:n].copy(),
        model=model, friction=friction, solver=solver,
        events={"t": ev_t[:n_events].copy(), "mode": switch_modes(ev_mode[:n_events], event_modes)},
        extra=extra or {},
    )
