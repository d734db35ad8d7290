"""Frequency response of the forced oscillator: the whole curve, and per forcing period.

    python benchmarks/bench_response.py [N_OMEGA] [PERIODS]

Case: Den Hartog's forced Coulomb oscillator on a fixed surface with viscous
damping (zeta = 0.05, F_d = F_s = 0.05, F_ex = 0.3, V_b = 0), Omega from 0.3
to 2.5, swept up and down with PERIODS forcing periods per frequency.  Goal
(issue 12): 200 frequencies x 2 directions x 300 periods in <= 5 s on 2
cores.  Baseline in the same run: the same curve with fixed-step RK4 (the
paper's method, dt = 1e-3 aligned to the forcing period) on a subset of the
frequencies, compared per forcing period.
"""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np
from _common import header

from frictionflow import RK4, BeltOscillator, Coulomb, Exact
from frictionflow.analysis.response import frequency_response

MODEL = BeltOscillator(zeta=0.05, vb=0.0, fex=0.3)
LAW = Coulomb(fd=0.05, fs=0.05)


def curve(solver, omegas, periods):
    t = time.perf_counter()
    ds = frequency_response(MODEL, LAW, omegas, solver=solver, periods=periods)
    return time.perf_counter() - t, ds


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    periods = int(sys.argv[2]) if len(sys.argv) > 2 else 300
    header(f"frequency response: {n} frequencies x 2 directions x {periods} periods")
    omegas = np.linspace(0.3, 2.5, n)
    curve(Exact(), omegas[:3], 20)  # compile
    wall, ds = curve(Exact(), omegas, periods)
    runs = 2 * n
    print(f"exact: {wall:.2f} s for the curve ({wall / runs * 1e3:.2f} ms per frequency, "
          f"{wall / (runs * periods) * 1e6:.1f} us per forcing period); goal <= 5 s")
    kinds = np.bincount(ds["kind"].values.ravel(), minlength=6)
    print(f"  kinds: {dict(zip(('periodic', 'equilibrium', 'not_settled', 'diverged', 'quasi', 'chaotic'), kinds.tolist()))}, "
          f"max energy residual {float(ds['energy_residual'].max()):.1e}")
    sub = omegas[:: max(1, n // 5)][:5]
    with warnings.catch_warnings():  # the baseline's coarse-step and thinning notes
        warnings.simplefilter("ignore")
        wall_rk4, ds_rk4 = curve(RK4(dt=1e-3), sub, periods)
    per_rk4 = wall_rk4 / (2 * len(sub) * periods)
    per_exact = wall / (runs * periods)
    print(f"rk4 (dt 1e-3), {len(sub)} frequencies: {per_rk4 * 1e6:.1f} us per forcing period; "
          f"exact is {per_rk4 / per_exact:.0f}x faster per period")
    amp = ds["amplitude"].sel(omega=sub).values
    print(f"  amplitudes exact vs rk4: max rel. difference {np.max(np.abs(amp - ds_rk4['amplitude'].values) / amp):.1e}")


if __name__ == "__main__":
    main()
