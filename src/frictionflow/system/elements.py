"""The elements of a linear structure with friction contacts: springs, dampers, contacts, forces, the initial state.

Each element acts along a direction e over the generalised coordinates q,
given as ``on``: the nonzero entries of e by dof name (missing entries are 0),
kept as (dof, coefficient) pairs in the system's dof order.  The records are
frozen and hashable; a :class:`~frictionflow.system.System` validates them
against its dof, naming each by its address (``spring.1.k``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from ..friction import FrictionLaw

Pairs = tuple[tuple[str, float], ...]


def pairs_of(value: Any) -> Any:
    """A mapping dof -> coefficient as a tuple of pairs (anything else unchanged, for the system to refuse).

    Parameters
    ----------
    value:
        A mapping, or (dof, coefficient) pairs already.
    """
    if isinstance(value, Mapping):
        return tuple((k, v) for k, v in value.items())
    if isinstance(value, list):
        return tuple(tuple(p) if isinstance(p, list) else p for p in value)
    return value


def vector(pairs: Pairs, dof: tuple[str, ...]) -> np.ndarray:
    """The coefficients as a float64 vector over ``dof`` (missing entries 0).

    Parameters
    ----------
    pairs:
        (dof, coefficient) pairs.
    dof:
        The system's dof names, in order.
    """
    given = dict(pairs)
    return np.array([float(given.get(name, 0.0)) for name in dof], dtype=np.float64)


@dataclass(frozen=True)
class Spring:
    """A spring: force -k (e^T q) along e.

    Parameters
    ----------
    on:
        The direction e: dof name -> coefficient (missing dof: 0).
    k:
        Stiffness k >= 0.
    """

    on: Pairs
    k: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "on", pairs_of(self.on))


@dataclass(frozen=True)
class Damper:
    """A viscous damper: force -c (e^T q') along e.

    Parameters
    ----------
    on:
        The direction e: dof name -> coefficient (missing dof: 0).
    c:
        Damping coefficient c >= 0.
    """

    on: Pairs
    c: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "on", pairs_of(self.on))


@dataclass(frozen=True)
class Normal:
    """A contact's normal load N = preload + n^T q (state dependent when n != 0).

    Parameters
    ----------
    preload:
        The load P at q = 0.
    on:
        The coefficients n: dof name -> coefficient (missing dof: 0).
    """

    preload: float
    on: Pairs = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "on", pairs_of(self.on))


@dataclass(frozen=True)
class Contact:
    """A friction contact along e on a belt moving at ``belt``: V_r = belt - e^T q'.

    Parameters
    ----------
    on:
        The direction e: dof name -> coefficient (missing dof: 0).
    belt:
        The belt speed b.
    law:
        The friction law with its parameters (a registered law's object, e.g. ``Coulomb(fd=0.3, fs=0.4)``).
    normal:
        The normal load (None: N = 1, and the law's levels are forces; otherwise they are coefficients).
    """

    on: Pairs
    belt: float
    law: FrictionLaw
    normal: Normal | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "on", pairs_of(self.on))

    @property
    def friction(self) -> str:
        """The law's registry name."""
        return self.law.name


@dataclass(frozen=True)
class Force:
    """A harmonic force amplitude cos(omega t + phi) along e.

    Parameters
    ----------
    on:
        The direction e: dof name -> coefficient (missing dof: 0).
    amplitude:
        Amplitude A >= 0.
    omega:
        Angular frequency Omega > 0.
    phi:
        Phase phi (rad).
    """

    on: Pairs
    amplitude: float
    omega: float
    phi: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "on", pairs_of(self.on))


@dataclass(frozen=True)
class Initial:
    """The initial state: displacements ``q`` and velocities ``v`` by dof name (missing: 0; a system keeps every dof).

    Parameters
    ----------
    q:
        q(0): dof name -> value.
    v:
        q'(0): dof name -> value.
    """

    q: Pairs = field(default=())
    v: Pairs = field(default=())

    def __post_init__(self) -> None:
        object.__setattr__(self, "q", pairs_of(self.q))
        object.__setattr__(self, "v", pairs_of(self.v))
