"""The adaptive structure solver: a one-dof Stribeck model against the single mass's adaptive solver (the
same motion, so the CPU-time ratio is the price of the general n-dof kernel), and chains of n masses.

    python benchmarks/bench_structure_adaptive.py [n ...]      (default 2 10)

The chains are :func:`bench_structure_exact.chain` with each contact's law
Stribeck (F_d 0.3, F_s 0.4, V_s 0.05) instead of Coulomb; rtol 1e-10,
atol 1e-12.  Prints the best of 3 CPU times (compiled first, not timed), the
steps (samples), the switches and the energy residual.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _common import header
from bench_structure_exact import chain

import frictionflow as ff
from frictionflow.solvers.structure import run_assembly, simulate_system
from frictionflow.system import System

LAW = ff.Stribeck(fd=0.3, fs=0.4, vs=0.05)
SETTINGS = {"rtol": 1e-10, "atol": 1e-12}


def cpu(fn, repeat: int = 3) -> float:
    """The best of ``repeat`` CPU times of ``fn()``."""
    best = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best


def one_dof() -> None:
    model = ff.BeltOscillator(zeta=0.05, vb=0.1)
    system = System.single_mass(model, LAW, x0=0.2, v0=0.0)
    solver = ff.solvers.Adaptive(**SETTINGS)
    run = lambda: ff.simulate(model, LAW, solver, t_end=500.0, x0=0.2, v0=0.0)  # noqa: E731
    structure = lambda: simulate_system(system, 500.0, solver="adaptive", **SETTINGS)  # noqa: E731
    run(), structure()
    single, general = cpu(run), cpu(structure)
    print(f"one dof, t_end 500: single mass {single:.4f} s, structure kernel {general:.4f} s, "
          f"ratio {general / single:.1f}")


def main() -> None:
    sizes = [int(a) for a in sys.argv[1:]] or [2, 10]
    header("adaptive structure solver: Stribeck contacts")
    one_dof()
    for n in sizes:
        asm = chain(n)
        asm = asm._replace(law=np.tile(LAW.kernel_params(), (n, 1)))
        t_end = 100.0
        motion = run_assembly(asm, t_end, solver="adaptive", settings=SETTINGS)
        seconds = cpu(lambda: run_assembly(asm, t_end, solver="adaptive", settings=SETTINGS))
        print(f"n = {n:4d}  t_end = {t_end:6g}  {len(motion.t):7d} samples  {len(motion.switches):6d} switches  "
              f"{seconds:8.3f} s  residual {motion.energy_residual:.1e}")


if __name__ == "__main__":
    main()
