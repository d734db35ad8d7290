"""Solvers: strategy objects over compiled kernels."""

from .base import CoarseStepWarning, Solver
from .rk4 import RK4

__all__ = ["CoarseStepWarning", "RK4", "Solver"]
