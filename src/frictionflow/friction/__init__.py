"""Friction laws."""

from .base import STICK_FORCES, FrictionLaw
from .coulomb import Coulomb
from .karnopp import Karnopp
from .stribeck import SlipLaw, Stribeck

__all__ = ["STICK_FORCES", "Coulomb", "FrictionLaw", "Karnopp", "SlipLaw", "Stribeck"]
