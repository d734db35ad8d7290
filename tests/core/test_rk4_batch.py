"""The batched RK4 kernel against single runs: same motion, same steady-state answers."""

import numpy as np
import pytest

from frictionflow import BeltOscillator, Karnopp, RK4, simulate
from frictionflow.analysis.steady_state import classify_trajectory
from frictionflow.core import rk4_batch, sections as sec


@pytest.fixture(scope="module")
def lanes():
    rng = np.random.default_rng(7)
    n = 70  # more than one block of 64 lanes
    zeta = rng.uniform(0.0, 0.1, n)
    zeta[:5] = 0.0
    vb = rng.uniform(0.005, 0.1, n)
    fd = rng.uniform(0.01, 0.05, n)
    fs = fd * rng.uniform(1.0, 2.0, n)
    spring = rng.random(n) < 0.5
    return zeta, vb, fd, fs, spring


def test_batch_equals_single_runs(lanes):
    zeta, vb, fd, fs, spring = lanes
    n = len(zeta)
    laws = [Karnopp(fd[j], fs=fs[j], stick_force="spring" if spring[j] else "resultant") for j in range(n)]
    p = np.array([law.kernel_params() for law in laws])
    dt, t_end = 2e-3, 60.0
    steps = int(round(t_end / dt))
    rk4_batch.warm_up()
    rec, nrec, tail, fin = rk4_batch.run_batch(0, zeta, vb, p, fd.copy(), vb.copy(), dt, steps, sec.tail_start(0.0, t_end))
    out = rk4_batch.summarize(rec, nrec, tail, fin, vb, fd, 1e-6, 3, dt, True, 1e-6)
    kinds = set()
    for j in range(0, n, 3):
        tr = simulate(BeltOscillator(zeta=zeta[j], vb=vb[j]), laws[j], RK4(dt=dt), t_end=t_end)
        # the same motion (fused multiply-adds may round differently in SIMD)
        assert fin[j, sec.A_E] == pytest.approx(tr.energy[-1], rel=1e-9)
        assert np.allclose(fin[j, sec.A_W0 : sec.A_W0 + 4], tr.work[-1, :4], rtol=1e-9, atol=1e-18)
        cls, summ = classify_trajectory(tr)
        assert out[j, sec.C_KIND] == cls[sec.C_KIND]
        kinds.add(int(cls[sec.C_KIND]))
        np.testing.assert_allclose(out[j, sec.NC :], summ, rtol=1e-6, atol=1e-15)
    assert len(kinds) >= 2  # the sample covers more than one kind of steady state
