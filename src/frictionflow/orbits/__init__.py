"""Periodic orbits, Floquet multipliers, continuation and bifurcation diagrams.

>>> from frictionflow import BeltOscillator, Coulomb
>>> from frictionflow.orbits import find_orbit
>>> orbit = find_orbit(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04))
>>> orbit.stable, orbit.has_stick          # a stick phase: nontrivial multiplier 0
(True, True)

Modules: :mod:`.hybrid` (phases, switches, saltation matrices),
:mod:`.flow_exact` / :mod:`.flow_compiled` / :mod:`.flow_smooth` (flow maps
with their Jacobians: closed forms, compiled DOP853 with parameter
derivatives and work integrals, solve_ivp), :mod:`.sensitivity` (exact slopes
along branches; folds and grazings located by Newton), :mod:`.monitors`
(extrema of per-orbit quantities along branches, continued in a second
parameter), :mod:`.chart` (two-parameter stability charts),
:mod:`.shooting` (Newton on the Poincare map), :mod:`.floquet`,
:mod:`.equilibria`, :mod:`.tracing` (pseudo-arclength, any problem), :mod:`.continuation`,
:mod:`.brute_force` (simulations to overlay), :mod:`.plotting`; the forced
oscillator's orbits (period fixed by the forcing): :mod:`.forced`, :mod:`.forced_plot`,
and its monitors and (Omega, F_ex) charts: :mod:`.forced_chart`; structures with several masses and contacts:
:mod:`.structure` (shooting, multipliers) on :mod:`.structure_flow` (return map, exact monodromy); laws with
internal state on their whole state: :mod:`.stateful` (shooting, multipliers) on :mod:`.flow_stiff` (the stiff
flow with its variational equations), :mod:`.stateful_equilibria` (steady sliding, Hopf points),
:mod:`.stateful_cycles` (cycle branches) and :mod:`.stateful_continuation`.
"""

from .branches import Bifurcation, Branch, BranchPoint, ContinuationResult
from .continuation import continuation
from .floquet import fd_monodromy, multipliers
from .forced import ForcedBranch, ForcedOrbit, continue_forced, find_forced_orbit, stroboscopic_sweep, switch_period_doubling
from .forced_plot import plot_forced_branches
from . import chart_plot, plotting  # noqa: F401  (register the figures of the results' .plot())
from .flow import make_flow
from .hybrid import Phase, Segment, Switch, saltation
from .parameters import parameter_names, with_param
from .shooting import PeriodicOrbit, ShootingError, find_orbit, shoot
from .stateful import StatefulOrbit, find_stateful_orbit
from .stateful_equilibria import state_equilibrium, state_hopf_points
from .brute_force import sweep
from .structure import StructureOrbit, fd_structure_monodromy, find_structure_orbit
from .chart import StabilityChart, stability_chart, stability_map
from .monitors import FORCED_MONITORS, MONITORS, Extremum, branch_extrema, continue_extremum
from .forced_chart import ForcedChart, continue_forced_extremum, forced_branch_extrema, forced_chart, forced_map
from .settings import ContinuationSettings, ForcedContinuationSettings
from .sensitivity import OrbitDerivatives, locate_fold, locate_grazing, orbit_derivatives, stick_slip_grazing

__all__ = [
    "Bifurcation",
    "Branch",
    "branch_extrema",
    "BranchPoint",
    "continuation",
    "ContinuationResult",
    "ContinuationSettings",
    "continue_extremum",
    "continue_forced",
    "continue_forced_extremum",
    "Extremum",
    "fd_monodromy",
    "fd_structure_monodromy",
    "find_forced_orbit",
    "find_orbit",
    "find_stateful_orbit",
    "find_structure_orbit",
    "forced_branch_extrema",
    "forced_chart",
    "forced_map",
    "ForcedContinuationSettings",
    "FORCED_MONITORS",
    "ForcedBranch",
    "ForcedChart",
    "ForcedOrbit",
    "locate_fold",
    "locate_grazing",
    "make_flow",
    "MONITORS",
    "multipliers",
    "orbit_derivatives",
    "OrbitDerivatives",
    "parameter_names",
    "PeriodicOrbit",
    "Phase",
    "plot_forced_branches",
    "saltation",
    "Segment",
    "shoot",
    "ShootingError",
    "stability_chart",
    "state_equilibrium",
    "state_hopf_points",
    "StatefulOrbit",
    "stability_map",
    "StabilityChart",
    "stick_slip_grazing",
    "stroboscopic_sweep",
    "StructureOrbit",
    "sweep",
    "Switch",
    "switch_period_doubling",
    "with_param",
]
