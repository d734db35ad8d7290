"""Lyapunov exponents on a belt whose speed varies, V_b(tau) = V_b + A sin(Omega_b tau + phi_b).

References written here, none of them the package's kernels: a hybrid integrator (scipy's DOP853 for slip,
the switch V_r = V_b(tau) - X' = 0 as its event; stick in closed form, X = X_s + int V_b, ended where the held
force X [+ 2 zeta V_b] + V_b' - f reaches F_s, found by a scan and brentq), whose finite differences give the
flow's derivative; its stroboscopic map's monodromy matrix; the divergence of two nearby runs.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from frictionflow import BeltOscillator, Coulomb, Stribeck, analyze, simulate
from frictionflow.analysis.forced import largest_exponent, section_indices
from frictionflow.analysis.lyapunov import lyapunov_exponents
from frictionflow.core import tangent as tg
from frictionflow.core.strobe import LYAPUNOV_PERIODS, LYAPUNOV_STEPS, LYAPUNOV_TRANSIENT
from frictionflow.quantities import KINDS
from frictionflow.solvers.adaptive import Adaptive
from frictionflow.solvers.base import kernel_params
from frictionflow.solvers.exact import Exact
from tests.cli.processes import cli

#: stick-slip on a belt that speeds up and slows down by 75 % of its mean speed
BELT = {"zeta": 0.05, "vb": 0.2, "vb_amplitude": 0.15, "vb_omega": 0.7, "vb_phi": 0.3}
#: a belt that runs backwards for part of its period (A > V_b): slip both ways, reversals through V_r = 0
REVERSING = {"zeta": 0.05, "vb": 0.1, "vb_amplitude": 0.4, "vb_omega": 1.3, "vb_phi": 0.0}
#: the stick-slip cycle of Coulomb(0.02, 0.04) at V_b = 0.01 (natural frequency 0.823 of the cycle), its belt
#: modulated by 10 % at the golden ratio of that frequency: the section fills a closed curve (found by a scan)
QUASI = ({"zeta": 0.05, "vb": 0.01, "vb_amplitude": 0.001, "vb_omega": 1.3316226292920887}, Coulomb(0.02, 0.04))
#: a period-2 stick-slip response of the same belt family (found by the same scan)
PERIODIC = ({"zeta": 0.01, "vb": 0.1, "vb_amplitude": 0.5, "vb_omega": 0.9}, Coulomb(0.5, 1.0))
#: chaotic stick-slip, one stick about every period: Stribeck's falling curve (found by the scan; lambda_1 ~ 0.03)
CHAOTIC = ({"zeta": 0.01, "vb": 0.1, "vb_amplitude": 0.2, "vb_omega": 0.6}, Stribeck(0.5, 1.0, 0.1))


# -- the reference integrator -------------------------------------------------------------------------

def v_belt(m: BeltOscillator, t: float) -> float:
    return m.vb + m.vb_amplitude * math.sin(m.vb_omega * t + m.vb_phi)


def a_belt(m: BeltOscillator, t: float) -> float:
    return m.vb_amplitude * m.vb_omega * math.cos(m.vb_omega * t + m.vb_phi)


def x_stick(m: BeltOscillator, xs: float, ts: float, t: float) -> float:
    """X in a stick from (ts, xs): xs + int_ts^t V_b."""
    return xs + m.vb * (t - ts) - m.vb_amplitude / m.vb_omega * (math.cos(m.vb_omega * t + m.vb_phi)
                                                                  - math.cos(m.vb_omega * ts + m.vb_phi))


def held(m: BeltOscillator, law, x: float, t: float) -> float:
    """The force the interface holds while sticking (X'' = V_b'): F_e + V_b' - f, F_e = X + 2 zeta V_b or X."""
    fe = x + 2.0 * m.zeta * v_belt(m, t) if law.stick_force == "resultant" else x
    return fe + a_belt(m, t) - m.fex * math.cos(m.omega * t + m.phi)


def slip_of(law):
    """|F| while slipping at speed s, written from the laws' definitions."""
    if isinstance(law, Stribeck):
        return lambda s: law.fd + (law.fs - law.fd) * math.exp(-((s / law.vs) ** law.delta))
    return lambda s: law.fd


def reference(m: BeltOscillator, law, x0: float, v0: float, times, scan: float = 0.01):
    """(X, X') at each of the increasing ``times`` from (x0, v0) slipping at tau = 0, and the switches' kinds."""
    slip, fs = slip_of(law), law.fs
    t, x, v = 0.0, float(x0), float(v0)
    mode = 1 if v_belt(m, 0.0) > v else -1
    out, kinds = [], []
    for tn in times:
        while t < tn:
            if mode == 0:
                gap = lambda s, x=x, t=t: abs(held(m, law, x_stick(m, x, t, s), s)) - fs  # noqa: E731
                grid = np.append(np.arange(t, tn, scan), tn)
                vals = np.array([gap(s) for s in grid])
                hit = np.flatnonzero(vals >= 0.0)
                te = tn if not len(hit) else brentq(gap, grid[hit[0] - 1], grid[hit[0]], xtol=1e-15, rtol=1e-15)
                x, t = x_stick(m, x, t, te), te
                v = v_belt(m, t)
                if te < tn:
                    mode = 1 if held(m, law, x, t) > 0.0 else -1
                    kinds.append("slip")
                continue
            d = mode

            def rhs(s, y, d=d):
                f = d * slip(d * (v_belt(m, s) - y[1]))
                return [y[1], f + m.fex * math.cos(m.omega * s + m.phi) - y[0] - 2.0 * m.zeta * y[1]]

            def switch(s, y, d=d):
                return d * (v_belt(m, s) - y[1])

            switch.terminal, switch.direction = True, -1
            sol = solve_ivp(rhs, (t, tn), [x, v], method="DOP853", rtol=1e-13, atol=1e-15, events=switch)
            t, x, v = float(sol.t[-1]), float(sol.y[0, -1]), float(sol.y[1, -1])
            if sol.status == 1:
                v = v_belt(m, t)
                q = held(m, law, x, t)
                mode = 0 if abs(q) < fs else (1 if q > 0.0 else -1)
                kinds.append("stick" if mode == 0 else "reversal")
        out.append((x, v))
    return np.array(out), kinds


def reference_jacobian(m, law, x0, v0, t_end, eps=1e-6):
    """d(X, X')(t_end) / d(x0, v0) by central differences of :func:`reference`."""
    J = np.empty((2, 2))
    for i in range(2):
        e = np.zeros(2)
        e[i] = eps
        plus = reference(m, law, x0 + e[0], v0 + e[1], [t_end])[0][0]
        minus = reference(m, law, x0 - e[0], v0 - e[1], [t_end])[0][0]
        J[:, i] = (plus - minus) / (2.0 * eps)
    return J


def kernel_flow(m, law, x0, v0, t_end, steps):
    """The tangent kernel over one block of length t_end from the identity: (X, X') there, the derivative, the switches."""
    row = np.zeros((1, tg.N_FRAME))
    est = np.full((1, 2), np.nan)
    counts = np.zeros(tg.N_COUNTS, dtype=np.int64)
    status, _, _, _ = tg.run_until(x0, v0, m.zeta, m.vb, kernel_params(m, law), t_end, steps, (0, 1), (2, 2, 0.0, 0.0),
                                   row, est, counts)
    assert status == tg.OK
    r = row[0]
    return r[:2], np.array([[r[3], r[5]], [r[4], r[6]]]), counts


def section_start(traj):
    i = section_indices(traj)[-1]
    return float(traj.x[i]), float(traj.v[i])


# -- the tangent vectors ------------------------------------------------------------------------------

@pytest.mark.parametrize(("belt", "law"), [
    (BELT, Coulomb(fd=0.5, fs=0.8)),
    (BELT, Coulomb(fd=0.5, fs=0.8, stick_force="spring")),
    (BELT, Stribeck(fd=0.5, fs=0.8, vs=0.1, delta=1.0)),
    (REVERSING, Stribeck(fd=0.1, fs=0.15, vs=0.2, delta=1.0)),
], ids=["coulomb", "coulomb-spring", "stribeck", "reversing"])
def test_tangent_vectors_match_finite_differences_of_a_reference_run(belt, law):
    m = BeltOscillator(**belt)
    x0, v0, t_end = 0.1, 0.0, 28.0  # it slips at t_end: both rows of the derivative are free
    state, M, counts = kernel_flow(m, law, x0, v0, t_end, 5000)
    ref, kinds = reference(m, law, x0, v0, [t_end])
    # the stretch has stick and slip (and, on the reversing belt, reversals): each switch's saltation is used
    assert counts[tg.C_STICK] == kinds.count("stick") >= 2 and counts[tg.C_SLIP] == kinds.count("slip") >= 2
    assert counts[tg.C_REVERSAL] == kinds.count("reversal")
    if belt is REVERSING:
        assert counts[tg.C_REVERSAL] >= 1
    assert np.abs(state - ref[0]).max() < 1e-9
    # the step balances the differences' truncation (eps^2) and the reference's rounding over 2 eps: on the
    # reversing belt, whose flow contracts the entries to ~5e-6, |M - J| / |J| is 5.6e-6, 2.2e-6, 2.1e-6 and
    # 4.1e-5 at eps 3e-4, 1e-4, 3e-5 and 1e-5 (rounding-dominated there: 3.5e-4 at 1e-6); the other cases'
    # fall as eps^2 to 3e-8 at 3e-5
    J = reference_jacobian(m, law, x0, v0, t_end, eps=3e-5)
    assert np.abs(M - J).max() < 2e-5 * np.abs(J).max()


# -- the exponents ------------------------------------------------------------------------------------

@pytest.mark.parametrize("drive", [{}, {"fex": 0.3, "omega": 1.3}], ids=["unforced", "forced"])
def test_zero_amplitude_gives_the_constant_belt_exponents_bit_for_bit(drive):
    law = Coulomb(0.5, 1.0)
    a = lyapunov_exponents(BeltOscillator(zeta=0.02, vb=0.1, **drive), law, t_transient=50.0, t_end=600.0)
    b = lyapunov_exponents(BeltOscillator(zeta=0.02, vb=0.1, vb_amplitude=0.0, vb_omega=2.7, vb_phi=1.1, **drive), law,
                           t_transient=50.0, t_end=600.0)
    assert a.exponents == b.exponents and a.switches == b.switches
    assert np.array_equal(a.sections, b.sections) and np.array_equal(a.running, b.running, equal_nan=True)


def test_a_periodic_moving_belt_point_has_the_negative_exponent_of_its_monodromy():
    belt, law = PERIODIC
    m = BeltOscillator(**belt)
    ss = analyze(simulate(m, law, Exact(), t_end=2000.0)).steady_state
    assert ss.kind == "periodic" and ss.forcing_multiple == 2
    T = m.drive_period
    y = reference(m, law, 0.0, 0.0, [100 * T])[0][0]
    assert np.abs(reference(m, law, *y, [2 * T])[0][0] - y).max() < 1e-9  # a period-2 orbit of the reference
    mu = np.abs(np.linalg.eigvals(reference_jacobian(m, law, *y, 2 * T)))
    expected = math.log(mu.max()) / (2 * T)
    r = lyapunov_exponents(m, law, x0=y[0], v0=y[1], t_transient=0.0, t_end=400 * T, steps_per_block=256)
    assert expected < -0.05
    assert r.exponents[0] == pytest.approx(expected, rel=1e-6)
    assert r.exponents[1] == -math.inf  # it sticks every other period


def test_a_quasi_periodic_moving_belt_point_has_a_zero_exponent():
    belt, law = QUASI
    m = BeltOscillator(**belt)
    T = m.drive_period
    traj = simulate(m, law, Exact(), t_end=3000.0)
    ss = analyze(traj).steady_state
    assert ss.kind == "quasi_periodic" and abs(ss.lyapunov) < 1e-4
    # the kernel's finite-time growth of a perturbation over 30 periods is the reference's
    x0, v0 = section_start(traj)
    r = lyapunov_exponents(m, law, x0=x0, v0=v0, t_transient=0.0, t_end=30 * T, steps_per_block=512)
    J = reference_jacobian(m, law, x0, v0, 30 * T)
    assert r.exponents[0] * 30 * T == pytest.approx(math.log(np.hypot(*J[:, 0])), abs=1e-6)
    # no repetition of the reference's section within 12 periods, and the long run's exponent is 0
    seq = reference(m, law, x0, v0, T * np.arange(1, 41))[0]
    assert min(np.abs(seq[k:] - seq[:-k]).max() for k in range(1, 13)) > 1e-4
    long = lyapunov_exponents(m, law, x0=x0, v0=v0, t_transient=100 * T, t_end=2100 * T, steps_per_block=256)
    assert abs(long.exponents[0]) < max(long.spread[0], 1e-5) and long.exponents[1] == -math.inf


def divergence_rate(m, law, starts, periods, d0=1e-9, saturation=1e-4):
    """The slope of log(separation / d0) of reference section sequences started d0 apart, before saturation."""
    T = m.drive_period
    ts, logs = [0.0], [0.0]
    for y in starts:
        times = T * np.arange(1, periods + 1)
        a = reference(m, law, *y, times)[0]
        b = reference(m, law, y[0] + d0, y[1], times)[0]
        for k, dk in enumerate(np.hypot(*(a - b).T), start=1):
            if dk > saturation or dk == 0.0:
                break
            ts.append(k * T)
            logs.append(math.log(dk / d0))
    return float(np.polyfit(ts, logs, 1)[0]), len(ts)


def test_a_chaotic_moving_belt_point_has_the_positive_exponent_of_diverging_runs():
    belt, law = CHAOTIC
    m = BeltOscillator(**belt)
    T = m.drive_period
    r = lyapunov_exponents(m, law, 0.0, 0.0, t_transient=100 * T, t_end=1100 * T, steps_per_block=256)
    assert r.chaotic and r.exponents[0] > 0.02 and r.exponents[1] == -math.inf
    seq = reference(m, law, 0.0, 0.0, T * np.arange(1, 121))[0]
    # over 10 periods from a point of the attractor, the kernel's growth of a perturbation is the reference's
    # (RK4 converges onto it at fourth order: 2e-4 off at 256 steps a period, 1e-8 at 2048)
    short = lyapunov_exponents(m, law, *seq[30], t_transient=0.0, t_end=10 * T, steps_per_block=2048)
    J = reference_jacobian(m, law, *seq[30], 10 * T, eps=1e-7)
    assert short.exponents[0] * 10 * T == pytest.approx(math.log(np.hypot(*J[:, 0])), abs=1e-7)
    # nearby reference runs separate at about that rate (a finite-time estimate: within its statistics)
    rate, n = divergence_rate(m, law, seq[21::5][:20], periods=30)
    assert n > 300 and rate > 0.0
    assert rate == pytest.approx(r.exponents[0], rel=0.3)


# -- every path agrees --------------------------------------------------------------------------------

def test_a_non_repeating_moving_belt_point_is_classified_alike_by_every_path():
    from frictionflow.sweep.compute import VARIABLES, compute_chunk

    belt, law = CHAOTIC
    m = BeltOscillator(**belt)
    traj = simulate(m, law, Adaptive(), t_end=1500.0)
    ss = analyze(traj).steady_state
    assert ss.kind == "chaotic" and ss.lyapunov > 0.0
    # the classifier's exponent is lyapunov_exponents' from the last section state, with its settings
    x0, v0 = section_start(traj)
    T = m.drive_period
    assert largest_exponent(traj)[0] == ss.lyapunov
    direct = lyapunov_exponents(m, law, x0, v0, t_transient=LYAPUNOV_TRANSIENT * T,
                                t_end=(LYAPUNOV_TRANSIENT + LYAPUNOV_PERIODS) * T, steps_per_block=LYAPUNOV_STEPS)
    assert direct.exponents[0] == ss.lyapunov
    # the command line from the same state
    code, out, err, _ = cli("lyapunov", "--friction", "stribeck", "--fd", "0.5", "--fs", "1.0", "--vs", "0.1",
                            *(f"--{k.replace('_', '-')}={v!r}" for k, v in belt.items()), f"--x0={x0!r}", f"--v0={v0!r}",
                            "--t-transient", repr(LYAPUNOV_TRANSIENT * T), "--t-end",
                            repr((LYAPUNOV_TRANSIENT + LYAPUNOV_PERIODS) * T), "--steps-per-period",
                            str(LYAPUNOV_STEPS), "--json")
    assert code == 0, err
    assert json.loads(out)["exponents"][0] == ss.lyapunov
    # a sweep over the belt's amplitude runs the point through the façade: the same kind
    settings = {"friction": "stribeck", "fd": 0.5, "fs": 1.0, "vs": 0.1, "solver": "adaptive", "t_end": 1500.0,
                **{k: v for k, v in belt.items() if k != "vb_amplitude"}}
    rows = compute_chunk({"settings": settings, "grid": {"vb_amplitude": [0.0, belt["vb_amplitude"]]}}, (0,), (2,))
    names = [v[0] for v in VARIABLES]
    assert KINDS[int(rows[names.index("kind"), 1])] == "chaotic"
    values = analyze(traj).quantities()
    for k in ("P_fin", "R_c", "TR_B", "stick_fraction"):
        assert rows[names.index(k), 1] == pytest.approx(values[k], rel=1e-12)


# -- refused ------------------------------------------------------------------------------------------

def test_moving_belt_runs_without_one_period_or_with_another_block_are_refused_with_one_line():
    m = BeltOscillator(**BELT, fex=0.1, omega=0.8)
    with pytest.raises(ValueError, match=r"^vb_omega=0.7 differs from omega=0.8: .*set vb_omega equal to omega$") as e:
        lyapunov_exponents(m, Coulomb(0.5, 0.8), 0.5, 0.2)
    assert "\n" not in str(e.value)
    with pytest.raises(ValueError, match=r"^a moving-belt run renormalises once per period of the belt's speed "
                                         r"8.97597901026; got block=1.0$"):
        lyapunov_exponents(BeltOscillator(**BELT), Coulomb(0.5, 0.8), 0.5, 0.2, block=1.0)
