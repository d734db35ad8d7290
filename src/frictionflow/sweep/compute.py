"""Compute one chunk of a sweep: a pure function of the config and the chunk's index.

It is what a Dask worker runs, so it takes and returns only picklable plain
data, and gives the same numbers wherever it runs.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import quantities as Q
from ..analysis import analyze
from ..core import batch
from ..core import layout as kf
from ..core.threads import over_points
from ..friction.base import FrictionLaw
from ..parameters import with_defaults
from ..params import BeltOscillator
from ..simulate import simulate
from .config import SweepConfig, parse_sweep

#: the result variables, in the kernels' row order: (name, units, long name), from the quantities table
VARIABLES = tuple((q.name, q.units, q.long_name) for q in Q.SWEPT)
KIND_NAMES = Q.KINDS
#: the external force's parameters: a sweep that sets or varies them runs the forced path
FORCING = ("fex", "omega", "phi")
#: the axis that makes the belt move (its frequency and phase alone leave it at constant speed)
BELT = "vb_amplitude"


def chunk_slices(chunk: tuple[int, ...], chunks: tuple[int, ...], shape: tuple[int, ...]) -> tuple[slice, ...]:
    return tuple(slice(c * k, min((c + 1) * k, n)) for c, k, n in zip(chunk, chunks, shape))


def _friction_rows(cfg: SweepConfig, law: FrictionLaw, pts: dict[str, np.ndarray]) -> np.ndarray:
    """Per-point kernel parameters: the law's settings, with the swept ones (and what defaults to them) per point."""
    n = len(pts["zeta"])
    swept = {p.name: pts[p.name] for p in law.parameters if p.name in cfg.axes}
    values = with_defaults(law.parameters, {**cfg.run.values(), **swept})
    rows = np.zeros((n, kf.N_PARAMS))
    for slot, column in type(law).kernel_columns(values).items():
        rows[:, slot] = column
    return rows


def _starts(p: np.ndarray, pts: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(X(0), X'(0)) per point of a batched kernel: the given values, else the static laws' start (F_d, V_b),
    :meth:`FrictionLaw.default_start` per point (laws with internal states, whose start differs, run the façade)."""
    return (np.where(np.isnan(pts["x0"]), p[:, kf.FD], pts["x0"]), np.where(np.isnan(pts["v0"]), pts["vb"], pts["v0"]))


def compute_chunk(source: dict[str, Any], chunk: tuple[int, ...], chunks: tuple[int, ...]) -> np.ndarray:
    """Results (len(VARIABLES), *chunk_shape) for one chunk of the sweep described by ``source``."""
    cfg = parse_sweep({**source["settings"], "grid": source["grid"]}, check_points=False)  # checked by the runner
    sl = chunk_slices(chunk, chunks, cfg.shape)
    index = np.indices([s.stop - s.start for s in sl]).reshape(len(sl), -1)
    index = tuple(ix + s.start for ix, s in zip(index, sl))
    pts = cfg.point_params(index)
    run = cfg.run
    model, law, solver = run.build()
    shape = tuple(s.stop - s.start for s in sl)
    if law.internal_names:
        return _stateful_points(cfg, law, solver, pts).T.reshape((batch.NR, *shape))
    if model.driven or any(name in cfg.axes for name in (*FORCING, BELT)):
        return _forced_points(cfg, law, solver, pts).T.reshape((batch.NR, *shape))
    p = _friction_rows(cfg, law, pts)
    zeta, vb = pts["zeta"], pts["vb"]
    x0, v0 = _starts(p, pts)
    rtol = run.rtol if run.rtol is not None else solver.steady_rtol
    out = np.empty((len(zeta), batch.NR))
    solver.run_points(p, zeta, vb, x0, v0, run.t_end, rtol, 3, out)  # its batched kernel, with its settings
    return out.T.reshape((batch.NR, *shape))


def _forced_points(cfg: SweepConfig, law: FrictionLaw, solver, pts: dict[str, np.ndarray]) -> np.ndarray:
    """Rows of the swept quantities for the points of a forced sweep, each as ``analyze(simulate(...))`` gives it.

    A forced point is judged on the stroboscopic section
    (:mod:`frictionflow.analysis.forced`).  Points with F_ex > 0 run batched
    where the solver declares a forced batched kernel (``batched_forced``; the
    exact solver's :mod:`frictionflow.core.batch_forced`: the same run and the
    same classifier, compiled); the rest -- other solvers, points without
    forcing, and what the batched kernel leaves to it -- run one by one through
    the façade.  A point on a moving belt (``vb_amplitude`` > 0) is judged on the section of its period too,
    through the façade (the batched kernels run a belt at constant speed).
    """
    n = len(pts["zeta"])
    out = np.empty((n, batch.NR))
    facade = np.ones(n, dtype=bool)
    j = np.flatnonzero((pts["fex"] > 0.0) & ~(pts[BELT] > 0.0))
    if len(j):
        sub = {k: v[j] for k, v in pts.items()}
        p = _friction_rows(cfg, law, sub)
        p[:, kf.FEX], p[:, kf.OMEGA], p[:, kf.PHI] = sub["fex"], sub["omega"], sub["phi"]
        x0, v0 = _starts(p, sub)
        rtol = cfg.run.rtol if cfg.run.rtol is not None else solver.steady_rtol
        rows = np.empty((len(j), batch.NR))
        left = solver.run_forced_points(p, sub["zeta"], sub["vb"], x0, v0, cfg.run.t_end, rtol, law, rows)
        out[j] = rows
        facade[j] = left
    _facade_points(cfg, law, solver, pts, np.flatnonzero(facade), out)
    return out


#: pieces per thread for stateful points: a few each (a point is a whole stiff run, milliseconds or more)
STATEFUL_PIECES = 4


def _stateful_points(cfg: SweepConfig, law: FrictionLaw, solver, pts: dict[str, np.ndarray]) -> np.ndarray:
    """Rows of the swept quantities for the points of a law with internal states, each ``analyze(simulate(...))``.

    Each point is a run of the stiff engine (forced or not) and its
    analysis; the points spread over numba's threads
    (:func:`~frictionflow.core.threads.over_points`): the engine releases the
    GIL (:func:`frictionflow.core.stiff_points.run_released`, the kernel
    ``simulate`` runs), so the runs proceed at once while the Python parts
    take turns.
    """
    n = len(pts["zeta"])
    out = np.empty((n, batch.NR))
    over_points(lambda start, stop: _facade_points(cfg, law, solver, pts, np.arange(start, stop), out), n,
                per_thread=STATEFUL_PIECES)
    return out


def _facade_points(cfg: SweepConfig, law: FrictionLaw, solver, pts: dict[str, np.ndarray], which: np.ndarray,
                   out: np.ndarray) -> None:
    """Rows ``out[which]``: one ``simulate`` and ``analyze`` per point."""
    run = cfg.run
    base = run.values()
    model_names = [p.name for p in BeltOscillator.parameters]
    law_names = [p.name for p in law.parameters]
    for j in which:
        point = {k: float(v[j]) for k, v in pts.items() if not np.isnan(v[j])}
        model = BeltOscillator.from_values({**base, **{k: point[k] for k in model_names if k in point}})
        point_law = type(law).from_values({**base, **{k: point[k] for k in law_names if k in point}})
        x0, v0 = point_law.start(model.vb, point.get("x0"), point.get("v0"))
        traj = simulate(model, point_law, solver, t_end=run.t_end, x0=x0, v0=v0)
        values = analyze(traj, rtol=run.rtol).quantities()
        out[j] = [values[q.name] for q in Q.SWEPT]
