"""Exact event-driven solver with harmonic forcing vs scipy, at the same accuracy.

    python benchmarks/bench_exact_forced.py

Cases: forced Coulomb friction, X'' + 2 zeta X' + X = F_c + F_ex cos(Omega tau),
(a) stick-slip on a moving belt, (b) a fixed surface (V_b = 0) with stops.
Goal (issue 12): the exact solver >= 1000x faster than scipy.solve_ivp at the
same accuracy.

scipy is what a careful user writes: DOP853 phase by phase, slip stopped by an
event at X' = V_b, stick (X' = V_b) integrated with events where the held
force |X + 2 zeta V_b - f| reaches F_s (max_step an eighth of the forcing
period, so that no excursion is stepped over), augmented with the work
integrals W_dv and W_ex as the exact solver computes them.

Accuracy: the state at tau = 200 against scipy at its tightest tolerance
(rtol 3e-14, the reference; its own error is estimated against rtol 1e-13
and printed).  scipy is timed at rtol 1e-10 ... 1e-13 with its error; the
ratio at the same accuracy is taken at the loosest rtol whose error is at most
the exact solver's (or, if none reaches it, at the tightest: then a lower
bound).  Times are per switch (scipy timed over tau = 200, the exact solver
over 2000: both costs are linear in the switches).
"""

from __future__ import annotations

import math

import numpy as np
from _common import best_of, header
from scipy.integrate import solve_ivp

from frictionflow import BeltOscillator, Coulomb, Exact, simulate

CASES = {
    "belt stick-slip": dict(zeta=0.05, vb=0.05, fd=0.02, fs=0.04, fex=0.05, omega=0.8),
    "fixed surface, stops": dict(zeta=0.05, vb=0.0, fd=0.02, fs=0.03, fex=0.1, omega=0.7),
}
X0, V0 = 0.01, 0.0
T_END = 2000.0
T_SCIPY = 200.0


def exact_run(c: dict, t_end: float):
    model = BeltOscillator(c["zeta"], c["vb"], fex=c["fex"], omega=c["omega"])
    return simulate(model, Coulomb(c["fd"], c["fs"]), Exact(), t_end=t_end, x0=X0, v0=V0)


def scipy_run(c: dict, t_end: float, rtol: float) -> tuple[np.ndarray, int]:
    """(X, X', W_dv, W_ex at t_end, number of switches): DOP853 with events, phase by phase."""
    zeta, vb, fd, fs, fex, om = c["zeta"], c["vb"], c["fd"], c["fs"], c["fex"], c["omega"]
    opts = dict(method="DOP853", rtol=rtol, atol=rtol * 1e-3)
    held = lambda t, x: x + 2 * zeta * vb - fex * math.cos(om * t)
    t, x, v, w = 0.0, X0, V0, np.zeros(2)
    mode = 1 if v < vb else (-1 if v > vb else (0 if abs(held(t, x)) <= fs else int(np.sign(held(t, x)))))
    switches = 0
    while True:
        if mode == 0:
            def stick(tt, y):
                return [vb, 2 * zeta * vb * vb, vb * fex * math.cos(om * tt)]
            hi = lambda tt, y: held(tt, y[0]) - fs
            lo = lambda tt, y: held(tt, y[0]) + fs
            hi.terminal = lo.terminal = True
            hi.direction, lo.direction = 1, -1
            sol = solve_ivp(stick, (t, t_end), [x, *w], events=(hi, lo), max_step=2 * math.pi / om / 8, **opts)
            if sol.status != 1:
                return np.array([sol.y[0, -1], vb, *sol.y[1:, -1]]), switches
            which = 0 if len(sol.t_events[0]) else 1
            t, y = sol.t_events[which][0], sol.y_events[which][0]
            x, v, w = y[0], vb, y[1:]
            mode = 1 if which == 0 else -1
        else:
            force = mode * fd

            def slip(tt, y):
                f = fex * math.cos(om * tt)
                return [y[1], force + f - y[0] - 2 * zeta * y[1], 2 * zeta * y[1] ** 2, y[1] * f]
            belt = lambda tt, y: y[1] - vb
            belt.terminal = True
            belt.direction = 1 if mode == 1 else -1
            sol = solve_ivp(slip, (t, t_end), [x, v, *w], events=belt, **opts)
            if sol.status != 1:
                return sol.y[:, -1].copy(), switches
            t, y = sol.t_events[0][0], sol.y_events[0][0]
            x, v, w = y[0], vb, y[2:]
            h = held(t, x)
            mode = 0 if abs(h) <= fs else (1 if h > 0 else -1)
        switches += 1


RTOLS = (1e-10, 1e-11, 1e-12, 1e-13)
REF_RTOL = 3e-14


def main() -> None:
    header("exact solver with harmonic forcing vs scipy solve_ivp (DOP853 + events), forced Coulomb friction")
    for name, c in CASES.items():
        exact_run(c, 50.0)  # compile
        tr = exact_run(c, T_END)
        n_exact = len(tr.events["t"])
        t_exact = best_of(lambda: exact_run(c, T_END), 20)
        per_exact = t_exact / n_exact
        # accuracy at T_SCIPY against scipy at its tightest
        ref, _ = scipy_run(c, T_SCIPY, REF_RTOL)
        ref_loose, _ = scipy_run(c, T_SCIPY, 1e-13)
        short = exact_run(c, T_SCIPY)
        w = short.dwork.sum(axis=0)
        got = np.array([short.x[-1], short.v[-1], w[0], w[4]])
        err_exact = float(np.max(np.abs(got[:2] - ref[:2])))
        print(f"\n## {name}: {c}")
        print(f"reference: scipy rtol {REF_RTOL:g}; its state differs from rtol 1e-13 by "
              f"{float(np.max(np.abs(ref_loose[:2] - ref[:2]))):.1e}")
        print(f"exact   {t_exact * 1e3:8.3f} ms for t_end {T_END:g}: {n_exact} switches, {len(tr.t)} samples, "
              f"{per_exact * 1e6:6.3f} us per switch; state error at {T_SCIPY:g} {err_exact:.1e} "
              f"(W_dv, W_ex {abs(got[2] - ref[2]):.1e}, {abs(got[3] - ref[3]):.1e})")
        matched = None
        for rtol in RTOLS:
            t_sp = best_of(lambda: scipy_run(c, T_SCIPY, rtol), 2)
            y, n_sp = scipy_run(c, T_SCIPY, rtol)
            err = float(np.max(np.abs(y[:2] - ref[:2])))
            per = t_sp / max(n_sp, 1)
            print(f"scipy rtol {rtol:g}: {per * 1e6:8.1f} us per switch ({n_sp} switches over {T_SCIPY:g}), "
                  f"state error {err:.1e} (exact {err_exact:.1e}); exact is {per / per_exact:6.0f}x faster per switch")
            if matched is None and err <= err_exact:
                matched = (rtol, err, per)
        rtol, err, per = matched or (rtol, err, per)
        bound = "" if matched else ", a lower bound: scipy does not reach the exact solver's error"
        print(f"at the same accuracy (scipy rtol {rtol:g}: error {err:.1e} vs exact {err_exact:.1e}): "
              f"exact {per_exact * 1e6:.3f} us vs scipy {per * 1e6:.1f} us per switch, "
              f"{per / per_exact:.0f}x (goal >= 1000x){bound}")


if __name__ == "__main__":
    main()
