"""The exact structure engine on chains of n masses: time per switch and how it grows with n.

    python benchmarks/bench_structure_exact.py [n ...]      (default 2 10 100)

Each mass sits on a ground spring (k 1), a damper (c 0.02) and a Coulomb
contact (F_d 0.3, F_s 0.4) on its own belt (speeds 0.05 ... 0.15); neighbours
are coupled by springs (k 0.5); the start is a seeded random displacement.
Prints the best of 3 wall times of ``run_assembly`` (compiled first, not
timed), the switches, and the time per switch.  Every switch with stuck
contacts in new combinations builds and eigen-decomposes its reduced
matrix (O(n^3)); the walk to the next event costs O(n k) per point.  On
bench_structure.py's chains (CPU time): 38 us per switch at n = 2, 84 us at
n = 10, 1.8 ms at n = 100 (docs/performance.md).
On a shared machine run it with ``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1``:
threaded BLAS under load made a 100 x 100 complex eig take seconds.
"""

from __future__ import annotations

import sys

import numpy as np
from _common import best_of, header

from frictionflow import Coulomb
from frictionflow.core.assembly import Assembly
from frictionflow.solvers.structure import run_assembly

T_END = {2: 400.0, 10: 100.0, 100: 2.0}


def chain(n: int, seed: int = 1) -> Assembly:
    """The chain described in the module's docstring."""
    eye = np.eye(n)
    sd = np.vstack([eye, eye[:-1] - eye[1:]])
    sk = np.concatenate([np.ones(n), np.full(n - 1, 0.5)])
    rng = np.random.default_rng(seed)
    return Assembly(
        mass=np.eye(n), stiffness=sd.T @ (sk[:, None] * sd), damping=0.02 * np.eye(n), contact_dir=eye.copy(),
        belt=np.linspace(0.05, 0.15, n), law=np.tile(Coulomb(fd=0.3, fs=0.4).kernel_params(), (n, 1)),
        normal=np.hstack([np.ones((n, 1)), np.zeros((n, n))]), force_dir=np.zeros((0, n)), force_amp=np.zeros(0),
        force_omega=np.zeros(0), force_phi=np.zeros(0), spring_dir=sd, spring_k=sk, damper_dir=eye.copy(),
        damper_c=np.full(n, 0.02), q0=rng.uniform(-0.5, 0.5, n), v0=np.zeros(n),
    )


def main() -> None:
    sizes = [int(a) for a in sys.argv[1:]] or [2, 10, 100]
    header("exact structure engine: chains of n masses with a Coulomb contact each")
    run_assembly(chain(2), 1.0)  # compiled, not timed
    for n in sizes:
        asm, t_end = chain(n), T_END.get(n, 10.0)
        motion = run_assembly(asm, t_end)
        seconds = best_of(lambda: run_assembly(asm, t_end), repeat=3 if n < 100 else 1)
        count = max(1, len(motion.switches))
        print(f"n = {n:4d}  t_end = {t_end:6g}  {len(motion.switches):6d} switches  {seconds:8.3f} s  "
              f"{1e3 * seconds / count:9.3f} ms per switch  residual {motion.energy_residual:.1e}")


if __name__ == "__main__":
    main()
