"""The friction laws by name: what the CLI, configs, sweeps and orbits look laws up in.

A law registers itself with :func:`register` (a class decorator) in its own
module; :mod:`frictionflow.friction` imports every built-in law's module.
Nothing outside this package names a law.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

from ..parameters import declare

if TYPE_CHECKING:
    from .base import FrictionLaw

_LAWS: dict[str, type["FrictionLaw"]] = {}


#: the default law of commands that need Coulomb's stick rule (the run's default, Karnopp, has a velocity band)
SWITCH_LAW = "coulomb"
#: ... and of those that need a smooth falling slip curve too (Hopf points, stability charts)
SMOOTH_SWITCH_LAW = "stribeck"


def register(cls: type["FrictionLaw"]) -> type["FrictionLaw"]:
    """Class decorator: make ``cls`` available by its ``name`` (``--friction NAME``)."""
    if cls.name in _LAWS and _LAWS[cls.name] is not cls:
        raise ValueError(f"a friction law named {cls.name!r} is registered already")
    if cls.name not in _LAWS:
        declare(cls.parameters, cls.name)  # its parameters join the declared ones (its name: in their help)
    _LAWS[cls.name] = cls
    return cls


def law_names(configurable: bool = True, where: Callable[[type["FrictionLaw"]], bool] | None = None) -> tuple[str, ...]:
    """Names of the registered laws, in the order they were registered.

    Parameters
    ----------
    configurable:
        Only those a config or the command line can build (not ``SlipLaw``, which takes a function).
    where:
        Only those whose class passes this test, e.g. ``lambda law: law.has_tangent_kernel`` (for messages).
    """
    return tuple(n for n, c in _LAWS.items() if (c.configurable or not configurable) and (where is None or where(c)))


def tangent_law_names() -> tuple[str, ...]:
    """The configurable laws the tangent and flow-map kernels run (``has_tangent_kernel``), for messages and help."""
    return law_names(where=lambda law: law.has_tangent_kernel)


def switch_law_names() -> tuple[str, ...]:
    """The configurable laws with Coulomb's stick rule (``stick_rule == "switch"``), for messages and help."""
    return law_names(where=lambda law: law.stick_rule == "switch")


def law_classes() -> tuple[type["FrictionLaw"], ...]:
    return tuple(_LAWS.values())


def law_class(name: str) -> type["FrictionLaw"]:
    """The law registered as ``name``; ValueError listing the names otherwise.

    Parameters
    ----------
    name:
        A name of :func:`law_names` (``karnopp``, ``coulomb``, ...).
    """

    cls = _LAWS.get(name)
    if cls is None or not cls.configurable:
        raise ValueError(f"friction must be one of {', '.join(law_names())}, got {name!r}")
    return cls
