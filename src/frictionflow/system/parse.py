"""A model's mapping (a TOML file's tables, or the same through the API) read into element records.

This module checks the mapping's shape -- which keys a table may and must
hold, that the kinds are arrays of tables, the friction law and its own
parameters -- and leaves the numbers to :class:`~frictionflow.system.System`,
which checks every entry against its dof.  Messages start with the entry's
address; the system puts the file in front.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

from ..friction import FrictionLaw
from ..friction.base import STICK_RULE_WORDS
from ..friction.registry import law_class, law_names
from ..parameters import MODEL_MAX, Param
from . import checks
from .elements import Contact, Damper, Force, Initial, Normal, Spring

#: the kinds of element, by their key in a model file (``[[spring]]``) and in element names (``spring.0``)
KINDS = ("spring", "damper", "contact", "force")
TOP_KEYS = ("dof", "mass", *KINDS, "initial")
SPRING_KEYS = ("on", "k")
DAMPER_KEYS = ("on", "c")
CONTACT_KEYS = ("on", "belt", "friction", "normal")
FORCE_KEYS = ("on", "amplitude", "omega", "phi")
INITIAL_KEYS = ("q", "v")


def fields(data: Any) -> dict[str, Any]:
    """The keyword arguments of :class:`~frictionflow.system.System` that ``data`` describes.

    Parameters
    ----------
    data:
        The model's mapping: ``dof``, ``mass``, the arrays of tables ``spring``, ``damper``,
        ``contact``, ``force`` and the table ``initial`` (see :doc:`/guide/models`).
    """
    data = checks.table("the model", data)
    checks.keys("top level", data, TOP_KEYS, ("dof", "mass"))
    mass = data["mass"]
    if isinstance(mass, (list, tuple)) and mass and all(isinstance(row, (list, tuple)) for row in mass):
        mass = tuple(tuple(row) for row in mass)
    elif isinstance(mass, list):
        mass = tuple(mass)
    return {
        "dof": tuple(data["dof"]) if isinstance(data["dof"], list) else data["dof"],
        "mass": mass,
        "springs": tuple(_spring(f"spring.{i}", t) for i, t in enumerate(_items(data, "spring"))),
        "dampers": tuple(_damper(f"damper.{i}", t) for i, t in enumerate(_items(data, "damper"))),
        "contacts": tuple(_contact(f"contact.{i}", t) for i, t in enumerate(_items(data, "contact"))),
        "forces": tuple(_force(f"force.{i}", t) for i, t in enumerate(_items(data, "force"))),
        "initial": _initial(data.get("initial", {})),
    }


def _items(data: Mapping[str, Any], kind: str) -> list[Mapping[str, Any]]:
    """The tables of one kind (none when the key is missing), each checked to be a table."""
    items = data.get(kind, [])
    if isinstance(items, (str, bytes, Mapping)) or not isinstance(items, (list, tuple)):
        raise ValueError(f"{kind} must be an array of tables ([[{kind}]]), got {items!r}")
    return [checks.table(f"{kind}.{i}", item) for i, item in enumerate(items)]


def _spring(address: str, t: Mapping[str, Any]) -> Spring:
    checks.keys(address, t, SPRING_KEYS, SPRING_KEYS)
    return Spring(on=t["on"], k=t["k"])


def _damper(address: str, t: Mapping[str, Any]) -> Damper:
    checks.keys(address, t, DAMPER_KEYS, DAMPER_KEYS)
    return Damper(on=t["on"], c=t["c"])


def _force(address: str, t: Mapping[str, Any]) -> Force:
    checks.keys(address, t, FORCE_KEYS, FORCE_KEYS[:3])
    return Force(on=t["on"], amplitude=t["amplitude"], omega=t["omega"], phi=t.get("phi", 0.0))


def _initial(t: Any) -> Initial:
    t = checks.table("initial", t)
    checks.keys("initial", t, INITIAL_KEYS)
    return Initial(q=checks.table("initial.q", t.get("q", {})), v=checks.table("initial.v", t.get("v", {})))


def _contact(address: str, t: Mapping[str, Any]) -> Contact:
    """A contact: its direction, belt, normal load and its law built from the law's own parameters."""
    cls = _law_class(address, t.get("friction"))
    names = tuple(p.name for p in cls.parameters)
    checks.keys(address, t, CONTACT_KEYS + names, CONTACT_KEYS[:3])
    given = {name: t[name] for name in names if name in t}
    if isinstance(t["friction"], FrictionLaw):
        law = t["friction"] if not given else _law(address, cls, {**t["friction"].values(), **given})
    else:
        law = _law(address, cls, given)
    return Contact(on=t["on"], belt=t["belt"], law=law, normal=_normal(address, t.get("normal")))


def _law_class(address: str, friction: Any) -> type[FrictionLaw]:
    """The law's class from its registry name (or from a law object given through the API).

    A name must be one of :func:`structure_laws`: a law with an internal state has no place in a structure's state
    (its coordinates and velocities only), and one without Coulomb's stick rule (Karnopp's stick band) no
    structure solver runs: it would be refused only when the model runs.  A law object is the Python API's:
    it must be without an internal state (a solver that does not run it names the contact when the model runs).
    """
    cls = None
    if isinstance(friction, FrictionLaw):
        cls = type(friction)
    elif friction is None:
        raise ValueError(f"{address}: missing friction (required: {', '.join(CONTACT_KEYS[:3])})")
    elif isinstance(friction, str) and friction in law_names():
        cls = law_class(friction)
    runnable = ", ".join(structure_laws())
    if cls is None:
        raise ValueError(f"{address}.friction must be one of {runnable} (the laws a structure's contacts take), "
                         f"got {friction!r}")
    if cls.internal_names:
        raise ValueError(f"{address}.friction: {cls.name} has an internal state ({', '.join(cls.internal_names)}); "
                         f"a structure's contacts take the laws without one, with Coulomb's stick rule: {runnable}")
    if not isinstance(friction, FrictionLaw) and cls.stick_rule != "switch":
        raise ValueError(f"{address}.friction: {cls.name} has {STICK_RULE_WORDS[cls.stick_rule]}, which no structure "
                         f"solver runs; a structure's contacts take the laws with Coulomb's stick rule: {runnable}")
    return cls


def structure_laws() -> tuple[str, ...]:
    """The registered laws a model's contact may name (registry order): those with Coulomb's stick rule and no
    internal state -- a stuck contact is the constraint V_r = 0 the structure engines switch on, and a structure's
    state is its coordinates and velocities only.  (The structure solvers declare the laws they run,
    ``Solver.structure_laws``; a test holds this rule to them.)"""
    return law_names(where=lambda c: c.stick_rule == "switch" and not c.internal_names)


def _law(address: str, cls: type[FrictionLaw], given: Mapping[str, Any]) -> FrictionLaw:
    """The law from its parameters, its own checks' messages naming the contact's entry."""
    if not cls.configurable:
        raise ValueError(f"{address}: the law {cls.name!r} is built from a function: give its object as friction")
    try:
        return cls.from_values(given, in_model_units(cls.parameters))
    except (ValueError, TypeError) as e:
        text = str(e)
        first = text.split(" ", 1)[0]
        raise type(e)(f"{address}.{text}" if first in {p.name for p in cls.parameters} else f"{address}: {text}") from None


def in_model_units(params: tuple[Param, ...]) -> tuple[Param, ...]:
    """A law's parameter declarations for a model file's values: a number capped by the nondimensional single
    mass's :data:`~frictionflow.parameters.MODEL_MAX` (a force, a speed, a coefficient) may reach the model's
    :data:`~.checks.MAGNITUDE_MAX` (any consistent units: 1e5 N of friction); narrower caps (an exponent's)
    and every lower end are kept."""
    return tuple(replace(p, upper=checks.MAGNITUDE_MAX) if p.kind == "real" and p.upper is not None
                 and p.upper >= MODEL_MAX else p for p in params)


def _normal(address: str, t: Any) -> Normal | None:
    """The normal load's table: ``preload`` and the coefficients by dof."""
    if t is None:
        return None
    if isinstance(t, Normal):
        return t
    t = checks.table(f"{address}.normal", t)
    if "preload" not in t:
        raise ValueError(f"{address}.normal: missing preload (required: preload; then coefficients by dof)")
    return Normal(preload=t["preload"], on={k: v for k, v in t.items() if k != "preload"})
