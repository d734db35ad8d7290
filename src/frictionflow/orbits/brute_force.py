"""Brute-force parameter sweep: what long simulations settle on, to overlay on a bifurcation diagram.

Simulations only find attractors (and only those the start state leads to),
which is exactly why they are a useful independent check of the stable parts
of continued branches.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from ..analysis import analyze
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..simulate import RUN, simulate
from ..solvers.base import Solver
from .parameters import with_param


def sweep(
    model: BeltOscillator,
    friction: FrictionLaw,
    param: str,
    values: Iterable[float],
    *,
    t_end: float = 500.0,
    x0: float | None = None,
    v0: float | None = None,
    solver: Solver | None = None,
) -> list[dict[str, Any]]:
    """Simulate and analyze at each value of ``param``; one dict per value (NaN where undefined).

    Parameters
    ----------
    model, friction:
        The oscillator and the law at every other parameter's value.
    param:
        The parameter to vary (a name of the oscillator or of the law, such as ``zeta`` or ``vb``).
    values:
        Its values.
    t_end:
        Length of each simulation (finite, > 0; checked before any run).
    x0, v0:
        Initial state (default the paper's X(0) = F_d, X'(0) = V_b).
    solver:
        A solver (default: the law's).
    """
    t_end = RUN["t_end"].check(t_end)  # before any run: None, text, inf or <= 0 name t_end
    out = []
    for lam in values:
        m, law = with_param(model, friction, param, float(lam))
        res = analyze(simulate(m, law, solver, t_end=t_end, x0=x0, v0=v0))
        ss, av = res.steady_state, res.power.averages()
        out.append(
            {
                "value": float(lam),
                "kind": ss.kind,
                "period": ss.period,
                "amplitude": 0.5 * (res.amplitude["X_max"] - res.amplitude["X_min"]),
                "X_max": res.amplitude["X_max"],
                "X_min": res.amplitude["X_min"],
                "stick_fraction": ss.stick_fraction,
                **{k: av[k] for k in ("P_fin", "P_df", "P_dv", "R_c", "R_f")},
                "TR_B": res.TR_B,
                "energy_residual": res.power.energy_residual,
            }
        )
    return out
