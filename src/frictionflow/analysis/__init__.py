"""Analysis of trajectories: steady state, power flow, transmissibility."""

from .lyapunov import LyapunovResult, lyapunov_exponents
from .power_flow import PowerFlow, instantaneous_power, power_flow
from .response import frequency_response
from .steady_state import KINDS, SteadyState, steady_state
from .summary import Analysis, analyze
from .transmissibility import amplitude, transmissibility

__all__ = [
    "KINDS",
    "Analysis",
    "LyapunovResult",
    "PowerFlow",
    "SteadyState",
    "amplitude",
    "analyze",
    "frequency_response",
    "instantaneous_power",
    "lyapunov_exponents",
    "power_flow",
    "steady_state",
    "transmissibility",
]
