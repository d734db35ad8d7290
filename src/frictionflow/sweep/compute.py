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
    if model.forced or any(name in cfg.axes for name in FORCING):
        return _forced_points(cfg, law, solver, pts).T.reshape((batch.NR, *shape))
    p = _friction_rows(cfg, law, pts)
    zeta, vb = pts["zeta"], pts["vb"]
    x0 = np.where(np.isnan(pts["x0"]), p[:, kf.FD], pts["x0"])
    v0 = np.where(np.isnan(pts["v0"]), vb, pts["v0"])
    rtol = run.rtol if run.rtol is not None else solver.steady_rtol
    out = np.empty((len(zeta), batch.NR))
    solver.run_points(p, zeta, vb, x0, v0, run.t_end, rtol, 3, out)  # its batched kernel, with its settings
    return out.T.reshape((batch.NR, *shape))


def _forced_points(cfg: SweepConfig, law: FrictionLaw, solver, pts: dict[str, np.ndarray]) -> np.ndarray:
    """Rows of the swept quantities for forced points, one run and analysis each.

    The batched kernels integrate the autonomous system and classify on the
    section X' = 0; a forced point is judged on the stroboscopic section
    (:mod:`frictionflow.analysis.forced`), so it runs through the façade.
    """
    run = cfg.run
    n = len(pts["zeta"])
    out = np.empty((n, batch.NR))
    base = run.values()
    model_names = [p.name for p in BeltOscillator.parameters]
    law_names = [p.name for p in law.parameters]
    for j in range(n):
        point = {k: float(v[j]) for k, v in pts.items() if not np.isnan(v[j])}
        model = BeltOscillator.from_values({**base, **{k: point[k] for k in model_names if k in point}})
        point_law = type(law).from_values({**base, **{k: point[k] for k in law_names if k in point}})
        x0 = point.get("x0", point_law.fd)
        v0 = point.get("v0", model.vb)
        traj = simulate(model, point_law, solver, t_end=run.t_end, x0=x0, v0=v0)
        values = analyze(traj, rtol=run.rtol).quantities()
        out[j] = [values[q.name] for q in Q.SWEPT]
    return out
