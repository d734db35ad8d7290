"""The compiled port of the stroboscopic test (core.strobe) gives numpy's bits, piece by piece."""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, simulate
from frictionflow.analysis import forced
from frictionflow.analysis.steady_state import stick_fraction
from frictionflow.core import strobe
from frictionflow.solvers.exact import Exact


@pytest.mark.parametrize("n", [*range(1, 40), 127, 128, 129, 255, 256, 257, 1000, 4099])
def test_pairwise_sum_is_numpys_sum_bit_for_bit(n):
    rng = np.random.default_rng(n)
    a = rng.random(n + 3) * 10.0 ** rng.uniform(-9, 0, n + 3)
    assert strobe.pairwise_sum(a, 3, n) == np.sum(a[3:])


def _repeat_multiple_numpy(x, v, tol, min_periods, max_multiple=strobe.MAX_MULTIPLE):
    """An independent statement of the repetition test, in numpy (what the analysis ran before it used the kernel)."""
    n = len(x)
    for m in range(1, max_multiple + 1):
        if n < (min_periods + 1) * m:
            break
        d = np.maximum(np.abs(x[m:] - x[:-m]), np.abs(v[m:] - v[:-m]))
        bad = np.flatnonzero(d > tol)
        run = len(d) - (bad[-1] + 1 if len(bad) else 0)
        if run >= min_periods * m:
            last = np.column_stack([x, v])[n - m:]  # a shorter cycle still converging is no m-cycle
            loose = strobe.SUBCYCLE_SPREAD * tol
            if any(np.all(np.abs(last[k:] - last[:-k]) <= loose) for k in range(1, m) if m % k == 0):
                return 0, 0
            return m, run // m
    return 0, 0


def _revisits_numpy(x, v, tol):
    h = len(x) // 2
    if h < 8:
        return False
    a = np.column_stack([x[:h], v[:h]])
    b = np.column_stack([x[h:], v[h:]])
    near = np.min(np.max(np.abs(b[:, None, :] - a[None, :, :]), axis=2), axis=1)
    return bool(np.all(near <= tol))


def test_repeat_multiple_and_revisits_agree_with_numpy_statements():
    rng = np.random.default_rng(0)
    for trial in range(300):
        m_true = int(rng.integers(1, 6))
        n = int(rng.integers(2, 40))
        base = rng.random((m_true, 2))
        seq = base[np.arange(n) % m_true] + rng.normal(0, 10.0 ** rng.uniform(-14, -6), (n, 2)) * (np.arange(n) < rng.integers(0, n))[:, None]
        x, v = np.ascontiguousarray(seq[:, 0]), np.ascontiguousarray(seq[:, 1])
        tol = 10.0 ** rng.uniform(-12, -7)
        assert strobe.repeat_multiple(x, v, tol, 3) == _repeat_multiple_numpy(x, v, tol, 3)
        if m_true > 1:  # a cycle whose points lie 1 to 1000 tolerances apart: a shorter cycle converging or not
            near = base[0] + (base[np.arange(n) % m_true] - base[0]) * tol * 10.0 ** rng.uniform(0, 3)
            xn, vn = np.ascontiguousarray(near[:, 0]), np.ascontiguousarray(near[:, 1])
            assert strobe.repeat_multiple(xn, vn, tol, 3) == _repeat_multiple_numpy(xn, vn, tol, 3)
        assert strobe.revisits(x, v, 0.3) == _revisits_numpy(x, v, 0.3)
        assert forced.repeat_multiple(x, v, tol, 3) == _repeat_multiple_numpy(x, v, tol, 3)  # the analysis uses it


def test_sections_and_window_values_of_a_forced_run_are_the_analysis_values():
    traj = simulate(BeltOscillator(zeta=0.01, vb=0.01, fex=0.02, omega=1.4), Coulomb(0.02, 0.04), Exact(), t_end=150.0,
                    x0=0.02, v0=0.01)
    period = traj.model.forcing_period
    k = len(traj.t)
    idx = strobe.section_indices(traj.t, k, period)
    # independently: the sample nearest to each k T, which must lie within 1e-9 T of it
    times = period * np.arange(int(traj.t[-1] / period * (1 + 1e-12)) + 1)
    nearest = np.abs(traj.t[None, :] - times[:, None]).argmin(axis=1)
    assert np.all(np.abs(traj.t[nearest] - times) <= 1e-9 * period * np.maximum(1.0, np.arange(len(times))))
    assert np.array_equal(idx, nearest)
    assert np.array_equal(forced.section_indices(traj), idx)  # the analysis uses it
    i0, i1 = int(idx[len(idx) // 3]), int(idx[-1])
    assert strobe.stick_fraction(traj.t, traj.mode, i0, i1) == stick_fraction(traj, (traj.t[i0], traj.t[i1]))
    assert 0.0 < strobe.stick_fraction(traj.t, traj.mode, i0, i1) < 1.0
