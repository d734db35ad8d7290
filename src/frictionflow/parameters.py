"""Every parameter declared once: name, symbol, meaning, unit, default, allowed range and owner.

A :class:`Param` is the single source for everything said about a parameter:
validation (``check``, one-line ``ValueError`` naming it and its range), the
CLI option (``--name``, its help), the TOML key (its ``name``), whether it can
be a sweep axis, the JSON ``params`` and the xarray attributes (``units``,
``long_name``).  The owners declare their own parameters -- the oscillator in
:mod:`frictionflow.params`, each friction law in its module, each solver in
its module, the run in :mod:`frictionflow.config` -- and :func:`declared`
collects them; nothing else lists parameter names.

A default is a value, or a function of the other values of the same owner
(``fs`` defaults to ``fd``): it then works on scalars and on the per-point
arrays of a sweep alike.
"""

from __future__ import annotations

import math
import numbers
import sys
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Mapping

import numpy as np

OWNERS = ("oscillator", "law", "solver", "run")
#: The model is non-dimensional (natural frequency 1, forces in units of k l_0):
#: coefficients beyond MODEL_MAX and states beyond STATE_MAX describe nothing
#: physical, and their products in the power balance would approach overflow.
MODEL_MAX = 1e3
STATE_MAX = 1e6
KINDS = ("real", "int", "choice", "text")
#: a parameter's physical dimension: how ``--dimensional`` input converts to it (paper Eq. 3: time by omega0 = sqrt(k/m),
#: length by l_0, force by k l_0); "none" for a dimensionless parameter (given as is, never converted)
DIMENSIONS = ("none", "force", "length", "velocity", "stiffness", "damping", "frequency", "angle")
#: the smallest positive normal float: a nonzero value below it in magnitude is subnormal
SUBNORMAL_BELOW = sys.float_info.min


@dataclass(frozen=True)
class Param:
    """One parameter.

    Attributes
    ----------
    name:
        Key in the API, configs, sweep grids and JSON (``t_end``); the CLI option is ``--t-end``.
    symbol, meaning, unit:
        For help texts and the xarray attributes (``long_name = "meaning symbol"``).
    owner:
        ``oscillator``, ``law``, ``solver`` or ``run``.
    default:
        A value, a function of the owner's other (resolved) values, or None (none: optional).
    default_text:
        How the default reads in help texts (by default ``str(default)``).
    lower, upper, lower_open, upper_open:
        The allowed range of a ``real`` or ``int`` (None: unbounded; ``real`` is always finite).
    kind:
        ``real``, ``int``, ``choice`` (one of ``choices``) or ``text`` (free text, parsed by its owner).
    choices:
        For a ``choice``, the values allowed (a law's or a solver's registry names, ...), as the help lists
        them; empty for the other kinds.
    sweepable:
        Whether it can be a sweep axis (every ``real`` of the oscillator, a law or the initial state).
    report:
        Whether it appears in the JSON ``params`` of a run.
    subnormal_ok:
        Whether a subnormal ``real`` (0 < |x| < 2.2e-308) is a value like any other (a state: as good as 0).
        Otherwise it is refused as degenerate: a time, a step, a rate or a coefficient that small has lost
        its precision, and the work built on it does not exist (its products underflow to 0, its reciprocals
        overflow: a forcing period or a sample count of inf).
    """

    name: str
    symbol: str
    meaning: str
    owner: str
    default: Any = None
    default_text: str | None = None
    lower: float | None = None
    upper: float | None = None
    lower_open: bool = False
    upper_open: bool = False
    kind: str = "real"
    choices: tuple[str, ...] = ()
    unit: str = "1"
    sweepable: bool = False
    report: bool = True
    subnormal_ok: bool = False
    #: for ``text``, turns the given value (text, or a TOML list/table) into the setting
    parse: Callable[[Any], Any] | None = None
    #: one of ``DIMENSIONS``
    dimension: str = "none"
    #: its key in a ``dimensional`` table (by default ``name``; ``v_b`` for ``vb``)
    dimensional_name: str | None = None
    #: the other ranges declared under this name, (range, owners), that the help states beside this one
    #: (``declared()`` fills it; not part of the parameter's identity)
    variants: tuple[tuple[str, tuple[str, ...]], ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        if self.owner not in OWNERS or self.kind not in KINDS or self.dimension not in DIMENSIONS:
            raise ValueError(f"{self.name}: owner must be one of {OWNERS}, kind one of {KINDS} and dimension one of "
                             f"{DIMENSIONS}")

    # -- validation ------------------------------------------------------------
    @property
    def allowed(self) -> str:
        """The allowed values in words, as error messages and help texts say them."""
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        if self.kind == "text":
            return "text"
        base = "an integer" if self.kind == "int" else "finite"
        lo, hi = self.lower, self.upper
        if lo is not None and hi is not None:
            return f"{base} and in {'(' if self.lower_open else '['}{lo:g}, {hi:g}{')' if self.upper_open else ']'}"
        if lo is not None:
            return f"{base} and {'>' if self.lower_open else '>='} {lo:g}"
        if hi is not None:
            return f"{base} and {'<' if self.upper_open else '<='} {hi:g}"
        return "an integer" if self.kind == "int" else "a finite real number"

    def check(self, value: Any) -> Any:
        """``value`` converted and validated; ValueError naming this parameter otherwise."""
        if self.kind == "choice":
            if value not in self.choices:
                raise ValueError(f"{self.name} must be {self.allowed}, got {value!r}")
            return value
        if self.kind == "text":
            if self.parse is not None:
                return self.parse(value)
            if not isinstance(value, str):
                raise ValueError(f"{self.name} must be text, got {value!r}")
            return value
        x = self._number(value)
        if (self.lower is not None and (x < self.lower or (self.lower_open and x == self.lower))) or (
            self.upper is not None and (x > self.upper or (self.upper_open and x == self.upper))
        ):
            raise self._bad(value)
        if self.kind == "real" and not self.subnormal_ok and x != 0.0 and abs(x) < SUBNORMAL_BELOW:
            raise ValueError(f"{self.name} must be {self.allowed}, got {value!r}: a subnormal number (0 < |x| < "
                             f"{SUBNORMAL_BELOW:.3g}) makes the work degenerate (its products underflow to 0)")
        return x

    def _number(self, value: Any) -> float | int:
        if isinstance(value, (bool, np.bool_, str)) or value is None:
            raise self._bad(value)  # true/"10" in a config are mistakes, not numbers
        if self.kind == "int" and isinstance(value, numbers.Integral):
            return int(value)  # exactly: through a float, 2^63 - 1 would be 2^63 and 2^53 + 1 would be 2^53
        try:
            x = float(value)
        except (TypeError, ValueError):
            raise self._bad(value) from None
        if not math.isfinite(x) or (self.kind == "int" and not x.is_integer()):
            raise self._bad(value)
        return int(x) if self.kind == "int" else x

    def _bad(self, value: Any) -> ValueError:
        return ValueError(f"{self.name} must be {self.allowed}, got {value!r}")

    @property
    def dimensional_key(self) -> str | None:
        """Its key in a ``dimensional`` table; None for a dimensionless parameter (never converted)."""
        return None if self.dimension == "none" else (self.dimensional_name or self.name)

    # -- defaults ----------------------------------------------------------------
    def default_for(self, values: Mapping[str, Any]) -> Any:
        """The default given the owner's other resolved values."""
        return self.default(values) if callable(self.default) else self.default

    # -- presentation ------------------------------------------------------------
    @property
    def flag(self) -> str:
        return "--" + self.name.replace("_", "-")

    @property
    def long_name(self) -> str:
        return f"{self.meaning} {self.symbol}".strip()

    @property
    def attrs(self) -> dict[str, str]:
        """xarray attributes of a variable or coordinate holding this parameter."""
        return {"units": self.unit, "long_name": self.long_name}

    @property
    def range_text(self) -> str | None:
        """The allowed range as the help says it (``in (0, 100]``, ``>= 0``); None for an unbounded number or
        a choice or text."""
        if self.kind not in ("real", "int") or self.allowed in ("a finite real number", "an integer"):
            return None
        return self.allowed.removeprefix("finite and ").removeprefix("an integer and ")

    def narrowed(self, **bounds: Any) -> "Param":
        """The same parameter with a narrower range (``lower``, ``upper``, ``lower_open``, ``upper_open``) for
        an owner that refuses part of the shared one (LuGre's delta >= 1); ValueError if it is not narrower."""
        out = replace(self, **bounds)
        # the shared declaration must stay the widest: it checks a value before the law is known
        if not (_within(out.lower, out.lower_open, self.lower, self.lower_open, 1.0)
                and _within(out.upper, out.upper_open, self.upper, self.upper_open, -1.0)):
            raise ValueError(f"{self.name}: {out.range_text} is not inside {self.range_text}")
        return out

    def help(self) -> str:
        """One line for ``--help``: meaning, symbol, range (and the narrower ranges of some owners) and default."""
        shown = self.default_text if self.default_text is not None else (None if self.default is None else f"{self.default:g}" if isinstance(self.default, float) else str(self.default))
        text = f"{self.meaning[0].upper()}{self.meaning[1:]} {self.symbol}".rstrip()
        if self.range_text is not None:
            text += ", " + self.range_text
            text += "".join(f"; {rng} for {', '.join(owners)}" for rng, owners in self.variants)
        if self.kind == "choice":
            text += ": " + ", ".join(self.choices)
        return text + (f" [{shown}]." if shown is not None else ".")

    def with_default(self, default: Any, text: str | None = None) -> "Param":
        """The same parameter with another owner's default (Stribeck's F_s = 2 F_d)."""
        return replace(self, default=default, default_text=text)


def resolve(params: tuple[Param, ...], given: Mapping[str, Any]) -> dict[str, Any]:
    """Validated values of ``params`` from ``given`` (None or missing: the default), in declaration order."""
    by_name = params_by_name(params)
    return with_defaults(params, {k: (None if v is None else by_name[k].check(v)) for k, v in given.items() if k in by_name})


def with_defaults(params: tuple[Param, ...], values: Mapping[str, Any]) -> dict[str, Any]:
    """``values`` completed with the defaults, in declaration order; no checks (values may be per-point arrays).

    Defaults that are functions see the values resolved before them.
    """
    out: dict[str, Any] = {}
    for p in params:
        v = values.get(p.name)
        out[p.name] = p.default_for(out) if v is None else v
    return out


class Sealed:
    """An object whose parameters are checked once, when it is built: setting one afterwards is refused.

    A changed value would skip its range check, and a friction law's kernel parameters are computed once and
    kept.  The constructor calls ``_seal`` when every value is set; pickling and copying restore the
    object's ``__dict__`` directly, so copies are sealed too.
    """

    def _seal(self) -> None:
        self.__dict__["_sealed"] = True

    def __setattr__(self, name: str, value: Any) -> None:
        if self.__dict__.get("_sealed"):
            raise AttributeError(f"{type(self).__name__} cannot change {name} after it is built: make a new one "
                                 f"with {name}={value!r}")
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        if self.__dict__.get("_sealed"):
            raise AttributeError(f"{type(self).__name__} cannot remove {name} after it is built")
        object.__delattr__(self, name)


def params_by_name(params: tuple[Param, ...]) -> dict[str, Param]:
    return {p.name: p for p in params}


def declared() -> dict[str, Param]:
    """Every parameter of the package by name (oscillator, every registered law and solver, the run).

    Collected from the groups the owners :func:`declare` (on import of their
    modules, which ``import frictionflow`` runs) in the order of ``OWNERS``;
    built once, and again after a law registers.  A name several owners
    declare (the laws' fd, delta, ...) is the first declaration, the widest
    (:meth:`Param.narrowed`): what a config or an option may hold before the
    law is known.  The narrower ranges of the others are its ``variants``, so
    that its help states the range each law enforces.
    """
    if not _DECLARED:
        missing = [owner for owner in OWNERS if not _GROUPS[owner]]
        if missing:  # an owner's module not imported yet: a partial table would be cached
            raise RuntimeError(f"parameters of {', '.join(missing)} not declared yet: import frictionflow first")
        variants: dict[str, dict[str, list[str]]] = {}
        for owner in OWNERS:
            for by, group in _GROUPS[owner]:
                for p in group:
                    first = _DECLARED.setdefault(p.name, p)  # shared law parameters (fd, fs, ...) are one declaration
                    if p.range_text != first.range_text:
                        variants.setdefault(p.name, {}).setdefault(p.range_text, []).append(by or owner)
        for name, ranges in variants.items():
            _DECLARED[name] = replace(_DECLARED[name], variants=tuple((r, tuple(b)) for r, b in ranges.items()))
    return _DECLARED


#: the declared groups by owner, (who declared it, the group), in the order they were declared
_GROUPS: dict[str, list[tuple[str | None, tuple[Param, ...]]]] = {owner: [] for owner in OWNERS}
_DECLARED: dict[str, Param] = {}


def declare(group: tuple[Param, ...], by: str | None = None) -> None:
    """Add an owner's parameters to :func:`declared`; ``by`` names the owner in help texts (a law's name).

    The owners call it -- the oscillator and the run in their modules, the law
    and solver registries for each class -- so that this module, the lowest
    layer, names none of them.
    """
    owners = {p.owner for p in group}
    if len(owners) != 1:
        raise ValueError(f"a declared group has one owner, got {sorted(owners)}")
    _GROUPS[owners.pop()].append((by, group))
    forget_declarations()


def forget_declarations() -> None:
    """Drop the collected declarations (a group was declared: a law was registered)."""
    _DECLARED.clear()


def dimensional_parameters() -> dict[str, Param]:
    """The declared parameters with a physical dimension, by their key in a ``dimensional`` table."""
    return {p.dimensional_key: p for p in declared().values() if p.dimensional_key is not None}


def sweep_axes() -> tuple[str, ...]:
    """Names that can be sweep axes: the real parameters of the oscillator, the laws and the initial state."""
    return tuple(name for name, p in declared().items() if p.sweepable)


def _within(bound: float | None, is_open: bool, outer: float | None, outer_open: bool, inward: float) -> bool:
    """Whether a range's end (``bound``, open or not) is no wider than ``outer``'s; ``inward``: +1 for lower
    ends, -1 for upper ends (None: unbounded)."""
    if outer is None:
        return True
    if bound is None:
        return False
    return inward * (bound - outer) > 0 or (bound == outer and (is_open or not outer_open))


def positive_real(name: str, symbol: str, meaning: str, owner: str, default: Any, **kw: Any) -> Param:
    """A real > 0."""
    return Param(name, symbol, meaning, owner, default, lower=0.0, lower_open=True, **kw)


def nonnegative_real(name: str, symbol: str, meaning: str, owner: str, default: Any, **kw: Any) -> Param:
    """A real >= 0."""
    return Param(name, symbol, meaning, owner, default, lower=0.0, **kw)

