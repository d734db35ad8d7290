"""A model's entries by address: ``spring.1.k``, ``contact.0.belt``, ``contact.0.fd``, ``mass.1``, ``initial.q.x1``.

An address is the element's name, then its key: ``kind.index.key`` with the
keys of the model file (``k``, ``c``, ``belt``, a law's parameters,
``amplitude``, ``omega``, ``phi``), ``kind.index.on.DOF`` for a direction's
coefficient, ``contact.index.normal.preload`` and ``contact.index.normal.DOF``
for the normal load; ``mass.i`` is a diagonal entry and ``mass.i.j`` an
off-diagonal one (set in both triangles); ``initial.q.DOF`` and
``initial.v.DOF`` the initial state.  The functions work on the system's
:meth:`~frictionflow.system.System.to_dict` mapping, so that a changed entry
goes through the same checks as a file's.
"""

from __future__ import annotations

from typing import Any, Mapping

from .parse import KINDS

#: each kind's numeric keys besides ``on`` (a contact adds its law's parameters)
NUMERIC_KEYS = {"spring": ("k",), "damper": ("c",), "contact": ("belt",), "force": ("amplitude", "omega", "phi")}
KIND_ITEMS = {"spring": "springs", "damper": "dampers", "contact": "contacts", "force": "forces"}
NUMERIC_KINDS = ("real", "int")

Slot = tuple[list[tuple[Any, Any]], Any]


def addresses(system: Any) -> tuple[str, ...]:
    """The address of every numeric entry of ``system`` (directions: the dof they give; initial: every dof).

    Parameters
    ----------
    system:
        A :class:`~frictionflow.system.System`.
    """
    n = system.n
    out = [f"mass.{i}" for i in range(n)]
    if isinstance(system.mass[0], tuple):
        out += [f"mass.{i}.{j}" for i in range(n) for j in range(i + 1, n)]
    for kind in KINDS:
        for i, element in enumerate(getattr(system, KIND_ITEMS[kind])):
            name = f"{kind}.{i}"
            out += [f"{name}.{key}" for key in _numeric_keys(kind, element)]
            out += [f"{name}.on.{dof}" for dof, _ in element.on]
            if kind == "contact" and element.normal is not None:
                out += [f"{name}.normal.preload"] + [f"{name}.normal.{dof}" for dof, _ in element.normal.on]
    return tuple(out + [f"initial.{x}.{dof}" for x in ("q", "v") for dof in system.dof])


def value(system: Any, address: str) -> Any:
    """The value at ``address`` (a missing direction or initial entry: 0; no normal load: preload 1).

    Parameters
    ----------
    system:
        A :class:`~frictionflow.system.System`.
    address:
        The entry's address.
    """
    places, default = _slot(system, system.to_dict(), address)
    container, key = places[0]
    if isinstance(container, dict):
        return container.get(key, default)
    return container[key]


def replaced(system: Any, address: str, new: Any) -> dict[str, Any]:
    """``system.to_dict()`` with the entry at ``address`` set to ``new`` (checked when the system is rebuilt).

    Parameters
    ----------
    system:
        A :class:`~frictionflow.system.System`.
    address:
        The entry's address.
    new:
        Its new value.
    """
    return replaced_all(system, {address: new})


def replaced_all(system: Any, new: Mapping[str, Any]) -> dict[str, Any]:
    """``system.to_dict()`` with every entry of ``new`` (address -> value) set at once: checked together when the
    system is rebuilt, so that entries that limit each other (``fd`` and ``fs``) can move together.

    Parameters
    ----------
    system:
        A :class:`~frictionflow.system.System`.
    new:
        The addresses and their new values.
    """
    data = system.to_dict()
    for address, value in new.items():
        places, _ = _slot(system, data, address)
        for container, key in places:
            container[key] = value
    return data


def _numeric_keys(kind: str, element: Any) -> tuple[str, ...]:
    keys = NUMERIC_KEYS[kind]
    if kind == "contact":
        keys += tuple(p.name for p in element.law.parameters if p.kind in NUMERIC_KINDS)
    return keys


def _slot(system: Any, data: dict[str, Any], address: str) -> Slot:
    """Where ``address`` lives in ``data``: the (container, key) places it fills, and its value when missing."""
    if not isinstance(address, str):
        raise TypeError(f"an entry's address must be text, got {address!r}")
    parts = address.split(".")
    if parts[0] == "mass":
        return _mass_slot(system, data, address, parts[1:])
    if parts[0] == "initial":
        if len(parts) == 3 and parts[1] in ("q", "v") and parts[2] in system.dof:
            return [(data["initial"][parts[1]], parts[2])], 0.0
        raise ValueError(f"no entry {address!r}: the initial state's are initial.q.DOF and initial.v.DOF "
                         f"(dof: {', '.join(system.dof)})")
    if parts[0] in KINDS:
        items = data.get(parts[0], [])
        if len(parts) < 3 or not parts[1].isdigit() or int(parts[1]) >= len(items):
            names = ", ".join(f"{parts[0]}.{i}" for i in range(len(items))) or "none"
            raise ValueError(f"no entry {address!r}: its element does not exist ({parts[0]}: {names})")
        element = getattr(system, KIND_ITEMS[parts[0]])[int(parts[1])]
        return _element_slot(system, element, data[parts[0]][int(parts[1])], address, parts)
    raise ValueError(f"no entry {address!r}: an address starts with mass, {', '.join(KINDS)} or initial")


def _element_slot(system: Any, element: Any, table: dict[str, Any], address: str, parts: list[str]) -> Slot:
    kind, rest = parts[0], parts[2:]
    keys = NUMERIC_KEYS[kind] + (tuple(p.name for p in element.law.parameters) if kind == "contact" else ())
    if len(rest) == 1 and rest[0] in keys:
        # a law built from a function keeps its parameters in its object, not in the table
        return [(table, rest[0])], getattr(element.law, rest[0], None) if kind == "contact" else None
    if len(rest) == 2 and rest[0] == "on" and rest[1] in system.dof:
        return [(table["on"], rest[1])], 0.0
    if kind == "contact" and len(rest) == 2 and rest[0] == "normal" and (rest[1] == "preload" or rest[1] in system.dof):
        normal = table.setdefault("normal", {"preload": 1.0})  # N = 1 is the load without a normal-load table
        return [(normal, rest[1])], 0.0
    allowed = [*keys, "on.DOF"] + (["normal.preload", "normal.DOF"] if kind == "contact" else [])
    raise ValueError(f"no entry {address!r}: {parts[0]}.{parts[1]}'s entries are {', '.join(allowed)} "
                     f"(dof: {', '.join(system.dof)})")


def _mass_slot(system: Any, data: dict[str, Any], address: str, rest: list[str]) -> Slot:
    n = system.n
    index = [int(r) for r in rest if r.isdigit() and int(r) < n]
    if len(index) != len(rest) or len(rest) not in (1, 2):
        raise ValueError(f"no entry {address!r}: the mass's are mass.i (diagonal) and mass.i.j, 0 <= i, j < {n}")
    mass = data["mass"]
    full = isinstance(mass[0], list)
    if len(rest) == 1:
        return ([(mass[index[0]], index[0])] if full else [(mass, index[0])]), None
    i, j = index
    if not full:  # an off-diagonal entry makes the diagonal mass a full matrix
        data["mass"] = mass = [[mass[r] if r == c else 0.0 for c in range(n)] for r in range(n)]
    return [(mass[i], j), (mass[j], i)], None
