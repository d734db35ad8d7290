"""``solver="auto"``: exact for piecewise-constant laws, adaptive otherwise."""

from .registry import auto_solver

__all__ = ["auto_solver"]
