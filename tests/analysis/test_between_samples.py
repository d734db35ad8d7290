"""Extremes, TR_B and stick shares between samples (analysis.between_samples), against closed forms and against an
independent Radau integration with located events."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import BeltOscillator, LuGre, Stiff, analyze, simulate
from frictionflow.analysis.between_samples import hermite_extremes, share_below
from frictionflow.orbits import find_orbit


def test_the_interpolant_of_a_cubic_is_the_cubic_so_its_extremes_are_exact():
    p = np.polynomial.Polynomial([0.3, -1.0, 0.2, 1.5])  # critical points at s = (-0.4 -+ sqrt(18.16)) / 9
    t = np.array([-1.3, -0.2, 0.9])
    crit = p.deriv().roots()
    lo, hi = hermite_extremes(t, p(t), p.deriv()(t))
    assert hi == pytest.approx(max(p(crit[(crit > t[0]) & (crit < t[-1])]).max(), p(t).max()), abs=1e-14)
    assert lo == pytest.approx(min(p(crit[(crit > t[0]) & (crit < t[-1])]).min(), p(t).min()), abs=1e-14)
    assert hi > p(t).max()  # the samples alone miss the peak


def _worst_errors(n: int) -> tuple[float, float]:
    """The largest errors of the share of |sin| < 1/2 (a third) and of its peak (1) over grid offsets."""
    h, shares, peaks = 2.0 * math.pi / n, [], []
    for offset in np.linspace(0.0, h, 10, endpoint=False):
        t = np.linspace(0.0, 2.0 * math.pi, n + 1) + offset
        shares.append(abs(share_below(t, np.sin(t), np.cos(t), 0.5) - 1.0 / 3.0))
        peaks.append(abs(hermite_extremes(t, np.sin(t), np.cos(t))[1] - 1.0))
    return max(shares), max(peaks)


def test_extremes_and_share_of_a_sine_converge_at_fourth_order():
    """The samples' own share is off by O(h) and their peak by O(h^2); the interpolant's by O(h^4): halving the
    step divides the worst error over grid offsets by about 16 (4 for second order)."""
    coarse, fine = _worst_errors(16), _worst_errors(32)
    assert coarse[0] / fine[0] > 12.0 and coarse[1] / fine[1] > 12.0


def test_a_step_that_dips_through_the_level_and_back_counts_its_inside_part():
    """Both ends outside, the middle inside: y = 4 (s - 1/2)^2 on [0, 1] is below 1/4 for s in (1/4, 3/4)."""
    t = np.array([0.0, 1.0])
    assert share_below(t, np.array([1.0, 1.0]), np.array([-4.0, 4.0]), 0.25) == pytest.approx(0.5, abs=1e-14)


# -- a run: the stiff solver's LuGre cycle against Radau with located crossings --------------------------------
LAW = LuGre(fd=0.02, fs=0.04, vs=0.01, delta=2.0, sigma0=100.0, sigma1=5.0)
MODEL = BeltOscillator(zeta=0.05, vb=0.01)


def _rhs(_t, y):
    x, v, z = y
    vr = MODEL.vb - v
    g = LAW.fd + (LAW.fs - LAW.fd) * math.exp(-((abs(vr) / LAW.vs) ** LAW.delta))
    dz = vr - LAW.sigma0 * abs(vr) * z / g
    return [v, LAW.sigma0 * z + LAW.sigma1 * dz - x - 2.0 * MODEL.zeta * v, dz]


def _radau_cycle(state, period):
    """One period from the orbit's state: the share with |V_r| < the stick speed from located crossings, and the
    extremes of X' at located zeros of X''."""
    level = LAW.stick_speed()
    cross = [lambda t, y, s=s: (MODEL.vb - y[1]) - s * level for s in (1.0, -1.0)]
    turn = lambda t, y: _rhs(t, y)[1]  # noqa: E731
    force_turn = lambda t, y: y[1] + 2.0 * MODEL.zeta * _rhs(t, y)[1]  # noqa: E731  (F_T' = X' + 2 zeta X'')
    sol = solve_ivp(_rhs, (0.0, period), state, method="Radau", rtol=1e-12, atol=1e-14,
                    events=[*cross, turn, force_turn], dense_output=True)
    times = np.sort(np.concatenate([[0.0, period], *sol.t_events[:2]]))
    inside = np.abs(MODEL.vb - sol.sol(0.5 * (times[:-1] + times[1:]))[1]) < level
    share = float(np.sum(np.diff(times)[inside]) / period)
    v_turns = sol.y_events[2][:, 1]
    peak = float(np.max(np.abs(sol.y_events[3][:, 0] + 2.0 * MODEL.zeta * sol.y_events[3][:, 1])))
    return share, float(v_turns.min()), float(v_turns.max()), peak


def test_stick_share_and_velocity_extremes_agree_with_located_events():
    orbit = find_orbit(MODEL, LAW, tol=1e-13)
    share, vmin, vmax, peak = _radau_cycle(np.asarray(orbit.state, dtype=float), orbit.period)
    run = analyze(simulate(MODEL, LAW, Stiff(rtol=1e-8), t_end=300.0))
    q = run.quantities()
    for got in (orbit.stick_fraction, q["stick_fraction"]):
        assert got == pytest.approx(share, rel=1e-6)  # the samples' own share was 2 % off
    for ext in (orbit.measures.extremes, q):
        assert ext["V_max"] == pytest.approx(vmax, rel=1e-8) and ext["V_min"] == pytest.approx(vmin, rel=1e-8)
    for trb in (orbit.measures.TR_B, q["TR_B"]):  # max |X + 2 zeta X'| / F_d: the steps' was 1.4e-5 low
        assert trb == pytest.approx(peak / LAW.fd, rel=1e-8)
