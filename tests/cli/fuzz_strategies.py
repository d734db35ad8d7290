"""Hypothesis strategies for whole command lines of every ``frictionflow`` command.

The options come from the commands themselves (the click objects typer builds:
name, flag, annotation, default, required) and, for the declared parameters,
from their declarations (:func:`frictionflow.parameters.declared`: kind, range,
choices, whether a subnormal is a value).  Each option's value is drawn as

* ``cheap``: inside the allowed range, where the run stays short (for the few
  options that set the amount of work, a cheap sub-range -- :data:`CHEAP`);
* ``hostile``: at and beyond the range's ends, subnormal, huge, ``nan``/``inf``
  text, a wrong type (``abc``, ``1.5`` for an integer), an empty value.

What click cannot tell -- the base command line that makes a cheap valid run,
the shape of a free-text option (``FROM:TO:N``) -- is the small table below.
"""

from __future__ import annotations

import math
import sys
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import typer
from hypothesis import strategies as st

from frictionflow import quantities as Q
from frictionflow.cli import load_commands
from frictionflow.cli._app import app
from frictionflow.friction import law_class, law_names
from frictionflow.parameters import Param, declared

PARAMS = declared()
SUBNORMAL = 5e-324

#: A cheap valid run of each command: its required options and the options that set the amount of work kept small.
BASE: dict[str, dict[str, str]] = {
    "simulate": {"t_end": "30"},
    "orbit": {"t_end": "30"},
    "continue": {"vary": "vb=0.01:0.03:5", "max_points": "5", "t_end": "30"},
    "forced-orbit": {"fex": "0.05", "zeta": "0.05", "omega": "0.8", "friction": "coulomb", "transient_periods": "2",
                     "steps_per_period": "64"},
    "forced-continue": {"fex": "0.05", "zeta": "0.05", "vary": "omega=0.8:0.9", "max_points": "5",
                        "steps_per_period": "64", "friction": "coulomb"},
    "response": {"vary": "omega=0.5:1.5:3", "fex": "0.01", "zeta": "0.05", "periods": "8"},
    "lyapunov": {"t_end": "50", "t_transient": "10", "steps_per_period": "64"},
    "basins": {"x0_range": "-0.1:0.1:3", "v0_range": "-0.1:0.1:3", "t_end": "30"},
    "map": {"x": "vb=0.005:0.02:3", "y": "zeta=0:0.1:21", "friction": "coulomb"},
    "sweep": {"out": "r.zarr"},
    "reproduce": {"out": "rep", "quick": "", "t_end": "50", "workers": "1"},
    "stability": {"model": str(Path(__file__).resolve().parent / "models" / "flutter_2dof.toml"),
                  "vary": "contact.0.fd=0.1:0.8:9"},
}

#: Valid values that keep the work small, for the options that set its amount (declared or a command's own).
CHEAP: dict[str, tuple[float, float]] = {
    "t_end": (1.0, 40.0), "dt": (2e-3, 0.05), "dense_dt": (0.05, 1.0), "max_steps": (10**5, 10**7),
    "record_every": (1, 50), "x0": (-0.1, 0.1), "v0": (-0.1, 0.1), "zeta": (0.0, 0.5), "vb": (-0.2, 0.2),
    "fd": (0.0, 0.05), "fs": (0.0, 0.1), "vd": (1e-4, 1e-2), "vs": (1e-3, 0.1), "delta": (0.5, 3.0),
    "viscous": (0.0, 0.1), "k1": (0.0, 0.3), "k3": (5.0, 50.0), "rk4_band": (1e-5, 1e-3), "rtol": (1e-10, 1e-4), "ode_rtol": (1e-10, 1e-6),
    "max_memory": (0.05, 1.0), "fex": (0.0, 0.1), "omega": (0.5, 2.0), "phi": (-3.2, 3.2),
    # a command's own options
    "max_points": (2, 6), "transient_periods": (0, 3), "steps_per_period": (16, 128), "periods": (8, 16),
    "t_transient": (0.0, 20.0), "attractor_tol": (1e-4, 1e-2),
    "max_period": (10.0, 500.0), "step": (0.01, 0.1), "returns": (1, 2), "tol": (1e-11, 1e-6), "m": (1, 2),
    "fold_every": (1, 3), "seed": (0, 1000), "sample": (1, 6), "chunk_size": (1, 50), "workers": (1, 1),
    "block": (1.0, 10.0), "scheduler_timeout": (0.5, 5.0),
}

#: Free-text options: valid shapes (what the help text describes), beside the generic hostile texts.
_MODEL = [n for n, p in PARAMS.items() if p.sweepable and p.owner in ("oscillator", "law")]
TEXT: dict[str, list[str]] = {
    "x": [f"{n}=0.005:0.02:3" for n in _MODEL], "y": [f"{n}=0:0.1:11" for n in _MODEL],
    "direction": ["up", "down", "both"], "x0_range": ["-0.1:0.1:3", "-0.1:0.1", "0:0:1"],
    "v0_range": ["-0.1:0.1:3", "-0.1:0.1:2"], "seeds": ["hopf", "start", "stop", "hopf,start,stop"],
    "monitor": ["P_fin", "TR_B", "R_c"], "curves": ["hopf", "grazing", "hopf,grazing"], "m": ["1", "1,2"],
    "heat": ["R_c", "TR_B", "P_fin"], "overlay": ["2x2", "0", "3"],
    "vary": ["zeta=0:0.1:2", "fd=0.02,0.03", "vb=0.01:0.03:3", "omega=0.5:1.5:3", "omega=0.8:0.9", "fex=0.01:0.05:2"],
    "window": ["10:20", "0:30", "20:10"], "dimensional": ["m=1,c=0.08,k=4,v_b=0.02,f_d=0.08"],
    "scheduler": ["notanaddress", "tcp://", "tcp://256.0.0.1:x"],
}
HOSTILE_TEXT = ["", " ", "abc", "nan", "inf", "-inf", "1e999", "0x10", "--", "1e", "true", "a:b:c", ":", "1:2:3:4",
                "1:2:1e9", "0:1:-3", "nan:1:3", "é", "1" * 40]
#: Output paths: name (suffix) variants; files land in the case's own directory.
PATHS = ["out.nc", "out.zarr", "out.csv", "out.png", "out.txt", "", ".", "missing/dir/out.nc", "out"]


@dataclass(frozen=True)
class Option:
    """One option of a command, as click has it (and its declaration when it is a declared parameter)."""

    name: str
    flag: str
    kind: str  # real, int, choice, text, flag, path
    param: Param | None
    required: bool
    default: Any


#: how a declared parameter's option is typed on the command line
_AS_TYPED = {"real": "real", "int": "int", "choice": "text", "text": "text"}


def _kind(p: Any) -> str:
    """``real``/``int``/``text``/``flag``/``path`` from the option's annotation (``Optional[...]`` unwrapped)."""
    if getattr(p, "is_flag", False):
        return "flag"
    ann = p.type_descriptor.annotation
    args = [a for a in typing.get_args(ann) if a is not type(None)]
    ann = args[0] if args else ann
    return {float: "real", int: "int", str: "text", Path: "path", bool: "flag"}.get(ann, "text")


def command_options() -> dict[str, dict[str, Option]]:
    """Every command's options by name, from the click objects."""
    load_commands(None)
    group = typer.main.get_command(app)
    out: dict[str, dict[str, Option]] = {}
    for name, cmd in group.commands.items():
        opts = {}
        for p in cmd.params:
            kind = _kind(p)
            decl = PARAMS.get(p.name)
            same = decl is not None and decl.flag in p.opts and _AS_TYPED[decl.kind] == kind
            decl = decl if same else None  # (response's --omega FROM:TO:N is its own option, not the frequency)
            kind = decl.kind if decl is not None and decl.kind != "text" else kind
            flag = p.opts[0] if p.opts[0].startswith("-") else ""  # "" for an argument (sweep's CONFIG)
            opts[p.name] = Option(p.name, flag, kind, decl, bool(p.required), p.default)
        out[name] = opts
    return out


OPTIONS = command_options()
COMMANDS = sorted(OPTIONS)


def cheap(opt: Option) -> st.SearchStrategy[str]:
    """A valid value that keeps the run short."""
    p = opt.param
    if opt.kind == "choice":
        return st.sampled_from(p.choices)
    if opt.kind == "flag":
        return st.just("")
    if opt.kind == "path":
        return st.sampled_from([s for s in PATHS if s and "/" not in s and s != "."])
    if opt.kind == "text":
        return st.sampled_from(TEXT.get(opt.name, ["x"]))
    lo, hi = CHEAP.get(opt.name, _around(opt))
    if p is not None:  # the cheap range clipped to the declared one
        lo = max(lo, p.lower) if p.lower is not None else lo
        hi = min(hi, p.upper) if p.upper is not None else hi
    assert lo <= hi, f"{opt.name}: the cheap range ({lo}, {hi}) is outside the declared one"
    if opt.kind == "int":
        return st.integers(int(math.ceil(lo)), int(hi)).map(str)
    low_open = p is not None and p.lower_open and lo == p.lower
    return st.floats(lo, hi, exclude_min=low_open, allow_subnormal=bool(p and p.subnormal_ok)).map(repr)


def _around(opt: Option) -> tuple[float, float]:
    """A number without a cheap range: a span about its default (the declared one for a declared parameter)."""
    d = opt.param.default if opt.param is not None else opt.default
    d = d if isinstance(d, (int, float)) and not isinstance(d, bool) else 1.0
    return (d / 4, d * 4) if d > 0 else (0.0, 1.0)


def hostile(opt: Option) -> st.SearchStrategy[str]:
    """A value at or beyond the allowed range's ends, degenerate, huge, non-finite or of the wrong type."""
    if opt.kind == "flag":
        return st.just("")
    if opt.kind in ("choice", "text"):
        near = [c.upper() for c in (opt.param.choices if opt.param else TEXT.get(opt.name, []))]
        return st.sampled_from(HOSTILE_TEXT + near)
    if opt.kind == "path":
        return st.sampled_from(PATHS)
    numbers = [0.0, -0.0, 1.0, -1.0, SUBNORMAL, -SUBNORMAL, sys.float_info.min, 1e-300, 1e300, sys.float_info.max,
               2.0**53 + 1, 1e20, 0.5]
    p = opt.param
    ends = [e for e in (opt.param.lower, opt.param.upper) if e is not None] if opt.param is not None else []
    texts = [repr(x) for x in numbers] + ["nan", "inf", "-inf", "1e999", "abc", "", "1e"]
    if opt.kind == "int":
        texts += ["0", "-1", "99999999999999999999", "1.5", "1e3"] + [str(int(e) + d) for e in ends for d in (-1, 0, 1)]
    else:
        texts += [repr(x) for e in ends for x in (e, math.nextafter(e, -math.inf), math.nextafter(e, math.inf))]
    return st.sampled_from(texts)


def edge(opt: Option) -> st.SearchStrategy[str]:
    """A value the declaration allows at an extreme: an end of the range (the nearest float inside an open
    end), the smallest normal number, 1e-300 -- the work it asks for may be huge (then refused up front)."""
    p = opt.param
    if p is None or opt.kind not in ("real", "int"):
        return cheap(opt)
    ends = [math.nextafter(e, math.inf if e == p.lower else -math.inf) if is_open else e
            for e, is_open in ((p.lower, p.lower_open), (p.upper, p.upper_open)) if e is not None]
    values = []
    for x in (*ends, sys.float_info.min, 1e-300, -1e-300, 1e-9, 1.0):
        try:
            values.append(p.check(int(x) if opt.kind == "int" and float(x).is_integer() else x))
        except ValueError:
            pass  # not allowed: the hostile draws have it
    return st.sampled_from([str(v) if opt.kind == "int" else repr(float(v)) for v in values] or ["1"])


@dataclass
class Case:
    """A drawn command line: the options given (name -> text, '' for a flag), and a config file's values."""

    command: str
    given: dict[str, str]
    config: dict[str, Any] = field(default_factory=dict)
    hostile: set[str] = field(default_factory=set)

    def argv(self, config_path: str | None) -> list[str]:
        """The command line (with ``--config`` when the case has a config file)."""
        opts = OPTIONS[self.command]
        argv = [self.command]
        for name, value in self.given.items():
            opt = opts[name]
            if not opt.flag:
                argv.append(value)
            elif opt.kind == "flag":
                argv.append(opt.flag)
            else:
                argv += [opt.flag, value]
        if config_path is not None:
            argv += [config_path] if self.command == "sweep" else ["--config", config_path]
        if "as_json" in opts and "as_json" not in self.given:
            argv.append("--json")
        return argv


def _draw_values(draw: Any, names: list[str], opts: dict[str, Option], mode: str) -> dict[str, tuple[str, bool]]:
    """A value for each of ``names``: cheap, or (mode ``hostile``/``edge``) hostile or at an allowed extreme
    for at least one of them."""
    out = {}
    plain = [n for n in names if opts[n].kind != "flag"]
    odd = mode in ("hostile", "edge")
    odd_one = draw(st.sampled_from(plain)) if odd and plain else None
    unusual = hostile if mode == "hostile" else edge
    for n in names:
        is_odd = n == odd_one or (odd and draw(st.booleans()))
        out[n] = (draw(unusual(opts[n]) if is_odd else cheap(opts[n])), is_odd)
    return out


@st.composite
def cases(draw: Any, command: str, modes: tuple[str, ...] = ("cheap", "cheap", "hostile")) -> Case:
    """A command line of ``command``: its base, a few options changed (each cheap, or hostile), some of the
    model's values in a config file instead (TOML-typed: a number stays a number, junk becomes a string).

    ``modes``: what the case's values are drawn as -- ``cheap`` (all valid and cheap), ``hostile`` (at least
    one hostile value), ``edge`` (at least one value at an allowed extreme); one of them is drawn."""
    opts = OPTIONS[command]
    plain = sorted(n for n, o in opts.items() if n != "config" and o.flag and o.kind != "flag")
    flags = sorted(n for n, o in opts.items() if n != "as_json" and o.kind == "flag")
    mode = draw(st.sampled_from(modes))
    names = draw(st.lists(st.sampled_from(plain), min_size=int(mode != "cheap"), max_size=3, unique=True))
    names += draw(st.lists(st.sampled_from(flags), max_size=2, unique=True)) if flags else []
    values = _draw_values(draw, names, opts, mode)
    given = dict(BASE[command])
    given.update({n: v for n, (v, _) in values.items()})
    bad = {n for n, (_, b) in values.items() if b}
    if mode != "hostile" and "friction" in opts:
        _law_having(draw, given)
    config: dict[str, Any] = {}
    if "config" in opts or command == "sweep":
        config = draw(_config(command, opts, given, mode == "hostile"))
    for n in config:
        if n in given and draw(st.booleans()):  # only in the file (else in both: the command line wins)
            del given[n]
    return Case(command, given, config, bad)


def _law_having(draw: Any, given: dict[str, str]) -> None:
    """A cheap case names a friction law that has the law parameters it gives (one of them, drawn)."""
    wanted = {n for n in given if PARAMS.get(n) is not None and PARAMS[n].owner == "law"}
    laws = [law for law in law_names() if wanted <= {p.name for p in law_class(law).parameters}]
    if wanted and laws and given.get("friction") not in laws:
        given["friction"] = draw(st.sampled_from(laws))


def toml_value(text: str) -> Any:
    """The option's text as a TOML value: numbers stay numbers (non-finite included), the rest a string."""
    try:
        return int(text) if text.lstrip("-").isdigit() else float(text)
    except ValueError:
        return text


@st.composite
def _config(draw: Any, command: str, opts: dict[str, Option], given: dict[str, str], bad: bool) -> dict[str, Any]:
    """Values for a config file: some of the declared options the command takes (sweep: also its grid);
    cheap ones, or (``bad``) also hostile ones and values of the wrong TOML type."""
    declared_opts = sorted(n for n, o in opts.items() if o.param is not None)
    if command == "sweep":
        return draw(_sweep_config(bad))
    if not draw(st.booleans()):
        return {}
    names = draw(st.lists(st.sampled_from(declared_opts), max_size=3, unique=True))
    out = {}
    for n in names:
        if n in given and draw(st.booleans()):
            out[n] = toml_value(given[n])
        elif bad:
            out[n] = draw(st.one_of(cheap(opts[n]).map(toml_value), hostile(opts[n]).map(toml_value),
                                    st.sampled_from([True, [1.0], {"a": 1}])))
        else:
            out[n] = draw(cheap(opts[n]).map(toml_value))
    if not bad and "friction" in opts:
        _law_having(draw, out)
    return out


@st.composite
def _sweep_config(draw: Any, bad: bool) -> dict[str, Any]:
    """A sweep's TOML: run settings (declared parameters) and a [grid] of one or two sweepable axes."""
    run_names = [n for n, p in PARAMS.items() if p.kind != "text"]
    runs = {"t_end": 20.0, "friction": "coulomb"}
    for n in draw(st.lists(st.sampled_from(run_names), max_size=2, unique=True)):
        o = Option(n, PARAMS[n].flag, PARAMS[n].kind, PARAMS[n], False, None)
        runs[n] = toml_value(draw(st.one_of(cheap(o), hostile(o)) if bad else cheap(o)))
    axes = draw(st.lists(st.sampled_from([n for n, p in PARAMS.items() if p.sweepable]), min_size=1, max_size=2,
                         unique=True))
    grid = {}
    for n in axes:
        o = Option(n, PARAMS[n].flag, PARAMS[n].kind, PARAMS[n], False, None)
        one = st.one_of(cheap(o), cheap(o), hostile(o)) if bad else cheap(o)
        values = st.lists(one.map(toml_value), min_size=1, max_size=3)
        lo, hi = CHEAP.get(n, (0.0, 0.1))
        nums = st.one_of(st.integers(1, 3), st.sampled_from([0, -1, 10**12, 2.5, "3"])) if bad else st.integers(1, 3)
        grid[n] = draw(st.one_of(values, st.builds(lambda num: {"start": lo, "stop": hi, "num": num}, nums)))
    if not bad:
        named = runs | {n: "" for n in grid}  # the axes' law parameters too
        _law_having(draw, named)
        runs = {k: v for k, v in runs.items() if k not in grid} | {"friction": named["friction"]}
    return {**runs, "grid": grid}


def toml_text(values: dict[str, Any]) -> str:
    """``values`` as a TOML document (tables last)."""
    lines, tables = [], []
    for k, v in values.items():
        if isinstance(v, dict) and k == "grid":
            tables.append(f"[{k}]")
            tables += [f"{g} = {_toml(x)}" for g, x in v.items()]
        else:
            lines.append(f"{k} = {_toml(v)}")
    return "\n".join(lines + tables) + "\n"


def _toml(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml(x)}" for k, x in v.items()) + " }"
    return '"' + str(v).replace("\\", "\\\\").replace('"', '\\"') + '"'
