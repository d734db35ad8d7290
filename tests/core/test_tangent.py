"""The tangent kernel's pieces: switch location against closed forms, saltation against finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from frictionflow import BeltOscillator, Coulomb
from frictionflow.core import tangent as tg
from frictionflow.solvers.base import kernel_params
from tests.conftest import slip_solution


def _state(x, v):
    y = np.zeros(tg.NY)
    y[0], y[1], y[2], y[5] = x, v, 1.0, 1.0
    return y


def test_slip_switch_is_located_on_the_closed_form_motion():
    # unforced Coulomb slip+: X'' + 2 zeta X' + X = F_d in closed form; V_r = 0 where X' = V_b
    zeta, vb, fd = 0.05, 0.01, 0.02
    p = kernel_params(BeltOscillator(zeta=zeta, vb=vb), Coulomb(fd, 0.04))
    x0, v0 = 0.01, -0.02
    t_hit = brentq(lambda t: slip_solution(t, x0, v0, fd, zeta)[1] - vb, 0.5, 3.0, xtol=1e-15)
    sc = tg.scratch()
    out = sc.out
    y = _state(x0, v0)
    t, h = 0.0, 0.001  # RK4's own error then ~1e-15: what remains is the location
    while True:
        theta, switched = tg.slip_until(y, t, h, 1.0, zeta, vb, p, False, sc)
        if switched:
            break
        y[:] = out
        t += h
    assert t + theta == pytest.approx(t_hit, abs=1e-12)
    assert out[0] == pytest.approx(slip_solution(t_hit, x0, v0, fd, zeta)[0], abs=1e-12)


def test_a_touch_of_v_b_inside_one_step_is_found():
    # zeta = 0: slip+ on a circle about F_d with speed amplitude R = V_b (1 + 5e-3): X' stays above V_b
    # for 2 acos(1 / (1 + 5e-3)) ~ 0.2 time units, inside one step of 0.4 whose ends are both below V_b
    vb, fd = 0.01, 0.02
    p = kernel_params(BeltOscillator(zeta=0.0, vb=vb), Coulomb(fd, 0.04))
    R = vb * (1 + 5e-3)
    t_peak = 0.2  # X' = R sin(t + pi/2 - t_peak): the maximum at t_peak
    x0, v0 = fd - R * math.cos(math.pi / 2 - t_peak), R * math.sin(math.pi / 2 - t_peak)
    t_hit = t_peak - math.acos(vb / R)
    sc = tg.scratch()
    out = sc.out
    y = _state(x0, v0)
    theta, switched = tg.slip_until(y, 0.0, 0.4, 1.0, 0.0, vb, p, False, sc)
    assert switched
    # one RK4 step of 0.1 errs by ~R 0.1^5 / 120 ~ 1e-9 in X', over the crossing's slope R sin(0.1) ~ 1e-3
    assert theta == pytest.approx(t_hit, abs=1e-5)
    assert out[1] == pytest.approx(vb, abs=1e-15)


def _first_arrival(q, t0, t1, fs):
    """The first time |q| >= F_s on a fine scan, refined by brentq to the last bits (xtol ~0, rtol 4 eps), and its side."""
    grid = np.linspace(t0, t1, 30001)
    first = next(i for i, t in enumerate(grid) if abs(q(t)) >= fs)
    side = 1 if q(grid[first]) > 0 else -1
    return brentq(lambda t: side * q(t) - fs, grid[first - 1], grid[first], xtol=1e-300), side


def test_stick_exit_is_where_the_interface_force_reaches_fs():
    zeta, vb, fs, fex, omega = 0.05, 0.1, 1.0, 0.5, 1.3
    p = kernel_params(BeltOscillator(zeta=zeta, vb=vb, fex=fex, omega=omega), Coulomb(0.5, fs))
    x0, t0 = 0.2, 0.3

    def q(t):  # F_e - f(tau) while sticking
        return x0 + vb * (t - t0) + 2 * zeta * vb - fex * math.cos(omega * t)

    expected, side = _first_arrival(q, t0, t0 + 30.0, fs)
    xs, ts, te = tg.stick_phase(x0, t0, t0 + 30.0, zeta, vb, p)
    assert (xs, ts) == (x0, t0)
    assert te == pytest.approx(expected, rel=2e-15)
    assert side * q(te) >= fs * (1 - 1e-15)


def test_stick_exit_at_an_interior_maximum_is_found():
    # V_b = 0: the interface force is X + 0 - f(tau), maximal at Omega tau = pi: reaches F_s before it
    fs, fex, omega, x0 = 0.4, 0.5, 1.0, 0.0
    p = kernel_params(BeltOscillator(zeta=0.0, vb=0.0, fex=fex, omega=omega), Coulomb(0.2, fs))
    te = tg.stick_phase(x0, math.pi - 1.0, math.pi + 1.0, 0.0, 0.0, p)[2]
    assert te == pytest.approx(math.acos(-fs / fex), rel=1e-15)


def test_a_phase_held_past_fs_goes_on_past_its_monotone_piece():
    # a stick phase begins where the stick rule held the interface (rest_mode): begun past F_s moving outwards
    # (no consistent slip direction), it ends only where the held force, back inside, next reaches F_s outwards
    zeta, vb, fs, fex, omega = 0.0, 0.002, 0.04, 0.03, 1.0
    p = kernel_params(BeltOscillator(zeta=zeta, vb=vb, fex=fex, omega=omega), Coulomb(0.02, fs, stick_force="spring"))
    t0 = 2.5
    x0 = 1.01 * fs + fex * math.cos(omega * t0)  # F_e - f = 1.01 F_s, rising: V_b - f' = V_b + F_ex sin 2.5 > 0

    def q(t):
        return x0 + vb * (t - t0) - fex * math.cos(omega * t)

    turn = brentq(lambda t: vb + fex * omega * math.sin(omega * t), 2.6, 4.0, xtol=1e-15)  # its maximum
    back = brentq(lambda t: q(t) - fs, turn, turn + 2.0, xtol=1e-15)  # back inside
    expected, side = _first_arrival(q, back + 1e-9, back + 20.0, fs)
    te = tg.stick_phase(x0, t0, 50.0, zeta, vb, p)[2]
    assert te == pytest.approx(expected, rel=2e-15)


def test_unforced_stick_exit_is_the_closed_form():
    # F_e = X + 2 zeta V_b grows at V_b: it reaches F_s after (F_s - F_e) / V_b
    zeta, vb, fs = 0.05, 0.01, 0.04
    p = kernel_params(BeltOscillator(zeta=zeta, vb=vb), Coulomb(0.02, fs))
    x0, t0 = -0.01, 2.0
    te = tg.stick_phase(x0, t0, 100.0, zeta, vb, p)[2]
    assert te == pytest.approx(t0 + (fs - x0 - 2 * zeta * vb) / vb, rel=1e-15)
    assert tg.stick_phase(x0, t0, 5.0, zeta, vb, p)[2] == 5.0  # not before the end


def _block_map(p, zeta, vb, block, y, n_sub=512):
    """The kernel's state after one block from y, and (|J e1|, log|det J| - log|J e1|) from its tangent vectors."""
    strobe, est, counts = np.zeros((1, 3)), np.zeros((1, 2)), np.zeros(tg.N_COUNTS, dtype=np.int64)
    status, s1, s2 = tg.run(float(y[0]), float(y[1]), zeta, vb, p, block, n_sub, 0, 1, strobe, est, counts)
    assert status == tg.OK
    return strobe[0, :2], s1, s2, counts


def _fd_jacobian(p, zeta, vb, block, y, eps=1e-7):
    J = np.empty((2, 2))
    for i in range(2):
        e = np.zeros(2)
        e[i] = eps
        J[:, i] = (_block_map(p, zeta, vb, block, y + e)[0] - _block_map(p, zeta, vb, block, y - e)[0]) / (2 * eps)
    return J


@pytest.mark.parametrize("start,kind", [((-0.3, 0.2), "slip_reversals"), ((0.3, -0.2), "slip_reversals")])
def test_tangent_map_across_slip_reversals_is_the_flow_map_jacobian(start, kind):
    # forced, F_d = F_s: reversals through V_r = 0 and no stick; saltation diag(1, a+ / a-) at each
    zeta, vb, omega = 0.05, 0.01, 1.2
    model = BeltOscillator(zeta=zeta, vb=vb, fex=0.3, omega=omega)
    p = kernel_params(model, Coulomb(0.05, 0.05))
    y = np.array(start)
    _, s1, s2, counts = _block_map(p, zeta, vb, model.forcing_period, y)
    assert counts[tg.C_REVERSAL] >= 1 and counts[tg.C_STICK] == 0
    J = _fd_jacobian(p, zeta, vb, model.forcing_period, y)
    assert math.exp(s1) == pytest.approx(np.linalg.norm(J[:, 0]), rel=1e-6)
    assert math.exp(s1 + s2) == pytest.approx(abs(np.linalg.det(J)), rel=1e-6)


def test_tangent_map_across_stick_phases_is_the_flow_map_jacobian():
    # forced stick-slip from a sliding start: a stick onset (diag(1, 0)) and a slip onset (the
    # time-dependent surface |F_e - f(tau)| = F_s) in the block; the map is singular
    zeta, vb, omega = 0.05, 0.1, 1.0
    model = BeltOscillator(zeta=zeta, vb=vb, fex=0.5, omega=omega)
    p = kernel_params(model, Coulomb(0.5, 1.0))
    y = np.array([0.2, -0.3])
    block = 2 * model.forcing_period
    _, s1, s2, counts = _block_map(p, zeta, vb, block, y)
    assert counts[tg.C_STICK] >= 1 and counts[tg.C_SLIP] >= 1
    J = _fd_jacobian(p, zeta, vb, block, y)
    assert math.exp(s1) == pytest.approx(np.linalg.norm(J[:, 0]), rel=1e-6)
    assert s2 == -math.inf
    assert abs(np.linalg.det(J)) < 1e-6 * np.abs(J).max() ** 2


def test_tangent_map_from_a_sticking_start_is_the_flow_map_jacobian():
    # starting stuck: the slip onset's saltation [[1, 0], [a+ / (V_b - f'), 1]] carries dX into dX'
    zeta, vb, omega = 0.05, 0.1, 1.0
    model = BeltOscillator(zeta=zeta, vb=vb, fex=0.5, omega=omega)
    p = kernel_params(model, Coulomb(0.5, 1.0))
    y = np.array([0.5, vb])
    block = model.forcing_period / 2
    _, s1, _, counts = _block_map(p, zeta, vb, block, y)
    assert counts[tg.C_SLIP] == 1 and counts[tg.C_STICK] == 0
    J = _fd_jacobian(p, zeta, vb, block, y)
    assert np.linalg.norm(J[:, 1]) < 1e-5  # a perturbed X' slips back onto the belt at once
    assert math.exp(s1) == pytest.approx(np.linalg.norm(J[:, 0]), rel=1e-6)
