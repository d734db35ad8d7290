"""The checks of a model's entries, each naming the entry it refuses by its full address.

Every function raises ``ValueError`` with one line that starts with the
entry's address (``spring.1.k must be >= 0, got -2``); the system adds the
file in front (``model m.toml: ...``).  Text, booleans and None are not
numbers here, whatever Python would convert them to: in a model file they
are mistakes.
"""

from __future__ import annotations

import math
import re
from typing import Any, Mapping, Sequence

import numpy as np

from ..parameters import Param

#: a dof name: an identifier (addresses are dotted, and ``preload`` is the normal load's own key)
DOF_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
RESERVED = ("preload",)
#: the initial state's entries, by key, in words for the messages
INITIAL_BOUNDS = {"q": "initial displacement", "v": "initial velocity"}
#: contact directions are dependent when the smallest singular value of their unit vectors is below this share
#: of the largest (a relative tolerance: rounding in the written coefficients is far above it)
DEPENDENT_RTOL = 1e-9
#: a direction's nonzero coefficients lie within [1 / DIRECTION_MAX, DIRECTION_MAX] in magnitude: a contact along
#: 1e16 sticks within ~1e-33 of its start, far below the switch times' rounding (its mass then ends up 3e-9 from
#: where it stuck, not 4e-16), and below 1e-154 the products e M^-1 e underflow to zero
DIRECTION_MAX = 1e12
#: every number of a model file is at most this in magnitude (any consistent units: SI's stiffest contacts are
#: ~1e10 N/m).  Beyond, products the engine forms overflow (a preload or force of 1e300 stopped the run "stuck")
#: or the modes' scales part by more than double resolves (masses 1e30 and 1 made a mode defective)
MAGNITUDE_MAX = 1e15


def number(address: str, value: Any, allowed: str = "a finite number", limit: float | None = MAGNITUDE_MAX) -> float:
    """``value`` as a float; it must be a finite number (not text, a boolean or None) of magnitude at most
    ``limit``.

    Parameters
    ----------
    address:
        The entry's address, for the message (``spring.0.k``).
    value:
        The given value.
    allowed:
        The allowed values in words, for the message of a value that is no number at all.
    limit:
        The largest magnitude (None: the caller's own, narrower check follows and names the entry's range).
    """
    if isinstance(value, (bool, str)) or value is None:
        raise ValueError(f"{address} must be {allowed}, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{address} must be {allowed}, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{address} must be finite, got {value!r}")
    if limit is not None and abs(x) > limit:
        raise ValueError(f"{address} must be at most {limit:g} in magnitude (a model's numbers, in any "
                         f"consistent units), got {value!r}")
    return x


def nonnegative(address: str, value: Any) -> float:
    """A finite number >= 0 (a stiffness, a damping coefficient, an amplitude).

    Parameters
    ----------
    address:
        The entry's address, for the message.
    value:
        The given value.
    """
    x = number(address, value, "a finite number >= 0")
    if x < 0.0:
        raise ValueError(f"{address} must be >= 0, got {value!r}")
    return x


def positive(address: str, value: Any) -> float:
    """A finite number > 0 (a mass, a forcing frequency).

    Parameters
    ----------
    address:
        The entry's address, for the message.
    value:
        The given value.
    """
    x = number(address, value, "a finite number > 0")
    if x <= 0.0:
        raise ValueError(f"{address} must be > 0, got {value!r}")
    return x


def table(address: str, value: Any) -> Mapping[str, Any]:
    """``value``, which must be a table (a mapping with text keys).

    Parameters
    ----------
    address:
        The entry's address, for the message.
    value:
        The given value.
    """
    if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
        raise ValueError(f"{address} must be a table, got {value!r}")
    return value


def keys(address: str, given: Mapping[str, Any], allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> None:
    """Refuse a key of ``given`` outside ``allowed`` and a missing key of ``required``.

    Parameters
    ----------
    address:
        The table's address (``contact.0``), for the message.
    given:
        The table.
    allowed:
        Every key it may hold, listed by the message.
    required:
        The keys it must hold.
    """
    for key in given:
        if key not in allowed:
            raise ValueError(f"{address}: unknown key {key!r} (allowed: {', '.join(allowed)})")
    missing = [key for key in required if key not in given]
    if missing:
        raise ValueError(f"{address}: missing {', '.join(missing)} (required: {', '.join(required)})")


def dof_names(value: Any) -> tuple[str, ...]:
    """The dof list: at least one name, each an identifier other than ``preload``, none twice.

    Parameters
    ----------
    value:
        The given ``dof`` (a list of text).
    """
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"dof must be a non-empty list of names, got {value!r}")
    seen: set[str] = set()
    for i, name in enumerate(value):
        if not isinstance(name, str) or not DOF_NAME.fullmatch(name) or name in RESERVED:
            raise ValueError(f"dof.{i} must be a name (letters, digits, _; not {', '.join(RESERVED)}), got {name!r}")
        if name in seen:
            raise ValueError(f"dof: duplicate dof {name!r}")
        seen.add(name)
    return tuple(value)


def coefficients(address: str, value: Any, dof: tuple[str, ...], where: str,
                 limit: float | None = MAGNITUDE_MAX) -> tuple[tuple[str, float], ...]:
    """A table dof -> finite coefficient as (dof, value) pairs in dof order, each at most ``limit`` in magnitude
    (:func:`number`).

    Parameters
    ----------
    address:
        The owning element's address (``spring.1``), for the message.
    value:
        The given table (a mapping, or (dof, value) pairs).
    dof:
        The system's dof names.
    where:
        The entry the table is (``on``, ``normal``, ``initial.q``), for the message.
    limit:
        The largest magnitude of a coefficient (None: the caller checks its own range).
    """
    given = _as_table(f"{address}.{where}", value)
    for key in given:
        if key not in dof:
            raise ValueError(f"{address}: unknown dof {key!r} (dof: {', '.join(dof)}) in {where}")
    return tuple((name, number(f"{address}.{where}.{name}", given[name], limit=limit)) for name in dof if name in given)


def _as_table(address: str, value: Any) -> Mapping[str, Any]:
    """A table given as a mapping or as (key, value) pairs (how the element records keep it)."""
    if isinstance(value, (tuple, list)):
        try:
            value = dict(value)
        except (TypeError, ValueError):
            raise ValueError(f"{address} must be a table, got {value!r}") from None
    return table(address, value)


def direction(address: str, value: Any, dof: tuple[str, ...]) -> tuple[tuple[str, float], ...]:
    """An element's direction ``on``: :func:`coefficients` of which at least one is nonzero, each nonzero one
    within [1 / :data:`DIRECTION_MAX`, :data:`DIRECTION_MAX`] in magnitude.

    Parameters
    ----------
    address:
        The element's address (``damper.0``), for the message.
    value:
        The given ``on`` table.
    dof:
        The system's dof names.
    """
    pairs = coefficients(address, value, dof, "on", limit=None)  # DIRECTION_MAX below
    if not any(c != 0.0 for _, c in pairs):
        raise ValueError(f"{address}.on must have a nonzero entry over the dof ({', '.join(dof)}): a zero-length "
                         f"direction, got {dict(pairs)!r}")
    for name, c in pairs:
        if c != 0.0 and not 1.0 / DIRECTION_MAX <= abs(c) <= DIRECTION_MAX:
            raise ValueError(f"{address}.on.{name} must be 0 or within {1.0 / DIRECTION_MAX:g} <= |value| <= "
                             f"{DIRECTION_MAX:g} (beyond, switch times lose the motion to rounding), got {c!r}")
    return pairs


def initial(address: str, key: str, pairs: tuple[tuple[str, float], ...]) -> tuple[tuple[str, float], ...]:
    """The initial state's entries of ``key`` (``q`` or ``v``) within [-MAGNITUDE_MAX, MAGNITUDE_MAX], the range of
    every number of a model file, each refused by its address.  (The single mass's own range, 1e6, refused a
    start the model's belts could reach: a chain in nanoseconds rides its belt at 5e7.)

    Parameters
    ----------
    address:
        ``initial``, for the message (``initial.v.x1 must be ...``).
    key:
        ``q`` or ``v``.
    pairs:
        The (dof, value) pairs, already finite numbers (:func:`coefficients`).
    """
    what = INITIAL_BOUNDS[key]
    return tuple((name, Param(f"{address}.{key}.{name}", "", what, "run", 0.0, lower=-MAGNITUDE_MAX,
                              upper=MAGNITUDE_MAX, subnormal_ok=True).check(x)) for name, x in pairs)


def independent(named: Sequence[tuple[str, np.ndarray]],
                reason: str = "contacts along dependent directions are not supported") -> None:
    """Refuse directions that are linearly dependent, naming the first one that is a combination of earlier ones.

    Two stuck contacts along dependent directions hold forces that no equation fixes (only their combination
    is), so the switching engines cannot hold them; the rank is judged on unit vectors with
    :data:`DEPENDENT_RTOL`.

    Parameters
    ----------
    named:
        (address, direction over the dof) per element, in file order (directions nonzero).
    reason:
        Why dependence is refused, for the message.
    """
    units = [_unit(np.asarray(v, dtype=float)) for _, v in named]
    if not units:
        return
    s = np.linalg.svd(np.array(units), compute_uv=False)
    tol = DEPENDENT_RTOL * s[0]
    if np.count_nonzero(s > tol) == len(units):  # the usual case: one decomposition
        return
    basis: list[int] = []
    for j, (address, v) in enumerate(named):
        if _rank(np.array([units[i] for i in basis] + [units[j]]), tol) > len(basis):
            basis.append(j)
            continue
        weights = np.linalg.lstsq(np.array([named[i][1] for i in basis]).T, v, rcond=None)[0]
        used = [named[i][0] for i, w in zip(basis, weights) if abs(w) > DEPENDENT_RTOL * np.abs(weights).max()]
        of = f"{used[0]}'s" if len(used) == 1 else f"those of {', '.join(used[:-1])} and {used[-1]}"
        raise ValueError(f"{address}: its direction is {'a multiple' if len(used) == 1 else 'a combination'} of {of}: "
                         f"{reason} (stuck together, their forces are indeterminate); merge them into one contact "
                         f"(e.g. two Coulomb contacts along one direction on one belt: fd = fd0 + fd1, fs = fs0 + fs1)")
    names = ", ".join(address for address, _ in named)  # dependent as a whole only (at the tolerance's edge)
    raise ValueError(f"the directions of {names} are nearly dependent: {reason} (stuck together, their forces are "
                     f"indeterminate)")


def _unit(v: np.ndarray) -> np.ndarray:
    """``v`` / |v|, scaled by its largest entry first (|v| of 1e-200 or 1e200 entries under- or overflows)."""
    scaled = v / np.max(np.abs(v))
    return scaled / np.linalg.norm(scaled)


def _rank(rows: np.ndarray, tol: float) -> int:
    """The rank of ``rows``: their singular values above ``tol``."""
    return int(np.count_nonzero(np.linalg.svd(rows, compute_uv=False) > tol))
