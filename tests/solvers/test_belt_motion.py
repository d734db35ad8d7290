"""A belt whose speed varies, V_b(tau) = V_b + A sin(Omega_b tau + phi_b), through the single-mass solvers.

Checked against what the test derives itself: the stick phase's closed form X = X0 + int V_b, the exit of a
stick where the held force X + 2 zeta V_b + V_b' - f reaches F_s (solved here with brentq), a hybrid
integrator written here (scipy's solve_ivp for slip with the switch V_r = 0 as an event, the closed form for
stick), the energy balance, and RK4's order on a slip phase against solve_ivp.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow import quantities as Q
from frictionflow.sweep import parse_sweep, run_sweep
from frictionflow.analysis.power_flow import instantaneous_power
from frictionflow.friction.coulomb import Coulomb
from frictionflow.friction.karnopp import Karnopp
from frictionflow.friction.stribeck import Stribeck
from frictionflow.solvers.adaptive import Adaptive
from frictionflow.solvers.exact import Exact
from frictionflow.solvers.registry import solver_classes
from frictionflow.solvers.rk4 import RK4

#: a belt that speeds up and slows down by 75 % of its mean speed: stick-slip with stick phases on a moving belt
BELT = {"zeta": 0.05, "vb": 0.2, "vb_amplitude": 0.15, "vb_omega": 0.7, "vb_phi": 0.3}
COULOMB = Coulomb(fd=0.5, fs=0.8)
STRIBECK = Stribeck(fd=0.5, fs=0.8, vs=0.1, delta=1.0)


def belt_solvers():
    """The solvers that declare they run a moving belt (the ones this file checks)."""
    return [cls for cls in solver_classes() if cls.supports_belt_motion]


# -- the motion as the test derives it ---------------------------------------------------------------

def v_belt(m: BeltOscillator, t):
    return m.vb + m.vb_amplitude * np.sin(m.vb_omega * t + m.vb_phi)


def a_belt(m: BeltOscillator, t):
    return m.vb_amplitude * m.vb_omega * np.cos(m.vb_omega * t + m.vb_phi)


def stick_x(m: BeltOscillator, xs: float, ts: float, t):
    """X in a stick from (ts, xs): xs + int_ts^t V_b."""
    return xs + m.vb * (t - ts) - m.vb_amplitude / m.vb_omega * (np.cos(m.vb_omega * t + m.vb_phi)
                                                                  - np.cos(m.vb_omega * ts + m.vb_phi))


def stick_force(m: BeltOscillator, x, t):
    """F_c while sticking, X'' = V_b': X + 2 zeta V_b + V_b' - f (the held force of the resultant rule)."""
    return x + 2.0 * m.zeta * v_belt(m, t) + a_belt(m, t) - m.fex * np.cos(m.omega * t + m.phi)


def stick_exit(m: BeltOscillator, fs: float, xs: float, ts: float, t_end: float, scan: float = 1e-3) -> float:
    """The first time after ts where |F_c| reaches F_s along the stick (scan, then brentq); t_end if never."""
    g = lambda t: abs(stick_force(m, stick_x(m, xs, ts, t), t)) - fs  # noqa: E731
    grid = np.arange(ts, t_end, scan)
    vals = np.array([g(t) for t in grid])
    out = np.flatnonzero(vals >= 0.0)
    if not len(out):
        return t_end
    i = out[0]
    return brentq(g, grid[i - 1], grid[i], xtol=1e-15, rtol=1e-15) if i > 0 else ts


def reference(m: BeltOscillator, slip, fs: float, x0: float, v0: float, t_end: float):
    """A hybrid integration written here: (switch times, X(t_end), X'(t_end), int F_c V_b).

    Slip in direction d: X'' = d F(|V_r|) + f - X - 2 zeta X' by solve_ivp (DOP853) until V_r = 0 (an event);
    there the mass sticks if |F_c| < F_s, else slips back.  Stick: the closed form to :func:`stick_exit`.
    """
    t, x, v, w_belt, switches = 0.0, x0, v0, 0.0, []
    mode = 0 if v0 == v_belt(m, 0.0) else int(np.sign(v_belt(m, 0.0) - v0))
    while t < t_end:
        if mode == 0:
            te = stick_exit(m, fs, x, t, t_end)
            w_belt += quad(lambda s: stick_force(m, stick_x(m, x, t, s), s) * v_belt(m, s), t, te,
                           epsabs=1e-14, epsrel=1e-13, limit=200)[0]
            x, v = stick_x(m, x, t, te), v_belt(m, te)
            mode = int(np.sign(stick_force(m, x, te)))
            t = te
        else:
            d = mode

            def rhs(s, y, d=d):
                vr = v_belt(m, s) - y[1]
                f = d * slip(abs(vr))
                return [y[1], f + m.fex * np.cos(m.omega * s + m.phi) - y[0] - 2.0 * m.zeta * y[1], f * v_belt(m, s)]

            def switch(s, y, d=d):
                return d * (v_belt(m, s) - y[1])

            switch.terminal, switch.direction = True, -1
            sol = solve_ivp(rhs, (t, t_end), [x, v, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, events=switch)
            w_belt += sol.y[2, -1]
            x, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
            if sol.status == 1:
                v = v_belt(m, t)
                mode = 0 if abs(stick_force(m, x, t)) < fs else -d
        if t < t_end:
            switches.append(t)
    return np.array(switches), x, v, w_belt


def coulomb_slip(speed):
    return 0.5


def stribeck_slip(speed):
    return 0.5 + 0.3 * math.exp(-speed / 0.1)


def _stick_runs(traj):
    """(first, last) sample indices of each run of stick samples, the sample after it included (its exit)."""
    st = np.flatnonzero(traj.mode == 0)
    if not len(st):
        return []
    runs = np.split(st, np.flatnonzero(np.diff(st) != 1) + 1)
    return [(r[0], min(r[-1] + 1, len(traj.t) - 1)) for r in runs]


# -- constant belts are today's results ---------------------------------------------------------------

@pytest.mark.parametrize("forced", [False, True])
@pytest.mark.parametrize("solver", [Adaptive, RK4, Exact])
def test_zero_amplitude_is_todays_run_bit_for_bit(solver, forced):
    """A = 0 with any Omega_b, phi_b is the constant belt: the same samples to the bit."""
    drive = {"fex": 0.3, "omega": 1.3} if forced else {}
    law = Coulomb(fd=0.5, fs=0.8)
    a = simulate(BeltOscillator(zeta=0.05, vb=0.2, **drive), law, solver(), t_end=40.0, x0=0.0, v0=0.2)
    b = simulate(BeltOscillator(zeta=0.05, vb=0.2, vb_amplitude=0.0, vb_omega=2.7, vb_phi=1.1, **drive), law, solver(),
                 t_end=40.0, x0=0.0, v0=0.2)
    for name in ("t", "state", "force", "modes", "dwork"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


# -- the stick phase -----------------------------------------------------------------------------------

@pytest.mark.parametrize("solver", [Adaptive, Exact])
def test_a_stick_phase_follows_the_belt_exactly(solver):
    m = BeltOscillator(**BELT)
    traj = simulate(m, COULOMB, solver(dense_dt=0.05), t_end=40.0, x0=0.0, v0=float(v_belt(m, 0.0)))
    runs = _stick_runs(traj)
    assert len(runs) >= 4 and sum(j - i for i, j in runs) > 100
    for i, j in runs:
        t = traj.t[i:j + 1]
        assert np.allclose(traj.v[i:j + 1], v_belt(m, t), rtol=0.0, atol=4e-16)  # X' = V_b(tau) to rounding
        x = stick_x(m, traj.x[i], traj.t[i], t)
        assert np.allclose(traj.x[i:j + 1], x, rtol=0.0, atol=1e-14)


@pytest.mark.parametrize("solver", [Adaptive, Exact])
def test_a_stick_ended_by_the_belts_acceleration_ends_where_the_closed_form_says(solver):
    """A fast belt (Omega_b = 3): its acceleration A Omega_b cos(...) takes the held force to F_s within a second,
    where a belt at constant speed would hold for 2.8 (X + 2 zeta V_b rising at V_b = 0.2 from 0.14 to 0.6)."""
    m = BeltOscillator(zeta=0.1, vb=0.2, vb_amplitude=0.5, vb_omega=3.0, vb_phi=math.pi / 2)
    law = Coulomb(fd=0.3, fs=0.6)
    traj = simulate(m, law, solver(), t_end=5.0, x0=0.0, v0=float(v_belt(m, 0.0)))
    want = stick_exit(m, 0.6, 0.0, 0.0, 5.0)
    assert want < 1.0
    assert traj.events["t"][0] == pytest.approx(want, rel=1e-13, abs=1e-14)
    assert traj.mode[0] == 0 and traj.events["mode"][0] == np.sign(stick_force(m, stick_x(m, 0.0, 0.0, want), want))


def test_rk4s_band_leaves_a_stick_ended_by_the_belts_acceleration_when_karnopps_band_says():
    """RK4 steps through Karnopp's band |V_r| <= V_d: past the exit the band holds F_s while the held force H
    grows on at H', so V_r ~ H' s^2 / 2 leaves the band sqrt(2 V_d / |H'|) after the closed form's exit."""
    m = BeltOscillator(zeta=0.1, vb=0.2, vb_amplitude=0.5, vb_omega=3.0, vb_phi=math.pi / 2)
    want = stick_exit(m, 0.6, 0.0, 0.0, 5.0)
    held = lambda t: stick_force(m, stick_x(m, 0.0, 0.0, t), t)  # noqa: E731
    rate = abs(held(want + 1e-6) - held(want - 1e-6)) / 2e-6
    for dt, band in ((1e-4, 1e-5), (1e-5, 1e-6)):
        traj = simulate(m, Coulomb(fd=0.3, fs=0.6, rk4_band=band), RK4(dt=dt), t_end=1.0, x0=0.0, v0=float(v_belt(m, 0.0)))
        delay = traj.t[np.flatnonzero(traj.mode != 0)[0]] - want
        assert delay == pytest.approx(math.sqrt(2.0 * band / rate), rel=0.03), (dt, band)


# -- against an integration written here ---------------------------------------------------------------

@pytest.mark.parametrize("law,slip", [(COULOMB, coulomb_slip), (STRIBECK, stribeck_slip)], ids=["coulomb", "stribeck"])
@pytest.mark.parametrize("forced", [False, True], ids=["free", "forced"])
def test_adaptive_agrees_with_solve_ivp(law, slip, forced):
    drive = {"fex": 0.2, "omega": 0.9} if forced else {}
    m = BeltOscillator(**BELT, **drive)
    v0 = float(v_belt(m, 0.0))
    switches, x, v, w_belt = reference(m, slip, law.fs, 0.0, v0, 40.0)
    traj = simulate(m, law, Adaptive(rtol=1e-12, atol=1e-14), t_end=40.0, x0=0.0, v0=v0)
    assert len(switches) >= 6
    np.testing.assert_allclose(traj.events["t"], switches, rtol=0, atol=1e-8)
    assert traj.x[-1] == pytest.approx(x, abs=1e-8) and traj.v[-1] == pytest.approx(v, abs=1e-8)
    w = traj.dwork.sum(axis=0)
    assert w[1] - w[2] + w[3] == pytest.approx(w_belt, rel=1e-8)  # P_belt = F_c V_b(tau): friction work + heat


def test_exact_agrees_with_solve_ivp():
    """The exact engine's closed-form slips, their return to the moving belt and its stick phases against the
    hybrid integration written here, free and forced."""
    for drive in ({}, {"fex": 0.2, "omega": 0.9}):
        m = BeltOscillator(**BELT, **drive)
        v0 = float(v_belt(m, 0.0))
        switches, x, v, w_belt = reference(m, coulomb_slip, COULOMB.fs, 0.0, v0, 40.0)
        traj = simulate(m, COULOMB, Exact(), t_end=40.0, x0=0.0, v0=v0)
        assert len(switches) >= 6
        np.testing.assert_allclose(traj.events["t"], switches, rtol=0, atol=1e-8)
        assert traj.x[-1] == pytest.approx(x, abs=1e-8) and traj.v[-1] == pytest.approx(v, abs=1e-8)
        w = traj.dwork.sum(axis=0)
        assert w[1] - w[2] + w[3] == pytest.approx(w_belt, rel=1e-8)  # P_belt = F_c V_b(tau): friction work + heat


@pytest.mark.parametrize("forced", [False, True], ids=["free", "forced"])
def test_exact_agrees_with_adaptive_at_tight_tolerance(forced):
    """Two engines sharing the stick phase but not the slip (closed form against Dormand-Prince at 1e-12):
    the switches, the state, and every work integral, over 60 time units of stick-slip on the moving belt."""
    m = BeltOscillator(**BELT, **({"fex": 0.2, "omega": 0.9} if forced else {}))
    v0 = float(v_belt(m, 0.0))
    e = simulate(m, COULOMB, Exact(), t_end=60.0, x0=0.0, v0=v0)
    a = simulate(m, COULOMB, Adaptive(rtol=1e-12, atol=1e-14), t_end=60.0, x0=0.0, v0=v0)
    assert len(e.events["t"]) == len(a.events["t"]) >= 8
    np.testing.assert_allclose(e.events["t"], a.events["t"], rtol=0, atol=1e-9)
    assert np.array_equal(e.events["mode"], a.events["mode"])
    assert e.x[-1] == pytest.approx(a.x[-1], abs=1e-10) and e.v[-1] == pytest.approx(a.v[-1], abs=1e-10)
    np.testing.assert_allclose(e.dwork.sum(axis=0), a.dwork.sum(axis=0), rtol=1e-9, atol=1e-12)


def test_an_exact_slip_returns_to_a_belt_that_catches_up_briefly():
    """A fast belt (Omega_b = 20) whose speed overtakes the sliding mass for under 0.01 time units, a sliver of
    the natural period, near X''s minimum: V_r = V_b(tau) - X' is positive only in that short excursion.  The
    return to the belt is found where brentq on the slip's closed form (written here, scanned finely) puts it."""
    m = BeltOscillator(zeta=0.05, vb=-1.0, vb_amplitude=0.3, vb_omega=20.0, vb_phi=1.5 * math.pi)
    law = Coulomb(fd=0.1, fs=0.2)
    x0, v0 = 0.66, 0.0  # X' > V_b: V_r < 0, friction -F_d
    traj = simulate(m, law, Exact(), t_end=3.0, x0=x0, v0=v0)
    wd = math.sqrt(1.0 - m.zeta**2)
    c1, c2 = x0 + law.fd, (v0 + m.zeta * (x0 + law.fd)) / wd  # Y = X + F_d = e^{-zeta t}(c1 cos + c2 sin)(wd t)

    def vr(t):
        dy = np.exp(-m.zeta * t) * ((c2 * wd - m.zeta * c1) * np.cos(wd * t) - (c1 * wd + m.zeta * c2) * np.sin(wd * t))
        return v_belt(m, t) - dy

    grid = np.arange(0.0, 3.0, 1e-5)
    inside = np.flatnonzero(vr(grid) >= 0.0)
    assert len(inside) and 0 < inside[-1] - inside[0] < 1000  # one excursion, shorter than 0.01
    want = brentq(vr, grid[inside[0] - 1], grid[inside[0]], xtol=1e-15, rtol=1e-15)
    assert traj.events["t"][0] == pytest.approx(want, rel=1e-12, abs=1e-13)


def test_exact_refuses_karnopps_band_on_a_moving_belt_with_one_line():
    with pytest.raises(ValueError, match=r"^solver=exact runs a belt whose speed varies .* Coulomb's switch only") as e:
        simulate(BeltOscillator(**BELT), Karnopp(fd=0.5, fs=0.8), Exact(), t_end=5.0)
    assert "\n" not in str(e.value)


# -- energy ------------------------------------------------------------------------------------------

def _residual(traj) -> float:
    """K + U at the end less at the start, less the work of friction and the external force net of the damper's."""
    e = 0.5 * traj.x**2 + 0.5 * traj.v**2
    w = traj.dwork.sum(axis=0)
    return float(e[-1] - e[0] - (w[1] - w[2] + w[4] - w[0]))


@pytest.mark.parametrize("solver", [Adaptive, Exact])
def test_the_energy_balance_closes_on_a_moving_belt(solver):
    m = BeltOscillator(**BELT, fex=0.2, omega=0.9)
    traj = simulate(m, COULOMB, solver(), t_end=40.0, x0=0.0, v0=float(v_belt(m, 0.0)))
    # the exact engine's works are closed forms and Gauss-Legendre to rounding: its balance closes to rounding
    assert abs(_residual(traj)) < (1e-13 if solver is Exact else 1e-9)
    p = instantaneous_power(traj)
    slip = traj.mode != 0
    np.testing.assert_allclose(p["P_belt"][slip], traj.fc[slip] * v_belt(m, traj.t[slip]), rtol=1e-12, atol=1e-15)


def test_rk4s_energy_balance_closes_at_its_order():
    """RK4's residual is its quadrature's across the stick band's edges: it falls as dt^4 (a quarter of the step:
    at least 50 times less), on a moving belt as on a constant one."""
    m = BeltOscillator(**BELT, fex=0.2, omega=0.9)
    res = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the band's step warning: the coarse step is the point)
        for dt in (1e-3, 2.5e-4):
            res.append(abs(_residual(simulate(m, COULOMB, RK4(dt=dt), t_end=40.0, x0=0.0, v0=float(v_belt(m, 0.0))))))
    assert res[1] < res[0] / 50.0 and res[1] < 1e-7


# -- RK4's order -------------------------------------------------------------------------------------

def test_rk4_converges_at_its_order_on_a_moving_belt():
    """A slip phase (V_r > 0 throughout) under Stribeck's law, whose force reads V_b(tau): errors against
    solve_ivp fall as dt^4."""
    m = BeltOscillator(zeta=0.1, vb=1.0, vb_amplitude=0.3, vb_omega=2.0, vb_phi=0.4)
    law = Stribeck(fd=0.5, fs=0.8, vs=0.1, delta=1.0)
    sol = solve_ivp(lambda s, y: [y[1], stribeck_slip(v_belt(m, s) - y[1]) - y[0] - 0.2 * y[1]], (0.0, 2.0 * math.pi),
                    [0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-15)
    assert np.all(v_belt(m, sol.t) - sol.y[1] > 0.1)
    errors, steps = [], []
    for dt in (0.04, 0.02, 0.01):
        traj = simulate(m, law, RK4(dt=dt), t_end=2.0 * math.pi, x0=0.0, v0=0.0)
        errors.append(math.hypot(traj.x[-1] - sol.y[0, -1], traj.v[-1] - sol.y[1, -1]))
        steps.append(traj.solver.get("dt", dt))
    orders = np.diff(np.log(errors)) / np.diff(np.log(steps))
    assert np.all(np.abs(orders - 4.0) < 0.3), orders


# -- the stroboscopic section ---------------------------------------------------------------------------

@pytest.mark.parametrize("forced,law,solver", [
    (False, Coulomb(fd=0.02, fs=0.04), Adaptive), (True, Coulomb(fd=0.02, fs=0.04), Adaptive),
    (True, Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1.0), RK4)], ids=["belt", "belt+force", "belt+force-rk4"])
def test_classification_finds_the_period_of_the_belt(forced, law, solver):
    drive = {"fex": 0.01, "omega": 0.8} if forced else {}
    m = BeltOscillator(zeta=0.05, vb=0.01, vb_amplitude=0.005, vb_omega=0.8, vb_phi=0.3, **drive)
    ss = analyze(simulate(m, law, solver(), t_end=300.0)).steady_state
    assert ss.kind == "periodic"
    assert ss.period == pytest.approx(2.0 * math.pi / 0.8, rel=1e-12)


def test_a_force_and_a_belt_without_a_common_period_are_not_classified():
    m = BeltOscillator(zeta=0.05, vb=0.01, vb_amplitude=0.005, vb_omega=0.7, fex=0.01, omega=0.8)
    traj = simulate(m, Coulomb(fd=0.02, fs=0.04), Adaptive(), t_end=50.0)
    with pytest.raises(ValueError, match=r"^vb_omega=0.7 differs from omega=0.8: .*set vb_omega equal to omega$"):
        analyze(traj)


# -- refused ---------------------------------------------------------------------------------------------

def test_bad_belt_parameters_are_refused_with_one_line():
    for kwargs, name in (({"vb_amplitude": -0.1}, "vb_amplitude"), ({"vb_omega": 0.0}, "vb_omega"),
                         ({"vb_phi": math.nan}, "vb_phi")):
        with pytest.raises(ValueError, match=rf"^{name} must") as e:
            BeltOscillator(**kwargs)
        assert "\n" not in str(e.value)


def test_paths_that_run_a_constant_belt_only_refuse_a_moving_one():
    from frictionflow import frequency_response
    from frictionflow.orbits import find_forced_orbit, find_orbit

    m = BeltOscillator(**BELT, fex=0.1, omega=0.7)
    calls = (lambda: find_orbit(m, COULOMB), lambda: find_forced_orbit(m, COULOMB, 1, 0.5, 0.2),
             lambda: frequency_response(m, COULOMB, [0.7]))
    for call in calls:
        with pytest.raises(ValueError, match=r"^vb_amplitude must be 0 for .*got 0.15; simulate a moving belt") as e:
            call()
        assert "\n" not in str(e.value)


def test_a_solver_that_does_not_run_a_moving_belt_refuses_it():
    for cls in solver_classes():
        if cls.supports_belt_motion:
            continue
        solver = cls()
        law = next((law for law in (COULOMB, Stribeck(fd=0.5, fs=0.8)) if solver.supports(law)), None)
        if law is None:
            continue
        with pytest.raises(ValueError, match=rf"^solver={cls.name} does not run a belt whose speed varies"):
            simulate(BeltOscillator(**BELT), law, solver, t_end=10.0)


def test_sweeps_refuse_a_moving_belt_they_cannot_run():
    from frictionflow.sweep.config import parse_sweep

    base = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "t_end": 50.0}
    with pytest.raises(ValueError) as direct:  # the point through simulate: the line the sweep must repeat
        simulate(BeltOscillator(vb=0.01, vb_amplitude=0.005, vb_omega=0.8), Karnopp(fd=0.02, fs=0.04), Exact(),
                 t_end=5.0)
    assert str(direct.value).startswith("solver=exact runs a belt whose speed varies")
    assert str(direct.value).endswith("; use solver=auto or rk4")  # the registry names the solvers that run it
    with pytest.raises(ValueError) as grid:
        parse_sweep({**base, "friction": "karnopp", "solver": "exact", "grid": {"vb_amplitude": [0.0, 0.005]}})
    assert str(grid.value) == f"grid: {direct.value}"
    with pytest.raises(ValueError, match=r"^grid: points with both an external force and a moving belt need vb_omega"):
        parse_sweep({**base, "solver": "adaptive", "fex": 0.01, "omega": 0.8, "grid": {"vb_amplitude": [0.0, 0.005]}})


def test_a_sweep_over_the_belts_amplitude_runs_each_point_as_simulate_does():
    from frictionflow.quantities import KINDS
    from frictionflow.sweep.compute import VARIABLES, compute_chunk

    settings = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "zeta": 0.05, "vb": 0.01, "vb_omega": 0.8,
                "vb_phi": 0.3, "solver": "adaptive", "t_end": 300.0}
    out = compute_chunk({"settings": settings, "grid": {"vb_amplitude": [0.0, 0.005]}}, (0,), (2,))
    names = [v[0] for v in VARIABLES]
    for j, amp in enumerate((0.0, 0.005)):
        m = BeltOscillator(zeta=0.05, vb=0.01, vb_amplitude=amp, vb_omega=0.8, vb_phi=0.3)
        q = analyze(simulate(m, Coulomb(fd=0.02, fs=0.04), Adaptive(), t_end=300.0)).quantities()
        assert KINDS[int(out[names.index("kind"), j])] == KINDS[int(q["kind"])]
        for k in ("P_fin", "R_c", "TR_B"):
            assert out[names.index(k), j] == pytest.approx(q[k], rel=1e-6), (amp, k)
    assert out[names.index("period"), 1] == pytest.approx(2.0 * math.pi / 0.8, rel=1e-12)


def test_auto_picks_a_solver_that_runs_a_moving_belt():
    from frictionflow.friction.karnopp import Karnopp
    from frictionflow.solvers.registry import auto_solver

    moving, constant = BeltOscillator(**BELT), BeltOscillator(zeta=0.05, vb=0.2)
    assert auto_solver(COULOMB, moving).name == "adaptive" and auto_solver(COULOMB, constant).name == "exact"
    assert auto_solver(Karnopp(fd=0.5, fs=0.8), moving).name == "rk4"
    assert simulate(moving, COULOMB, t_end=5.0).solver["name"] == "adaptive"


@pytest.mark.parametrize("solver", [Adaptive, Exact])
def test_the_trajectory_between_stick_samples_is_the_belts_motion(solver):
    """``traj(t)`` inside a stick phase: X' = V_b(t) and X = X0 + int V_b, not a straight line."""
    m = BeltOscillator(**BELT)
    traj = simulate(m, COULOMB, solver(), t_end=40.0, x0=0.0, v0=float(v_belt(m, 0.0)))
    runs = [(i, j) for i, j in _stick_runs(traj) if traj.t[j] - traj.t[i] > 1.0]
    assert runs
    for i, j in runs:
        t = np.linspace(traj.t[i], traj.t[j], 41)[1:-1]
        x, v = traj.at(t)
        np.testing.assert_allclose(v, v_belt(m, t), rtol=0.0, atol=1e-15)
        np.testing.assert_allclose(x, stick_x(m, traj.x[i], traj.t[i], t), rtol=0.0, atol=1e-14)


def test_the_exact_trajectory_between_slip_samples_is_the_closed_form():
    """``traj(t)`` inside a slip on the moving belt: against the hybrid integration written here, run to t."""
    m = BeltOscillator(**BELT, fex=0.2, omega=0.9)
    v0 = float(v_belt(m, 0.0))
    traj = simulate(m, COULOMB, Exact(), t_end=20.0, x0=0.0, v0=v0)
    slips = np.flatnonzero((traj.mode[:-1] != 0) & (np.diff(traj.t) > 0.3))
    assert len(slips) >= 3
    for i in slips[:3]:
        t = 0.5 * (traj.t[i] + traj.t[i + 1])
        _, x, v, _ = reference(m, coulomb_slip, COULOMB.fs, 0.0, v0, t)
        got = traj.at(np.array([t]))
        assert got[0][0] == pytest.approx(x, abs=1e-8) and got[1][0] == pytest.approx(v, abs=1e-8)


def test_a_users_slip_law_runs_on_a_moving_belt_as_the_built_in_one():
    """The kernel rebuilt around a user's function (its own variants) on a moving belt: Stribeck's curve given as
    a Python function switches where the built-in Stribeck law does."""
    from frictionflow.friction.user import SlipLaw

    m = BeltOscillator(**BELT)
    user = simulate(m, SlipLaw(stribeck_slip, fs=0.8), Adaptive(), t_end=30.0, x0=0.0, v0=0.2)
    built_in = simulate(m, STRIBECK, Adaptive(), t_end=30.0, x0=0.0, v0=0.2)
    np.testing.assert_allclose(user.events["t"], built_in.events["t"], rtol=0, atol=1e-9)


def test_a_sweep_over_the_belts_amplitude_with_solver_auto_runs_one_solver_that_runs_it(tmp_path):
    spec = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "zeta": 0.05, "vb": 0.01, "t_end": 60.0,
            "grid": {"vb_amplitude": [0.005, 0.01]}}
    assert parse_sweep(spec).run.solver == "adaptive"  # exact (auto's pick on a constant belt) cannot run A > 0
    # a still belt too: auto would pick exact there, a sweep runs one solver (simulate's pick at every point or none)
    with pytest.raises(ValueError, match=r"solver = auto picks exact where grid.vb_amplitude = 0 and adaptive where"):
        parse_sweep({**spec, "grid": {"vb_amplitude": [0.0, 0.005]}})
    spec = {**spec, "solver": "adaptive", "grid": {"vb_amplitude": [0.0, 0.005]}}
    swept = run_sweep(spec, tmp_path / "s.zarr").load()
    for amp in (0.0, 0.005):
        model = BeltOscillator(zeta=0.05, vb=0.01, vb_amplitude=amp)
        want = analyze(simulate(model, Coulomb(fd=0.02, fs=0.04), Adaptive(), t_end=60.0)).quantities()
        row = swept.sel(vb_amplitude=amp)
        got = np.array([float(row[q.name]) for q in Q.SWEPT])
        np.testing.assert_array_equal(got, np.array([want[q.name] for q in Q.SWEPT], dtype=float))
