"""Attractors told apart and labelled over a whole sweep dataset.

Labelling runs once, after the sweep, over every point together, so a label
means the same attractor in every chunk (and on every Dask worker): no chunk
names an attractor on its own.

What counts as one attractor
----------------------------
* **equilibrium** -- points of kind ``equilibrium``, told apart by their
  position X* (one for a single-valued slip law at V_b != 0);
* **periodic orbits** -- points of kind ``periodic``, told apart by their
  period T, amplitude A = (X_max - X_min) / 2 and stick fraction s.  An orbit that
  sticks (s > ``Tolerances.stick``) is a ``stick_slip_cycle``, else a
  ``slip_cycle``; several of one sort are numbered by amplitude
  (``stick_slip_cycle``, ``stick_slip_cycle_2``, ...);
* the other kinds are outcomes, not attractors, each with its own negative
  code (``OUTCOMES``): ``not_settled`` -1 (also a periodic point or an
  equilibrium without finite values), ``diverged`` -2, ``quasi_periodic`` -3
  and ``chaotic`` -4 (forced runs).  Every point has exactly one outcome, so
  the basin stabilities add up to 1.

Points go together when, along every feature, the sorted values have no gap
wider than the tolerance (single linkage, feature by feature, until no gap is
left; :func:`clusters`).  The result depends only on the set of values, not
on their order or on how the sweep was chunked.

Why the default tolerances (:class:`Tolerances`) are 1e-3
----------------------------------------------------------
A point is classified ``periodic`` once successive returns to its section
agree to the steady-state tolerance (1e-8 adaptive, 1e-10 exact, 1e-6 RK4),
so two points on one orbit report T, A and s equal to about 1e-6 or better
(the bistable Stribeck case of the tests spreads by < 1e-8).  Distinct
attractors of a friction oscillator differ by far more: a stick-slip cycle
and a pure-slip cycle at the same parameters differ in stick fraction by its
whole value and in amplitude by tens of percent; only orbits near a
bifurcation (a fold, a grazing) come closer than 1e-3, and those are what a
basin study should not split hairs over.  1e-3 sits orders of magnitude from
both: relative for T and A (with an absolute floor ``floor`` for amplitudes
and positions near 0), absolute for s (a share of time).

No tolerance finer than the runs resolve (:func:`resolution`)
--------------------------------------------------------------
Whatever tolerance is asked for, points are never split finer than
``Tolerances.resolution``, which :func:`~frictionflow.basins.basins` sets
from the solver (:func:`resolution`): :data:`RESOLUTION_FACTOR` (10) times

* the steady-state tolerance the runs were classified with (``rtol``, else
  the solver's ``steady_rtol``): one orbit's points agree to about it;
* and, for a fixed-step solver, its step ``dt`` (in units of 1 / omega_n,
  the natural period being 2 pi).  Such a run locates a switch only to
  within a step and is accepted as periodic while its cycles jitter (see
  :mod:`frictionflow.analysis.steady_state`), so one orbit's points differ
  by a few dt, not by rtol: RK4 at dt = 1e-3 through a Karnopp band spreads
  period, amplitude and stick fraction by 1e-3 to 3e-3 relative (2.6e-3
  over 36 points of one stick-slip cycle; 1.7e-3 at dt = 5e-4, 3.2e-3 at
  dt = 2e-3).  Ten steps -- 1e-2 at the default dt -- keeps such an orbit
  one attractor, and still parts attractors that differ by more than 1 %.

The resolution is capped at :data:`MAX_RESOLUTION` (a run that cannot tell
50 % apart tells nothing apart).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, Callable

import numpy as np

from .. import quantities as Q

#: the codes of the outcomes that are not attractors: every steady-state kind but periodic and equilibrium
NOT_SETTLED, DIVERGED, QUASI_PERIODIC, CHAOTIC = -1, -2, -3, -4
OUTCOMES = {NOT_SETTLED: "not_settled", DIVERGED: "diverged", QUASI_PERIODIC: "quasi_periodic", CHAOTIC: "chaotic"}
_KIND = {name: code for code, name in enumerate(Q.KINDS)}
#: the resolution of a run (:func:`resolution`) in multiples of its steady-state rtol and of a fixed step dt
RESOLUTION_FACTOR = 10.0
#: the coarsest resolution (a run that cannot tell 50 % apart tells nothing apart)
MAX_RESOLUTION = 0.5


def check_tolerance(name: str, value: object, zero: bool = False) -> float:
    """``value`` if it is a tolerance :class:`Tolerances` takes (a number in (0, 1), or [0, 1) with ``zero``);
    ValueError starting with ``name`` otherwise -- the field, or the command-line option that sets it
    (``--attractor-tol``)."""
    low_ok = (lambda v: v >= 0) if zero else (lambda v: v > 0)
    if isinstance(value, bool) or not (isinstance(value, (int, float)) and np.isfinite(value) and low_ok(value) and value < 1):
        raise ValueError(f"{name} must be a number in {'[0, 1)' if zero else '(0, 1)'}, got {value!r}")
    return float(value)


def resolution(solver: Any, rtol: float | None = None) -> float:
    """The finest difference between attractors that runs of ``solver`` resolve (see the module docstring).

    :data:`RESOLUTION_FACTOR` times the steady-state tolerance of the runs
    (``rtol``, else the solver's declared ``steady_rtol``) and, for a solver
    that declares ``fixed_step``, times its step ``dt``; at most
    :data:`MAX_RESOLUTION`.

    Parameters
    ----------
    solver:
        The solver the points were run with (a :class:`~frictionflow.solvers.base.Solver`).
    rtol:
        The steady-state tolerance they were classified with, or None for the solver's default.
    """
    finest = RESOLUTION_FACTOR * float(solver.steady_rtol if rtol is None else rtol)
    if solver.fixed_step:
        finest = max(finest, RESOLUTION_FACTOR * float(solver.describe()["dt"]))
    return min(finest, MAX_RESOLUTION)


@dataclass(frozen=True)
class Tolerances:
    """How close two points' steady states must be to count as one attractor (see the module docstring)."""

    period: float = 1e-3  #: relative, on the period T
    amplitude: float = 1e-3  #: relative, on the amplitude (X_max - X_min) / 2 and on the equilibrium's X*
    stick: float = 1e-3  #: absolute, on the stick fraction (and the least stick fraction of a stick-slip cycle)
    floor: float = 1e-9  #: absolute floor of the amplitude and position comparisons (solver noise)
    #: what the runs resolve (``resolution()``, set by :func:`~frictionflow.basins.basins`); period, amplitude
    #: and stick are never finer
    resolution: float = 0.0

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            check_tolerance(f"tolerance {name}", value, zero=name in ("floor", "resolution"))

    def used(self, name: str) -> float:
        """The tolerance ``name`` (period, amplitude or stick) as applied: never finer than :attr:`resolution`."""
        return max(float(getattr(self, name)), self.resolution)

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


@dataclass
class Attractor:
    """One attractor found among some points: its name, kind and representative (median) steady state."""

    name: str  #: ``equilibrium``, ``slip_cycle``, ``stick_slip_cycle`` (``_2``, ``_3``, ... by amplitude)
    kind: str  #: ``equilibrium`` or ``periodic``
    members: np.ndarray  #: flat indices of its points
    period: float  #: the median period of its points (NaN for the equilibrium)
    amplitude: float  #: the median amplitude (X_max - X_min) / 2 of its points
    stick_fraction: float  #: the median stick fraction of its points
    x_mid: float  #: the middle (X_max + X_min) / 2, X* for the equilibrium


def _relative(rel: float, floor: float) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    return lambda a, b: rel * np.maximum(np.abs(a), np.abs(b)) + floor


def _absolute(tol: float) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    return lambda a, b: np.full(len(a), tol)


def clusters(idx: np.ndarray, features: list[np.ndarray], gaps: list[Callable]) -> list[np.ndarray]:
    """Split points ``idx`` at every gap wider than allowed along any feature, until no feature has one.

    ``features[k][i]`` is feature k of point i; ``gaps[k](a, b)`` the widest
    gap allowed between neighbouring sorted values a <= b.  The clusters come
    back in no particular order; each holds its points in ascending order.
    """
    done: list[np.ndarray] = []
    todo = [idx] if len(idx) else []
    while todo:  # (a stack, not recursion: any number of splits)
        part = todo.pop()
        for values, allowed in zip(features, gaps):
            v = values[part]
            order = np.argsort(v, kind="stable")
            sv = v[order]
            cut = np.nonzero(np.diff(sv) > allowed(sv[:-1], sv[1:]))[0]
            if len(cut):
                todo.extend(np.sort(piece) for piece in np.split(part[order], cut + 1))
                break
        else:
            done.append(part)
    return done


def find_attractors(q: dict[str, np.ndarray], tol: Tolerances) -> list[Attractor]:
    """The attractors among points with flat quantities ``q`` (kind, period, X_min, X_max, stick_fraction)."""
    kind = q["kind"]
    amp = 0.5 * (q["X_max"] - q["X_min"])  # half the range, as the orbits and continuation report it
    mid = 0.5 * (q["X_max"] + q["X_min"])
    found: list[Attractor] = []
    # (a point without finite values cannot be told apart: it stays unlabelled, i.e. not settled)
    eq = np.nonzero((kind == _KIND["equilibrium"]) & np.isfinite(mid))[0]
    amplitude = _relative(tol.used("amplitude"), tol.floor)
    for members in sorted(clusters(eq, [mid], [amplitude]), key=lambda m: np.median(mid[m])):
        found.append(_attractor("equilibrium", "equilibrium", members, q, amp, mid))
    per = np.nonzero((kind == _KIND["periodic"]) & np.isfinite(amp + q["period"] + q["stick_fraction"]))[0]
    gaps = [amplitude, _relative(tol.used("period"), 0.0), _absolute(tol.used("stick"))]
    cycles = [_attractor("", "periodic", m, q, amp, mid) for m in clusters(per, [amp, q["period"], q["stick_fraction"]], gaps)]
    for sort in ("slip_cycle", "stick_slip_cycle"):
        mine = sorted((c for c in cycles if (c.stick_fraction > tol.used("stick")) == (sort == "stick_slip_cycle")),
                      key=lambda c: (c.amplitude, c.period))
        for i, c in enumerate(mine):
            c.name = sort if i == 0 else f"{sort}_{i + 1}"
            found.append(c)
    _number_equilibria(found)
    return found


def _number_equilibria(found: list[Attractor]) -> None:
    """Several equilibria (rest positions of a stick band, ...) are numbered by position."""
    eqs = [a for a in found if a.kind == "equilibrium"]
    for i, a in enumerate(eqs[1:], start=2):
        a.name = f"equilibrium_{i}"


def _attractor(name: str, kind: str, members: np.ndarray, q: dict[str, np.ndarray], amp: np.ndarray, mid: np.ndarray) -> Attractor:
    """Median values: robust to the odd point still a little off the orbit."""
    med = lambda a: float(np.median(a[members]))  # noqa: E731
    period = med(q["period"]) if kind == "periodic" else float("nan")
    return Attractor(name, kind, members, period, med(amp) if kind == "periodic" else 0.0, med(q["stick_fraction"]), med(mid))


def codes(groups: list[list[Attractor]]) -> dict[str, int]:
    """One code per attractor name over all groups: 0, 1, ... by amplitude (averaged where it exists), then name.

    The equilibrium (amplitude 0) comes first; the outcomes that are not
    attractors have their negative codes (``OUTCOMES``).
    """
    amps: dict[str, list[float]] = {}
    for found in groups:
        for a in found:
            amps.setdefault(a.name, []).append(a.amplitude)
    order = sorted(amps, key=lambda n: (float(np.mean(amps[n])), n))
    return {name: i for i, name in enumerate(order)}


def labels_of(kind: np.ndarray, found: list[Attractor], code: dict[str, int]) -> np.ndarray:
    """Per point (flat): the code of its attractor, else of its outcome (``OUTCOMES``); a periodic point or an
    equilibrium that no attractor holds (without finite values) is not settled."""
    out = np.full(kind.shape, NOT_SETTLED, dtype=np.int8)
    for code_, name in OUTCOMES.items():
        out[kind == _KIND[name]] = code_
    for a in found:
        out[a.members] = code[a.name]
    return out


def meanings(code: dict[str, int]) -> tuple[list[int], str]:
    """CF ``flag_values`` and ``flag_meanings`` of the labels: the attractors, then the other outcomes (-1, -2, ...)."""
    pairs = sorted(code.items(), key=lambda kv: kv[1]) + [(n, c) for c, n in OUTCOMES.items()]
    return [c for _, c in pairs], " ".join(n for n, _ in pairs)


def describe(tol: Tolerances) -> dict[str, Any]:
    """Dataset attributes saying how the labels were made."""
    return {
        "labels": "attractors found over the whole dataset after the sweep; periodic orbits told apart by period "
        "(relative tolerance label_tol_period), amplitude (X_max - X_min) / 2 (relative, label_tol_amplitude, floor label_tol_floor) "
        "and stick fraction (absolute, label_tol_stick), none finer than the runs resolve (label_tol_resolution); "
        "equilibria by position; codes 0.. ordered by amplitude, -1 not settled, -2 diverged, -3 quasi-periodic, -4 chaotic",
        **{f"label_tol_{k}": float(v) for k, v in tol.as_dict().items()},
    }


#: the per-outcome tables of a labelled dataset: (variable, what it holds, units)
TABLES = (
    ("basin_count", "points whose steady state is this outcome", "1"),
    ("basin_stability", "basin stability: fraction of the initial states ending on this outcome", "1"),
    ("basin_stability_stderr", "binomial standard error of the basin stability sqrt(p (1 - p) / N)", "1"),
    ("attractor_period", "period of the attractor (median over its points; NaN unless periodic)", "1"),
    ("attractor_amplitude", "amplitude (X_max - X_min) / 2 of the attractor (median over its points)", "1"),
    ("attractor_stick_fraction", "stick fraction of the attractor (median over its points)", "1"),
    ("attractor_x_mid", "middle (X_max + X_min) / 2 of the attractor: X* for the equilibrium", "1"),
)


def label_attractors(ds, along: str | None = None, tolerances: Tolerances | None = None):
    """A finished sweep ``ds`` with the attractor label of every point and the basin-stability tables.

    Attractors are found over all points at once (per value of ``along``, a
    swept parameter, when given: a basin-stability study against it) and
    share one set of codes.  Adds ``label`` (the sweep's dims), an
    ``outcome`` dimension (the codes: attractors 0.., -1 not settled, -2
    diverged, -3 quasi-periodic, -4 chaotic) and the ``TABLES`` over
    ([``along``,] ``outcome``); every point has one outcome, so each group's
    ``basin_stability`` adds up to 1.
    Returns the new dataset and, per group, the attractors found.

    Parameters
    ----------
    ds:
        A finished sweep over initial states (every point has a result).
    along:
        A swept parameter to label separately at each of its values, or
        None to label all points together.
    tolerances:
        How close two points' steady states must be to count as one
        attractor (default :class:`Tolerances`).
    """

    import xarray as xr

    tol = tolerances or Tolerances()
    kind = np.asarray(ds["kind"].values)
    if (kind < 0).any():
        raise ValueError(f"{int((kind < 0).sum())} points have no result (an unfinished sweep); finish it first")
    dims = tuple(ds["kind"].dims)
    if along is not None and along not in dims:
        raise ValueError(f"along: {along!r} is not a dimension of the dataset ({', '.join(dims)})")
    order = (along, *[d for d in dims if d != along]) if along else dims
    q = {n: np.asarray(ds[n].transpose(*order).values) for n in ("kind", "period", "X_min", "X_max", "stick_fraction")}
    n_groups = q["kind"].shape[0] if along else 1
    flat = [{n: v[g].ravel() if along else v.ravel() for n, v in q.items()} for g in range(n_groups)]
    found = [find_attractors(f, tol) for f in flat]
    code = codes(found)
    labels = [labels_of(f["kind"], a, code) for f, a in zip(flat, found)]
    label = np.stack(labels).reshape(q["kind"].shape)
    values, names = meanings(code)
    tables = _tables(labels, found, values, names.split())
    lead = (along,) if along else ()
    out = ds.assign(label=(order, label)).transpose(*dims, ...)
    out["label"].attrs.update(long_name="attractor the initial state ends on", flag_values=values, flag_meanings=names)
    out = out.assign_coords(outcome=("outcome", np.asarray(values, dtype=np.int8)))
    out["outcome"].attrs.update(long_name="outcome code (as label)", flag_values=values, flag_meanings=names)
    for (var, long_name, units), table in zip(TABLES, tables):
        out[var] = xr.DataArray(table if along else table[0], dims=(*lead, "outcome"), attrs={"long_name": long_name, "units": units})
    out.attrs.update(describe(tol))
    return out, found


def _tables(labels: list[np.ndarray], found: list[list[Attractor]], values: list[int], names: list[str]) -> list[np.ndarray]:
    """The ``TABLES`` as arrays (group, outcome), counted from the labels: every point in exactly one outcome."""
    shape = (len(labels), len(values))
    count = np.array([[np.count_nonzero(label == v) for v in values] for label in labels], dtype=np.int64).reshape(shape)
    props = [np.full(shape, np.nan) for _ in range(4)]
    for g, attractors in enumerate(found):
        by_name = {a.name: a for a in attractors}
        for j, name in enumerate(names):
            a = by_name.get(name)
            if a is not None:
                for p, v in zip(props, (a.period, a.amplitude, a.stick_fraction, a.x_mid)):
                    p[g, j] = v
    n = np.array([len(label) for label in labels])[:, None]
    p = count / n
    return [count, p, np.sqrt(p * (1.0 - p) / n), *props]
