"""frictionflow: dynamics and vibration power flow of dry-friction oscillators.

>>> from frictionflow import BeltOscillator, Coulomb, simulate, analyze
>>> traj = simulate(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04), t_end=100)
>>> result = analyze(traj)           # the exact solver by default
>>> result.steady_state.kind
'periodic'
"""

from . import basins  # the subpackage (its function: basins.basins, or compute_basins)
from . import plotting  # noqa: F401  (imported to register the figures of Trajectory.plot and Analysis.plot)
from . import stability_plot  # noqa: F401  (registers the figure of StabilityScan.plot)
from ._version import __version__
from .analysis import (
    Analysis,
    LyapunovResult,
    PowerFlow,
    SteadyState,
    amplitude,
    analyze,
    frequency_response,
    instantaneous_power,
    lyapunov_exponents,
    power_flow,
    steady_state,
    transmissibility,
)
from .analysis.equilibrium import SlidingEquilibrium, sliding_equilibrium
from .analysis.stability import StabilityScan, SteadySliding, stability_scan, steady_sliding
from .analysis.stability_chart import StabilityChart, stability_chart
from .basins import Basins
from .basins import basins as compute_basins
from .friction import Coulomb, Cubic, Dahl, ElastoPlastic, FrictionLaw, Karnopp, LuGre, RateState, SlipLaw, Stribeck
from .modes import SwitchMode
from .params import BeltOscillator, DimensionalParams
from .simulate import simulate
from .solvers import RK4, Adaptive, CoarseStepWarning, Exact, Solver, StepLimitError, Stiff
from .trajectory import Trajectory

__all__ = [
    "Adaptive",
    "Analysis",
    "Basins",
    "BeltOscillator",
    "CoarseStepWarning",
    "Coulomb",
    "Cubic",
    "Dahl",
    "DimensionalParams",
    "ElastoPlastic",
    "Exact",
    "FrictionLaw",
    "Karnopp",
    "LuGre",
    "RateState",
    "LyapunovResult",
    "PowerFlow",
    "RK4",
    "SlidingEquilibrium",
    "SlipLaw",
    "Solver",
    "StabilityChart",
    "StabilityScan",
    "SteadySliding",
    "SteadyState",
    "StepLimitError",
    "Stiff",
    "Stribeck",
    "SwitchMode",
    "Trajectory",
    "__version__",
    "amplitude",
    "analyze",
    "basins",
    "compute_basins",
    "frequency_response",
    "instantaneous_power",
    "lyapunov_exponents",
    "power_flow",
    "simulate",
    "sliding_equilibrium",
    "stability_chart",
    "stability_scan",
    "steady_sliding",
    "steady_state",
    "transmissibility",
]
