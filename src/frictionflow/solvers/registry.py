"""The solvers by name (``--solver NAME``), and ``auto``: exact for piecewise-constant laws, adaptive otherwise."""

from __future__ import annotations

from typing import Any, Mapping

from ..friction.base import FrictionLaw
from ..parameters import declare
from .adaptive import Adaptive
from .base import Solver
from .exact import Exact
from .rk4 import RK4

#: every solver, in the order the CLI lists them
SOLVERS: tuple[type[Solver], ...] = (Exact, Adaptive, RK4)
for _cls in SOLVERS:
    declare(_cls.parameters)


def solver_classes() -> tuple[type[Solver], ...]:
    return SOLVERS


def solver_names() -> tuple[str, ...]:
    """``auto`` and the name of every solver."""
    return ("auto", *(cls.name for cls in solver_classes()))


def solver_class(name: str, friction: FrictionLaw) -> type[Solver]:
    """The class of solver ``name`` (``auto``: the default for ``friction``)."""
    if name == "auto":
        return type(auto_solver(friction))
    for cls in solver_classes():
        if cls.name == name:
            return cls
    raise ValueError(f"solver must be one of {', '.join(solver_names())}, got {name!r}")


def auto_solver(friction: FrictionLaw) -> Solver:
    """The default solver for ``friction``."""
    return Exact() if friction.piecewise_constant else Adaptive()


def build_solver(name: str, friction: FrictionLaw, values: Mapping[str, Any]) -> Solver:
    """Solver ``name`` for ``friction`` with its declared parameters taken from ``values``."""
    cls = solver_class(name, friction)
    solver = cls.from_values(values)
    if not solver.supports(friction):
        raise ValueError(f"solver={name} does not support friction={friction.name}; use solver=auto")
    return solver
