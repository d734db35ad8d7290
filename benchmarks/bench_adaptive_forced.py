"""Adaptive solver under harmonic forcing: wall time per run, next to the unforced run.

    python benchmarks/bench_adaptive_forced.py [t_end]

Prints, for each case, the best of 3 wall times of ``simulate`` to ``t_end``
(default 2000), the samples kept and the switches.  The unforced Stribeck
run is the reference the forced ones are compared with; the unforced kernel
itself is compared with the previous release by running this script on both
trees (PYTHONPATH), alternating.
"""

from __future__ import annotations

import sys

from _common import best_of, header

from frictionflow import Adaptive, BeltOscillator, Coulomb, Stribeck, simulate

STRIBECK = Stribeck(0.02, 0.04, vs=0.02)
CASES = {
    "unforced Stribeck stick-slip": (BeltOscillator(zeta=0.05, vb=0.01), STRIBECK),
    "forced Stribeck stick-slip (F_ex 0.02, Omega 0.8)": (BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=0.8), STRIBECK),
    "forced Stribeck sliding (V_b 0.3, Omega 3)": (BeltOscillator(zeta=0.05, vb=0.3, fex=0.1, omega=3.0), STRIBECK),
    "forced Coulomb V_b = 0 with stops (Omega 1.3)": (BeltOscillator(zeta=0.05, vb=0.0, fex=0.06, omega=1.3), Coulomb(0.02, 0.04)),
    "forced Coulomb held (V_b = 0, F_ex < F_s, Omega 10)": (BeltOscillator(zeta=0.05, vb=0.0, fex=0.039, omega=10.0),
                                                            Coulomb(0.02, 0.04)),
}


def main() -> None:
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 2000.0
    header(f"adaptive solver, forced and unforced, t_end = {t_end:g}")
    for name, (model, law) in CASES.items():
        simulate(model, law, Adaptive(), t_end=1.0, x0=0.0, v0=0.0)  # compiled, not timed
        tr = simulate(model, law, Adaptive(), t_end=t_end, x0=0.0, v0=0.0)
        seconds = best_of(lambda: simulate(model, law, Adaptive(), t_end=t_end, x0=0.0, v0=0.0))
        print(f"{name:55s} {1e3 * seconds:8.1f} ms  {len(tr.t):8d} samples  {len(tr.events['t']):6d} switches")


if __name__ == "__main__":
    main()
