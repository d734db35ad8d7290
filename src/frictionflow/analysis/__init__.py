"""Analysis of trajectories: steady state, power flow, transmissibility."""

from .power_flow import PowerFlow, instantaneous_power, power_flow
from .steady_state import KINDS, SteadyState, steady_state
from .summary import Analysis, analyze
from .transmissibility import amplitude, transmissibility

__all__ = [
    "KINDS",
    "Analysis",
    "PowerFlow",
    "SteadyState",
    "amplitude",
    "analyze",
    "instantaneous_power",
    "power_flow",
    "steady_state",
    "transmissibility",
]
