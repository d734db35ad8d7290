"""Model sweeps (issue 22, item 2): points/s and CPU per point, this checkout against another source tree, in one run.

    python benchmarks/bench_sweep_model.py [--against /work/main/src] [--repeat 3]

Cases (chains of unit masses, each on a spring k = 1 and a damper c = 0.04
to the ground, springs between neighbours, one Coulomb contact per mass,
F_d/F_s alternating 0.2/0.4 and 0.1/0.35, started from q_i = 0.5 sin(i) at
rest -- the chains of ``bench_structure.py``):

* ``chain2``: 2 masses over ``contact.0.belt`` (8 values) x ``spring.1.k``
  (the coupling spring, 4 values), t_end 200: 32 points;
* ``chain10``: 10 masses over ``contact.0.belt`` (8 values), t_end 100;
* ``stribeck2``: ``chain2`` with Stribeck contacts (v_s 0.05): the adaptive
  solver's points (``--cases stribeck2`` runs it alone).

Each side runs in its own process (``PYTHONPATH`` = its ``src``), the
kernels compiled first on a warm-up chunk, then every chunk of the grid
through ``compute_model_chunk`` as the sweep runner calls it (chunks of the
default size; no store, so that the file system is not timed).  Per side:
the wall rate (points per wall second) and the CPU time per point (all
threads of the process), best of the repeats, the sides alternating so that
load from other processes falls on both, and the kinds each side found
(a point whose section does not repeat costs this checkout a Lyapunov
exponent to tell quasi-periodic, chaotic and not settled apart).  The ratios are B / A for times
(> 1: this checkout faster) and A / B for rates.  ``A plain`` is this
checkout with a non-repeating section left ``not_settled`` without its
exponent: the threads' effect alone, the same work as B.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

from _common import header

HERE = Path(__file__).resolve().parents[1] / "src"


def chain_model(n: int, law: dict | None = None) -> dict:
    """The model mapping of a chain of ``n`` masses (spring.1 couples the first two); ``law``: the contacts'
    friction and its own parameters beyond fd, fs (default Coulomb's)."""
    dof = [f"x{i + 1}" for i in range(n)]
    springs = [{"on": {dof[0]: 1.0}, "k": 1.0}]
    for i in range(n - 1):
        springs.append({"on": {dof[i]: 1.0, dof[i + 1]: -1.0}, "k": 0.5})
        springs.append({"on": {dof[i + 1]: 1.0}, "k": 1.0})
    laws = [(0.2, 0.4) if i % 2 == 0 else (0.1, 0.35) for i in range(n)]
    return {"dof": dof, "mass": [1.0] * n, "spring": springs,
            "damper": [{"on": {d: 1.0}, "c": 0.04} for d in dof],
            "contact": [{"on": {d: 1.0}, "belt": 0.1, "friction": "coulomb", "fd": fd, "fs": fs, **(law or {})}
                        for d, (fd, fs) in zip(dof, laws)],
            "initial": {"q": {d: 0.5 * math.sin(i + 1) for i, d in enumerate(dof)}}}


CASES = {
    "chain2": (2, 200.0, {"contact.0.belt": {"start": 0.05, "stop": 0.3, "num": 8},
                          "spring.1.k": {"start": 0.2, "stop": 1.0, "num": 4}}),
    "chain10": (10, 100.0, {"contact.0.belt": {"start": 0.05, "stop": 0.3, "num": 8}}),
    # Stribeck contacts: the adaptive structure solver's points (simulate --model's choice for the law)
    "stribeck2": (2, 200.0, {"contact.0.belt": {"start": 0.05, "stop": 0.3, "num": 8},
                             "spring.1.k": {"start": 0.2, "stop": 1.0, "num": 4}}, {"friction": "stribeck", "vs": 0.05}),
}


def child(case: str, plain: bool = False) -> dict:
    """Time one case in this process (the source tree on PYTHONPATH): wall and CPU over the whole grid.

    ``plain``: a section that does not repeat is ``not_settled`` without its exponent (the verdict before the
    quasi-periodic and chaotic kinds), so that the threads' effect is measured alone.
    """
    import itertools

    import numba
    import numpy as np

    from frictionflow.analysis.structure import STRUCTURE_KINDS
    from frictionflow.sweep.model import compute_model_chunk, default_model_chunk, parse_model_sweep
    from frictionflow.system import System

    if plain:
        from frictionflow.analysis import structure

        structure._not_periodic = lambda motion: ("not_settled", math.nan)
    n, t_end, grid, *law = CASES[case]
    cfg = parse_model_sweep({"t_end": t_end, "grid": grid}, System.from_dict(chain_model(n, *law), source=None))
    size = default_model_chunk(cfg)
    chunks = tuple(min(size, s) if i == len(cfg.shape) - 1 else 1 for i, s in enumerate(cfg.shape))
    todo = list(itertools.product(*(range(math.ceil(s / c)) for s, c in zip(cfg.shape, chunks))))
    compute_model_chunk(cfg.source, todo[0], chunks)  # compiles (or loads) every kernel
    wall, cpu = time.perf_counter(), time.process_time()
    kinds = [compute_model_chunk(cfg.source, chunk, chunks)[0] for chunk in todo]
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    codes, counts = np.unique(np.concatenate([k.ravel() for k in kinds]).astype(int), return_counts=True)
    found = {STRUCTURE_KINDS[c]: int(n) for c, n in zip(codes, counts)}
    return {"points": cfg.size, "wall": wall, "cpu": cpu, "threads": numba.get_num_threads(), "kinds": found}


def measure(src: str, case: str, plain: bool = False) -> dict:
    env = dict(os.environ, PYTHONPATH=src)
    done = subprocess.run([sys.executable, __file__, "--child", case, *(["--plain"] if plain else [])], env=env,
                          capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--against", default="/work/main/src", help="the other source tree (B)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--child")
    parser.add_argument("--plain", action="store_true")
    parser.add_argument("--cases", nargs="+", choices=sorted(CASES), default=list(CASES))
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args.child, args.plain)))
        return
    header("model sweeps: this checkout (A) vs " + args.against + " (B)")
    print(f"# load average at start: {os.getloadavg()[0]:.2f}")
    for case in args.cases:
        sides = {"A": (str(HERE), False), "A plain": (str(HERE), True), "B": (args.against, False)}
        best = {side: None for side in sides}
        for _ in range(args.repeat):
            for side, (src, plain) in sides.items():
                got = measure(src, case, plain)
                old = best[side]
                best[side] = got if old is None else {**got, "wall": min(got["wall"], old["wall"]),
                                                       "cpu": min(got["cpu"], old["cpu"])}
        b, pts = best["B"], best["B"]["points"]
        print(f"{case}: {pts} points, {b['threads']} threads")
        for side, r in best.items():
            print(f"  {side:8s} {pts / r['wall']:8.1f} points/s wall, {1e3 * r['cpu'] / pts:8.2f} ms CPU per point, "
                  f"wall rate vs B {b['wall'] / r['wall']:.2f}x, CPU per point B/this {b['cpu'] / r['cpu']:.2f}x; "
                  f"kinds {r['kinds']}")


if __name__ == "__main__":
    main()
