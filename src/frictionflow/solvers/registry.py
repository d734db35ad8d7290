"""The solvers by name (``--solver NAME``), and ``auto``: exact for piecewise-constant laws, adaptive otherwise."""

from __future__ import annotations

from typing import Any, Callable, Mapping

from .._continuous import declare_interpolant
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..parameters import declare
from .adaptive import Adaptive
from .base import Solver
from .exact import Exact
from .rk4 import RK4
from .stiff import Stiff

#: every solver, in the order the CLI lists them
SOLVERS: tuple[type[Solver], ...] = (Exact, Adaptive, RK4, Stiff)
for _cls in SOLVERS:
    declare(_cls.parameters)
    declare_interpolant(_cls.name, _cls.interpolant)  # Trajectory.at evaluates its runs with it


def solver_classes() -> tuple[type[Solver], ...]:
    return SOLVERS


def solver_names() -> tuple[str, ...]:
    """``auto`` and the name of every solver."""
    return ("auto", *(cls.name for cls in solver_classes()))


def solver_names_where(test: Callable[[type[Solver]], bool]) -> tuple[str, ...]:
    """Names of the solvers whose class passes ``test`` (for messages listing what would do)."""
    return tuple(cls.name for cls in solver_classes() if test(cls))


def solver_named(name: Any) -> type[Solver] | None:
    """The solver class registered as ``name`` (the name a run's ``solver`` record keeps); None if none is."""
    return next((cls for cls in solver_classes() if cls.name == name), None)


def solver_class(name: str, friction: FrictionLaw, model: BeltOscillator | None = None) -> type[Solver]:
    """The class of solver ``name`` (``auto``: the default for ``friction`` and ``model``)."""
    if name == "auto":
        return type(auto_solver(friction, model))
    cls = solver_named(name)
    if cls is not None:
        return cls
    raise ValueError(f"solver must be one of {', '.join(solver_names())}, got {name!r}")


def auto_solver(friction: FrictionLaw, model: BeltOscillator | None = None) -> Solver:
    """The default solver for ``friction``: :class:`~frictionflow.Stiff` for laws with internal state, :class:`~frictionflow.Exact` for
    piecewise-constant laws, else :class:`~frictionflow.Adaptive`; on a moving belt (``model.belt_varies``) the first of these
    that runs one, else the first solver that runs it and the law.

    Parameters
    ----------
    friction:
        A friction law.
    model:
        The oscillator, if known (its belt may rule the default out).
    """
    if friction.internal_names:
        default: Solver = Stiff()
    else:
        default = Exact() if friction.piecewise_constant else Adaptive()
    if model is None or not model.belt_varies or (default.auto_belt_motion and default.runs_belt_motion(friction)):
        return default
    able = (cls() for cls in solver_classes() if cls.supports_belt_motion and cls.auto_belt_motion)
    return next((s for s in able if s.supports(friction) and s.runs_belt_motion(friction)), default)


def unsupported(solver: str, friction: FrictionLaw) -> str:
    """The one line refusing ``solver`` for ``friction``, naming the solvers that run it."""
    able = solver_names_where(lambda cls: cls().supports(friction))
    return f"solver={solver} does not support friction={friction.name}; use solver={' or '.join(('auto', *able))}"


def belt_motion_refusal(solver: Solver, friction: FrictionLaw) -> str | None:
    """The one line refusing a varying belt speed to ``solver`` under ``friction`` (its
    :meth:`~.base.Solver.belt_motion_problem`), naming the solvers that run it; None when it runs it."""
    problem = solver.belt_motion_problem(friction)
    if problem is None:
        return None
    able = tuple(cls.name for cls in solver_classes() if cls().supports(friction) and cls().runs_belt_motion(friction))
    return f"{problem}; " + (f"use solver={' or '.join(('auto', *able))}" if able else "no solver runs it yet")


def build_solver(name: str, friction: FrictionLaw, values: Mapping[str, Any], model: BeltOscillator | None = None) -> Solver:
    """Solver ``name`` for ``friction`` (and ``model``, for ``auto``) with its declared parameters taken from ``values``."""
    cls = solver_class(name, friction, model)
    solver = cls.from_values(values)
    if not solver.supports(friction):
        raise ValueError(unsupported(name, friction))
    return solver
