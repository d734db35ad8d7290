"""frictionflow: dynamics and vibration power flow of dry-friction oscillators.

>>> from frictionflow import BeltOscillator, Karnopp, RK4, simulate, analyze
>>> traj = simulate(BeltOscillator(zeta=0.0, vb=0.01), Karnopp(fd=0.02), RK4(dt=1e-3), t_end=100)
>>> result = analyze(traj)
>>> result.steady_state.kind
'periodic'
"""

from importlib.metadata import PackageNotFoundError, version

from .analysis import (
    Analysis,
    PowerFlow,
    SteadyState,
    amplitude,
    analyze,
    instantaneous_power,
    power_flow,
    steady_state,
    transmissibility,
)
from .friction import FrictionLaw, Karnopp
from .params import BeltOscillator, DimensionalParams
from .simulate import simulate
from .solvers import RK4, CoarseStepWarning, Solver
from .trajectory import Trajectory

try:
    __version__ = version("frictionflow")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0+unknown"

__all__ = [
    "Analysis",
    "BeltOscillator",
    "CoarseStepWarning",
    "DimensionalParams",
    "FrictionLaw",
    "Karnopp",
    "PowerFlow",
    "RK4",
    "Solver",
    "SteadyState",
    "Trajectory",
    "__version__",
    "amplitude",
    "analyze",
    "instantaneous_power",
    "power_flow",
    "simulate",
    "steady_state",
    "transmissibility",
]
