"""Solvers: strategy objects over compiled kernels.

=============  =============================================================
``Exact``      switch to switch in closed form (Karnopp, Coulomb): the default
``Adaptive``   Dormand-Prince 5(4), switches located (Stribeck, user laws)
``RK4``        fixed-step classical RK4 through a stick band (the paper's method)
``Stiff``      Rodas4 on the whole state, for laws with internal state (LuGre)
=============  =============================================================
"""

from .adaptive import Adaptive, StepLimitError
from .auto import auto_solver
from .base import CoarseStepWarning, Solver
from .exact import Exact
from .rk4 import RK4
from .stiff import Stiff

__all__ = ["Adaptive", "CoarseStepWarning", "Exact", "RK4", "Solver", "Stiff", "StepLimitError", "auto_solver"]
