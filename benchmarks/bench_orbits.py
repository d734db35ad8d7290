"""Orbit speed: one Poincare-map evaluation, one shooting, one continuation.

    python benchmarks/bench_orbits.py

Prints milliseconds per Poincare-map evaluation (flow to the next section
crossing with its monodromy) for the closed-form engine (Coulomb) and the
smooth-law engine (Stribeck: compiled DOP853 since issue 13, solve_ivp
before), per Newton shooting from a guess (its power flow included), and the
time of a continuation through a fold of cycles (Stribeck, zeta 0.2 -> 0.4;
best of 3), and of a two-parameter stability chart where the code has one.  Uses only the public API, so the same script times an older
checkout: ``PYTHONPATH=<old>/src python benchmarks/bench_orbits.py``.
"""

from __future__ import annotations

from _common import best_of, header

from frictionflow import BeltOscillator, Coulomb, Stribeck
from frictionflow.orbits import continuation, make_flow, shoot


def main() -> None:
    header("frictionflow orbits")
    cases = {
        "coulomb (closed form)": (BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04), 0.045),
        "stribeck (smooth)": (BeltOscillator(zeta=0.3, vb=0.016), Stribeck(0.02, 0.04, 0.01), 0.031),
    }
    for name, (model, law, x) in cases.items():
        flow = make_flow(model, law)
        flow.run((x, 0.0), returns=1)  # compile / warm up
        t_map = best_of(lambda flow=flow, x=x: flow.run((x, 0.0), returns=1), repeat=5)
        t_shoot = best_of(lambda model=model, law=law, x=x: shoot(model, law, x), repeat=3)
        print(f"{name:24s} Poincare map {1e3 * t_map:8.2f} ms   shooting {1e3 * t_shoot:8.1f} ms")
    model, law = cases["stribeck (smooth)"][:2]
    t_cont = best_of(lambda: continuation(model, law, "zeta", 0.2, 0.4, seeds=("hopf",), n_equilibria=21), repeat=3)
    print(f"continuation through a fold of cycles: {t_cont:.3f} s")
    try:  # issue 13's two-parameter chart (absent from older checkouts)
        import numpy as np

        from frictionflow.orbits import stability_chart
    except ImportError:
        return
    t_chart = best_of(lambda: stability_chart(model, law, "vb", np.linspace(0.004, 0.03, 14), "zeta", (0.0, 1.0), fold_every=1), repeat=1)
    print(f"stability chart (14 values of V_b; Hopf, grazing, fold curves): {t_chart:.2f} s")


if __name__ == "__main__":
    main()
