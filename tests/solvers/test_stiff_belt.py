"""The stiff solver with a belt whose speed varies, V_b(tau) = V_b + A sin(Omega_b tau + phi_b): against the
constant belt, an independent Radau integration, the energy balances and the linear presliding closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from frictionflow import BeltOscillator, simulate
from frictionflow.core import stiff
from frictionflow.core.layout import VB_AMP, VB_OMEGA, VB_PHI
from frictionflow.friction import Coulomb, LuGre
from frictionflow.solvers import Adaptive, Stiff
from frictionflow.solvers.base import kernel_params

# stick-slip on a Stribeck dip, bristles stiff enough to stick (sigma0 |z| reaches F_S)
P = dict(fd=0.3, fs=0.5, vs=0.05, delta=2.0, sigma0=1e3, sigma1=30.0, sigma2=0.1)
BELT = dict(vb_amplitude=0.2, vb_omega=0.8, vb_phi=0.3)


def belt_rhs(p, zeta, vb, amp, om, ph, fex=0.0, omega=0.0, phi=0.0):
    """(X, X', z)' of LuGre friction on the belt V_b(t) = vb + amp sin(om t + ph), written from the equations."""
    def rhs(t, y):
        x, v, z = y
        vr = vb + amp * math.sin(om * t + ph) - v
        gv = p["fd"] + (p["fs"] - p["fd"]) * math.exp(-abs(vr / p["vs"]) ** p["delta"])
        zd = vr - p["sigma0"] * abs(vr) * z / gv
        f = p["sigma0"] * z + p["sigma1"] * zd + p["sigma2"] * vr
        return [v, -x - 2.0 * zeta * v + f + fex * math.cos(omega * t + phi), zd]
    return rhs


def _kernel_run(q, model, rtol=1e-9):
    tol = np.array([rtol * 1e-2, rtol * 1e-2, rtol * 1e-2 * 1e-3, rtol])
    steps = np.array([1e-5, 0.5, 1e7, 2.0 * math.pi / 0.7])
    cap = 20000
    t, y, w = np.empty(cap), np.empty((3, cap)), np.empty((cap, stiff.N_CHANNELS))
    n = stiff.run(q, model.zeta, model.vb, np.zeros(3), 40.0, tol, steps, t, y, w, np.zeros(stiff.N_AT))[0]
    return t[:n], y[:, :n], w[:n]


def test_a_zero_amplitude_is_the_constant_belt_to_the_bit():
    model = BeltOscillator(zeta=0.05, vb=0.3, fex=0.1, omega=0.7)
    q = kernel_params(model, LuGre(**P))
    idle = q.copy()
    idle[VB_AMP], idle[VB_OMEGA], idle[VB_PHI] = 0.0, 2.3, 0.9  # a frequency and a phase, no amplitude
    for a, b in zip(_kernel_run(q, model), _kernel_run(idle, model)):
        np.testing.assert_array_equal(a, b)
    # through simulate: a model whose belt does not vary runs the constant belt's trajectory
    plain = simulate(model, LuGre(**P), Stiff(), t_end=40.0, x0=0.0, v0=0.0)
    still = simulate(BeltOscillator(zeta=0.05, vb=0.3, fex=0.1, omega=0.7, vb_omega=2.3, vb_phi=0.9), LuGre(**P),
                     Stiff(), t_end=40.0, x0=0.0, v0=0.0)
    for name in ("t", "x", "v", "fc", "internal", "dwork", "dbelt"):
        np.testing.assert_array_equal(getattr(plain, name), getattr(still, name))


@pytest.mark.parametrize("forced", [False, True])
def test_the_varying_belt_against_an_independent_radau_run(forced):
    force = dict(fex=0.1, omega=BELT["vb_omega"], phi=1.1) if forced else {}
    model = BeltOscillator(zeta=0.05, vb=0.3, **BELT, **force)
    t_end = 30.0
    ref = solve_ivp(belt_rhs(P, 0.05, 0.3, BELT["vb_amplitude"], BELT["vb_omega"], BELT["vb_phi"], *force.values()),
                    (0.0, t_end), [0.0, 0.0, 0.0], method="Radau", rtol=1e-12, atol=1e-14, dense_output=True)
    errs = []
    for rtol in (1e-8, 1e-10):
        traj = simulate(model, LuGre(**P), Stiff(rtol=rtol, atol=rtol), t_end=t_end, x0=0.0, v0=0.0)
        y = ref.sol(traj.t)
        errs.append(max(np.max(np.abs(traj.x - y[0])), np.max(np.abs(traj.v - y[1])),
                        P["sigma0"] * np.max(np.abs(traj.internal[0] - y[2]))))
        grid = np.linspace(0.0, t_end, 3001)
        np.testing.assert_allclose(traj(grid)[0], ref.sol(grid)[0], rtol=0.0, atol=1000 * rtol)
        # between the samples too: the bristles' interpolant takes their rate at V_b(tau)
        ds = traj.to_xarray(points_per_period=2000)
        added = ~ds["is_sample"].values
        tau = ds["tau"].values[added]
        assert added.sum() > 1000
        np.testing.assert_allclose(P["sigma0"] * ds["z"].values[added], P["sigma0"] * ref.sol(tau)[2], rtol=0.0,
                                   atol=1000 * rtol)
    assert errs[1] < 1000 * 1e-10 and errs[1] < errs[0] / 10.0, errs
    # it is a stick-slip run whose belt varies: the constant belt's differs by far more than the error
    const = simulate(BeltOscillator(zeta=0.05, vb=0.3, **force), LuGre(**P), Stiff(), t_end=t_end, x0=0.0, v0=0.0)
    assert np.max(np.abs(const(traj.t)[0] - traj.x)) > 1e-2


def test_the_samples_fall_on_every_belt_period():
    model = BeltOscillator(zeta=0.05, vb=0.3, **BELT)
    traj = simulate(model, LuGre(**P), Stiff(), t_end=60.0, x0=0.0, v0=0.0)
    period = 2.0 * math.pi / BELT["vb_omega"]
    k = np.arange(1, int(60.0 / period) + 1)
    assert np.all(np.isin(k * period, traj.t))


def test_energy_balances_with_storage_close_with_the_varying_belt():
    model = BeltOscillator(zeta=0.05, vb=0.3, fex=0.1, omega=BELT["vb_omega"], **BELT)
    rtol = 1e-10
    traj = simulate(model, LuGre(**P), Stiff(rtol=rtol, atol=rtol), t_end=40.0, x0=0.0, v0=0.0)
    # the contact: the belt's work F V_b(tau) goes into the mass, into heat and into the bristles
    bal = traj.interface_balance(0, -1)
    assert abs(bal.belt) > 1.0 and abs(bal.residual) < 1e-8 * abs(bal.belt), bal
    belt = np.cumsum(traj.dbelt)[-1]
    assert belt == pytest.approx(bal.belt, rel=1e-14)
    # the mass: its energy changes by the friction's work less the damper's plus the external force's
    w = traj.dwork.sum(axis=0)
    e = 0.5 * (traj.v**2 + traj.x**2)
    assert abs(e[-1] - e[0] - (w[1] - w[2] - w[0] + w[4])) < 1e-8 * (w[1] + w[2])
    # P_belt is F V_b(tau), not F V_b: its integral against the samples' trapezoid (coarse, a sanity bound)
    vb_t = model.belt_speed(traj.t)
    assert belt == pytest.approx(np.trapezoid(traj.fc * vb_t, traj.t), rel=1e-2)
    assert abs(belt - np.trapezoid(traj.fc * model.vb, traj.t)) > 0.1 * abs(belt)


def test_presliding_on_a_slowly_oscillating_belt_follows_the_linear_bristle_spring():
    # the belt oscillates about rest, V_b = A sin(Omega_b tau), displacing B = A/Omega_b (1 - cos Omega_b tau);
    # far below breakaway the bristles are a linear spring-damper: z' = V_r (the neglected term sigma0 |V_r| z / g
    # is eps = sigma0 |z| / F_C at most, relative), z = B - X, and
    #   X'' + (2 zeta + c) X' + (1 + sigma0) X = sigma0 B + c B',  c = sigma1 + sigma2
    p = dict(fd=0.5, fs=0.75, vs=0.001, delta=2.0, sigma0=5e4, sigma1=220.0, sigma2=0.3)
    zeta, amp, om = 0.05, 1e-5, 0.1
    model = BeltOscillator(zeta=zeta, vb=0.0, vb_amplitude=amp, vb_omega=om)
    t_end = 2.0 * 2.0 * math.pi / om
    traj = simulate(model, LuGre(**p), Stiff(rtol=1e-10, atol=1e-14), t_end=t_end, x0=0.0, v0=0.0)
    s0, c = p["sigma0"], p["sigma1"] + p["sigma2"]
    # steady state: the constant part of B statically, its harmonic -A/Omega_b e^{i Omega_b tau} through H(i Omega_b)
    s = 1j * om
    gain = (s0 + c * s) / (s * s + (2.0 * zeta + c) * s + 1.0 + s0)
    b0 = amp / om

    def steady(t):
        return s0 / (1.0 + s0) * b0 - b0 * np.real(gain * np.exp(s * t)), -b0 * np.real(s * gain * np.exp(s * t))

    # and the transient from rest, exact: the homogeneous system's matrix exponential
    m = np.array([[0.0, 1.0], [-(1.0 + s0), -(2.0 * zeta + c)]])
    x0, v0 = steady(0.0)
    grid = np.linspace(0.0, t_end, 801)
    lin = np.array([steady(t)[0] + (expm(m * t) @ np.array([-x0, -v0]))[0] for t in grid])
    eps = s0 * np.max(np.abs(traj.internal[0])) / p["fd"]
    assert eps < 1e-3  # far below breakaway
    assert np.max(np.abs(traj(grid)[0] - lin)) < 2.0 * eps * np.max(np.abs(lin))
    # the mass follows the belt: the displacement returns each period, X' = V_b to within the bristles' give
    assert np.max(np.abs(traj.v - model.belt_speed(traj.t))) < 2.0 * eps * amp + amp / (1.0 + s0) * 10.0


def test_forcing_and_belt_at_different_frequencies_are_refused_in_one_line():
    model = BeltOscillator(zeta=0.05, vb=0.3, fex=0.1, omega=0.9, **BELT)
    with pytest.raises(ValueError, match=r"^vb_omega must equal omega when the belt's speed and the external force "
                                         r"both vary \(one stroboscopic period\), got vb_omega=0.8, omega=0.9$"):
        simulate(model, LuGre(**P), Stiff(), t_end=1.0)


def test_the_stiff_solver_runs_the_varying_belt_and_is_named_by_the_others_refusal():
    assert Stiff.supports_belt_motion
    model = BeltOscillator(zeta=0.05, vb=0.3, **BELT)
    assert simulate(model, LuGre(**P), t_end=1.0).solver["name"] == "stiff"  # auto
    if not Adaptive.supports_belt_motion:  # a solver that does not run it names those that do
        with pytest.raises(ValueError, match=r"^solver=adaptive does not run a belt whose speed varies .*stiff"):
            simulate(model, Coulomb(), Adaptive(), t_end=1.0)


def test_rodas4_keeps_order_four_with_the_belts_time_derivative():
    # Rosenbrock methods take df/dtau at fixed y exactly for their order: the belt's acceleration enters it
    # through V_r (X'', z' and the work).  Sliding throughout (V_r well away from 0: |V_r| smooth), soft bristles
    # (the classical order shows), a forced belt oscillator on a varying belt
    smooth = dict(fd=0.3, fs=0.5, vs=0.05, delta=2.0, sigma0=10.0, sigma1=0.5, sigma2=0.1)
    model = BeltOscillator(zeta=0.1, vb=1.0, fex=0.2, omega=1.3, phi=0.4, vb_amplitude=0.3, vb_omega=1.3, vb_phi=0.2)
    q = kernel_params(model, LuGre(**smooth))
    t_end = 4.0
    ref = solve_ivp(belt_rhs(smooth, 0.1, 1.0, 0.3, 1.3, 0.2, 0.2, 1.3, 0.4), (0.0, t_end), [0.0, 0.0, 0.0],
                    method="Radau", rtol=1e-13, atol=1e-15).y[:, -1]
    errors = []
    for n in (40, 80, 160):
        y, ynew, w, h = np.zeros(3), np.empty(3), np.empty(stiff.N_CHANNELS), t_end / n
        ws = stiff.scratch(3)
        for k in range(n):
            stiff.rodas_step(q, 0.1, 1.0, k * h, y, h, ynew, w, np.array([1.0, 1.0, 1.0, 0.0]), ws)
            y[:] = ynew
        errors.append(np.max(np.abs(y - ref)))
    orders = [math.log2(errors[i] / errors[i + 1]) for i in range(2)]
    assert all(3.7 < p < 4.6 for p in orders), (errors, orders)
