"""The one range syntax of the command line and the configs: ``FROM:TO:N`` (N values from FROM to TO).

Every option or TOML value that is a range of a parameter is written so;
``NAME=FROM:TO:N`` names the parameter where the option does not.  Whether
N must, may or must not be given is the caller's (a sample's range has no N,
a continuation chooses its own points).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: whether a range's N is ``required``, ``optional`` or refused (``none``)
COUNTS = ("required", "optional", "none")


@dataclass(frozen=True)
class Range:
    """FROM, TO and (if given) N of a range."""

    start: float
    stop: float
    num: int | None = None

    def text(self) -> str:
        """The range as it is written."""
        return f"{self.start:g}:{self.stop:g}" + ("" if self.num is None else f":{self.num}")

    def grid(self, num: int) -> np.ndarray:
        """``num`` evenly spaced values from FROM to TO, each within two units in the last place of a decimal of
        12 digits taken as that decimal (0.5:0.8:7 holds 0.7, not 0.7000000000000001, which a bound such as
        F_s = 0.7 would refuse; 0:1:4 keeps 1/3's nearest float)."""
        return decimal_values(np.linspace(self.start, self.stop, num))


def decimal_values(values: np.ndarray) -> np.ndarray:
    """``values`` with each one within two units in the last place of a decimal of 12 digits replaced by that
    decimal: a grid's values as its range implies them (:meth:`Range.grid`; the sweep's axes alike)."""
    values = np.asarray(values, dtype=float)
    snapped = np.array([float(f"{v:.12g}") for v in values.ravel()]).reshape(values.shape)
    close = np.abs(snapped - values) <= 2.0 * np.spacing(np.abs(values))
    return np.where(close, snapped, values)


def syntax(count: str) -> str:
    """How a range with this ``count`` rule is written, for help texts and messages."""
    return {"required": "FROM:TO:N", "optional": "FROM:TO[:N]", "none": "FROM:TO"}[count]


def parse_range(name: str, text: str, count: str = "required", least: int = 1) -> Range:
    """``FROM:TO:N`` -> :class:`Range` (N >= ``least``); ValueError naming ``name`` (the option or key) and the syntax
    otherwise."""
    if count not in COUNTS:
        raise ValueError(f"count must be one of {', '.join(COUNTS)}, got {count!r}")
    want = syntax(count)
    parts = str(text).split(":")
    allowed = {"required": (3,), "optional": (2, 3), "none": (2,)}[count]
    if len(parts) not in allowed:
        raise ValueError(f"{name} must be {want}, got {text!r}")
    try:
        start, stop = float(parts[0]), float(parts[1])
        num = int(parts[2]) if len(parts) == 3 else None
    except ValueError:
        raise ValueError(f"{name} must be {want} with numbers (N an integer), got {text!r}") from None
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise ValueError(f"{name} must be {want} with finite FROM and TO, got {text!r}")
    if num is not None and num < least:
        raise ValueError(f"{name}: N must be >= {least}, got {text!r}")
    return Range(start, stop, num)


def parse_named_range(name: str, text: str, count: str = "required", least: int = 1) -> tuple[str, Range]:
    """``NAME=FROM:TO:N`` -> (NAME with underscores, :class:`Range` with N >= ``least``); ValueError naming ``name``
    otherwise."""
    key, sep, rest = str(text).partition("=")
    key = key.strip().replace("-", "_")
    if not sep or not key:
        raise ValueError(f"{name} must be NAME={syntax(count)} (e.g. vb=0.01:0.03{':21' if count != 'none' else ''}), got {text!r}")
    return key, parse_range(f"{name} {key}", rest.strip(), count, least)
