"""The contract every solver satisfies.

A solver is a small immutable strategy object: it validates its settings in
``__init__`` and its :meth:`Solver.solve` turns (model, friction law, initial
state, end time) into a :class:`~frictionflow.trajectory.Trajectory` whose
``work`` columns it integrated itself.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..trajectory import Trajectory


class CoarseStepWarning(UserWarning):
    """The fixed step is too coarse for the stick band or for RK4's stability."""


class Solver(ABC):
    """Base class of solvers."""

    name: str = "abstract"

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
