"""Power flow, TR_B and amplitudes of one period of an orbit.

One period is integrated again by the package's own solver (exact or
adaptive) from the orbit's point on the section, so the averages are the
solver's exact work integrals over exactly one period -- the same numbers
``frictionflow simulate`` reports for a converged run, without the transient.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import quantities as Q
from ..analysis.equilibrium import equilibrium_values
from ..analysis.power_flow import PowerFlow, power_flow
from ..analysis.transmissibility import amplitude, transmissibility
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..simulate import simulate
from ..solvers.auto import auto_solver
from ..solvers.base import Solver
from ..trajectory import Trajectory

#: the averages an orbit reports, in the paper's order
POWER_KEYS = Q.PAPER_AVERAGES


@dataclass(frozen=True)
class OrbitMeasures:
    """Averages over one period, TR_B and the extremes of X and X'.

    Attributes
    ----------
    power:
        The power flow averaged over the period (a :class:`~frictionflow.PowerFlow`:
        P_dv, P_df, P_fin, R_c, R_f, P_belt, P_heat, P_f, P_ex and the energy
        residual of the period's power balance); at an equilibrium, the
        table's values there (no vibration power; R_c, R_f undefined).
    TR_B:
        The force transmissibility max |X + 2 zeta X'| / F_ex over the period
        (F_ex = F_d unforced); NaN when the reference force is 0.
    extremes:
        The extremes of X and X' over the period, by name: ``X_min``,
        ``X_max``, ``V_min``, ``V_max`` (V: X').
    """

    power: PowerFlow
    TR_B: float
    extremes: dict[str, float]

    @property
    def amplitude(self) -> float:
        """Half the peak-to-peak displacement, (X_max - X_min) / 2."""
        return 0.5 * (self.extremes["X_max"] - self.extremes["X_min"])

    def averages(self, forced: bool = False) -> dict[str, float]:
        """The averages by name in the paper's order; with ``forced``, the external force's ``P_ex`` after them."""
        extra = tuple(k for k in Q.FORCED_AVERAGES if k not in POWER_KEYS) if forced else ()
        return {k: getattr(self.power, k) for k in (*POWER_KEYS, *extra)}


def one_period(
    model: BeltOscillator,
    friction: FrictionLaw,
    state: tuple[float, float],
    period: float,
    *,
    solver: Solver | None = None,
    dense_dt: float | None = None,
) -> Trajectory:
    """One period from ``state`` by :func:`frictionflow.simulate` (optionally densely sampled)."""
    if solver is None and dense_dt is not None:
        solver = type(auto_solver(friction))(dense_dt=dense_dt)
    return simulate(model, friction, solver, t_end=period, x0=float(state[0]), v0=float(state[1]))


def measure(model: BeltOscillator, friction: FrictionLaw, state: tuple[float, float], period: float, *, solver: Solver | None = None) -> OrbitMeasures:
    """Power flow, TR_B and extremes of the orbit through ``state`` with ``period``."""
    if not (period > 0 and math.isfinite(period)):
        raise ValueError(f"period must be finite and > 0, got {period!r}")
    return measures_of(one_period(model, friction, state, period, solver=solver))


def measures_of(traj: Trajectory) -> OrbitMeasures:
    """Power flow, TR_B and extremes over the whole of ``traj`` (one period of an orbit)."""
    return OrbitMeasures(power=power_flow(traj), TR_B=transmissibility(traj), extremes=amplitude(traj))


def equilibrium_measures(x_star: float, vb: float, fd: float) -> OrbitMeasures:
    """The same quantities at the sliding equilibrium: no motion, so no vibration power.

    The belt still delivers F_c V_b = X* V_b, all of it turned into heat at
    the interface; R_c, R_f are undefined (nothing enters the vibration).
    """
    power, trb, extremes = equilibrium_values(x_star, vb, fd, window=(0.0, 0.0))
    return OrbitMeasures(power=power, TR_B=trb, extremes=extremes)
