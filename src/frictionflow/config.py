"""Run settings shared by the CLI commands and TOML configs.

A :class:`RunConfig` holds the settings given for one run, by parameter name
(the CLI option names with underscores: ``t_end``, ``stick_force``, ...).
Which names exist, their ranges and defaults come from the declarations
(:func:`frictionflow.parameters.declared`): the oscillator's, every registered
law's and solver's, and the run's own below.  Every value is validated here,
before any work starts, so a bad input costs nothing.
"""

from __future__ import annotations

from typing import Any, Mapping

from . import _validate as check
from .friction import FrictionLaw, law_class, law_names
from .parameters import STATE_MAX, Param, declare, declared, dimensional_parameters
from .params import SCALE_KEYS, BeltOscillator, DimensionalParams
from .solvers import Solver
from .solvers.base import DEFAULT_MAX_MEMORY
from .solvers.registry import build_solver, solver_names

#: the keys a dimensional table must have: the scales and the belt (the law's own, f_d, when it has one)
DIMENSIONAL_REQUIRED = ("m", "c", "k", "v_b")


def dimensional_keys() -> tuple[str, ...]:
    """The keys of a dimensional table: the scales, then every declared parameter with a dimension."""
    return (*SCALE_KEYS, *dimensional_parameters())


def set_by_dimensional(name: str) -> bool:
    """Whether a dimensional table sets parameter ``name`` (zeta, by c, and every parameter with a dimension)."""
    p = declared().get(name)
    return name == "zeta" or (p is not None and p.dimensional_key is not None)


def parse_window(value: Any) -> tuple[float, float]:
    """``"T0:T1"`` or a pair of numbers -> (T0, T1)."""
    if isinstance(value, str):
        parts = value.split(":")
        if len(parts) != 2:
            raise ValueError(f"window must be T0:T1 with T0 < T1, got {value!r}")
        a, b = parts
    else:
        try:
            a, b = value
        except (TypeError, ValueError):
            raise ValueError(f"window must be T0:T1 with T0 < T1, got {value!r}") from None
    t0, t1 = check.finite("window T0", a), check.finite("window T1", b)
    if not t0 < t1:
        raise ValueError(f"window must be T0:T1 with T0 < T1, got {value!r}")
    return t0, t1


def parse_dimensional(value: Any) -> dict[str, float]:
    """``"m=1,c=0.02,k=1,v_b=0.01,f_d=0.02"`` (or a TOML table) -> dict, keys checked."""
    if not isinstance(value, str):
        return _dimensional_table(value)
    out: dict[str, Any] = {}
    for item in filter(None, (s.strip() for s in value.split(","))):
        key, sep, val = item.partition("=")
        if not sep:
            raise ValueError(f"dimensional must be KEY=VALUE pairs separated by commas, got {item!r}")
        if key.strip() in out:  # (a TOML table cannot repeat a key: its reader refuses it)
            raise ValueError(f"dimensional: {key.strip()} is given twice ({out[key.strip()]} and {val.strip()})")
        out[key.strip()] = val.strip()
    return _dimensional_table(out)


def _dimensional_table(table: Any) -> dict[str, float]:
    keys = dimensional_keys()
    if not isinstance(table, Mapping):
        raise ValueError(f"dimensional must be a table of {', '.join(keys)}")
    out = {}
    for key, val in table.items():
        if key not in keys:
            raise ValueError(f"dimensional: unknown key {key!r}; allowed: {', '.join(keys)}")
        out[key] = check.finite(f"dimensional {key}", val)
    missing = [k for k in ("m", "c", "k") if k not in out]
    if missing:
        raise ValueError(f"dimensional: missing {', '.join(missing)} (required: m, c, k, v_b, and f_d for a law with F_d)")
    return out


def refuse_mixing(given: Mapping[str, Any], source: str) -> None:
    """With a ``dimensional`` table in ``given``, a parameter it sets given as a non-dimensional value is refused."""
    if "dimensional" not in given:
        return
    both = [k for k in given if set_by_dimensional(k)]
    if both:
        key = declared()[both[0]].dimensional_key or "c"
        raise ValueError(f"{source}: give {both[0]} or dimensional, not both (with dimensional: {key}=... "
                         "inside it)")


def nondimensional_values(values: Mapping[str, Any], friction: str, present: tuple[str, ...] = ()) -> dict[str, Any]:
    """``values`` with its ``dimensional`` table converted: the parameters it sets, non-dimensional.

    Parameters
    ----------
    values:
        Settings by name (checked), with a parsed ``dimensional`` table or without (returned as given).
    friction:
        The law's name: a table key that is none of its (or the oscillator's) parameters is refused.
    present:
        Dimensional keys given elsewhere (a sweep's axes): not missing from the table.
    """
    table = values.get("dimensional")
    if table is None:
        return dict(values)
    law = law_class(friction)
    own = {p.name for p in law.parameters} | {p.name for p in BeltOscillator.parameters}
    known = dimensional_parameters()
    foreign = [k for k in table if k in known and known[k].name not in own]
    if foreign:
        raise ValueError(f"dimensional: {foreign[0]} sets {known[foreign[0]].name}, not a parameter of "
                         f"friction={friction}")
    required = (*DIMENSIONAL_REQUIRED, *(("f_d",) if "fd" in own else ()))
    missing = [k for k in required if k not in table and k not in present]
    if missing:
        raise ValueError(f"dimensional: missing {', '.join(missing)} (required for friction={friction}: "
                         f"{', '.join(required)})")
    nd = DimensionalParams.from_table(table).nondimensional()
    return {**values, **{k: v for k, v in nd.items() if k in own}}


#: the run's own parameters (the oscillator, laws and solvers declare theirs)
RUN_PARAMETERS: tuple[Param, ...] = (
    Param("t_end", "tau_end", "end time", "run", 500.0, lower=0.0, lower_open=True, upper=1e12),
    Param("x0", "X(0)", "initial displacement", "run", None, default_text="the law's start, F_d for most",
          lower=-STATE_MAX, upper=STATE_MAX, sweepable=True, subnormal_ok=True),
    Param("v0", "X'(0)", "initial velocity", "run", None, default_text="the law's start, V_b for most",
          lower=-STATE_MAX, upper=STATE_MAX, sweepable=True, subnormal_ok=True),
    Param("friction", "", "friction law", "run", "karnopp", kind="choice", choices=law_names()),
    Param("solver", "", "solver (auto: exact for piecewise-constant laws, stiff for laws with internal states, "
          "else adaptive; on a moving belt one that runs it)", "run", "auto", kind="choice", choices=solver_names()),
    Param("window", "", "average over T0:T1 instead of the detected steady-state window", "run", None,
          kind="text", parse=parse_window),
    Param("rtol", "", "steady-state convergence tolerance", "run", None, lower=1e-15, upper=1.0,
                  default_text="rk4 1e-6, adaptive 1e-8, exact 1e-10"),
    Param("max_memory", "", "GiB the samples of a run may take (a longer run is refused up front)", "run",
          DEFAULT_MAX_MEMORY, lower=0.0, lower_open=True, upper=1e6, unit="GiB"),
    Param("dimensional", "", "dimensional input instead: 'm=..,c=..,k=..,v_b=..,f_d=..[,f_ms=..,v_d=..,l_0=..,"
          "sigma0=..,dc=..,...]' (every parameter with a dimension, by its key; the others as usual)",
          "run", None, kind="text", parse=parse_dimensional),
)
declare(RUN_PARAMETERS)


class RunConfig:
    """The settings of one run and its analysis: the values given, by name; the rest default.

    Attribute access gives a setting's value (``cfg.t_end``): the value given,
    else its declared default (None for a default that depends on other
    values, such as F_s = F_d).

    Parameters
    ----------
    given:
        The values given, by declared name (``t_end``, not ``t-end``); a value of
        None counts as not given and is dropped.  Kept as they are, unchecked:
        :meth:`from_mapping` checks and validates them.  The attribute
        ``given`` holds them afterwards.
    """

    def __init__(self, given: Mapping[str, Any] | None = None) -> None:
        self.given: dict[str, Any] = {k: v for k, v in (given or {}).items() if v is not None}

    def __getattr__(self, name: str) -> Any:
        params = declared()
        if name.startswith("_") or name not in params:
            raise AttributeError(name)
        value = self.__dict__["given"].get(name)
        if value is None and not callable(params[name].default):
            value = params[name].default
        return value

    def __repr__(self) -> str:
        return f"RunConfig({self.given!r})"

    @staticmethod
    def keys() -> tuple[str, ...]:
        return tuple(declared())

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any], *, source: str = "config") -> "RunConfig":
        """Build and validate from a mapping; unknown keys are refused by name."""
        given = cls.checked(values, source=source)
        refuse_mixing(given, source)
        cfg = cls(given)
        cfg.validate()
        return cfg

    @staticmethod
    def checked(values: Mapping[str, Any], *, source: str = "config") -> dict[str, Any]:
        """Each value of ``values`` checked by its declaration, by name (None: not given; an unknown key refused).

        Only each value on its own: how they fit together is :meth:`validate`'s.  A config's values are checked
        so before options override them: a wrong one is an error whether or not it is overridden.
        """
        params = declared()
        given: dict[str, Any] = {}
        for key, value in values.items():
            name = key.replace("-", "_")
            if name not in params:
                raise ValueError(f"{source}: unknown key {key!r}; allowed: {', '.join(sorted(params))}")
            if value is not None:
                given[name] = params[name].check(value)
        return given

    def replace(self, **changes: Any) -> "RunConfig":
        """A copy with some settings changed (validated)."""
        return RunConfig.from_mapping({**self.given, **changes})

    def validate(self) -> None:
        """Raise ValueError naming the first bad setting."""
        if self.window is not None:
            t0, t1 = self.window
            if not (0 <= t0 < t1 <= self.t_end):
                raise ValueError(f"window must satisfy 0 <= T0 < T1 <= t_end = {self.t_end:g}, got {t0:g}:{t1:g}")
        law = law_class(self.friction)
        own = {p.name for p in law.parameters}
        foreign = [k for k in self.given if declared()[k].owner == "law" and k not in own]
        if foreign:
            raise ValueError(f"{foreign[0]} is not a parameter of friction={self.friction} "
                             f"(its parameters: {', '.join(p.name for p in law.parameters)})")
        self.build()  # the model, law and solver validate themselves and each other

    def values(self) -> dict[str, Any]:
        """Every setting given, with a dimensional input converted to the model's and law's parameters."""
        return nondimensional_values(self.given, self.friction)

    def nondimensional(self) -> dict[str, float]:
        """The oscillator's parameters and those of the law a dimensional table can set, after converting
        ``dimensional`` if given."""
        values = self.values()
        names = [p.name for p in (*BeltOscillator.parameters, *law_class(self.friction).parameters)
                 if set_by_dimensional(p.name)]
        return {k: values.get(k, getattr(self, k)) for k in names}

    def build(self) -> tuple[BeltOscillator, FrictionLaw, Solver]:
        """The model, friction law and solver this config describes."""
        values = self.values()
        model = BeltOscillator.from_values(values)
        friction = law_class(self.friction).from_values(values)
        return model, friction, self.make_solver(friction, model)

    def make_solver(self, friction: FrictionLaw, model: BeltOscillator | None = None) -> Solver:
        """The solver this config names (``auto``: exact for piecewise-constant laws, else adaptive; on a moving
        belt one that runs it)."""
        return build_solver(self.solver, friction, self.given, model)
