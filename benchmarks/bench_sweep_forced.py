"""Forced sweep speed: a grid of forced Coulomb points (Omega, zeta) on the exact solver, to t_end = 300.

    python benchmarks/bench_sweep_forced.py [--points 1000] [--omega 0.5 1.5] [--zeta 0.02 0.1]
    python benchmarks/bench_sweep_forced.py --ab /work/main/src src [--repeat 2]

Prints points/s, the process's CPU time per point and the steady-state
kinds (points whose stroboscopic section does not repeat need the largest
Lyapunov exponent, a tangent run of up to 420 forcing periods, ended once
the exponent is clearly negative: they dominate the time).  The CPU time is what a point costs whatever else the machine runs:
on a shared machine compare it rather than the rate.  The heap is collected
before the timed run (as ``timeit`` keeps the collector out of its timing):
a full collection costs ~0.1 s whatever the sweep.  ``--ab OLD NEW`` runs
the same benchmark with ``PYTHONPATH=OLD`` and ``PYTHONPATH=NEW`` alternately
(each ``--repeat`` times, in fresh processes) and prints the ratios of the
best rates and of the least CPU per point.  Goal (issue 19, item 7):
>= 10,000 points/s on 2 cores, i.e. at most 200 us of CPU per point.
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def config(n_side: int, omega: tuple[float, float], zeta: tuple[float, float]) -> dict:
    return {
        "friction": "coulomb", "fd": 0.02, "fs": 0.04, "vb": 0.01, "fex": 0.05, "t_end": 300.0,
        "grid": {"omega": {"start": omega[0], "stop": omega[1], "num": n_side},
                 "zeta": {"start": zeta[0], "stop": zeta[1], "num": n_side}},
    }


def measure(args: argparse.Namespace) -> dict:
    from frictionflow.quantities import KINDS
    from frictionflow.sweep import run_sweep

    n_side = round(args.points ** 0.5)
    tmp = Path(tempfile.mkdtemp())
    try:
        run_sweep(config(2, args.omega, args.zeta), tmp / "warm.zarr")  # load (or compile) the kernels
        # a full collection of the heap the imports and the loaded kernels left (~0.1 s) would otherwise fall
        # inside or outside the timed run by chance, with how many objects each version happens to allocate
        gc.collect()
        t, cpu = time.perf_counter(), time.process_time()
        ds = run_sweep(config(n_side, args.omega, args.zeta), tmp / "sweep.zarr")
        elapsed, cpu = time.perf_counter() - t, time.process_time() - cpu
        kinds = ds["kind"].values.ravel()
    finally:
        shutil.rmtree(tmp)
    counts = {k: int(np.count_nonzero(kinds == i)) for i, k in enumerate(KINDS) if np.any(kinds == i)}
    return {"points": int(kinds.size), "seconds": elapsed, "rate": kinds.size / elapsed, "cpu_us": 1e6 * cpu / kinds.size,
            "kinds": counts}


def ab(args: argparse.Namespace) -> None:
    """The benchmark under two source trees, alternating, in fresh processes: best rate and least CPU of each, ratios."""
    best: dict[str, float] = {}
    least: dict[str, float] = {}
    for _ in range(args.repeat):
        for src in args.ab:
            env = {**os.environ, "PYTHONPATH": os.path.abspath(src)}
            cmd = [sys.executable, __file__, "--json", "--points", str(args.points), "--omega", *map(str, args.omega),
                   "--zeta", *map(str, args.zeta)]
            r = json.loads(subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout)
            print(f"PYTHONPATH={src}: {r['points']:,} points in {r['seconds']:.2f} s = {r['rate']:,.0f} points/s, "
                  f"{r['cpu_us']:,.0f} us CPU/point {r['kinds']}", flush=True)
            best[src] = max(best.get(src, 0.0), r["rate"])
            least[src] = min(least.get(src, math.inf), r["cpu_us"])
    old, new = args.ab
    print(f"best: {best[old]:,.0f} -> {best[new]:,.0f} points/s, ratio {best[new] / best[old]:.2f}x; "
          f"least CPU: {least[old]:,.0f} -> {least[new]:,.0f} us/point, ratio {least[old] / least[new]:.2f}x")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=1000)
    ap.add_argument("--omega", type=float, nargs=2, default=(0.5, 1.5))
    ap.add_argument("--zeta", type=float, nargs=2, default=(0.02, 0.1))
    ap.add_argument("--ab", nargs=2, metavar=("OLD_SRC", "NEW_SRC"))
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--json", action="store_true", help="print the measurement as JSON (for --ab)")
    args = ap.parse_args()
    if args.ab:
        ab(args)
        return
    r = measure(args)
    if args.json:
        print(json.dumps(r))
        return
    from _common import header

    header(f"forced sweep of {r['points']:,} points (Coulomb, exact solver, t_end 300)")
    print(f"{r['points']:,} points in {r['seconds']:.2f} s: {r['rate']:,.0f} points/s, {r['cpu_us']:,.0f} us CPU/point "
          f"(goal >= 10,000 points/s on 2 cores: <= 200 us; {r['kinds']})")


if __name__ == "__main__":
    main()
