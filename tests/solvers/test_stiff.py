"""The stiff solver (Rodas4): its order, what it runs and refuses, and what its trajectories carry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.cli import main
from frictionflow.core import stiff
from frictionflow.friction import Coulomb, LuGre
from frictionflow.solvers import Adaptive, Exact, RK4, Stiff
from frictionflow.solvers.base import kernel_params
from frictionflow.trajectory import WORK_NAMES

from ..friction.test_lugre import lugre_rhs

# soft bristles: the classical order shows (with stiff ones, h sigma0 >> 1, Rosenbrock methods lose order in
# the bristles' initial layer: their stage order is 1)
SMOOTH = dict(fd=0.3, fs=0.5, vs=0.05, delta=2.0, sigma0=10.0, sigma1=0.5, sigma2=0.1)


def _fixed_steps(q, zeta, vb, y0, t_end, n):
    y, ynew, w = y0.copy(), np.empty(3), np.empty(stiff.N_CHANNELS)
    tol = np.array([1.0, 1.0, 1.0, 0.0])
    h = t_end / n
    ws = stiff.scratch(3)
    for k in range(n):
        stiff.rodas_step(q, zeta, vb, k * h, y, h, ynew, w, tol, ws)
        y[:] = ynew
    return y


def test_rodas4_converges_with_order_four_on_a_smooth_forced_problem():
    # sliding throughout (V_r near 1 >> v_s: |V_r| is smooth there), with an external force: the
    # non-autonomous terms of the method are exercised too
    model = BeltOscillator(zeta=0.1, vb=1.0, fex=0.2, omega=1.3, phi=0.4)
    law = LuGre(**SMOOTH)
    q = kernel_params(model, law)
    y0 = np.array([0.0, 0.0, 0.0])
    t_end = 4.0
    ref = solve_ivp(lugre_rhs(SMOOTH, 0.1, 1.0, 0.2, 1.3, 0.4), (0.0, t_end), y0, method="Radau",
                    rtol=1e-13, atol=1e-15).y[:, -1]
    errors = [np.max(np.abs(_fixed_steps(q, 0.1, 1.0, y0, t_end, n) - ref)) for n in (40, 80, 160)]
    orders = [math.log2(errors[i] / errors[i + 1]) for i in range(2)]
    assert all(3.7 < p < 4.6 for p in orders), (errors, orders)


def test_the_error_falls_with_the_tolerance():
    model = BeltOscillator(zeta=0.1, vb=1.0, fex=0.2, omega=1.3, phi=0.4)
    law = LuGre(**SMOOTH)
    ref = solve_ivp(lugre_rhs(SMOOTH, 0.1, 1.0, 0.2, 1.3, 0.4), (0.0, 20.0), [0.0, 0.0, 0.0], method="Radau",
                    rtol=1e-13, atol=1e-15, dense_output=True)
    errs = []
    for rtol in (1e-6, 1e-8, 1e-10):
        traj = simulate(model, law, Stiff(rtol=rtol, atol=rtol), t_end=20.0, x0=0.0, v0=0.0)
        errs.append(np.max(np.abs(traj.x - ref.sol(traj.t)[0])))
        assert errs[-1] < 100 * rtol
    assert errs[0] > errs[1] > errs[2]


def test_the_other_solvers_refuse_lugre_naming_the_stiff_one():
    model = BeltOscillator(zeta=0.05, vb=0.02)
    for solver in (Exact(), Adaptive(), RK4()):
        with pytest.raises(ValueError, match=f"^solver={solver.name} does not support friction=lugre; "
                                             "use solver=auto or stiff$"):
            simulate(model, LuGre(), solver, t_end=1.0)
    with pytest.raises(ValueError, match="^solver=stiff does not support friction=coulomb; use solver=auto or exact"):
        simulate(model, Coulomb(), Stiff(), t_end=1.0)
    assert type(simulate(model, LuGre(), t_end=1.0).solver) is dict
    assert simulate(model, LuGre(), t_end=1.0).solver["name"] == "stiff"  # auto


def test_trajectory_carries_and_labels_the_internal_states():
    model = BeltOscillator(zeta=0.05, vb=0.02)
    law = LuGre()
    traj = simulate(model, law, t_end=30.0)
    assert traj.internal.shape == (1, len(traj.t)) and traj.internal_names == ("z",)
    # the force the trajectory records is the law's, from the state (formulas written here)
    vr = model.vb - traj.v
    z = traj.internal[0]
    gz = law.fd + (law.fs - law.fd) * np.exp(-np.abs(vr / law.vs) ** law.delta)
    zd = vr - law.sigma0 * np.abs(vr) * z / gz
    np.testing.assert_allclose(traj.fc, law.sigma0 * z + law.sigma1 * zd + law.sigma2 * vr, rtol=1e-12, atol=1e-15)
    ds = traj.to_xarray()
    assert ds["z"].attrs["long_name"] == "internal state z of friction=lugre"
    np.testing.assert_array_equal(ds["z"].values[ds["is_sample"].values], z)
    np.testing.assert_allclose(ds["E_s"].values, 0.5 * law.sigma0 * ds["z"].values ** 2, rtol=1e-14)
    raw = traj.to_xarray(dense=False)
    assert raw["W_belt"].values[-1] == pytest.approx(traj.dbelt.sum())


def test_the_command_line_runs_lugre_with_its_options(capsys):
    args = ["simulate", "--friction", "lugre", "--solver", "stiff", "--sigma0", "2e4", "--sigma1", "150",
            "--sigma2", "0.01", "--vs", "0.005", "--fs", "0.03", "--t-end", "20", "--json"]
    assert main(args) == 0, capsys.readouterr().err
    assert '"sigma0": 20000.0' in capsys.readouterr().out
    assert main(["simulate", "--friction", "lugre", "--solver", "adaptive"]) == 2
    assert "solver=adaptive does not support friction=lugre; use solver=auto or stiff" in capsys.readouterr().err


def test_an_unforced_periodic_run_samples_the_section_and_its_window_balances():
    # stick-slip on a Stribeck dip: a periodic orbit.  The steady-state window runs from a downward X' = 0
    # crossing to another; with a sample on each crossing it is whole periods, and over whole periods the
    # mass's mechanical energy returns: the friction's net input P_fin - P_df is the damper's P_dv
    p = dict(fd=0.3, fs=0.5, vs=0.05, delta=2.0, sigma0=1e4, sigma1=100.0, sigma2=0.0)
    model = BeltOscillator(zeta=0.02, vb=0.2)
    solver = Stiff()
    traj = simulate(model, LuGre(**p), solver, t_end=300.0, x0=0.0, v0=0.0)
    v = traj.v
    down = np.flatnonzero((v[:-1] > 0.0) & (v[1:] <= 0.0)) + 1
    assert np.all(v[down] == 0.0)
    # the crossings are those of an independent integrator's solution (located by its event finder)
    ev = lambda t, y: y[1]
    ev.direction = -1.0
    ref = solve_ivp(lugre_rhs(p, 0.02, 0.2), (0.0, 40.0), [0.0, 0.0, 0.0], method="Radau", rtol=1e-11,
                    atol=1e-13, events=ev).t_events[0]
    assert len(ref) >= 3
    np.testing.assert_allclose(traj.t[down][:len(ref)], ref, rtol=0.0, atol=1e-6)
    result = analyze(traj)
    t0, t1 = result.steady_state.window
    assert result.steady_state.kind == "periodic" and t0 in traj.t[down] and t1 in traj.t[down]
    q = result.quantities()
    assert abs(q["P_fin"] - q["P_df"] - q["P_dv"]) <= Stiff.section_noise(solver.describe()) * q["P_fin"]


def test_a_run_whose_samples_outgrow_their_buffers_goes_on_to_the_bit():
    # the kernel stops when its sample buffers are full; called again with larger ones and the same position
    # record it goes on where it stopped: the same steps as one call with room for all
    model = BeltOscillator(zeta=0.02, vb=0.2, fex=0.05, omega=0.9)
    q = kernel_params(model, LuGre(**SMOOTH))
    tol, steps = np.array([1e-10, 1e-10, 1e-10, 1e-8]), np.array([1e-5, 0.5, 1e7, 2.0 * math.pi / 0.9])

    def run(cap):
        at = np.zeros(stiff.N_AT)
        t, y, w = np.empty(cap), np.empty((3, cap)), np.empty((cap, stiff.N_CHANNELS))
        while True:
            n, status, _, _ = stiff.run(q, 0.02, 0.2, np.zeros(3), 60.0, tol, steps, t, y, w, at)
            if status != stiff.FULL:
                return t[:n], y[:, :n], w[:n]
            t, y, w = (np.concatenate([t, np.empty(cap)]), np.concatenate([y, np.empty((3, cap))], axis=1),
                       np.concatenate([w, np.empty((cap, stiff.N_CHANNELS))]))

    whole = run(100_000)
    assert len(whole[0]) > 300
    for a, b in zip(whole, run(37)):
        np.testing.assert_array_equal(a, b)


def _friction_input_reference(p, zeta, vb, t_end):
    """int max(P_f, 0) over [0, t_end] by Radau from rest, P_f = X' F: the integrand rides along as a fourth
    component and every zero of P_f ends an integration (an event), so each piece's integrand is smooth."""
    rhs = lugre_rhs(p, zeta, vb)

    def power(t, y):
        x, v, _ = y[:3]
        return v * (rhs(t, y[:3])[1] + x + 2.0 * zeta * v)  # X' F, F from X'' = -X - 2 zeta X' + F

    def augmented(t, y):
        return [*rhs(t, y[:3]), max(power(t, y), 0.0)]

    def event(t, y):
        return power(t, y)

    event.terminal = True
    t, y = 0.0, np.zeros(4)
    while t < t_end:
        sol = solve_ivp(augmented, (t, t_end), y, method="Radau", rtol=1e-12, atol=1e-15, events=event)
        t, y = sol.t[-1], sol.y[:, -1]
        if sol.status == 1:  # on a zero of P_f: step just past it (the event would fire again at the start)
            nxt = solve_ivp(augmented, (t, min(t + 1e-9, t_end)), y, method="Radau", rtol=1e-12, atol=1e-15)
            t, y = nxt.t[-1], nxt.y[:, -1]
    return y[3]


def test_the_friction_input_splits_at_every_kink_of_max_p_f():
    """W_fin = int max(X' F, 0) has a kink at every zero of X' F; the stiff run ends a step on each (X' = 0 both
    ways, F = 0).  Integrated across them by the steps' quadrature it was off by ~1e-7 of the step's work at each
    upward crossing: simulate's P_fin differed from the orbit's by 3.5e-6 (a QA report), beyond the 1e-6 the
    solvers guide promises."""
    model = BeltOscillator(zeta=0.8, vb=0.05)
    traj = simulate(model, LuGre(**SMOOTH), Stiff(rtol=1e-11, atol=1e-13), t_end=60.0, x0=0.0, v0=0.0)
    ref = _friction_input_reference(SMOOTH, 0.8, 0.05, 60.0)
    assert traj.work[-1, WORK_NAMES.index("W_fin")] == pytest.approx(ref, rel=1e-9)


def test_the_extremes_of_x_are_samples():
    """A step ends on every zero of X', upwards too: the largest and smallest X over the samples are those of an
    independent Radau run at its events (X_min was the steps', 5e-6 off in a QA report)."""
    zeta, vb, t_end = 0.8, 0.05, 60.0
    traj = simulate(BeltOscillator(zeta=zeta, vb=vb), LuGre(**SMOOTH), Stiff(rtol=1e-11, atol=1e-13), t_end=t_end,
                    x0=0.0, v0=0.0)
    rhs = lugre_rhs(SMOOTH, zeta, vb)
    ref = solve_ivp(rhs, (0.0, t_end), [0.0, 0.0, 0.0], method="Radau", rtol=1e-12, atol=1e-15,
                    events=lambda t, y: y[1])
    x = np.concatenate([ref.y[0, [0, -1]], ref.y_events[0][:, 0]])
    assert len(ref.y_events[0]) > 10  # a few cycles' turns
    assert traj.x.max() == pytest.approx(x.max(), rel=1e-9)
    assert traj.x.min() == pytest.approx(x.min(), rel=1e-9, abs=1e-12)
    assert np.sum(traj.v == 0.0) >= len(ref.y_events[0])  # every turn a sample, X' = 0 there
