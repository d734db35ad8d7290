"""Friction laws."""

from .base import STICK_FORCES, FrictionLaw
from .karnopp import Karnopp

__all__ = ["STICK_FORCES", "FrictionLaw", "Karnopp"]
