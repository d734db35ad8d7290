"""Exact event-driven solver vs compiled RK4 and vs scipy, in one run.

    python benchmarks/bench_exact.py

Case: ideal Coulomb stick-slip, zeta = 0.05, F_d = 0.02, F_s = 0.04, V_b = 0.01
(a damped stick-slip limit cycle with ~ 40 % sticking).  Goals: exact >= 100x
(issue 3; issue 9: >= 500x, moonshot 1000x) faster than the compiled RK4 at
dt = 1e-3 over the same simulated time, and >= 1000x faster than
scipy.solve_ivp (DOP853 with events, rtol 1e-10) reaching the same accuracy on
the period and the averages.

Prints the cost per switch of ``simulate`` and of the kernel alone (the
difference is the solver facade: buffers, copies, the Trajectory), both
against RK4 timed in the same rounds (best of several, interleaved, so that
load from other processes hits both alike).

The exact solver copies a stretch of switches that repeats bit for bit (here
the stick-slip cycle, from its second release on) instead of integrating it
again (``Exact(replicate=...)``, :func:`frictionflow.core.exact.run`): both
are timed, with how many switches were integrated and how many copied, and
the two trajectories are checked to be identical.
"""

from __future__ import annotations

import math

import numpy as np
from _common import best_of, header
from scipy.integrate import solve_ivp

from frictionflow import RK4, BeltOscillator, Coulomb, Exact, analyze, simulate
from frictionflow.core import exact as kernel
from frictionflow.core import sections
from frictionflow.core.records import run_record
from frictionflow.solvers.base import output_buffers

ZETA, VB, FD, FS = 0.05, 0.01, 0.02, 0.04
T_END = 2000.0


def exact_run(t_end: float = T_END, replicate: bool = True):
    return simulate(BeltOscillator(ZETA, VB), Coulomb(FD, FS), Exact(replicate=replicate), t_end=t_end)


def rk4_run(t_end: float = T_END):
    return simulate(BeltOscillator(ZETA, VB), Coulomb(FD, FS, rk4_band=1e-4), RK4(dt=1e-3), t_end=t_end)


def scipy_run(t_end: float) -> dict[str, float]:
    """What a careful user writes with scipy: DOP853 slip phases stopped by events, analytic stick.

    Augmented with the work integrals; returns the period (between the last two
    stick onsets) and the averages over that period.
    """

    def slip(t, y):
        f = FD  # slip+ (the only slip direction on this orbit)
        v = y[1]
        return [v, f - y[0] - 2 * ZETA * v, 2 * ZETA * v * v, max(v * f, 0.0), max(-v * f, 0.0)]

    def reach_belt(t, y):
        return y[1] - VB

    reach_belt.terminal = True
    reach_belt.direction = 1
    t, x, w = 0.0, FD, np.zeros(3)
    onsets, works = [], []
    while t < t_end:
        # stick: X' = V_b until X + 2 zeta V_b = F_s (the resultant force reaches F_s)
        t_st = max(0.0, (FS - 2 * ZETA * VB - x) / VB)
        p = VB * ((x + 2 * ZETA * VB) * t_st + 0.5 * VB * t_st**2)
        w += [2 * ZETA * VB**2 * t_st, max(p, 0.0), max(-p, 0.0)]
        t, x = t + t_st, x + VB * t_st
        if t >= t_end:
            break
        sol = solve_ivp(slip, (t, t_end), [x, VB - 1e-14, *w], method="DOP853", rtol=1e-10, atol=1e-14, events=reach_belt)
        if sol.status != 1:
            break
        t, x, w = sol.t_events[0][0], sol.y_events[0][0][0], sol.y_events[0][0][2:]
        onsets.append(t)
        works.append(w.copy())
    T = onsets[-1] - onsets[-2]
    dw = works[-1] - works[-2]
    return {"period": T, "P_dv": dw[0] / T, "P_fin": dw[1] / T, "P_df": dw[2] / T}


def kernel_run(t_end: float = T_END, replicate: bool = True):
    """The exact kernel alone, on buffers allocated once (what ``simulate`` adds: the facade).

    Returns the call and its ``t_mode`` array, whose slot 1 receives the number of switches copied.
    """
    p = Coulomb(FD, FS).kernel_params()
    bufs = output_buffers(int(16 * t_end / (2 * math.pi)) + 64)
    t_mode = np.zeros(2, dtype=np.int64)
    t_tail = sections.tail_start(0.0, t_end)

    run = run_record((FD, VB), t_end, ZETA, VB, t_tail, 0.0, (0.0, 0.0, 0), (False, False, 0.0, 3), (0.0, 0.0))

    def go():
        return kernel.run(run, p, *bufs, t_mode, replicate, None)

    return go, t_mode


def identical(a, b) -> bool:
    """The same samples, work integrals and events, bit for bit."""
    return (all(np.array_equal(getattr(a, k), getattr(b, k)) for k in ("t", "x", "v", "fc", "mode", "dwork"))
            and all(np.array_equal(a.events[k], b.events[k]) for k in ("t", "mode")))


def main() -> None:
    header("exact event-driven solver vs compiled RK4 and scipy (Coulomb stick-slip)")
    exact_run(100.0)
    exact_run(100.0, replicate=False)
    rk4_run(100.0)
    go, counts = kernel_run()
    go_full, _ = kernel_run(replicate=False)
    go()
    go_full()
    ref = analyze(exact_run())
    # rounds of (exact, kernel, each with and without replication, best of 30; RK4 once): best of each over the rounds
    t_exact = t_kernel = t_full = t_kernel_full = t_rk4 = float("inf")
    for _ in range(4):
        t_exact = min(t_exact, best_of(exact_run, 30))
        t_kernel = min(t_kernel, best_of(go, 30))
        t_full = min(t_full, best_of(lambda: exact_run(replicate=False), 30))
        t_kernel_full = min(t_kernel_full, best_of(go_full, 30))
        t_rk4 = min(t_rk4, best_of(rk4_run, 1))
    rk = analyze(rk4_run())
    t_sp_end = 200.0
    t_scipy = best_of(lambda: scipy_run(t_sp_end), 2) * (T_END / t_sp_end)
    sp = scipy_run(t_sp_end)
    events = len(exact_run().events["t"])
    samples = len(exact_run().t)
    go()
    copied = int(counts[1])
    same = identical(exact_run(), exact_run(replicate=False))
    print(f"simulated time {T_END:g} ({T_END / ref.steady_state.period:.0f} periods, {events} switches, {samples} samples)")
    print(f"exact        {t_exact * 1e3:9.3f} ms  period {ref.steady_state.period:.15f}  P_fin {ref.power.P_fin:.15e}")
    print(f"RK4 dt=1e-3  {t_rk4 * 1e3:9.3f} ms  period {rk.steady_state.period:.15f}  P_fin {rk.power.P_fin:.15e}")
    print(f"scipy DOP853 {t_scipy * 1e3:9.3f} ms  period {sp['period']:.15f}  P_fin {sp['P_fin']:.15e}  (timed over {t_sp_end:g}, scaled)")
    print(f"exact, no replication {t_full * 1e3:9.3f} ms  (every switch integrated)")
    print(f"exact replication: {events - copied} switches integrated, {copied} copied; trajectory identical to the "
          f"integrated one bit for bit: {same}")
    print(f"exact per switch: {t_exact / events * 1e9:6.0f} ns with simulate(), {t_kernel / events * 1e9:6.0f} ns kernel alone "
          f"({(t_exact - t_kernel) * 1e6:.0f} us per call in the facade)")
    print(f"  no replication: {t_full / events * 1e9:6.0f} ns with simulate(), {t_kernel_full / events * 1e9:6.0f} ns kernel alone "
          f"({(t_full - t_kernel_full) * 1e6:.0f} us per call in the facade)")
    print(f"exact vs RK4:   {t_rk4 / t_exact:8.0f}x faster (kernel alone {t_rk4 / t_kernel:.0f}x; goal >= 500x, moonshot 1000x); "
          f"RK4's period error {abs(rk.steady_state.period - ref.steady_state.period):.1e}")
    print(f"  no replication: {t_rk4 / t_full:6.0f}x faster (kernel alone {t_rk4 / t_kernel_full:.0f}x)")
    print(f"exact vs scipy: {t_scipy / t_exact:8.0f}x faster (goal >= 1000x); scipy's period error "
          f"{abs(sp['period'] - ref.steady_state.period):.1e}, P_fin error {abs(sp['P_fin'] / ref.power.P_fin - 1):.1e}, "
          f"R_c {sp['P_dv'] / sp['P_fin']:.12f} vs {ref.power.R_c:.12f}")


if __name__ == "__main__":
    main()
