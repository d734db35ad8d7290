"""Sweep speed for a law with internal state: 10^4 grid points through the stiff solver, in one run.

    python benchmarks/bench_sweep_stateful.py [--law lugre] [--points 10000] [--t-end 100] [--set key=value ...]

Each point is a whole stiff run and its analysis, the points of a chunk on
numba's threads (the engine releases the GIL).  The grid is zeta x V_b and,
where the law names one (:data:`LAWS`), one of its own parameters, about
``--points`` points in all; a law not in :data:`LAWS` is swept over zeta x V_b at its defaults, ``--set`` fixing any
setting.  Prints points/s (wall clock) and the CPU seconds per point, and
the mix of steady states found.
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import header

from frictionflow.quantities import KINDS
from frictionflow.sweep import run_sweep

#: per law: its fixed settings and its own axis (name, start, stop, scale) -- stick-slip on a Stribeck dip
LAWS = {
    "lugre": ({"fd": 0.3, "fs": 0.5, "vs": 0.05, "delta": 2.0, "sigma1": 60.0}, ("sigma0", 1e3, 1e4, "log")),
    "elastoplastic": ({"fd": 0.3, "fs": 0.5, "vs": 0.05, "delta": 2.0, "sigma1": 60.0, "z_ba": 1e-5},
                      ("sigma0", 1e3, 1e4, "log")),
    "dahl": ({"fd": 0.3}, ("sigma0", 1e3, 1e4, "log")),
    # D_c across Rice & Ruina's critical slip distance (about 0.017 at V_b = 0.02): steady sliding and cycles
    "rate_state": ({"normal": 1.0, "a": 0.01, "b": 0.015, "vref": 0.01}, ("dc", 0.005, 0.05, "log")),
}


def config(law: str, points: int, t_end: float, fixed: dict[str, float]) -> dict:
    """The sweep: zeta x V_b (x the law's own axis), about ``points`` points."""
    settings, own = LAWS.get(law, ({}, None))
    axes = 2 if own is None else 3
    n = max(2, round(points ** (1.0 / axes)))
    grid = {"zeta": {"start": 0.0, "stop": 0.2, "num": n}, "vb": {"start": 0.02, "stop": 0.3, "num": n, "scale": "log"}}
    if own is not None and own[0] not in fixed:
        name, start, stop, scale = own
        grid[name] = {"start": start, "stop": stop, "num": n, "scale": scale}
    return {"friction": law, "solver": "stiff", "t_end": t_end, **settings, **fixed, "grid": grid}


def _setting(text: str) -> tuple[str, float]:
    key, _, value = text.partition("=")
    if not key or not value:
        raise argparse.ArgumentTypeError(f"--set takes key=value, got {text!r}")
    return key, float(value)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--law", default="lugre", help="a registered law with internal states")
    ap.add_argument("--points", type=int, default=10_000)
    ap.add_argument("--t-end", type=float, default=100.0)
    ap.add_argument("--set", type=_setting, action="append", default=[], help="a fixed setting, key=value")
    args = ap.parse_args()
    cfg = config(args.law, args.points, args.t_end, dict(args.set))
    size = int(np.prod([a["num"] for a in cfg["grid"].values()]))
    header(f"sweep of {size:,} points (friction={args.law}, stiff solver, t_end = {args.t_end:g})")
    tmp = Path(tempfile.mkdtemp())
    try:
        run_sweep(config(args.law, 8, 10.0, dict(args.set)), tmp / "warm.zarr")  # load the kernels
        wall, cpu = time.perf_counter(), time.process_time()
        ds = run_sweep(cfg, tmp / "sweep.zarr")
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        kinds = ds["kind"].values.ravel()
        counts = {k: int(np.count_nonzero(kinds == i)) for i, k in enumerate(KINDS) if np.any(kinds == i)}
        print(f"{kinds.size:,} points in {wall:.1f} s: {kinds.size / wall:,.1f} points/s "
              f"({cpu / kinds.size * 1e3:.2f} ms CPU per point; {counts})")
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
