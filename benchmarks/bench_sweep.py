"""Sweep speed: 10^6 grid points (zeta, F_d, V_b; Coulomb stick-slip; exact solver), in one run.

    python benchmarks/bench_sweep.py [--points 1000000]

Prints points/s, the peak memory of the process, and the ratio against a loop
of scipy.solve_ivp (the event-driven DOP853 integrator of bench_exact.py) over
a 10^3-point sample of the same grid.  Goal (issue 5): 10^6 points in <= 60 s
on this 2-core machine (>= 16,000 points/s).
"""

from __future__ import annotations

import argparse
import resource
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import header
from bench_exact import scipy_run

from frictionflow.sweep import parse_sweep, run_sweep


def config(n_side: int) -> dict:
    return {
        "friction": "coulomb",
        "t_end": 300.0,
        "grid": {
            "zeta": {"start": 0.0, "stop": 0.1, "num": n_side},
            "fd": {"start": 0.01, "stop": 0.03, "num": n_side},
            "vb": {"start": 0.002, "stop": 0.05, "num": n_side, "scale": "log"},
            "fs": 0.04,
        },
    }


def scipy_points(cfg_dict: dict, n: int, t_end: float) -> float:
    """Seconds per point for a loop of scipy over n points of the grid (same model)."""
    import bench_exact as be

    cfg = parse_sweep(cfg_dict)
    rng = np.random.default_rng(0)
    idx = [rng.integers(0, k, n) for k in cfg.shape]
    pts = cfg.point_params(tuple(idx))
    t = time.perf_counter()
    for j in range(n):
        be.ZETA, be.FD, be.VB = float(pts["zeta"][j]), float(pts["fd"][j]), float(pts["vb"][j])
        try:
            scipy_run(t_end)
        except (IndexError, ValueError):
            pass  # points that end sliding have fewer than two stick onsets
    return (time.perf_counter() - t) / n


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--scipy-points", type=int, default=1000)
    args = ap.parse_args()
    n_side = round(args.points ** (1 / 3))
    header(f"sweep of {n_side**3:,} points (Coulomb, exact solver)")
    tmp = Path(tempfile.mkdtemp())
    try:
        cfg = config(n_side)
        run_sweep(config(4), tmp / "warm.zarr")  # load the kernels
        t = time.perf_counter()
        ds = run_sweep(cfg, tmp / "sweep.zarr")
        elapsed = time.perf_counter() - t
        kinds = ds["kind"].values
        counts = {k: int(np.count_nonzero(kinds == i)) for i, k in enumerate(("periodic", "equilibrium", "not_settled"))}
        rate = kinds.size / elapsed
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        s_per_point = scipy_points(cfg, args.scipy_points, 300.0)
        print(f"{kinds.size:,} points in {elapsed:.1f} s: {rate:,.0f} points/s (goal >= 16,000; {counts})")
        print(f"peak memory (max RSS of this process): {peak:,.0f} MiB")
        print(f"scipy loop: {1 / s_per_point:,.1f} points/s over {args.scipy_points} points -> sweep is {rate * s_per_point:,.0f}x faster")
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
