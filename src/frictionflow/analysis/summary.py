"""Everything ``simulate --json`` reports about one run, in one call."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

from .. import quantities as Q
from ..trajectory import Trajectory
from .equilibrium import equilibrium_values
from .power_flow import PowerFlow, power_flow
from .steady_state import SteadyState, steady_state
from .transmissibility import amplitude, transmissibility


@dataclass(frozen=True)
class Analysis:
    """Steady state, power flow, TR_B and amplitudes over the steady-state window."""

    trajectory: Trajectory
    steady_state: SteadyState
    power: PowerFlow
    TR_B: float
    amplitude: dict[str, float]

    @property
    def energy_residual(self) -> float:
        return self.power.energy_residual

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dict (NaN becomes None); the reports in the order of the quantities table."""
        traj = self.trajectory
        report = {
            "steady_state": self.steady_state.to_dict(),
            "averages": self.power.averages(),
            "TR_B": self.TR_B,
            "amplitude": self.amplitude,
            "energy_residual": self.power.energy_residual,
        }
        d = {
            "params": {"zeta": traj.model.zeta, "vb": traj.model.vb, **traj.friction.as_dict()},
            "solver": traj.solver,
            **{key: report[key] for key in Q.REPORTS},
        }
        if traj.events is not None:
            d["events"] = int(len(traj.events["t"]))
        return _clean(d)


def _clean(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if hasattr(obj, "item"):  # numpy scalar
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


#: convergence tolerance of the steady-state test, by solver: fixed-step RK4
#: resolves orbits to about 1e-6, the adaptive solver to its rtol, the exact
#: solver to rounding
DEFAULT_RTOL = {"rk4": 1e-6, "adaptive": 1e-8, "exact": 1e-10}


def analyze(
    traj: Trajectory,
    *,
    window: tuple[float, float] | None = None,
    rtol: float | None = None,
    min_periods: int = 3,
) -> Analysis:
    """Find the steady state of ``traj`` and evaluate power flow, TR_B and amplitudes over it.

    For an equilibrium the averages, TR_B and amplitudes are those of the
    equilibrium itself (the motion left over the tail is below the
    convergence tolerance) and the energy residual is that of the whole run.
    """
    if rtol is None:
        rtol = DEFAULT_RTOL.get(traj.solver.get("name", ""), 1e-6)
    ss = steady_state(traj, rtol=rtol, min_periods=min_periods, window=window)
    if ss.kind == "equilibrium" and not ss.manual_window:
        return _at_equilibrium(traj, ss)
    if ss.kind == "diverged":  # nothing about the motion is meaningful: every number is NaN
        nan = float("nan")
        power = PowerFlow(**{f.name: nan for f in fields(PowerFlow)} | {"window": ss.window})
        return Analysis(trajectory=traj, steady_state=ss, power=power, TR_B=nan,
                        amplitude={k: nan for k in Q.AMPLITUDE})
    return Analysis(
        trajectory=traj,
        steady_state=ss,
        power=power_flow(traj, ss.window),
        TR_B=transmissibility(traj, ss.window),
        amplitude=amplitude(traj, ss.window),
    )


def _at_equilibrium(traj: Trajectory, ss: SteadyState) -> Analysis:
    """The equilibrium's own values: at rest, X = F_c; sliding, the belt's power is all heat."""
    x = ss.limit["x"] if ss.limit else float(traj.x[-1])
    whole = power_flow(traj)  # at rest nothing is left to balance: check the whole run
    power, trb, amp = equilibrium_values(
        x, traj.vb, traj.friction.fd, window=ss.window, stick=ss.stick_fraction, residual=whole.energy_residual
    )
    return Analysis(trajectory=traj, steady_state=ss, power=power, TR_B=trb, amplitude=amp)
