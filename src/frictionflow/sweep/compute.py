"""Compute one chunk of a sweep: a pure function of the config and the chunk's index.

It is what a Dask worker runs, so it takes and returns only picklable plain
data, and gives the same numbers wherever it runs.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analysis.summary import DEFAULT_RTOL
from ..core import batch
from ..core import friction as kf
from .config import SweepConfig, parse_sweep

#: the result variables, in the kernels' row order: (name, units, long name)
VARIABLES = (
    ("kind", "1", "steady state: 0 periodic, 1 equilibrium, 2 not settled"),
    ("period", "1", "period of the periodic steady state (tau units; NaN unless periodic)"),
    ("P_dv", "1", "time-averaged power dissipated by the damper"),
    ("P_df", "1", "time-averaged power taken out by friction (magnitude of the negative part of X' F_c)"),
    ("P_fin", "1", "time-averaged power put in by friction (positive part of X' F_c)"),
    ("R_c", "1", "power dissipation ratio of the damper P_dv / P_fin"),
    ("R_f", "1", "power dissipation ratio of friction P_df / P_fin"),
    ("P_belt", "1", "time-averaged power delivered by the belt F_c V_b"),
    ("P_heat", "1", "time-averaged heat generated at the interface F_c V_r"),
    ("TR_B", "1", "force transmissibility max|X + 2 zeta X'| / F_d"),
    ("X_min", "1", "minimum displacement over the steady-state window"),
    ("X_max", "1", "maximum displacement over the steady-state window"),
    ("V_min", "1", "minimum velocity over the steady-state window"),
    ("V_max", "1", "maximum velocity over the steady-state window"),
    ("stick_fraction", "1", "share of the steady-state window spent sticking"),
    ("energy_residual", "1", "relative residual of the power balance over the window"),
)
KIND_NAMES = ("periodic", "equilibrium", "not_settled")


def chunk_slices(chunk: tuple[int, ...], chunks: tuple[int, ...], shape: tuple[int, ...]) -> tuple[slice, ...]:
    return tuple(slice(c * k, min((c + 1) * k, n)) for c, k, n in zip(chunk, chunks, shape))


def _friction_rows(cfg: SweepConfig, law: Any, pts: dict[str, np.ndarray]) -> np.ndarray:
    """Per-point kernel parameters from one validated template law."""
    n = len(pts["zeta"])
    p = np.tile(law.kernel_params(), (n, 1))
    fd = pts["fd"]
    fs = np.where(np.isnan(pts["fs"]), fd, pts["fs"])
    if law.name == "stribeck" and "fs" not in cfg.axes and cfg.run.fs is None:
        fs = 2.0 * fd  # the Stribeck default, as in RunConfig.build
    p[:, kf.FD] = fd
    p[:, kf.FS] = fs
    if law.name == "karnopp":
        p[:, kf.VD] = pts["vd"]
    if law.name == "stribeck":
        p[:, kf.VS] = pts["vs"]
        p[:, kf.DELTA] = pts["delta"]
    return p


def compute_chunk(source: dict[str, Any], chunk: tuple[int, ...], chunks: tuple[int, ...]) -> np.ndarray:
    """Results (len(VARIABLES), *chunk_shape) for one chunk of the sweep described by ``source``."""
    cfg = parse_sweep({**source["settings"], "grid": source["grid"]})
    sl = chunk_slices(chunk, chunks, cfg.shape)
    index = np.indices([s.stop - s.start for s in sl]).reshape(len(sl), -1)
    index = tuple(ix + s.start for ix, s in zip(index, sl))
    pts = cfg.point_params(index)
    run = cfg.run
    _, law, solver = run.build()
    p = _friction_rows(cfg, law, pts)
    zeta, vb = pts["zeta"], pts["vb"]
    x0 = np.where(np.isnan(pts["x0"]), p[:, kf.FD], pts["x0"])
    v0 = np.where(np.isnan(pts["v0"]), vb, pts["v0"])
    rtol = run.rtol if run.rtol is not None else DEFAULT_RTOL[solver.name]
    out = np.empty((len(zeta), batch.NR))
    if solver.name == "exact":
        batch.exact_points(p, zeta, vb, x0, v0, run.t_end, rtol, 3, out)
    elif solver.name == "adaptive":
        batch.adaptive_points(p, zeta, vb, x0, v0, run.t_end, run.ode_rtol, 1e-13, run.max_steps, rtol, 3, out)
    else:
        batch.rk4_points(int(p[0, kf.LAW]), p, zeta, vb, x0, v0, run.t_end, run.dt, rtol, 3, out)
    shape = tuple(s.stop - s.start for s in sl)
    return out.T.reshape((batch.NR, *shape))
