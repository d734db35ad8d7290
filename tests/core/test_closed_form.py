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


# -- harmonic forcing ----------------------------------------------------------------------------------

FORCED = [  # dyn, zeta, force, x0, v0, F_ex, Omega, theta
    (cf.OSC, 0.0, 0.02, 0.03, 0.01, 0.05, 0.7, 0.3),
    (cf.OSC, 0.05, 0.02, 0.03, -0.01, 0.05, 1.0, 1.3),
    (cf.OSC, 0.05, -0.02, 0.0, 0.0, 0.2, 3.5, -2.0),
    (cf.OSC, 1.0, -0.02, 0.03, 0.01, 0.1, 0.8, 0.0),  # critical
    (cf.OSC, 2.5, 0.04, -0.03, 0.02, 0.1, 1.7, 2.0),  # overdamped
    (cf.EXP, 0.3, 0.0, 0.01, 0.01, 0.1, 1.2, 0.5),
    (cf.LIN, 0.3, 0.0, 0.01, 0.01, 0.1, 1.2, 0.5),
    (cf.LIN, 0.3, 0.0, 0.01, 0.0, 0.1, 1.2, 0.5),
]


def forced_reference(dyn, zeta, force, x0, v0, fex, om, theta, t):
    """The forced phase ODE by scipy: slip feels f, the held motions (LIN, EXP) do not."""
    def rhs(s, y):
        if dyn == cf.OSC:
            return [y[1], force + fex * math.cos(om * s + theta) - y[0] - 2 * zeta * y[1]]
        return [y[1], -2 * zeta * y[1] if dyn == cf.EXP else 0.0]

    sol = solve_ivp(rhs, (0, t), [x0, v0], method="DOP853", rtol=1e-13, atol=1e-15)
    return sol.y[:, -1]


@pytest.mark.parametrize("dyn, zeta, force, x0, v0, fex, om, theta", FORCED)
def test_forced_state_matches_integration(dyn, zeta, force, x0, v0, fex, om, theta):
    co, pz, fz = cf.forced_phase(dyn, zeta, force, x0, v0, fex, om, theta)
    for t in (0.0, 0.3, 2.0, 7.5):
        x, v, a, j, f, df, _, _ = cf.forced_state(co, dyn, zeta, force, pz, fz, om, t)
        xr, vr = forced_reference(dyn, zeta, force, x0, v0, fex, om, theta, t) if t > 0 else (x0, v0)
        assert x == pytest.approx(xr, abs=1e-12) and v == pytest.approx(vr, abs=1e-12)
        assert f == pytest.approx(fex * math.cos(om * t + theta), abs=1e-15)
        assert df == pytest.approx(-fex * om * math.sin(om * t + theta), abs=1e-15)
        if dyn == cf.OSC:
            assert a == pytest.approx(force + f - x - 2 * zeta * v, abs=1e-15)
            assert j == pytest.approx(df - v - 2 * zeta * a, abs=1e-15)


@pytest.mark.parametrize("dyn, zeta, force, x0, v0, fex, om, theta", FORCED)
def test_forced_work_matches_quadrature(dyn, zeta, force, x0, v0, fex, om, theta):
    co, pz, fz = cf.forced_phase(dyn, zeta, force, x0, v0, fex, om, theta)
    state = lambda s: cf.forced_state(co, dyn, zeta, force, pz, fz, om, s)
    for T in (1e-3, 0.1, 3.0, 12.0):
        v2, wex = cf.forced_work(co, dyn, zeta, force, pz, fz, om, T)
        q = dict(epsabs=1e-17, epsrel=1e-13, limit=400)
        want_v2, _ = quad(lambda s: state(s)[1] ** 2, 0, T, **q)
        want_ex, _ = quad(lambda s: state(s)[1] * fex * math.cos(om * s + theta), 0, T, **q)
        # X' = Y' + X_p' may be small against its parts (near resonance): rounding on the parts' scale
        parts = (abs(v0) + 2 * om * abs(pz) + fex) ** 2 * T
        assert v2 == pytest.approx(want_v2, rel=1e-11, abs=1e-13 * parts)
        assert wex == pytest.approx(want_ex, rel=1e-11, abs=1e-13 * parts)


@pytest.mark.parametrize("z", [0.3j, -0.2 + 1.1j, -2.0 + 0.0j, 1e-9j, -1.0 + 3.0j])
def test_exp_integrals_on_both_sides_of_the_series_switch(z):
    for L in (1e-3, 0.2, 0.49 / abs(z), 0.51 / abs(z), 5.0):
        i0, _ = quad(lambda t: (np.exp(z * t)).real, 0, L, epsabs=0, epsrel=1e-13)
        i0i, _ = quad(lambda t: (np.exp(z * t)).imag, 0, L, epsabs=0, epsrel=1e-13)
        i1, _ = quad(lambda t: (t * np.exp(z * t)).real, 0, L, epsabs=0, epsrel=1e-13)
        i1i, _ = quad(lambda t: (t * np.exp(z * t)).imag, 0, L, epsabs=0, epsrel=1e-13)
        assert cf.exp_integral(z, L) == pytest.approx(complex(i0, i0i), rel=1e-13, abs=1e-300)
        assert cf.texp_integral(z, L) == pytest.approx(complex(i1, i1i), rel=1e-13, abs=1e-300)


@pytest.mark.parametrize("dyn, zeta, force, x0, v0, fex, om, theta", FORCED)
@pytest.mark.parametrize("a, b, d", [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.1, 0.3)])
def test_the_bound_on_g_second_derivative_holds(dyn, zeta, force, x0, v0, fex, om, theta, a, b, d):
    # G'' = a X'' + b X''' + d X'''' - e f'' by finite differences of G' on a fine grid, against the bound
    e = 1.0
    co, pz, fz = cf.forced_phase(dyn, zeta, force, x0, v0, fex, om, theta)
    K1, K2 = cf.free_bound(co, dyn, zeta, a, b, d)
    Kp = om * om * abs(complex(a - om * om * d, om * b) * pz - e * fz)

    def dg(s):
        x, v, acc, jerk, f, df, _, _ = cf.forced_state(co, dyn, zeta, force, pz, fz, om, s)
        return a * v + b * acc + d * jerk - e * df

    ts = np.linspace(0.0, 15.0, 30001)
    h = 1e-5
    g2 = np.array([(dg(s + h) - dg(s - h)) / (2 * h) for s in ts])
    for t0 in (0.0, 2.0, 9.0):
        *_, e1, e2 = cf.forced_state(co, dyn, zeta, force, pz, fz, om, t0)
        m2 = cf.bound_at(co, dyn, K1, K2, Kp, t0, e1, e2)
        assert np.all(np.abs(g2[ts >= t0]) <= m2 * (1 + 1e-6) + 1e-12)


FROM_START = [c for c in FORCED if c[0] != cf.OSC or c[1] < 1.0] + [  # the representations work_rep covers
    (cf.OSC, 0.005, 0.02, 0.03, 0.01, 0.05, 0.7, 0.3),  # -2 zeta: a small rate, integrated piece by piece
    (cf.OSC, 0.002, 0.0, 0.01, 0.0, 0.05, 0.9999, 1.0),  # near resonance: lam + i Omega small too
    (cf.EXP, 0.003, 0.0, 0.01, 0.02, 0.1, 1.2, 0.5),
    (cf.EXP, 0.0, 0.0, 0.01, 0.02, 0.1, 1.2, 0.5),
]


@pytest.mark.parametrize("dyn, zeta, force, x0, v0, fex, om, theta", FROM_START)
def test_work_between_matches_quadrature_piece_by_piece(dyn, zeta, force, x0, v0, fex, om, theta):
    # pieces of a phase, long and very short, each from the phase-start representation, against quadrature
    co, pz, fz = cf.forced_phase(dyn, zeta, force, x0, v0, fex, om, theta)
    rep = cf.work_rep(co, dyn, zeta, pz, fz, om)
    state = lambda s: cf.forced_state(co, dyn, zeta, force, pz, fz, om, s)
    edges = [0.0, 1e-9, 1e-3, 0.7, 3.1, 3.1 + 1e-7, 9.0, 21.0]
    parts = (abs(v0) + 2 * om * abs(pz) + fex) ** 2
    q = dict(epsabs=1e-17, epsrel=1e-13, limit=400)
    ea = cf.phase_exps(co, dyn, om, 0.0)
    total = np.zeros(2)
    for ta, tb in zip(edges[:-1], edges[1:]):
        eb = cf.phase_exps(co, dyn, om, tb)
        v2, wex = cf.work_between(rep, dyn, *ea, *eb, tb - ta)
        want_v2, _ = quad(lambda s: state(s)[1] ** 2, ta, tb, **q)
        want_ex, _ = quad(lambda s: state(s)[1] * fex * math.cos(om * s + theta), ta, tb, **q)
        # a piece's value is a difference on the phase's scale: accurate to rounding of that scale
        assert v2 == pytest.approx(want_v2, rel=1e-11, abs=1e-14 * parts)
        assert wex == pytest.approx(want_ex, rel=1e-11, abs=1e-14 * parts)
        total += (v2, wex)
        ea = eb
    # and the whole phase, the pieces summed, as forced_work integrates it in one
    v2, wex = cf.forced_work(co, dyn, zeta, force, pz, fz, om, edges[-1])
    assert total[0] == pytest.approx(v2, rel=1e-12, abs=1e-14 * parts * edges[-1])
    assert total[1] == pytest.approx(wex, rel=1e-12, abs=1e-14 * parts * edges[-1])
