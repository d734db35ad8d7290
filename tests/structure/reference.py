"""An independent check of a structure's motion, phase by phase, written from the equations (numpy and scipy).

Within a phase the modes are fixed: slipping contacts push sigma F_d N_j(q) along e_j; the stuck ones hold
e_j . q' = b_j with the forces lambda = -(E M^-1 E^T)^-1 E M^-1 rest.  DOP853 integrates that from each
sample's state to the next sample; the stick/slip conditions are checked on a grid inside the phase.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from frictionflow.core.layout import FD, FS, RESULTANT


def forces(asm, modes, q, v, t, damped=True):
    """(rest, held forces of the stuck contacts by their rule, the same with the dampers: the friction)."""
    n = len(q)
    normal = asm.normal[:, 0] + asm.normal[:, 1:] @ q
    rest = -asm.stiffness @ q + asm.force_dir.T @ (asm.force_amp * np.cos(asm.force_omega * t + asm.force_phi))
    for j, m in enumerate(modes):
        if m != 0:
            rest = rest + m * asm.law[j, FD] * normal[j] * asm.contact_dir[j]
    stuck = np.flatnonzero(modes == 0)
    minv = np.linalg.inv(asm.mass)
    e = asm.contact_dir[stuck].reshape(len(stuck), n)
    g = np.linalg.inv(e @ minv @ e.T) if len(stuck) else np.zeros((0, 0))
    spring_only = -(g @ e @ minv @ rest) if len(stuck) else np.zeros(0)
    rest_d = rest - asm.damping @ v
    held = -(g @ e @ minv @ rest_d) if len(stuck) else np.zeros(0)
    rule = np.where(asm.law[stuck, RESULTANT] != 0.0, held, spring_only)
    return rest_d, stuck, e, held, rule, normal


def rhs(asm, modes):
    minv = np.linalg.inv(asm.mass)
    n = len(asm.q0)

    def f(t, y):
        q, v = y[:n], y[n:]
        rest, _, e, held, _, _ = forces(asm, modes, q, v, t)
        return np.concatenate((v, minv @ (rest + e.T @ held)))
    return f


def check_phases(motion, atol, grid=20):
    """Integrate every phase independently; the largest state error at the phase ends, relative to atol."""
    asm, n = motion.assembly, motion.n
    worst = 0.0
    for i in range(len(motion.t) - 1):
        t0, t1 = motion.t[i], motion.t[i + 1]
        if t1 <= t0:
            continue
        modes = motion.modes[:, i].astype(int)
        ts = np.linspace(t0, t1, grid + 2)
        sol = solve_ivp(rhs(asm, modes), (t0, t1), motion.state[:, i], method="DOP853", rtol=1e-12, atol=1e-14,
                        t_eval=ts, dense_output=False)
        assert sol.success
        end = motion.at(t1 - 1e-12 * max(1.0, t1)) if i + 1 < len(motion.t) - 1 else motion.state[:, -1]
        worst = max(worst, np.abs(sol.y[:, -1] - end).max() / atol)
        for k, t in enumerate(ts[1:-1], start=1):  # inside the phase every contact stays in its mode
            q, v = sol.y[:n, k], sol.y[n:, k]
            _, stuck, _, _, rule, normal = forces(asm, modes, q, v, t)
            vr = asm.belt - asm.contact_dir @ v
            for j, m in enumerate(modes):
                if m != 0:
                    assert m * vr[j] > -1e-9, (t, j, vr[j])
            for s, j in enumerate(stuck):
                assert abs(rule[s]) <= asm.law[j, FS] * normal[j] * (1 + 1e-9), (t, j, rule[s])
    return worst
