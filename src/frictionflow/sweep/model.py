"""Sweeps over a model file's entries: every point a :class:`~frictionflow.system.System` run and analysed.

::

    model = "chain.toml"      # relative to this file
    t_end = 300.0
    rtol = 1e-6               # optional: the steady state's repeat tolerance (simulate --model's)

    [grid]
    "contact.0.belt" = "0.01:0.1:10"     # quoted: the address is one key
    "spring.1.k" = [0.5, 1.0]
    "damper.0.c" = 0.05                  # a number: fixed, not an axis

Each point is ``simulate_system(system.with_entry(...)..., t_end)`` (on ``simulate --model``'s solver) and
:func:`~frictionflow.analysis.structure.analyze_structure`; a chunk's points run on
numba's threads at once (:func:`compute_model_chunk`).
The dataset's dims are the axes (named by their addresses); its variables
are the steady state's kind (a flag variable), period and stick fraction per
contact, the average powers per element (``P`` over ``element``: the springs,
dampers and forces; ``P_belt`` and ``P_heat`` over ``contact``), ``X_max``
and ``X_min`` over ``dof`` and the energy residual.  The store, its chunks,
resume, verification and Dask are the single-mass sweep's
(:mod:`frictionflow.sweep.store`, :mod:`frictionflow.sweep.runner`), given
this table of variables.
"""

from __future__ import annotations

import difflib
import itertools
import json
import math
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Mapping

import numpy as np

from ..analysis.structure import STRUCTURE_KINDS, analyze_structure, evaluations, swing_period
from ..core.threads import over_points
from ..estimate import Estimate
from ..io import read_config
from ..solvers.structure import AUTO, check_switchable, simulate_system, structure_solver_for, structure_solvers
from ..system import System, assemble, load_system
from .compute import chunk_slices
from .config import MAX_POINTS, Grid, Variable, _axis, parse_sweep

#: the top-level keys of a model sweep (besides ``grid``)
MODEL_KEYS = ("model", "t_end", "rtol")
#: simulate --model's defaults
T_END = 300.0
RTOL = 1e-6
#: grid values checked one by one through System.with_entry, per axis, at most (beyond: the extremes)
CHECK_EACH = 1000
#: up to this many axes, every corner of the grid is checked as a whole system (entries checked together)
CHECK_CORNERS = 6
#: the model-sweep's probe run for the estimate: at most this many of the structure's slowest natural periods
#: (its run's cost is scaled to t_end) -- about 50 time units for unit masses and springs
PROBE_SWINGS = 8.0
#: ... or, for a structure without a time scale of its own (masses on belts alone), this share of t_end
PROBE_SHARE = 0.05
#: the most states the estimate evaluates to time the analysis's grids
GRID_PROBE = 20_000
#: points per chunk (a chunk is a unit of commit and a Dask task)
CHUNK_POINTS = 8
#: pieces per thread in a chunk: one point each (a point costs milliseconds to seconds: the threads
#: finish together when each takes the next point)
POINTS_PER_PIECE = CHUNK_POINTS


@dataclass
class ModelSweepConfig(Grid):
    """A validated sweep over a model's entries: the base system, the axes, the run's length."""

    system: System  #: the model with the fixed grid entries applied
    axes: dict[str, np.ndarray]  #: entry address -> its values, in the grid's order
    t_end: float
    rtol: float = RTOL
    fixed: dict[str, float] = field(default_factory=dict)  #: entries given one value in the grid
    source: dict[str, Any] = field(default_factory=dict)  #: the model (as a mapping), settings and grid
    model_file: str | None = None  #: the model file, for the dataset's attributes
    sample: dict[str, np.ndarray] = field(default_factory=dict)  #: (no sampled axes in a model sweep)

    @property
    def solver(self) -> str:
        """The structure solver the base model runs on: ``simulate --model``'s choice (``auto``: the first that
        runs every contact's law and, where the structure has an undamped free motion, that too).  Each point
        takes its own (:func:`point_rows`): a point whose entries free a motion (a damper of 0) runs on the
        solver that runs it, as ``simulate --model`` at that point does."""
        return structure_solver_for(self.system)

    @property
    def labels(self) -> dict[str, tuple[str, ...]]:
        """The labels of the variables' dims beyond the grid's (a dim without labels is left out)."""
        s = self.system
        found = {"contact": s.contact_names, "element": s.spring_names + s.damper_names + s.force_names, "dof": s.dof}
        return {k: v for k, v in found.items() if v}

    @property
    def variables(self) -> tuple[Variable, ...]:
        """The result variables, in the order :func:`compute_model_chunk` returns them."""
        kinds = ", ".join(f"{i} {k.replace('_', ' ')}" for i, k in enumerate(STRUCTURE_KINDS))
        solvers = ", ".join(f"{i} {k}" for i, k in enumerate(structure_solvers()))
        table = [
            Variable("kind", "1", f"steady state: {kinds}", "i1", STRUCTURE_KINDS),
            Variable("solver", "1", f"the solver that ran the point: {solvers}", "i1", structure_solvers()),
            Variable("period", "", "period of the periodic steady state (NaN unless periodic)"),
            Variable("stick_fraction", "1", "share of the steady-state window the contact spends stuck", dims=("contact",)),
            Variable("P", "", "time-averaged power the element puts into the structure", dims=("element",)),
            Variable("P_belt", "", "time-averaged power the belt delivers through the contact (F b)", dims=("contact",)),
            Variable("P_heat", "", "time-averaged heat generated at the contact (F V_r)", dims=("contact",)),
            Variable("X_max", "", "maximum of the coordinate over the steady-state window", dims=("dof",)),
            Variable("X_min", "", "minimum of the coordinate over the steady-state window", dims=("dof",)),
            Variable("energy_residual", "1", "relative residual of the energy balance over the window"),
            Variable("t_lost", "", "time the contact's normal load reached zero, ending the run (NaN unless this "
                     "contact was lost)", dims=("contact",)),
        ]
        labels = self.labels
        return tuple(v for v in table if all(d in labels for d in v.dims))

    def axis_attrs(self, name: str) -> dict[str, str]:
        """The attributes of the axis ``name`` (an entry's address)."""
        return {"long_name": f"model entry {name}"}

    def attributes(self) -> dict[str, Any]:
        """The dataset's attributes beyond the provenance."""
        attrs: dict[str, Any] = {f"fixed_{k}": float(v) for k, v in self.fixed.items()}
        attrs.update({"model": json.dumps(self.source["model"], sort_keys=True, default=str), "solver": self.solver,
                      "t_end": self.t_end, "rtol": self.rtol})
        if self.model_file is not None:
            attrs["model_file"] = self.model_file
        return attrs

    def point_system(self, index: tuple[int, ...]) -> System:
        """The system at grid index ``index`` (one integer per axis)."""
        return self.system.with_entries({a: float(values[i]) for (a, values), i in zip(self.axes.items(), index)})

    def point_text(self, index: tuple[int, ...]) -> str:
        """The grid point at ``index`` in a line: ``grid point (entry = value, ...)``."""
        return "grid point (" + ", ".join(f"{k} = {float(a[i]):g}" for (k, a), i in zip(self.axes.items(), index)) + ")"


def flat_grid(grid: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """``[grid]`` with TOML's nested tables (an unquoted ``contact.0.belt = ...``) joined back into addresses.

    A table of range keys (``start``, ``stop``, ``num``, ``scale``) is a value, not a level.
    """
    out: dict[str, Any] = {}
    for key, value in grid.items():
        address = f"{prefix}{key}"
        if isinstance(value, Mapping) and value and not set(value) <= {"start", "stop", "num", "scale"}:
            out.update(flat_grid(value, address + "."))
        else:
            out[address] = value
    return out


def _unknown_entry(source: str, key: str, system: System) -> ValueError:
    """One line: the unknown address and a few valid ones (the closest first); a valid entry followed by a key
    (a range table with a misspelt key, which :func:`flat_grid` took for a level) is named as the single mass's
    sweep names it."""
    valid = system.entries()
    entry, _, last = key.rpartition(".")
    if not last.isdigit() and is_entry(system, entry):  # a digit is an index (mass.0.5), never a range key
        return ValueError(f"{source}: grid.{entry}: unknown key {last!r}; allowed: num, scale, start, stop")
    near = difflib.get_close_matches(key, valid, n=4, cutoff=0.5)
    shown = list(dict.fromkeys([*near, *valid]))[:6]
    return ValueError(f"{source}: unknown grid key {key!r}: not an entry of the model; its entries include "
                      f"{', '.join(shown)} ({len(valid)} in all: System.entries())")


def is_entry(system: System, address: str) -> bool:
    """Whether ``address`` is a numeric entry :meth:`System.with_entry <frictionflow.system.System.with_entry>` sets:
    the addresses :meth:`System.entry <frictionflow.system.System.entry>` reads (``stability --vary``'s test), with
    a number there.  That is more than :meth:`~frictionflow.system.System.entries` lists: ``mass.0.1`` of a diagonal
    mass (it makes the mass a full matrix), a direction's or a normal load's dof it does not give yet."""
    try:
        value = system.entry(address)
    except (ValueError, TypeError):
        return False
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _number(source: str):
    """``number(key, where, value)`` for :func:`~frictionflow.sweep.config._axis`: a finite number (the model's own
    checks follow, on whole systems: :func:`_check_values`, :func:`_check_corners`)."""

    def number(key: str, where: str, value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{source}: {where} must be a finite number, got {value!r}")
        return float(value)

    return number


def _settings(values: Mapping[str, Any], source: str) -> tuple[float, float]:
    """t_end and rtol, checked."""
    unknown = [k for k in values if k not in MODEL_KEYS]
    if unknown:
        raise ValueError(f"{source}: key {unknown[0]!r} is not used by a model sweep (allowed: {', '.join(MODEL_KEYS)}, "
                         "[grid]; the model's own entries go in the model file or the grid)")
    t_end, rtol = values.get("t_end", T_END), values.get("rtol", RTOL)
    if isinstance(t_end, bool) or not isinstance(t_end, (int, float)) or not (math.isfinite(t_end) and t_end > 0):
        raise ValueError(f"{source}: t_end must be a finite number > 0, got {t_end!r}")
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float)) or not 0.0 < rtol < 1.0:
        raise ValueError(f"{source}: rtol must be a number in (0, 1), got {rtol!r}")
    return float(t_end), float(rtol)


def parse_model_sweep(values: Mapping[str, Any], system: System, source: str = "config", *,
                      check_points: bool = True, model_file: str | None = None) -> ModelSweepConfig:
    """Validate a model sweep: the settings, and a ``[grid]`` of entry addresses of ``system``.

    Parameters
    ----------
    values:
        The sweep's mapping (a parsed TOML file): ``t_end``, ``rtol`` and ``grid`` (``model`` is read by the caller).
    system:
        The model the grid's addresses refer to.
    source:
        How error messages name where it came from.
    check_points:
        False skips checking each value and the grid's corners (for the chunks of a validated sweep).
    model_file:
        The model file's path, recorded in the dataset's attributes.
    """
    values = {k: v for k, v in values.items() if k != "model"}
    grid = values.pop("grid", None)
    if grid is None or not isinstance(grid, Mapping) or not grid:
        raise ValueError(f"{source}: a non-empty [grid] table of model entries to sweep is required")
    t_end, rtol = _settings(values, source)
    grid = flat_grid(grid)
    unknown = [k for k in grid if not is_entry(system, k)]
    if unknown:
        raise _unknown_entry(source, unknown[0], system)
    number = _number(source) if check_points else (lambda key, where, value: float(value))
    axes: dict[str, np.ndarray] = {}
    fixed: dict[str, float] = {}
    for key, val in grid.items():
        a = _axis(key, val, number)
        if isinstance(a, np.ndarray):
            axes[key] = a
        else:
            fixed[key] = a
    if not axes:
        raise ValueError(f"{source}: [grid] fixes every entry; give at least one list or range to sweep")
    points = math.prod(len(a) for a in axes.values())
    if points > MAX_POINTS:
        raise ValueError(f"{source}: the grid has {points:.3g} points; at most {MAX_POINTS:.0e}")
    base = _with_fixed(system, fixed, source) if check_points else system.with_entries(fixed)
    cfg = ModelSweepConfig(base, axes, t_end, rtol, fixed, {"model": system.to_dict(), "settings": values, "grid": dict(grid)},
                           model_file)
    if check_points:
        for key, val in grid.items():
            if key in axes:
                _check_values(cfg, key, _checked_places(key, val, axes[key]), source)
        _check_corners(cfg, source)
        _check_switchable(cfg, source)
    return cfg


def _check_switchable(cfg: ModelSweepConfig, source: str) -> None:
    """Contacts along dependent directions at any grid point, refused before anything runs (the engines cannot
    hold them stuck, :func:`~frictionflow.solvers.structure.check_switchable`): every point when an axis moves a
    contact's direction (directions are few values), else the fixed entries' model once."""
    moving = [k for k in cfg.axes if k.startswith("contact.") and ".on." in k]
    points = np.ndindex(*(len(a) for a in cfg.axes.values())) if moving else [None]
    for index in points:
        system = cfg.system if index is None else cfg.point_system(index)
        try:
            check_switchable(assemble(system), system.contact_names)
        except ValueError as e:
            at = "" if index is None else f"{cfg.point_text(index)}: "
            raise ValueError(f"{source}: {at}{e}") from None


def _with_fixed(system: System, fixed: Mapping[str, float], source: str) -> System:
    """``system`` with the grid's fixed entries set together (the model's message names the entry at fault)."""
    try:
        return system.with_entries(fixed)
    except (ValueError, TypeError) as e:
        at = ", ".join(f"{k} = {v:g}" for k, v in fixed.items())
        raise ValueError(f"{source}: the grid's fixed entries ({at}) are not a valid model: {e}") from None


def _checked_places(key: str, given: Any, values: np.ndarray) -> list[tuple[str, float]]:
    """(where, value) of an axis's values checked one by one: a list's each (its extremes only beyond CHECK_EACH
    values: the corners check those), a range's ends."""
    where = f"grid.{key}"
    if isinstance(given, list):
        if len(values) > CHECK_EACH:
            return []
        return [(f"{where}[{i}]", float(v)) for i, v in enumerate(values)]
    return [(f"{where}.start", float(values[0])), (f"{where}.stop", float(values[-1]))]


def _check_values(cfg: ModelSweepConfig, key: str, places: list[tuple[str, float]], source: str) -> None:
    """Each value a valid entry of the model: with the other entries as given, or else at some corner of the other
    axes (entries that bound each other, such as ``fd`` and ``fs``, are judged together: :func:`_check_corners`)."""
    others = {k: sorted({float(a.min()), float(a.max())}) for k, a in cfg.axes.items() if k != key}
    for where, v in places:
        try:
            cfg.system.with_entry(key, v)
            continue
        except (ValueError, TypeError) as e:
            first = e
        for corner in itertools.product(*others.values()):
            try:
                cfg.system.with_entries({key: v, **dict(zip(others, corner))})
                break
            except (ValueError, TypeError):
                continue
        else:
            raise ValueError(f"{source}: {where} = {v!r}: {first}") from None


def _check_corners(cfg: ModelSweepConfig, source: str) -> None:
    """Every axis's extremes, and (up to CHECK_CORNERS axes) every corner of the grid as a whole system."""
    ends = {k: sorted({float(a.min()), float(a.max())}) for k, a in cfg.axes.items()}
    combos = itertools.product(*ends.values()) if len(ends) <= CHECK_CORNERS else \
        ([*(v[0] for v in ends.values())], [*(v[-1] for v in ends.values())])
    for corner in combos:
        try:
            cfg.system.with_entries(dict(zip(ends, corner)))
        except (ValueError, TypeError) as e:
            at = ", ".join(f"{k} = {v:g}" for k, v in zip(ends, corner))
            raise ValueError(f"{source}: grid point ({at}) is not a valid model: {e}") from None


def load_model_sweep(path: str | Path, values: Mapping[str, Any] | None = None) -> ModelSweepConfig:
    """Read and validate a model sweep file (its ``model`` relative to the file).

    Parameters
    ----------
    path:
        The sweep's TOML file.
    values:
        Its parsed contents, if already read.
    """
    values = read_config(path) if values is None else values
    model = values.get("model")
    if not isinstance(model, str) or not model:
        raise ValueError(f"{path}: model must be the path of a model file (relative to {path}), got {model!r}")
    where = Path(model) if Path(model).is_absolute() else Path(path).parent / model
    if not where.is_file():
        raise ValueError(f"{path}: model: {str(where)!r} is not a file")
    return parse_model_sweep(values, load_system(where), source=str(path), model_file=str(where))


def load_any_sweep(path: str | Path):
    """A sweep file: a model sweep when it names a ``model``, else the single-mass sweep (:func:`~.config.load_sweep`).

    Parameters
    ----------
    path:
        The sweep's TOML file.
    """
    values = read_config(path)
    if "model" in values:
        return load_model_sweep(path, values)
    return parse_sweep(values, source=str(path))


def config_from_source(source: Mapping[str, Any], name: str = "config"):
    """The sweep a recorded ``source`` (:attr:`SweepConfig.source`) describes, without re-checking its points.

    Parameters
    ----------
    source:
        ``{"settings", "grid"}`` of a single-mass sweep, plus ``"model"`` (the model's mapping) for a model sweep.
    name:
        How error messages name where it came from.
    """
    if "model" in source:
        system = System.from_dict(source["model"], source=None)
        return parse_model_sweep({**source["settings"], "grid": source["grid"]}, system, name, check_points=False)
    return parse_sweep({**source["settings"], "grid": source["grid"]}, source=name, check_points=False)


def point_rows(cfg: ModelSweepConfig, system: System) -> list[np.ndarray]:
    """One point's values, one array per variable of ``cfg.variables`` (over its extra dims)."""
    result = analyze_structure(simulate_system(system, cfg.t_end, solver=AUTO), rtol=cfg.rtol)
    ss = result.steady_state
    lost = result.motion.lost  # (contact name, time) where a normal load reached zero, else None
    labels = cfg.labels
    elements = result.elements
    amp = result.amplitude

    def over(dim: str, get) -> np.ndarray:
        return np.array([get(name) for name in labels[dim]], dtype=float)

    values = {
        "kind": np.array(STRUCTURE_KINDS.index(ss.kind)),
        "solver": np.array(structure_solvers().index(result.motion.solver)),  # auto may rerun a point elsewhere
        "period": np.array(ss.period),
        "stick_fraction": np.array(ss.stick_fraction, dtype=float),
        "P": over("element", lambda e: elements.get(e, {}).get("P", math.nan)) if "element" in labels else None,
        "P_belt": over("contact", lambda c: elements.get(c, {}).get("P_belt", math.nan)) if "contact" in labels else None,
        "P_heat": over("contact", lambda c: elements.get(c, {}).get("P_heat", math.nan)) if "contact" in labels else None,
        "X_max": over("dof", lambda d: amp.get("X_max", {}).get(d, math.nan)),
        "X_min": over("dof", lambda d: amp.get("X_min", {}).get(d, math.nan)),
        "energy_residual": np.array(result.energy_residual),
        "t_lost": over("contact", lambda c: lost[1] if lost is not None and lost[0] == c else math.nan)
        if "contact" in labels else None,
    }
    return [values[v.name] for v in cfg.variables]


@contextmanager
def said_at(cfg: ModelSweepConfig, index: tuple[int, ...]) -> Iterator[None]:
    """A run at grid ``index`` that raises (ValueError, RuntimeError: a model the solver refuses, a run that
    stops) says at which point, one of thousands: its line begins with :meth:`ModelSweepConfig.point_text`."""
    try:
        yield
    except (ValueError, RuntimeError) as e:
        e.args = (f"{cfg.point_text(index)}: {e}", *e.args[1:])
        raise


def compute_model_chunk(source: dict[str, Any], chunk: tuple[int, ...], chunks: tuple[int, ...]) -> list[np.ndarray]:
    """Results of one chunk of the model sweep ``source``: per variable, (*chunk's shape, *its extra dims).

    A pure function of its arguments (a Dask task): each point is
    ``analyze_structure(simulate_system(system at the point, t_end))``, the
    points spread over numba's threads (:func:`~frictionflow.core.threads.over_points`):
    the engines and the grid evaluations release the GIL (``nogil`` kernels:
    :func:`frictionflow.core.structure.run.run`, :func:`frictionflow.core.structure.adaptive.run`,
    :func:`~frictionflow.core.structure.evaluate.states`), so their compiled parts run at once.
    """
    cfg = config_from_source(source)
    sl = chunk_slices(chunk, chunks, cfg.shape)
    shape = tuple(s.stop - s.start for s in sl)
    labels = cfg.labels
    out = [np.empty(shape + tuple(len(labels[d]) for d in v.dims), dtype="f8") for v in cfg.variables]
    points = list(np.ndindex(*shape))

    def some(start: int, stop: int) -> None:  # each thread writes its own points' cells only
        for local in points[start:stop]:
            index = tuple(i + s.start for i, s in zip(local, sl))
            with said_at(cfg, index):
                rows = point_rows(cfg, cfg.point_system(index))
            for arr, row in zip(out, rows):
                arr[local] = row

    over_points(some, len(points), per_thread=POINTS_PER_PIECE)
    return out


def model_sweep_estimate(cfg: ModelSweepConfig, out: str | Path | None = None, name: str = "out") -> Estimate:
    """The sweep's cost from a probe: the grid's first point run for :func:`probe_length`, the run scaled to t_end,
    its analysis counted once and the analysis's grids timed at t_end's size (:func:`_grid_seconds`).

    The probe runs twice and the cheaper run counts: a process's first run also loads the kernels from numba's
    cache and imports the analysis's modules (most of a second probe's cost: the 600-point sweep of the
    stick-slip chain to t_end 1000, 50 s, was estimated at 1.4 h), and on an empty cache compiles them.

    A bound in the sense of the single-mass sweep's (the points run to
    t_end), counted on one core: a chunk's points share the cores, but their Python parts take turns.
    """
    first = (0,) * len(cfg.axes)
    system = cfg.point_system(first)
    probe_t = probe_length(assemble(system), cfg.t_end)
    seconds = []
    for _ in range(2):  # a process's first run also loads its kernels (seconds) or compiles them (minutes)
        start = time.process_time()
        with said_at(cfg, first):
            motion = simulate_system(system, probe_t, solver=AUTO)  # as the points run
        ran = time.process_time()
        analyze_structure(motion, rtol=cfg.rtol)
        seconds.append((ran - start, time.process_time() - ran))
    run, analysis = min(seconds, key=sum)
    per_point = run * cfg.t_end / probe_t + analysis + _grid_seconds(motion, cfg.t_end)
    work = Estimate(float(cfg.size), f"model points of t_end {cfg.t_end:g} (probe: {probe_t:g})",
                    per_point * cfg.size, cores=1)
    cells = sum(math.prod(len(cfg.labels[d]) for d in v.dims) for v in cfg.variables)
    return work.writing(out, float(cfg.size) * 8 * cells, name)


def probe_length(assembly: Any, t_end: float) -> float:
    """How long the estimate's probe runs: ``PROBE_SWINGS`` of the structure's slowest natural periods
    (:func:`~frictionflow.analysis.structure.swing_period`), at most t_end; ``PROBE_SHARE`` of t_end without
    any.  A length in its own units of time: 50 time units were 8 periods of a unit chain but 5e-6 of one in
    units of time 1e7 (a 5 s sweep estimated at 78 days) and 5e7 of them in microseconds (a probe running for
    minutes)."""
    swing = swing_period(assembly)
    return min(t_end, PROBE_SWINGS * swing if swing > 0.0 else PROBE_SHARE * t_end)


def _grid_seconds(motion: Any, t_end: float) -> float:
    """CPU seconds the analysis's evaluations of a run to ``t_end`` take (:func:`~frictionflow.analysis.
    structure.evaluations`), timed on at most GRID_PROBE states of the probe's ``motion``, on a grid and at
    scattered times, and scaled: the probe's own analysis is counted as it is, not scaled to t_end -- most of
    it, where the probe has not settled, is the largest Lyapunov exponent, a fixed number of blocks (scaling it
    made a sweep of points periodic by t_end 1000 look 200 times its cost)."""
    seconds = 0.0
    t0, t1 = float(motion.t[0]), float(motion.t[-1])
    for count, spread in zip(evaluations(motion, t_end), (False, True)):
        probe = max(1, min(count, GRID_PROBE if not spread else GRID_PROBE // 100))
        times = np.linspace(t0, t1, probe)  # scattered: a few per probe, each in a phase of its own
        start = time.process_time()
        motion.states(times)
        seconds += (time.process_time() - start) * count / probe
    return seconds


def default_model_chunk(cfg: ModelSweepConfig) -> int:
    """Points per chunk: CHUNK_POINTS (a kill loses at most one chunk's points)."""
    return max(1, min(CHUNK_POINTS, cfg.size))


__all__ = ["ModelSweepConfig", "compute_model_chunk", "config_from_source", "load_any_sweep", "load_model_sweep",
           "model_sweep_estimate", "parse_model_sweep"]
