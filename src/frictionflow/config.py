"""Run settings shared by the CLI commands and TOML configs.

One :class:`RunConfig` holds what ``frictionflow simulate`` accepts; it is
built from a mapping (a TOML file, CLI options or both) whose keys are the CLI
option names with underscores (``t_end``, ``stick_force``, ...).  Every value
is validated here, before any work starts, so a bad input costs nothing.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any, Mapping

from . import _validate as check
from .friction import Coulomb, FrictionLaw, Karnopp, Stribeck
from .params import BeltOscillator, DimensionalParams
from .solvers import RK4, Adaptive, Exact, Solver, auto_solver

FRICTIONS = ("karnopp", "coulomb", "stribeck")
SOLVERS = ("auto", "exact", "adaptive", "rk4")
DIMENSIONAL_KEYS = ("m", "c", "k", "v_b", "f_d", "f_ms", "v_d", "l_0")


@dataclass
class RunConfig:
    """Everything that defines one run and its analysis."""

    fd: float = 0.02
    fs: float | None = None
    vb: float = 0.01
    zeta: float = 0.0
    vd: float = 1e-3
    x0: float | None = None
    v0: float | None = None
    vs: float = 0.01
    delta: float = 2.0
    viscous: float = 0.0
    t_end: float = 500.0
    dt: float = 1e-3
    record_every: int | None = None
    dense_dt: float | None = None
    ode_rtol: float = 1e-10
    max_steps: int = 10_000_000
    solver: str = "auto"
    friction: str = "karnopp"
    stick_force: str = "resultant"
    window: tuple[float, float] | None = None
    rtol: float | None = None
    dimensional: dict[str, float] | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls) if f.name != "extra")

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any], *, source: str = "config") -> "RunConfig":
        """Build and validate from a mapping; unknown keys are refused by name."""
        known = set(cls.keys())
        unknown = [k for k in values if k.replace("-", "_") not in known]
        if unknown:
            raise ValueError(f"{source}: unknown key {unknown[0]!r}; allowed: {', '.join(sorted(known))}")
        kw = {k.replace("-", "_"): v for k, v in values.items() if v is not None}
        if "window" in kw:
            kw["window"] = parse_window(kw["window"])
        if "dimensional" in kw:
            both = [k for k in ("zeta", "vb", "fd", "fs", "vd") if k in kw]
            if both:
                raise ValueError(f"{source}: give {both[0]} or dimensional, not both")
            kw["dimensional"] = _dimensional_table(kw["dimensional"])
        cfg = cls(**kw)
        cfg.validate()
        return cfg

    def validate(self) -> None:
        """Raise ValueError naming the first bad setting."""
        check.choice("solver", self.solver, SOLVERS)
        check.choice("friction", self.friction, FRICTIONS)
        check.positive("t_end", self.t_end)
        check.positive("dt", self.dt)
        if self.rtol is not None:
            check.positive("rtol", self.rtol)
        if self.dense_dt is not None:
            check.positive("dense_dt", self.dense_dt)
        if self.record_every is not None:
            check.positive_int("record_every", self.record_every)
        for name in ("x0", "v0"):
            if getattr(self, name) is not None:
                check.finite(name, getattr(self, name))
        if self.window is not None:
            t0, t1 = self.window
            if not (0 <= t0 < t1 <= self.t_end):
                raise ValueError(f"window must satisfy 0 <= T0 < T1 <= t_end = {self.t_end:g}, got {t0:g}:{t1:g}")
        model, friction, solver = self.build()  # these validate themselves
        if not solver.supports(friction):
            raise ValueError(f"solver={self.solver} does not support friction={self.friction}; use solver=auto")

    def nondimensional(self) -> dict[str, float]:
        """zeta, V_b, F_d, F_s, V_d after converting ``dimensional`` if given."""
        if self.dimensional is not None:
            nd = DimensionalParams(**self.dimensional).nondimensional()
            return {k: nd[k] for k in ("zeta", "vb", "fd", "fs", "vd")}
        return {"zeta": self.zeta, "vb": self.vb, "fd": self.fd, "fs": self.fs, "vd": self.vd}

    def build(self) -> tuple[BeltOscillator, FrictionLaw, Solver]:
        """The model, friction law and solver this config describes."""
        nd = self.nondimensional()
        model = BeltOscillator(zeta=nd["zeta"], vb=nd["vb"])
        friction: FrictionLaw
        if self.friction == "karnopp":
            friction = Karnopp(fd=nd["fd"], fs=nd["fs"], vd=nd["vd"], stick_force=self.stick_force)
        elif self.friction == "coulomb":
            friction = Coulomb(fd=nd["fd"], fs=nd["fs"], stick_force=self.stick_force)
        else:
            fs = nd["fs"] if nd["fs"] is not None else 2.0 * nd["fd"]
            friction = Stribeck(fd=nd["fd"], fs=fs, vs=self.vs, delta=self.delta, viscous=self.viscous, stick_force=self.stick_force)
        return model, friction, self.make_solver(friction)

    def make_solver(self, friction: FrictionLaw) -> Solver:
        """The solver this config names (``auto``: exact for piecewise-constant laws, else adaptive)."""
        if self.solver == "rk4":
            return RK4(dt=self.dt, record_every=self.record_every)
        if self.solver == "exact":
            return Exact(dense_dt=self.dense_dt)
        if self.solver == "adaptive":
            return Adaptive(rtol=self.ode_rtol, max_steps=self.max_steps, dense_dt=self.dense_dt)
        chosen = auto_solver(friction)
        if isinstance(chosen, Exact):
            return Exact(dense_dt=self.dense_dt)
        return Adaptive(rtol=self.ode_rtol, max_steps=self.max_steps, dense_dt=self.dense_dt)


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


def parse_dimensional(text: str) -> dict[str, float]:
    """``"m=1,c=0.02,k=1,v_b=0.01,f_d=0.02"`` -> dict, keys checked."""
    out: dict[str, Any] = {}
    for item in filter(None, (s.strip() for s in text.split(","))):
        key, sep, val = item.partition("=")
        if not sep:
            raise ValueError(f"dimensional must be KEY=VALUE pairs separated by commas, got {item!r}")
        out[key.strip()] = val.strip()
    return _dimensional_table(out)


def _dimensional_table(table: Any) -> dict[str, float]:
    if not isinstance(table, Mapping):
        raise ValueError(f"dimensional must be a table of {', '.join(DIMENSIONAL_KEYS)}")
    out = {}
    for key, val in table.items():
        if key not in DIMENSIONAL_KEYS:
            raise ValueError(f"dimensional: unknown key {key!r}; allowed: {', '.join(DIMENSIONAL_KEYS)}")
        out[key] = check.finite(f"dimensional {key}", val)
    missing = [k for k in ("m", "c", "k", "v_b", "f_d") if k not in out]
    if missing:
        raise ValueError(f"dimensional: missing {', '.join(missing)} (required: m, c, k, v_b, f_d)")
    return out
