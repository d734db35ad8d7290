"""``simulate``: the one entry point that runs a model with a friction law and a solver."""

from __future__ import annotations

import numpy as np

from . import _validate as check
from .config import RUN_PARAMETERS
from .estimate import enforce
from .friction.base import FrictionLaw
from .params import BeltOscillator
from .solvers.base import DEFAULT_MAX_MEMORY, Solver
from .solvers.auto import auto_solver
from .solvers.registry import belt_motion_refusal, solver_class, unsupported
from .trajectory import Trajectory

RUN = {p.name: p for p in RUN_PARAMETERS}


def simulate(
    model: BeltOscillator,
    friction: FrictionLaw,
    solver: Solver | None = None,
    *,
    t_end: float = 500.0,
    x0: float | None = None,
    v0: float | None = None,
    progress: bool = False,
    max_memory: float = DEFAULT_MAX_MEMORY,
) -> Trajectory:
    """Integrate the belt oscillator from tau = 0 to ``t_end``.

    Parameters
    ----------
    model, friction:
        The oscillator (zeta, V_b) and the friction law (F_d, F_s, ...).
    solver:
        A solver object, or a solver's name (``"auto"``, ``"exact"``, ... with its default settings); default
        (None or ``"auto"``): :class:`~frictionflow.Exact` for
        piecewise-constant laws (Karnopp, Coulomb), else
        :class:`~frictionflow.Adaptive`; for laws with internal state (LuGre)
        :class:`~frictionflow.Stiff`.
    t_end:
        Non-dimensional end time, > 0.
    x0, v0:
        Initial state; by default the law's start (:meth:`FrictionLaw.start`): the paper's
        X(0) = F_d, X'(0) = V_b (rate-and-state: X'(0) = 0, sliding at the belt's speed).
    progress:
        Draw a progress bar on stderr for long runs.
    max_memory:
        GiB the samples may take; a longer run is refused up front, saying so.
        Inside :func:`frictionflow.estimate.limited`, a run estimated above
        its limits (an hour of computing) is refused before it starts too.
    """
    check.instance("model", model, BeltOscillator, "a BeltOscillator")
    check.instance("friction", friction, FrictionLaw, "a FrictionLaw")
    t_end, max_memory = RUN["t_end"].check(t_end), RUN["max_memory"].check(max_memory)  # None is no number here
    x0, v0 = (RUN[k].check(v) if v is not None else None for k, v in (("x0", x0), ("v0", v0)))  # None: the default
    check.instance("progress", progress, (bool, np.bool_), "True or False")
    x0, v0 = friction.start(model.vb, x0, v0)
    solver = resolved_solver(solver, friction, model)
    if not solver.supports(friction):
        raise ValueError(unsupported(solver.name, friction))
    refusal = belt_motion_refusal(solver, friction) if model.belt_varies else None
    if refusal:
        raise ValueError(refusal)
    enforce(lambda: solver.cost(model, friction, t_end))  # within the limits in force (frictionflow.estimate.limited)
    return solver.solve(model, friction, x0, v0, t_end, progress=progress, max_memory=max_memory)


def resolved_solver(solver: Solver | str | None, friction: FrictionLaw, model: BeltOscillator) -> Solver:
    """``solver`` as a solver object: None and ``"auto"`` the default for the law and model, another name its
    solver with default settings; anything else refused (TypeError naming the argument)."""
    if solver is None or solver == "auto":
        return auto_solver(friction, model)
    if isinstance(solver, str):
        return solver_class(solver, friction, model)()
    if not isinstance(solver, Solver):
        raise TypeError(f"solver must be a Solver (frictionflow.solvers: Exact(), Adaptive(), RK4(), ...) or a "
                        f"solver's name, got {type(solver).__name__}")
    return solver
