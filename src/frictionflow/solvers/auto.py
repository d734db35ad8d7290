"""``solver="auto"``: exact for piecewise-constant laws, adaptive otherwise."""

from __future__ import annotations

from ..friction.base import FrictionLaw
from .adaptive import Adaptive
from .base import Solver
from .exact import Exact


def auto_solver(friction: FrictionLaw) -> Solver:
    """The default solver for ``friction``."""
    return Exact() if friction.piecewise_constant else Adaptive()
