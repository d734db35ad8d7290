"""Basins of attraction: our batched adaptive kernel vs scipy and vs a smoothed-sign RK4, in one run.

    python benchmarks/bench_basins.py [--points 5000]

Case (issue 11): the bistable Stribeck oscillator -- F_d = 0.02, F_s = 0.04,
V_s = 0.05, delta = 1, zeta = 0.03, V_b = 0.12 -- whose sliding equilibrium
and stick-slip cycle coexist; initial conditions X(0) in [-0.2, 0.3],
X'(0) in [-0.3, 0.3], t_end = 500.  Goals: the 61 x 31 grid in <= 3 s on
2 cores, 5000 initial conditions in <= 5 s.

Baselines, each on a subsample and scaled to points/s:
* scipy ``solve_ivp`` (DOP853, rtol 1e-10) with the stick switches as events
  and Coulomb's stick rule applied between them (what a careful user writes);
* a numpy-vectorised fixed-step RK4 over all points at once with the sign
  smoothed as tanh(V_r / eps) (the usual approach of basin-stability tools).
Both are classified the usual way (the motion of the last 20 time units: at
rest about X* -> equilibrium, else a cycle) and compared with ours point by point.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from _common import header
from scipy.integrate import solve_ivp

from frictionflow import Stribeck
from frictionflow.core.friction import rest_mode
from frictionflow.sweep.compute import compute_chunk
from frictionflow.sweep.config import parse_sweep

FD, FS, VS, DELTA, ZETA, VB, T_END = 0.02, 0.04, 0.05, 1.0, 0.03, 0.12, 500.0
LAW = Stribeck(FD, FS, VS, DELTA)
X_STAR = float(LAW.sliding_equilibrium(VB))
EQUILIBRIUM, PERIODIC = 1, 0


def F(s):
    return FD + (FS - FD) * np.exp(-((s / VS) ** DELTA))


def ours(nx: int, nv: int) -> tuple[float, np.ndarray]:
    spec = {"friction": "stribeck", "fd": FD, "fs": FS, "vs": VS, "delta": DELTA, "zeta": ZETA, "vb": VB, "t_end": T_END,
            "grid": {"x0": {"start": -0.2, "stop": 0.3, "num": nx}, "v0": {"start": -0.3, "stop": 0.3, "num": nv}}}
    cfg = parse_sweep(spec)
    t = time.perf_counter()
    out = compute_chunk(cfg.source, (0, 0), cfg.shape)
    return time.perf_counter() - t, out[0].ravel().astype(int)


def grid(nx: int, nv: int) -> tuple[np.ndarray, np.ndarray]:
    x, v = np.meshgrid(np.linspace(-0.2, 0.3, nx), np.linspace(-0.3, 0.3, nv), indexing="ij")
    return x.ravel(), v.ravel()


def _verdict(x: np.ndarray, v: np.ndarray) -> int:
    return EQUILIBRIUM if np.ptp(x) < 1e-4 and np.ptp(v) < 1e-4 else PERIODIC


def scipy_one(x0: float, v0: float) -> int:
    """Slip phases by DOP853 with V_r = 0 as a terminal event; at V_r = 0 Coulomb's stick rule; stick in closed form."""
    t, x, v = 0.0, x0, v0
    mode = 1 if VB - v > 0 else -1
    xs, vs = [], []
    while t < T_END:
        if mode == 0:  # stick: X' = V_b until |X + 2 zeta V_b| reaches F_s
            dt = min(T_END - t, (FS - (x + 2 * ZETA * VB)) / VB)
            if t + dt > T_END - 20:
                tail = np.linspace(max(t, T_END - 20), t + dt, 50)
                xs.append(x + VB * (tail - t)), vs.append(np.full(50, VB))
            t, x = t + dt, x + VB * dt
            mode = rest_mode(x, ZETA, VB, FS, True, FS, 0.0, 0.0) or 1
            continue

        def rhs(_t, y, d=mode):
            return [y[1], d * F(abs(VB - y[1])) - y[0] - 2 * ZETA * y[1]]

        def hit(_t, y, d=mode):
            return d * (VB - y[1])

        hit.terminal, hit.direction = True, -1
        sol = solve_ivp(rhs, (t, T_END), [x, v], method="DOP853", rtol=1e-10, atol=1e-13, events=hit, dense_output=True)
        if sol.t[-1] > T_END - 20:
            y = sol.sol(np.linspace(max(t, T_END - 20), sol.t[-1], 200))
            xs.append(y[0]), vs.append(y[1])
        t, x, v = sol.t[-1], sol.y[0, -1], sol.y[1, -1]
        if sol.status == 1:
            v = VB
            mode = rest_mode(x, ZETA, VB, FS, True, FS, 0.0, 0.0)  # unforced: no external force or rate
    return _verdict(np.concatenate(xs), np.concatenate(vs))


def tanh_rk4(x0: np.ndarray, v0: np.ndarray, dt: float = 5e-3, eps: float = 1e-3) -> np.ndarray:
    """All points at once: RK4 with F_c = tanh(V_r / eps) F(|V_r|)."""
    def acc(x, v):
        vr = VB - v
        return np.tanh(vr / eps) * F(np.abs(vr)) - x - 2 * ZETA * v

    x, v = x0.copy(), v0.copy()
    n = int(round(T_END / dt))
    keep = int(20 / dt)
    lo_x, hi_x, lo_v, hi_v = (np.full_like(x, s) for s in (np.inf, -np.inf, np.inf, -np.inf))
    for i in range(n):
        k1x, k1v = v, acc(x, v)
        k2x, k2v = v + 0.5 * dt * k1v, acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v)
        k3x, k3v = v + 0.5 * dt * k2v, acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v)
        k4x, k4v = v + dt * k3v, acc(x + dt * k3x, v + dt * k3v)
        x = x + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        v = v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        if i >= n - keep:
            lo_x, hi_x = np.minimum(lo_x, x), np.maximum(hi_x, x)
            lo_v, hi_v = np.minimum(lo_v, v), np.maximum(hi_v, v)
    return np.where((hi_x - lo_x < 1e-4) & (hi_v - lo_v < 1e-4), EQUILIBRIUM, PERIODIC)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=5000)
    ap.add_argument("--sample", type=int, default=10, help="points for the scipy baseline")
    ap.add_argument("--lanes", type=int, default=100, help="points for the smoothed RK4 baseline")
    args = ap.parse_args()
    header("basins of the bistable Stribeck oscillator: points/s, and agreement of classifications")
    ours(2, 1)  # compile / load the kernels
    t61, _ = ours(61, 31)
    print(f"ours 61 x 31 = 1891 points: {t61:.2f} s ({1891 / t61:.0f} points/s; goal <= 3 s)")
    nx = int(round(math.sqrt(args.points * 5 / 6)))
    nv = max(1, args.points // nx)
    t_ours, kinds = ours(nx, nv)
    n = nx * nv
    print(f"ours {n} points: {t_ours:.2f} s ({n / t_ours:.0f} points/s; goal 5000 in <= 5 s)"
          f"  equilibrium {np.mean(kinds == EQUILIBRIUM):.3f}, periodic {np.mean(kinds == PERIODIC):.3f}")
    x0, v0 = grid(nx, nv)
    rng = np.random.default_rng(1)
    pick = rng.choice(n, size=min(args.sample, n), replace=False)
    t = time.perf_counter()
    sp = np.array([scipy_one(x0[i], v0[i]) for i in pick])
    t_sp = (time.perf_counter() - t) / len(pick)
    agree = np.mean(sp == kinds[pick])
    print(f"scipy DOP853 + events: {1 / t_sp:.1f} points/s ({t_sp / (t_ours / n):.0f}x slower); agrees on {agree:.1%} of {len(pick)}")
    lanes = rng.choice(n, size=min(args.lanes, n), replace=False)
    t = time.perf_counter()
    th = tanh_rk4(x0[lanes], v0[lanes])
    t_th = (time.perf_counter() - t) / len(lanes)
    agree = np.mean(th == kinds[lanes])
    print(f"numpy RK4, tanh sign (eps 1e-3, dt 5e-3): {1 / t_th:.1f} points/s ({t_th / (t_ours / n):.0f}x slower); "
          f"agrees on {agree:.1%} of {len(lanes)}")


if __name__ == "__main__":
    main()
