"""Everything ``simulate --json`` reports about one run, in one call."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..trajectory import Trajectory
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
        """A JSON-ready dict (NaN becomes None)."""
        traj = self.trajectory
        d = {
            "params": {"zeta": traj.model.zeta, "vb": traj.model.vb, **traj.friction.as_dict()},
            "solver": traj.solver,
            "steady_state": self.steady_state.to_dict(),
            "averages": self.power.averages(),
            "TR_B": self.TR_B,
            "amplitude": self.amplitude,
            "energy_residual": self.power.energy_residual,
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


def analyze(
    traj: Trajectory,
    *,
    window: tuple[float, float] | None = None,
    rtol: float = 1e-6,
    min_periods: int = 3,
) -> Analysis:
    """Find the steady state of ``traj`` and evaluate power flow, TR_B and amplitudes over it."""
    ss = steady_state(traj, rtol=rtol, min_periods=min_periods, window=window)
    return Analysis(
        trajectory=traj,
        steady_state=ss,
        power=power_flow(traj, ss.window),
        TR_B=transmissibility(traj, ss.window),
        amplitude=amplitude(traj, ss.window),
    )
