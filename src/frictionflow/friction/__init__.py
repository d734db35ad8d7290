"""Friction laws, one module each, registered by name (:mod:`.registry`)."""

from .base import STICK_FORCES, STICK_RULES, FrictionLaw
from .karnopp import Karnopp  # noqa: I001  (registration order: the CLI lists laws in it)
from .coulomb import Coulomb
from .stribeck import Stribeck
from .cubic import Cubic
from .user import SlipLaw
from .lugre import LuGre
from .dahl import Dahl
from .elastoplastic import ElastoPlastic
from .rate_state import RateState
from .registry import law_class, law_classes, law_names, register

__all__ = [
    "STICK_FORCES", "STICK_RULES", "Coulomb", "Cubic", "Dahl", "ElastoPlastic", "FrictionLaw", "Karnopp", "LuGre", "RateState", "SlipLaw", "Stribeck",
    "law_class", "law_classes", "law_names", "register",
]
