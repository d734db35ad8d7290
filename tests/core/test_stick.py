"""The forced stick phase (core/stick.py) against an independent scan, in the walk itself and in the forced map's stick phases."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from frictionflow import BeltOscillator, Coulomb
from frictionflow.core import forced_map as fm
from frictionflow.core import stick
from frictionflow.solvers.base import kernel_params

#: (zeta, V_b, F_s, F_ex, Omega, phi, resultant): turning held forces (|V_b| < F_ex Omega) and a monotone one
CASES = [
    (0.05, 0.1, 1.0, 0.5, 1.3, 0.0, True),
    (0.02, -0.05, 0.3, 0.4, 0.7, 1.1, False),
    (0.0, 0.01, 0.25, 0.3, 2.0, -0.4, True),
    (0.1, 0.8, 0.5, 0.2, 1.5, 0.3, True),  # |V_b| > F_ex Omega: the held force never turns
]


def _p(zeta, vb, fs, fex, omega, phi, res):
    law = Coulomb(0.5 * fs, fs, stick_force="resultant" if res else "spring")
    return kernel_params(BeltOscillator(zeta=zeta, vb=vb, fex=fex, omega=omega, phi=phi), law)


def _held(x0, t0, t, zeta, vb, fex, omega, phi, res):
    """F_e - f(tau) while sticking from (t0, x0), written from the equations."""
    x = x0 + vb * (t - t0)
    return (x + 2.0 * zeta * vb if res else x) - fex * np.cos(omega * t + phi)


def _first_exit(x0, t0, t_end, zeta, vb, fs, fex, omega, phi, res):
    """The first time |F_e - f| >= F_s by a fine scan refined by brentq (t_end if none), and its side."""
    grid = np.linspace(t0, t_end, 400001)
    q = _held(x0, t0, grid, zeta, vb, fex, omega, phi, res)
    out = np.flatnonzero(np.abs(q) >= fs)
    if len(out) == 0:
        return t_end, 0
    i = out[0]
    side = 1.0 if q[i] > 0 else -1.0
    g = lambda t: side * _held(x0, t0, t, zeta, vb, fex, omega, phi, res) - fs  # noqa: E731
    return brentq(g, grid[i - 1], grid[i], xtol=1e-15, rtol=4 * np.finfo(float).eps), int(side)


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("start", [0.0, 0.5, -0.8])
def test_exit_time_is_the_first_arrival_at_fs(case, start):
    zeta, vb, fs, fex, omega, phi, res = case
    p = _p(*case)
    t0, t_end = 0.3, 40.0
    x0 = start * fs - _held(0.0, t0, t0, zeta, vb, fex, omega, phi, res)  # the held force starts at start F_s
    expected, _ = _first_exit(x0, t0, t_end, zeta, vb, fs, fex, omega, phi, res)
    te = stick.exit_time(x0, t0, t_end, False, zeta, vb, fs, res, p)
    assert te == pytest.approx(expected, rel=1e-13, abs=1e-13)


def test_a_short_excursion_is_not_stepped_over():
    # V_b = 0: F_e - f = x0 - F_ex cos(Omega tau), maximal x0 + F_ex at Omega tau = pi; put it 1e-10 above F_s
    fs, fex, omega = 0.4, 0.3, 1.0
    x0 = fs - fex + 1e-10
    p = _p(0.0, 0.0, fs, fex, omega, 0.0, True)
    te = stick.exit_time(x0, 0.0, 10.0, False, 0.0, 0.0, fs, True, p)
    assert te == pytest.approx(math.acos((x0 - fs) / fex), abs=1e-7)  # a root of multiplicity ~2: sqrt(eps) in time
    assert x0 - fex * math.cos(te) >= fs


@pytest.mark.parametrize("case", CASES[:3])
def test_friction_zero_is_where_the_held_friction_force_changes_sign(case):
    zeta, vb, fs, fex, omega, phi, res = case
    p = _p(*case)
    x0, t0 = -0.05, 0.0
    fc = lambda t: x0 + vb * (t - t0) + 2.0 * zeta * vb - fex * np.cos(omega * t + phi)  # noqa: E731
    grid = np.linspace(0.0, 20.0, 200001)
    i = np.flatnonzero(np.sign(fc(grid[1:])) != np.sign(fc(grid[:-1])))[0]
    expected = brentq(fc, grid[i], grid[i + 1], xtol=1e-15)
    z = stick.friction_zero(x0, t0, 0.0, 20.0, zeta, vb, res, p)
    assert z == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("case", CASES)
def test_the_forced_maps_stick_phase_ends_at_the_first_arrival(case):
    # the tangent integrator's stick phases (here the forced map's, which lists them) end by the same walk
    zeta, vb, fs, fex, omega, phi, res = case
    p = _p(*case)
    x0, t_end = 0.1, 40.0
    out = fm.map_out()
    status, n_sticks = fm.flow_map(x0, vb, zeta, vb, p, t_end, 800, out)
    assert status == fm.OK and n_sticks >= 1
    expected, _ = _first_exit(x0, 0.0, t_end, zeta, vb, fs, fex, omega, phi, res)
    assert out.sticks[0, 0] == 0.0
    assert out.sticks[0, 1] == pytest.approx(expected, rel=4e-15)


def test_held_force_and_its_turns():
    zeta, vb, fs, fex, omega, phi, res = CASES[1]
    p = _p(*CASES[1])
    for t in (0.0, 0.7, 3.9):
        assert stick.held_along(0.2, 0.1, t, zeta, vb, res, p) == pytest.approx(
            _held(0.2, 0.1, t, zeta, vb, fex, omega, phi, res), rel=1e-15, abs=1e-16)
        # the next turn: the rate V_b - f' = V_b + F_ex Omega sin(Omega t + phi) is 0 there and keeps its sign before
        tc = stick.next_turn(t, vb, p)
        rate = lambda s: vb + fex * omega * np.sin(omega * s + phi)  # noqa: E731
        assert abs(rate(tc)) <= 1e-15
        inside = np.linspace(t, tc, 1001)[1:-1]
        assert np.all(np.sign(rate(inside)) == np.sign(rate(inside[0])))
    assert stick.next_turn(0.0, 0.8, _p(*CASES[3])) == math.inf  # |V_b| > F_ex Omega
