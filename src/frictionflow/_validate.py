"""Argument checks shared by the API and the CLI.

Every check raises ``ValueError`` with one line that names the parameter and
the range it must lie in; the CLI prints that line and exits with code 2.
"""

from __future__ import annotations

import math

import numpy as np


def finite(name: str, value: float, allowed: str = "a finite real number") -> float:
    """Return ``value`` as a float; it must be a finite real number."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {allowed}, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be {allowed}, got {value!r}")
    return x


def number(name: str, value: object, allowed: str = "a finite real number") -> float:
    """:func:`finite`, refusing what only converts to a number: a boolean, text, None."""
    if isinstance(value, (bool, str)) or value is None:
        raise ValueError(f"{name} must be {allowed}, got {value!r}")
    return finite(name, value, allowed)  # type: ignore[arg-type]


def real(name: str, value: object, allowed: str = "a real number") -> float:
    """``value`` as a float (its range is the caller's to check: NaN and inf pass); a ValueError naming ``name``
    for a boolean, text, None or anything else ``float`` refuses.  Numpy scalars and 0-d arrays are numbers."""
    if isinstance(value, (bool, np.bool_, str)) or value is None:
        raise ValueError(f"{name} must be {allowed}, got {value!r}")
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {allowed}, got {value!r}") from None


def nonnegative(name: str, value: float) -> float:
    """A finite number >= 0."""
    x = finite(name, value, "finite and >= 0")
    if x < 0:
        raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
    return x


def positive(name: str, value: float) -> float:
    """A finite number > 0."""
    x = finite(name, value, "finite and > 0")
    if x <= 0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return x


def at_least(name: str, value: float, lower: float, lower_name: str) -> float:
    """A finite number >= ``lower`` (whose name is quoted in the message)."""
    x = finite(name, value, f"finite and >= {lower_name}")
    if x < lower:
        raise ValueError(f"{name} must be >= {lower_name} = {lower:g}, got {value!r}")
    return x


def positive_int(name: str, value: int) -> int:
    """An integer >= 1 (a whole float or a numpy integer too), returned as an int."""
    try:
        whole = not isinstance(value, (bool, np.bool_, str)) and float(value).is_integer()  # type: ignore[arg-type]
    except (TypeError, ValueError):
        whole = False
    if not whole or int(value) < 1:  # type: ignore[arg-type]
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)  # type: ignore[arg-type]


def choice(name: str, value: str, allowed: tuple[str, ...]) -> str:
    """One of ``allowed``."""
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(allowed)}, got {value!r}")
    return value


def instance(name: str, value: object, kind: type, what: str) -> None:
    """Refuse ``value`` unless it is a ``kind``: a TypeError naming the argument and what it must be (``what``, e.g.
    "a Trajectory (from simulate)"), not an AttributeError from deep inside."""
    if not isinstance(value, kind):
        raise TypeError(f"{name} must be {what}, got {type(value).__name__}")
