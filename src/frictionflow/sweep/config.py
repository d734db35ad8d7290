"""Sweep configs: the run settings of ``simulate`` plus a ``[grid]`` of parameters.

::

    friction = "coulomb"
    fs = 0.04
    t_end = 500.0

    [grid]
    zeta = { start = 0.0, stop = 0.1, num = 51 }
    vb = { start = 1e-3, stop = 0.1, num = 41, scale = "log" }
    fd = [0.01, 0.02, 0.04]
    vs = "0.01:0.05:5"       # FROM:TO:N, as ranges are written on the command line
    vd = 1e-3                # a number: fixed, not an axis

A ``sample`` entry is one axis of initial states drawn at random (uniformly
in each range, from a seeded PCG64 stream: the same points on every machine
and numpy version), for basins of attraction::

    [grid]
    sample = { num = 2000, seed = 1, x0 = [-0.3, 0.35], v0 = [-0.3, 0.3] }
    vb = [0.10, 0.12]        # the same sample at each V_b

Every key is checked before any work: unknown keys, empty axes, bad ranges
and invalid parameter values are refused with the key named.
"""

from __future__ import annotations

import hashlib
import json
import math
import warnings
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Mapping, NamedTuple

import numpy as np

from .. import _validate as check
from .. import quantities as Q
from .._ranges import decimal_values, parse_range
from ..config import DIMENSIONAL_REQUIRED, RunConfig, nondimensional_values, refuse_mixing, set_by_dimensional
from ..friction import law_class
from ..io import read_config
from ..parameters import declared, dimensional_parameters, sweep_axes, with_defaults
from ..params import SCALE_KEYS, unit_of
from ..solvers.base import CoarseStepWarning, check_memory
from ..solvers.registry import belt_motion_refusal

#: what can be an axis: every sweepable declared parameter (the oscillator's, the laws', the initial state)
GRID_KEYS = sweep_axes()
#: values on one axis, and grid points, at most (10^10 points: days of computing at 4e4 points/s)
MAX_AXIS = 10**7
MAX_POINTS = 10**10
#: settings that make no sense in a sweep (outputs of one run)
NOT_IN_SWEEPS = ("window", "record_every", "dense_dt")
#: the grid entry (and axis) of a random sample of initial states, and what it may draw
SAMPLE = "sample"
SAMPLE_KEYS = ("x0", "v0")


class Variable(NamedTuple):
    """One result variable of a sweep dataset: over the grid's dims, then ``dims`` (labelled by the config)."""

    name: str
    units: str
    long_name: str
    dtype: str = "f8"
    flags: tuple[str, ...] = ()  #: an integer code's meanings (CF flag_meanings)
    dims: tuple[str, ...] = ()  #: dimensions after the grid's (``contact``, ``dof``, ...), labelled by ``SweepConfig.labels``


#: the single-mass sweep's variables: the kernels' result row, as the quantities table describes it
SINGLE_MASS = tuple(Variable(q.name, q.units, q.long_name, q.dtype, q.flags) for q in Q.SWEPT)


class Grid:
    """What every sweep config has from its ``axes`` (name -> values) and ``source`` (what it was parsed from)."""

    axes: dict[str, np.ndarray]
    source: dict[str, Any]

    @property
    def dims(self) -> tuple[str, ...]:
        return tuple(self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a) for a in self.axes.values())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape, dtype=np.int64))

    def fingerprint(self) -> str:
        """A hash of everything that determines the results (to refuse resuming a changed sweep): ``source``.

        A model sweep's source holds the model's content, not its file's path:
        a moved file is the same sweep.
        """
        text = json.dumps(self.source, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()


@dataclass
class SweepConfig(Grid):
    """A validated sweep: fixed run settings, the swept axes, and how to chunk them."""

    run: RunConfig  #: the settings every point shares (law, solver, t_end, ...)
    axes: dict[str, np.ndarray]  #: the swept parameters and their values, in the grid's order
    fixed: dict[str, float] = field(default_factory=dict)  #: parameters given one value in the grid
    source: dict[str, Any] = field(default_factory=dict)  #: the settings and the grid it was parsed from (recorded in the output)
    #: the drawn values of each sampled parameter, per point of the ``sample`` axis
    sample: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def variables(self) -> tuple[Variable, ...]:
        """The result variables, in the order the chunks' results and checksums hold them."""
        return SINGLE_MASS

    @property
    def labels(self) -> dict[str, tuple[str, ...]]:
        """The labels of the variables' dims beyond the grid's (empty when every variable is one number per point)."""
        return {}

    def axis_attrs(self, name: str) -> dict[str, str]:
        """The attributes of axis ``name``'s coordinate."""
        if name == SAMPLE:
            return {"units": "1", "long_name": "index of the randomly drawn point (its values: the sampled coordinates)"}
        return dict(declared()[name].attrs)

    def attributes(self) -> dict[str, Any]:
        """The dataset's attributes beyond the provenance: the fixed settings of every point."""
        fixed = dict(self.fixed)
        model, law, _ = self.run.build()  # every setting of a point, defaults resolved
        settings = {**model.as_dict(), **law.values(), "x0": self.run.x0, "v0": self.run.v0}
        per_point = self._defaults_per_point(law)
        for key, value in settings.items():
            if key in GRID_KEYS and key not in self.axes and key not in per_point and value is not None:
                fixed.setdefault(key, value)
        attrs: dict[str, Any] = {f"fixed_{k}": float(v) for k, v in fixed.items()}
        attrs.update({"friction": self.run.friction, "solver": self.run.solver, "stick_force": self.run.stick_force,
                      "t_end": self.run.t_end})
        return attrs

    def _defaults_per_point(self, law: Any) -> set[str]:
        """The law's parameters left to defaults that follow an axis (Stribeck's F_s = 2 F_d over an ``fd`` axis):
        no fixed value to record."""
        values = self.run.values()
        out: set[str] = set()
        for axis, grid in self.axes.items():
            resolved = with_defaults(law.parameters, {**values, axis: np.asarray(grid, dtype=float)})
            out |= {k for k, v in resolved.items() if k != axis and np.ndim(v) and np.ptp(np.asarray(v, dtype=float)) > 0}
        return out

    def point_params(self, index: tuple[np.ndarray, ...]) -> dict[str, np.ndarray]:
        """Per-point parameter arrays for grid indices (one index array per axis)."""
        base = self.run
        n = len(index[0]) if index else 1
        out: dict[str, np.ndarray] = {}
        for key in GRID_KEYS:
            if key in self.axes:
                out[key] = self.axes[key][index[self.dims.index(key)]]
            elif key in self.sample:  # drawn: one value per point of the sample axis
                out[key] = self.sample[key][index[self.dims.index(SAMPLE)]]
            else:
                val = getattr(base, key)  # None (NaN): a default that depends on other values
                out[key] = np.full(n, np.nan if val is None else float(val))
        return out


def _value(key: str, where: str, value: Any) -> float:
    """One grid value, checked by the parameter's declaration (a boolean or text is not a number)."""
    try:
        return float(declared()[key].check(value))
    except ValueError as e:
        raise ValueError(f"{where}: {e}") from None


def _plain(value: Any) -> Any:
    """A value from the Python API as TOML gives it: a tuple or an array a list, a numpy scalar a number
    (a table's entries and a list's items too), so that every check and the recorded source see one form."""
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.ndarray, np.generic)):
        return value.tolist()  # an array: nested lists of Python scalars; a numpy scalar: its Python scalar
    return value


def _count(where: str, value: Any) -> int:
    value = _plain(value)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not float(value).is_integer() \
            or not 1 <= value <= MAX_AXIS:
        raise ValueError(f"{where} must be an integer in [1, {MAX_AXIS}], got {value!r}")
    return int(value)


def _axis(key: str, value: Any, number: Callable[[str, str, Any], float] | None = None) -> np.ndarray | float:
    """A grid entry: a number (fixed), a list, {start, stop, num, scale} or "FROM:TO:N" (the CLI's range).

    ``number(key, where, value)`` checks one value (default: the declared parameter ``key``'s check).
    """
    check_value = _value if number is None else number
    where, value = f"grid.{key}", _plain(value)
    if isinstance(value, str):
        if ":" not in value:  # no range meant: name every form a grid entry takes
            raise ValueError(f"{where} must be a number, a list, a {{start, stop, num, scale}} table or "
                             f"\"FROM:TO:N\", got {value!r}")
        r = parse_range(where, value)
        value = {"start": r.start, "stop": r.stop, "num": r.num}
    if isinstance(value, bool):
        raise ValueError(f"{where} must be a number, a list or a {{start, stop, num, scale}} table, got {value!r}")
    if isinstance(value, (int, float)):
        return check_value(key, where, value)
    if isinstance(value, list):
        if not value:
            raise ValueError(f"{where} is an empty list; give at least one value")
        if len(value) > MAX_AXIS:
            raise ValueError(f"{where} has {len(value)} values; at most {MAX_AXIS}")
        arr = np.array([check_value(key, f"{where}[{i}]", v) for i, v in enumerate(value)])
        if len(np.unique(arr)) != len(arr):
            raise ValueError(f"{where} has repeated values")
        return arr
    if isinstance(value, Mapping):
        allowed = {"start", "stop", "num", "scale"}
        extra = set(value) - allowed
        if extra:
            raise ValueError(f"{where}: unknown key {sorted(extra)[0]!r}; allowed: num, scale, start, stop")
        missing = {"start", "stop", "num"} - set(value)
        if missing:
            raise ValueError(f"{where}: missing {', '.join(sorted(missing))}")
        start = check_value(key, f"{where}.start", value["start"])
        stop = check_value(key, f"{where}.stop", value["stop"])
        num = _count(f"{where}.num", value["num"])
        scale = check.choice(f"{where}.scale", value.get("scale", "linear"), ("linear", "log"))
        if num > 1 and start == stop:
            raise ValueError(f"{where}: start == stop with num > 1 gives repeated values")
        if num == 1 and start != stop:  # (linspace would keep start and drop stop without a word)
            raise ValueError(f"{where}: num = 1 holds one value, but start {start:g} and stop {stop:g} differ; "
                             "give num >= 2, or the value alone")
        if scale == "log":
            if start <= 0 or stop <= 0:
                raise ValueError(f"{where}: a log axis needs start > 0 and stop > 0, got {start:g}, {stop:g}")
            return decimal_values(np.geomspace(start, stop, num))
        return decimal_values(np.linspace(start, stop, num))
    raise ValueError(f"{where} must be a number, a list or a {{start, stop, num, scale}} table, got {value!r}")


def _sample(value: Any) -> dict[str, np.ndarray]:
    """``{num, seed, x0 = [low, high], v0 = [low, high]}``: the drawn values of each sampled parameter."""
    where = f"grid.{SAMPLE}"
    if not isinstance(value, Mapping):
        raise ValueError(f"{where} must be a table {{num, seed, x0 = [low, high], v0 = [low, high]}}, got {value!r}")
    extra = set(value) - {"num", "seed", *SAMPLE_KEYS}
    if extra:
        raise ValueError(f"{where}: unknown key {sorted(extra)[0]!r}; allowed: num, seed, {', '.join(SAMPLE_KEYS)}")
    if "num" not in value or not set(SAMPLE_KEYS) & set(value):
        raise ValueError(f"{where}: needs num and at least one of {', '.join(SAMPLE_KEYS)}")
    num = _count(f"{where}.num", value["num"])
    seed = _plain(value.get("seed", 0))
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**63:
        raise ValueError(f"{where}.seed must be an integer in [0, 2^63), got {seed!r}")
    keys = [k for k in SAMPLE_KEYS if k in value]  # declaration order: the same draw whatever the table's order
    bits = np.random.PCG64(seed).random_raw(num * len(keys)).reshape(num, len(keys))
    unit = (bits >> np.uint64(11)).astype(np.float64) * 2.0**-53  # uniform in [0, 1), from the raw stream only
    out = {}
    for j, key in enumerate(keys):
        bounds = _plain(value[key])
        if not isinstance(bounds, list) or len(bounds) != 2:
            raise ValueError(f"{where}.{key} must be a range [low, high], got {bounds!r}")
        low, high = (_value(key, f"{where}.{key}[{i}]", b) for i, b in enumerate(bounds))
        if low > high:
            raise ValueError(f"{where}.{key}: low {low:g} > high {high:g}")
        out[key] = low + (high - low) * unit[:, j]
    return out


def _ranges(cfg: SweepConfig):
    """(key, values) of every parameter that varies: the axes, and the sample's draws instead of its index."""
    yield from ((k, a) for k, a in cfg.axes.items() if k != SAMPLE)
    yield from cfg.sample.items()


def parse_sweep(values: Mapping[str, Any], source: str = "config", *, check_points: bool = True) -> SweepConfig:
    """Validate a sweep config mapping (a parsed TOML file).

    Parameters
    ----------
    values:
        The mapping: simulate's settings plus a ``grid`` table.
    source:
        How error messages name where it came from (a file's path).
    check_points:
        False skips what only needs checking once per sweep (every axis's
        extremes, memory, step warnings): for the chunks of a validated sweep.
    """
    values = dict(values)
    grid = _plain(values.pop("grid", None))
    if grid is None or not isinstance(grid, Mapping) or not grid:
        raise ValueError(f"{source}: a non-empty [grid] table of parameters to sweep is required")
    dimensional = values.get("dimensional")
    if dimensional is not None:
        values, grid = _dimensionless(values, grid, source)
    for key in NOT_IN_SWEEPS:
        if key in values:
            raise ValueError(f"{source}: key {key!r} is not used by sweeps")
    unknown = [k for k in grid if k not in GRID_KEYS and k != SAMPLE]
    if unknown:
        raise ValueError(f"{source}: unknown grid key {unknown[0]!r}; allowed: {', '.join((*GRID_KEYS, SAMPLE))}")
    sample = _sample(grid[SAMPLE]) if SAMPLE in grid else {}
    both = [k for k in [*grid, *sample] if k in values]
    if both:
        raise ValueError(f"{source}: {both[0]!r} is given both at the top level and in [grid]")
    twice = [k for k in sample if k in grid]
    if twice:
        raise ValueError(f"{source}: {twice[0]!r} is both sampled (grid.{SAMPLE}) and a [grid] entry")
    axes: dict[str, np.ndarray] = {}
    fixed: dict[str, float] = {}
    for key, val in grid.items():
        a = np.arange(len(next(iter(sample.values()))), dtype=float) if key == SAMPLE else _axis(key, val)
        if isinstance(a, np.ndarray):
            axes[key] = a
        else:
            fixed[key] = a
    run = _auto_on_a_moving_belt(RunConfig.from_mapping({**values, **fixed}, source=source), axes, sample, source)
    _, law, solver = run.build()
    if solver.batched is None and not law.internal_names:  # (internal states: each point a run on the threads)
        raise ValueError(f"{source}: sweeps cannot run friction={law.name} with solver={solver.name}: it has no batched kernel")
    if not axes:
        raise ValueError(f"{source}: [grid] fixes every parameter; give at least one list or range to sweep")
    points = math.prod(len(a) for a in axes.values())
    if points > MAX_POINTS:
        raise ValueError(f"{source}: the grid has {points:.3g} points; at most {MAX_POINTS:.0e}")
    recorded = {"settings": values, "grid": {k: _jsonable(v) for k, v in grid.items()}}
    if dimensional is not None:
        recorded["dimensional"] = _jsonable(dimensional)
    cfg = SweepConfig(run=run, axes=axes, fixed=fixed, source=recorded, sample=sample)
    if check_points:
        _check_points(cfg)
        _check_size(cfg)
    return cfg


def _dimensionless(values: Mapping[str, Any], grid: Mapping[str, Any], source: str) -> tuple[dict, dict]:
    """A sweep with a ``dimensional`` table as the non-dimensional sweep it is: the table's parameters converted,
    and each [grid] entry named by a dimensional key (``v_b``, ``sigma0``, ``dc``) divided by its dimension's unit
    and named by its parameter (``vb``, ...); a parameter the table sets is refused by its non-dimensional name."""
    given = RunConfig.checked(values, source=source)
    refuse_mixing(given, source)
    table = given["dimensional"]
    known = dimensional_parameters()
    both = [k for k in grid if k not in known and set_by_dimensional(k)]
    if both:
        key = declared()[both[0]].dimensional_key or "c"
        raise ValueError(f"{source}: grid.{both[0]}: with dimensional, sweep it as grid.{key} (dimensional values)")
    scales = [k for k in grid if k in SCALE_KEYS]
    if scales:
        raise ValueError(f"{source}: grid.{scales[0]}: m, c, k and l_0 set the units of dimensional, not a sweep axis")
    axes = {k: known[k] for k in grid if k in known}
    out = {known[k].name if k in axes else k: _scaled(f"grid.{k}", v, unit_of(axes[k].dimension, table["m"], table["k"],
                                                                               table.get("l_0", 1.0)))
           if k in axes else v for k, v in grid.items()}
    friction = given.get("friction", declared()["friction"].default)
    # an axis's key: any value, dropped (f_d too: the table's f_ms is checked against it per point)
    filled = {**table, **{k: 0.0 for k in (*DIMENSIONAL_REQUIRED, "f_d") if k in axes}}
    nd = nondimensional_values({**given, "dimensional": filled}, friction, present=tuple(axes))
    swept = {p.name for p in axes.values()}
    return {k: v for k, v in nd.items() if k != "dimensional" and k not in swept}, out


def _scaled(where: str, entry: Any, unit: float) -> Any:
    """A grid entry (number, list, range table, "FROM:TO:N") with every value divided by ``unit``."""
    if isinstance(entry, str):
        r = parse_range(where, entry)
        entry = {"start": r.start, "stop": r.stop, "num": r.num}
    if isinstance(entry, Mapping):
        return {k: check.finite(f"{where}.{k}", v) / unit if k in ("start", "stop") else v for k, v in entry.items()}
    if isinstance(entry, list):
        return [check.finite(f"{where}[{i}]", v) / unit for i, v in enumerate(entry)]
    return check.finite(where, entry) / unit if isinstance(entry, (int, float)) and not isinstance(entry, bool) else entry


def _warn_coarse_steps(cfg: SweepConfig) -> None:
    """RK4's step warnings of ``simulate``, for the extreme values of every axis (once each)."""
    found: list[str] = []
    for key, arr in _ranges(cfg):
        for val in (arr.min(), arr.max()):
            # the sweep's solver, not the settings' (auto, which would pick exact where this point's belt stands still)
            run = RunConfig.from_mapping({**cfg.source["settings"], **cfg.fixed, "solver": cfg.run.solver,
                                          key: float(val)}, source="grid")
            model, law, solver = run.build()
            x0, v0 = law.start(model.vb, run.x0, run.v0)
            found += [f"grid.{key} = {val:g}: {m}" for m in solver.check_step(model, law, x0, v0)]
    for message in found[:3]:
        warnings.warn(message, CoarseStepWarning, stacklevel=3)


def _check_size(cfg: SweepConfig) -> None:
    """Each parallel point's samples must fit max_memory; RK4's steps must be countable."""
    import numba

    model, _, solver = cfg.run.build()
    if solver.fixed_step:
        solver.steps(cfg.run.t_end)  # the batched fixed-step kernel keeps section records, not samples
        _warn_coarse_steps(cfg)
        return
    threads = numba.get_num_threads()
    check_memory(solver.sample_estimate(cfg.run.t_end, model) * threads, cfg.run.max_memory,
                 f"{solver.sized(cfg.run.t_end)} on {threads} threads")


def _jsonable(v: Any) -> Any:
    return dict(v) if isinstance(v, Mapping) else v


def _check_points(cfg: SweepConfig) -> None:
    """Every value on every axis must make a valid model, law and solver (checked per axis, extremes suffice)."""
    for key, arr in _ranges(cfg):
        for val in (arr.min(), arr.max()):
            try:
                RunConfig.from_mapping({**cfg.source["settings"], **cfg.fixed, key: float(val)}, source="grid")
            except ValueError as e:
                raise ValueError(f"grid.{key}: {val:g} is not valid ({e})") from None
    _check_resonance(cfg)
    _check_belt(cfg)
    # F_s >= F_d must hold across both axes together
    fd = cfg.axes.get("fd", np.array([cfg.run.fd]))
    fs = cfg.axes.get("fs")
    if fs is not None and "fd" in {p.name for p in law_class(cfg.run.friction).parameters} and fs.min() < fd.max():
        raise ValueError(f"grid.fs: every F_s must be >= every F_d (min fs {fs.min():g} < max fd {fd.max():g})")


def _grid_values(cfg: SweepConfig, key: str) -> np.ndarray:
    """The values ``key`` takes on the grid: its axis, its sample, or the one fixed value."""
    found = cfg.axes.get(key, cfg.sample.get(key))
    return np.asarray(found if found is not None else [getattr(cfg.run, key)], dtype=float)


def _auto_on_a_moving_belt(run: RunConfig, axes: Mapping[str, np.ndarray], sample: Mapping[str, np.ndarray],
                           source: str) -> RunConfig:
    """``solver = auto`` on a grid whose belt moves at some point: the solver auto picks for a moving belt,
    for every point (one solver per sweep, as a moving belt's points need).

    A grid whose belt also stands still somewhere, where auto picks another solver, is refused: a sweep runs one
    solver, and its still points would not be what ``simulate`` (auto) gives there (Karnopp: exact there, RK4 on
    the moving belt, periods 0.5% apart).
    """
    amp = axes.get("vb_amplitude", sample.get("vb_amplitude"))
    if amp is None or not np.max(amp) > 0.0 or run.solver != "auto":
        return run
    model, law, _ = run.build()
    name = run.make_solver(law, replace(model, vb_amplitude=float(np.max(amp)))).name
    still = run.make_solver(law, replace(model, vb_amplitude=0.0)).name
    if np.min(amp) == 0.0 and still != name:
        raise ValueError(f"{source}: solver = auto picks {still} where grid.vb_amplitude = 0 and {name} where it is "
                         f"> 0, and a sweep runs one solver; set solver explicitly (solver = \"{name}\" runs every point)")
    return RunConfig.from_mapping({**run.given, "solver": name}, source=source)


def _check_belt(cfg: SweepConfig) -> None:
    """A moving belt (vb_amplitude > 0 at some point): the solver must run it, and where an external force acts too
    the two must share the stroboscopic period (vb_omega = omega, fixed); refused before any work."""
    if not _grid_values(cfg, "vb_amplitude").max() > 0.0:
        return
    _, law, solver = cfg.run.build()
    refusal = belt_motion_refusal(solver, law)
    if refusal:
        raise ValueError(f"grid: {refusal}")
    om, omb = _grid_values(cfg, "omega"), _grid_values(cfg, "vb_omega")
    if _grid_values(cfg, "fex").max() > 0.0 and (len(om) > 1 or len(omb) > 1 or om[0] != omb[0]):
        raise ValueError("grid: points with both an external force and a moving belt need vb_omega equal to omega, "
                         "both fixed (the period their stroboscopic classification shares)")


def _check_resonance(cfg: SweepConfig) -> None:
    """A forced point the solver refuses (the exact solver: undamped resonance): refuse the grid before any work."""
    solver = cfg.run.build()[2]

    def values(key: str) -> np.ndarray:
        return _grid_values(cfg, key)

    # the worst point of the grid: undamped if any point is, at omega = 1 if any point is, the largest forcing
    zeta = 0.0 if np.any(values("zeta") == 0.0) else 1.0
    omega = 1.0 if np.any(values("omega") == 1.0) else 0.5
    problem = solver.forcing_problem(zeta, omega, float(values("fex").max()))
    if problem:
        raise ValueError(f"grid: a point has {problem.split(': ', 1)[-1]}")


def load_sweep(path: str) -> SweepConfig:
    """Read and validate a sweep config file.

    Parameters
    ----------
    path:
        A TOML file: simulate's settings plus a ``[grid]`` table.
    """

    return parse_sweep(read_config(path), source=str(path))


def chunk_shape(shape: tuple[int, ...], target: int) -> tuple[int, ...]:
    """Chunks of about ``target`` points, filling the last axes first (C order)."""
    out = []
    left = max(1, target)
    for n in reversed(shape):
        c = max(1, min(n, left))
        out.append(c)
        left = max(1, left // c)
    return tuple(reversed(out))


def n_chunks(shape: tuple[int, ...], chunks: tuple[int, ...]) -> tuple[int, ...]:
    return tuple(math.ceil(n / c) for n, c in zip(shape, chunks))
