"""Forced periodic orbits: shooting time, continuation time per point, and one flow-map period.

    python benchmarks/bench_forced_orbits.py

Cases: the stable period-3 stick-slip orbit of the forced Coulomb belt
(zeta = 0.05, V_b = 0.1, F_ex = 0.5, Omega = 1, F_d = 0.5, F_s = 1) -- shot
from its transient (200 forcing periods) and from a converged guess -- and
the continuation of the harmonic orbit of a Stribeck belt in Omega from 0.8
to 1.2 (a Neimark-Sacker point, grazing corners, slip reversals), 512 RK4
steps per forcing period.  Compilation is excluded (one warm-up call).
"""

from __future__ import annotations

from dataclasses import replace

from _common import best_of, header

from frictionflow import BeltOscillator, Coulomb, Stribeck
from frictionflow.orbits.forced import continue_forced, find_forced_orbit, flow_run

SUB3 = BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.0)
SUB3_LAW = Coulomb(0.5, 1.0)
STRIBECK = BeltOscillator(zeta=0.03, vb=0.12, fex=0.02, omega=0.8)
STRIBECK_LAW = Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1.0)


def main() -> None:
    header("forced periodic orbits")
    o = find_forced_orbit(SUB3, SUB3_LAW, m=3)  # warm-up (compiles)
    t_map = best_of(lambda: flow_run(SUB3, SUB3_LAW, o.state, 1), repeat=20)
    print(f"flow map, one forcing period (512 steps, monodromy + work): {t_map * 1e6:8.1f} us")
    t_full = best_of(lambda: find_forced_orbit(SUB3, SUB3_LAW, m=3), repeat=5)
    print(f"shooting m=3 incl. 200-period transient:                    {t_full * 1e3:8.2f} ms")
    guess = o.state + [1e-3, 0.0]
    t_newton = best_of(lambda: find_forced_orbit(SUB3, SUB3_LAW, m=3, x0=guess[0], v0=guess[1]), repeat=5)
    print(f"shooting m=3 from a guess 1e-3 off (Newton only):           {t_newton * 1e3:8.2f} ms")
    continue_forced(replace(STRIBECK, omega=0.8), STRIBECK_LAW, "omega", 0.8, 0.82)  # warm-up
    branch = None

    def cont():
        nonlocal branch
        branch = continue_forced(STRIBECK, STRIBECK_LAW, "omega", 0.8, 1.2)

    t_cont = best_of(cont, repeat=3)
    n = len(branch)
    print(f"continuation Omega 0.8 -> 1.2: {n} points, {len(branch.events)} events, {t_cont:.2f} s, "
          f"{t_cont / n * 1e3:.1f} ms per point (events refined to 1e-8 included)")
    t_plain = best_of(lambda: continue_forced(STRIBECK, STRIBECK_LAW, "omega", 0.8, 1.2, detect=False), repeat=3)
    print(f"  without event detection: {t_plain:.2f} s, {t_plain / n * 1e3:.1f} ms per point")


if __name__ == "__main__":
    main()
