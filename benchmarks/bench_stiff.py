"""The stiff solver (Rodas4, compiled) against scipy's ``solve_ivp`` Radau on the LuGre stick-slip example.

    python benchmarks/bench_stiff.py [t_end]

The example of Canudas de Wit et al. (1995) (see tests/friction/test_lugre.py),
from the mass sticking on the belt, to ``t_end`` (default 20: two stick-slip
cycles).  Both are compared at the same accuracy: the largest error in X and
in X' (the larger of the two) on a grid of 4001 points, each solver's own dense
output, against a reference (Radau at rtol 1e-12, itself within 2e-13 of Radau
at 1e-13); for each tolerance of the stiff solver, the loosest Radau tolerance
(of 1e-3 .. 1e-11 by quarter decades) that is at least as accurate is timed,
without its dense output (the same steps).  Times are CPU seconds (best of 3,
in one process; the stiff solver's best of 20: a run of a millisecond or less),
the stiff solver's through ``simulate`` (the Trajectory included); the ratio is Radau's over the stiff solver's.  The scipy
right-hand side is plain Python with its analytic Jacobian (what a user
writes), one call per evaluation; for information, the last column times the
same Radau run with the right-hand side and Jacobian compiled by numba (what
scipy's own machinery costs, the Python of the user's functions taken out).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
from _common import best_of, header
from scipy.integrate import solve_ivp

from frictionflow import BeltOscillator, simulate
from frictionflow.friction import LuGre
from frictionflow.solvers import Stiff

W0 = math.sqrt(2.0)
P = dict(fd=0.5, fs=0.75, vs=0.001 / W0, delta=2.0, sigma0=5e4, sigma1=math.sqrt(1e5) * W0 / 2, sigma2=0.4 * W0 / 2)
MODEL = BeltOscillator(zeta=0.0, vb=0.1 / W0)
LAW = LuGre(**P)


def cpu_best(fn, repeat: int = 3) -> float:
    return best_of(fn, repeat, clock=time.process_time)


def g(s):
    return P["fd"] + (P["fs"] - P["fd"]) * math.exp(-(abs(s) / P["vs"]) ** P["delta"])


def rhs(t, y):
    x, v, z = y
    s = MODEL.vb - v
    zd = s - P["sigma0"] * abs(s) * z / g(s)
    return [v, -x + P["sigma0"] * z + P["sigma1"] * zd + P["sigma2"] * s, zd]


def jac(t, y):
    x, v, z = y
    s = MODEL.vb - v
    gs = g(s)
    u = abs(s) / P["vs"]
    dg = -(P["fs"] - P["fd"]) * math.exp(-u ** P["delta"]) * P["delta"] * u ** (P["delta"] - 1) / P["vs"] if s else 0.0
    sg = math.copysign(1.0, s) if s else 0.0
    dr_dz = -P["sigma0"] * abs(s) / gs
    dr_ds = 1.0 - P["sigma0"] * z * sg * (gs - abs(s) * dg) / gs**2
    df_ds = P["sigma1"] * dr_ds + P["sigma2"]
    return [[0.0, 1.0, 0.0], [-1.0, -df_ds, P["sigma0"] + P["sigma1"] * dr_dz], [0.0, -dr_ds, dr_dz]]


def radau(t_end: float, rtol: float, dense: bool = True, fun=rhs, jacobian=jac):
    return solve_ivp(fun, (0.0, t_end), [0.0, MODEL.vb, 0.0], method="Radau", rtol=rtol,
                     atol=[rtol * 1e-2, rtol * 1e-2, rtol * 1e-2 * P["fs"] / P["sigma0"]], jac=jacobian,
                     dense_output=dense)


def compiled():
    """The right-hand side and Jacobian above compiled by numba (arrays in and out)."""
    from numba import njit

    fd, fs, vs, s0, s1, s2, vb = P["fd"], P["fs"], P["vs"], P["sigma0"], P["sigma1"], P["sigma2"], MODEL.vb

    @njit
    def rhs_c(t, y):
        s = vb - y[1]
        gs = fd + (fs - fd) * math.exp(-(s / vs) ** 2)
        zd = s - s0 * abs(s) * y[2] / gs
        return np.array([y[1], -y[0] + s0 * y[2] + s1 * zd + s2 * s, zd])

    @njit
    def jac_c(t, y):
        s = vb - y[1]
        e = math.exp(-(s / vs) ** 2)
        gs = fd + (fs - fd) * e
        dg = -(fs - fd) * e * 2.0 * abs(s) / vs**2
        sg = 1.0 if s > 0.0 else (-1.0 if s < 0.0 else 0.0)
        dr_dz = -s0 * abs(s) / gs
        dr_ds = 1.0 - s0 * y[2] * sg * (gs - abs(s) * dg) / gs**2
        return np.array([[0.0, 1.0, 0.0], [-1.0, -(s1 * dr_ds + s2), s0 + s1 * dr_dz], [0.0, -dr_ds, dr_dz]])

    return rhs_c, jac_c


def error(sol, grid, ref):
    """The larger of the largest errors in X and in X' on ``grid``."""
    y = sol(grid)
    return max(np.max(np.abs(y[0] - ref[0])), np.max(np.abs(y[1] - ref[1])))


def stiff(t_end: float, rtol: float):
    return simulate(MODEL, LAW, Stiff(rtol=rtol, atol=rtol * 1e-2), t_end=t_end, x0=0.0, v0=MODEL.vb)


def main() -> None:
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 20.0
    header(f"stiff solver vs scipy Radau, LuGre stick-slip (Canudas de Wit et al. 1995), t_end = {t_end:g}")
    grid = np.linspace(0.0, t_end, 4001)
    ref = radau(t_end, 1e-12).sol(grid)[:2]
    stiff(1.0, 1e-8)  # compiled, not timed
    rhs_c, jac_c = compiled()
    radau(1.0, 1e-6, False, rhs_c, jac_c)
    radau_runs = {}
    for r in 10.0 ** -np.arange(3.0, 11.01, 0.25):  # quarter decades: the matched accuracy is close
        sol = radau(t_end, r)
        radau_runs[r] = (error(sol.sol, grid, ref), sol.t.size)
    print(f"{'stiff rtol':>10s} {'error':>9s} {'steps':>6s} {'CPU ms':>8s} | {'Radau rtol':>10s} {'error':>9s} "
          f"{'steps':>6s} {'CPU ms':>8s} | ratio | {'compiled rhs ms':>15s} ratio")
    for r in (1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
        tr = stiff(t_end, r)
        err = error(lambda g: tr(g)[:2], grid, ref)
        t_stiff = cpu_best(lambda: stiff(t_end, r), repeat=20)  # a few ms in all: best of 3 was the noise's
        match = [k for k, (e, _) in radau_runs.items() if e <= err]
        if not match:
            print(f"{r:10.0e} {err:9.2e} {len(tr.t):6d} {1e3 * t_stiff:8.2f} | no Radau tolerance down to 1e-11 is as accurate")
            continue
        rr = max(match)
        t_radau = cpu_best(lambda: radau(t_end, rr, False), repeat=1 if rr < 1e-9 else 3)
        t_comp = cpu_best(lambda: radau(t_end, rr, False, rhs_c, jac_c), repeat=1 if rr < 1e-9 else 3)
        e_r, n_r = radau_runs[rr]
        print(f"{r:10.0e} {err:9.2e} {len(tr.t):6d} {1e3 * t_stiff:8.2f} | {rr:10.1e} {e_r:9.2e} {n_r:6d} "
              f"{1e3 * t_radau:8.1f} | {t_radau / t_stiff:5.0f}x | {1e3 * t_comp:15.1f} {t_comp / t_stiff:4.0f}x")


if __name__ == "__main__":
    main()
