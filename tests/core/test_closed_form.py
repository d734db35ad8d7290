"""Closed forms of one phase against scipy quadrature and ODE integration."""

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from frictionflow.core import closed_form as cf


def reference(dyn, zeta, force, x0, v0, t):
    """The phase ODE integrated by scipy (independent of the closed form)."""
    def rhs(_, y):
        if dyn == cf.OSC:
            return [y[1], force - y[0] - 2 * zeta * y[1]]
        if dyn == cf.EXP:
            return [y[1], -2 * zeta * y[1]]
        return [y[1], 0.0]

    sol = solve_ivp(rhs, (0, t), [x0, v0], method="DOP853", rtol=1e-13, atol=1e-15)
    return sol.y[:, -1]


CASES = [
    (cf.OSC, 0.0, 0.02, 0.03, 0.01),
    (cf.OSC, 0.05, 0.02, 0.03, -0.01),
    (cf.OSC, 1.0, -0.02, 0.03, 0.01),  # critical
    (cf.OSC, 2.5, 0.04, -0.03, 0.02),  # overdamped
    (cf.EXP, 0.3, 0.0, 0.01, 0.01),
    (cf.LIN, 0.3, 0.0, 0.01, 0.01),
]


@pytest.mark.parametrize("dyn, zeta, force, x0, v0", CASES)
def test_state_matches_integration(dyn, zeta, force, x0, v0):
    for t in (0.3, 2.0, 7.5):
        x, v, a = cf.state(dyn, zeta, force, x0, v0, t)
        xr, vr = reference(dyn, zeta, force, x0, v0, t)
        assert x == pytest.approx(xr, abs=1e-12) and v == pytest.approx(vr, abs=1e-12)


@pytest.mark.parametrize("dyn, zeta, force, x0, v0", CASES)
def test_integral_of_v2_matches_quadrature(dyn, zeta, force, x0, v0):
    for T in (0.1, 3.0, 12.0):
        want, _ = quad(lambda s: cf.state(dyn, zeta, force, x0, v0, s)[1] ** 2, 0, T, epsabs=1e-16, epsrel=1e-13, limit=200)
        assert cf.integral_v2(dyn, zeta, force, x0, v0, T) == pytest.approx(want, rel=1e-11, abs=1e-18)


@pytest.mark.parametrize("dyn, zeta, force, x0, v0", CASES[:4])
@pytest.mark.parametrize("a, b", [(1.0, 0.0), (0.0, 1.0), (1.0, 0.1)])
def test_critical_points_are_where_g_turns(dyn, zeta, force, x0, v0, a, b):
    out = np.empty(64)
    n = cf.critical_points(cf.coefficients(dyn, zeta, force, x0, v0), dyn, a, b, 0.0, 20.0, out)
    for t in out[:n]:
        _, v, acc = cf.state(dyn, zeta, force, x0, v0, t)
        jerk = -v - 2 * zeta * acc
        # g' = a X' + b X'' vanishes there
        assert a * v + b * acc == pytest.approx(0.0, abs=1e-13)
        _ = jerk
    # and g is monotone between them: sample and count sign changes of g'
    ts = np.linspace(0, 20.0, 20001)
    gp = np.array([a * s[1] + b * s[2] for s in (cf.state(dyn, zeta, force, x0, v0, t) for t in ts)])
    changes = np.count_nonzero(np.diff(np.sign(gp)) != 0)
    assert changes == n


def test_underdamped_critical_points_repeat_every_half_period():
    out = np.empty(64)
    zeta = 0.1
    n = cf.critical_points(cf.coefficients(cf.OSC, zeta, 0.0, 0.1, 0.0), cf.OSC, 0.0, 1.0, 0.0, 30.0, out)
    assert n >= 8
    assert np.allclose(np.diff(out[:n]), math.pi / math.sqrt(1 - zeta**2), rtol=1e-12)


@pytest.mark.parametrize("dyn, zeta, force, x0, v0", CASES)
@pytest.mark.parametrize("a, b", [(1.0, 0.0), (0.0, 1.0), (1.0, 0.1)])
def test_first_critical_steps_through_the_critical_points(dyn, zeta, force, x0, v0, a, b):
    # the kernels generate critical points one at a time from (first, step): the same times, bit for bit
    co = cf.coefficients(dyn, zeta, force, x0, v0)
    out = np.empty(64)
    for t_from in (0.0, 1.3, 7.0):
        n = cf.critical_points(co, dyn, a, b, t_from, 20.0, out)
        t, step = cf.first_critical(co, dyn, a, b, t_from)
        got = []
        while t < 20.0:
            got.append(t)
            t += step
        assert got == list(out[:n])
        assert all(g > t_from for g in got)
