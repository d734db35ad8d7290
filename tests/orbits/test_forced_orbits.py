"""Forced periodic orbits: closed forms, brute-force simulation, Lyapunov exponents and the power balance."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Karnopp, Stribeck
from frictionflow.analysis.lyapunov import lyapunov_exponents
from frictionflow.core import tangent
from frictionflow.orbits.forced import (
    continue_forced, find_forced_orbit, flow_run, stroboscopic_sweep, switch_period_doubling,
)
from frictionflow.solvers.base import kernel_params

# the forced belt oscillator with a stable period-3 stick-slip orbit (chaotic at zeta = 0.01)
SUB3 = BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.0)
SUB3_LAW = Coulomb(0.5, 1.0)
# a Stribeck belt whose harmonic branch has a Neimark-Sacker point and grazings
STRIBECK_MODEL = BeltOscillator(zeta=0.03, vb=0.12, fex=0.02, omega=0.8)
STRIBECK_LAW = Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1.0)


def sections(model, law, x0, v0, periods, steps=512):
    """Brute force: the stroboscopic states of ``periods`` forcing periods from (x0, v0), and the switch counts."""
    p = kernel_params(model, law)
    strobe = np.zeros((periods, 3))
    est = np.zeros((periods, 2))
    counts = np.zeros(tangent.N_COUNTS, dtype=np.int64)
    status, _, _ = tangent.run(float(x0), float(v0), model.zeta, model.vb, p, model.forcing_period, steps, 0, periods,
                               strobe, est, counts)
    assert status == tangent.OK
    return strobe, counts


def test_slipping_orbit_is_the_linear_closed_form():
    # V_b far above every X': always slip+, Coulomb's force the constant F_d, so the orbit is the linear
    # oscillator's steady response about X = F_d: X = F_d + A cos(Omega tau - theta)
    zeta, omega, fex, fd = 0.1, 0.8, 0.3, 0.2
    model = BeltOscillator(zeta=zeta, vb=10.0, fex=fex, omega=omega)
    o = find_forced_orbit(model, Coulomb(fd, 0.3))
    amp = fex / math.hypot(1 - omega**2, 2 * zeta * omega)
    theta = math.atan2(2 * zeta * omega, 1 - omega**2)
    assert o.state[0] == pytest.approx(fd + amp * math.cos(theta), abs=1e-9)
    assert o.state[1] == pytest.approx(amp * omega * math.sin(theta), abs=1e-9)
    assert o.amplitude == pytest.approx(amp, rel=1e-8)  # extremes from cubic Hermite interpolants of the steps
    assert o.TR_B == pytest.approx((fd + amp * math.hypot(1, 2 * zeta * omega)) / fex, rel=1e-8)
    # multipliers exp((-zeta +- i sqrt(1 - zeta^2)) T): the free linear oscillator over one period
    lam = complex(-zeta, math.sqrt(1 - zeta**2))
    expected = sorted([np.exp(lam * o.period), np.exp(lam.conjugate() * o.period)], key=lambda z: z.imag)
    got = sorted(o.multipliers, key=lambda z: z.imag)
    assert np.allclose(got, expected, atol=1e-9)
    assert o.stable and not o.has_stick
    # power: P_ex = P_dv = zeta Omega^2 A^2, friction's net power 0 over a period
    assert o.averages["P_ex"] == pytest.approx(zeta * omega**2 * amp**2, rel=1e-8)
    assert o.averages["P_dv"] == pytest.approx(zeta * omega**2 * amp**2, rel=1e-8)
    assert abs(o.averages["P_f"]) < 1e-9


def test_stick_slip_orbit_is_the_brute_force_fixed_point_and_its_multipliers_the_lyapunov_exponents():
    o = find_forced_orbit(SUB3, SUB3_LAW, m=3)
    assert o.residual < 1e-10
    assert o.has_stick and o.stable
    assert abs(o.multipliers[1]) == 0.0  # the stick phase forgets X' perturbations
    # a long brute-force run from rest settles on the same 3-cycle of the section
    strobe, _ = sections(SUB3, SUB3_LAW, 0.0, 0.0, 900)
    tail = strobe[-3:, :2]
    assert np.min(np.max(np.abs(tail - o.state), axis=1)) < 1e-9
    # Lyapunov exponents from the orbit: log|mu| / T and -inf (the stick)
    r = lyapunov_exponents(SUB3, SUB3_LAW, float(o.state[0]), float(o.state[1]), t_transient=0.0, t_end=3000 * o.period / 3)
    assert r.exponents[0] == pytest.approx(math.log(abs(o.multipliers[0])) / o.period, abs=2e-5)
    assert r.exponents[1] == -math.inf and o.exponents[1] == -math.inf
    # the power balance over the period closes: P_ex = P_dv + P_df - P_fin
    a = o.averages
    assert a["P_ex"] == pytest.approx(a["P_dv"] + a["P_df"] - a["P_fin"], rel=1e-8)
    assert o.energy_residual < 1e-8


def test_monodromy_equals_finite_differences_of_the_map():
    # a stick-slip orbit whose section point slips (at tau = 0 the map is smooth in both directions)
    model = replace(STRIBECK_MODEL, omega=0.95)
    o = find_forced_orbit(model, STRIBECK_LAW)
    assert o.has_stick and o.state[1] != model.vb
    h = 1e-7
    cols = []
    for e in np.eye(2):
        plus = flow_run(model, STRIBECK_LAW, o.state + h * e).end
        minus = flow_run(model, STRIBECK_LAW, o.state - h * e).end
        cols.append((plus - minus) / (2 * h))
    assert np.allclose(np.column_stack(cols), o.monodromy, atol=1e-5)


def test_bad_input_is_refused_naming_the_parameter():
    with pytest.raises(ValueError, match="fex"):
        find_forced_orbit(BeltOscillator(zeta=0.05, vb=0.1), SUB3_LAW)
    with pytest.raises(ValueError, match="friction"):
        find_forced_orbit(SUB3, Karnopp(0.5, 1.0))
    with pytest.raises(ValueError, match="m must"):
        find_forced_orbit(SUB3, SUB3_LAW, m=0)
    with pytest.raises(ValueError, match="parameter"):
        continue_forced(SUB3, SUB3_LAW, "zeta", 0.05, 0.1)
    with pytest.raises(ValueError, match="stop"):
        continue_forced(SUB3, SUB3_LAW, "omega", 1.0, -1.0)


def _deviation_ratio(model, law, m, state, periods=40):
    """Brute force: the ratio of successive deviations of the m-period section from the orbit's state."""
    strobe, _ = sections(model, law, state[0] + 1e-7, state[1], m * periods)
    d = strobe[m - 1::m, 0] - state[0]
    return d[10:] / d[9:-1]


@pytest.fixture(scope="module")
def sub3_branch():
    return continue_forced(replace(SUB3, omega=1.25), SUB3_LAW, "omega", 1.25, 1.35, m=3)


def test_period_doubling_found_and_confirmed_by_brute_force(sub3_branch):
    pds = sub3_branch.events_of("period_doubling")
    assert len(pds) == 1
    pd = pds[0]
    assert np.min(np.abs(pd.multipliers + 1.0)) < 1e-6
    # either side, the brute-force section's deviations alternate with the ratio of the shooting's multiplier:
    # decaying (|mu| < 1) before the PD point, growing into a period-6 oscillation past it
    for delta, grows in ((-0.01, False), (0.01, True)):
        model = replace(SUB3, omega=pd.lam + delta)
        o = find_forced_orbit(model, SUB3_LAW, m=3, x0=pd.state[0], v0=pd.state[1])
        ratio = _deviation_ratio(model, SUB3_LAW, 3, o.state)
        assert np.all(ratio < 0)
        assert np.median(ratio) == pytest.approx(o.multipliers[0].real, abs=1e-3)
        assert (abs(np.median(ratio)) > 1) == grows
        assert o.stable != grows


def test_period_doubled_branch_is_a_brute_force_six_cycle(sub3_branch):
    b6 = switch_period_doubling(sub3_branch)
    assert b6.m == 6 and len(b6) >= 3
    for p in b6.points[1:]:
        model = b6.model_at(p.lam)
        strobe, _ = sections(model, SUB3_LAW, p.state[0], p.state[1], 6)
        assert np.max(np.abs(strobe[5, :2] - p.state)) < 1e-8  # back after 6 periods (independent integrator)
        assert np.max(np.abs(strobe[2, :2] - p.state)) > 1e-6  # not after 3
    # born at the PD point: the first orbits are close to the 3-orbit there
    pd = sub3_branch.events_of("period_doubling")[0]
    assert abs(b6.points[0].lam - pd.lam) < 1e-3


@pytest.fixture(scope="module")
def stribeck_branch():
    return continue_forced(STRIBECK_MODEL, STRIBECK_LAW, "omega", 0.8, 1.2)


def test_power_balance_closes_at_every_point(stribeck_branch):
    """Over one period the solver's run from the orbit's state closes the balance P_ex = P_dv + P_df - P_fin.

    The averages are the solver's over one period from the map's fixed point
    (:func:`frictionflow.orbits.forced.measures`), so the periodic balance
    also checks that the two agree on the orbit.  Within 1e-6 in Omega of a
    grazing (a stick phase that vanishes at a corner, its length ~ the square
    root of the distance) they may disagree on whether a stick phase of a few
    thousandths exists; there only the balance with Delta(K + U) is checked.
    """
    assert len(stribeck_branch) > 50
    grazings = [e.lam for e in stribeck_branch.events_of("grazing")]
    near = 0
    for p in stribeck_branch.points:
        a = p.averages
        flow = max(a["P_ex"], a["P_dv"], a["P_fin"], a["P_df"])
        assert p.energy_residual < 1e-8
        assert p.residual < 1e-9
        if min(abs(p.lam - g) for g in grazings) < 1e-6:
            near += 1
            continue
        assert abs(a["P_ex"] - (a["P_dv"] + a["P_df"] - a["P_fin"])) <= 1e-8 * flow, p.lam
    assert near < len(stribeck_branch) // 4  # the check still covers most of the branch


def test_neimark_sacker_and_grazing_against_brute_force(stribeck_branch):
    ns = stribeck_branch.events_of("neimark_sacker")
    assert ns, stribeck_branch
    first = ns[0]
    assert abs(abs(first.multipliers[0]) - 1.0) < 1e-6 and abs(first.multipliers[0].imag) > 0.1
    # brute force: the harmonic orbit attracts below the NS point, not above (a torus takes over)
    for delta, settles in ((-0.01, True), (0.01, False)):
        model = replace(STRIBECK_MODEL, omega=first.lam + delta)
        o = find_forced_orbit(model, STRIBECK_LAW, x0=first.state[0], v0=first.state[1])
        strobe, _ = sections(model, STRIBECK_LAW, o.state[0] + 1e-6, o.state[1], 600)
        assert (np.max(np.abs(strobe[-1, :2] - o.state)) < 1e-9) == settles
    # the stick onset (grazing) of the branch: a brute-force run sticks just above it, not below
    graze = [e for e in stribeck_branch.events_of("grazing") if e.detail.get("before") == [0, 0, 0]][0]
    for delta, sticks in ((-1e-3, False), (1e-3, True)):
        model = replace(STRIBECK_MODEL, omega=graze.lam + delta)
        o = find_forced_orbit(model, STRIBECK_LAW, x0=graze.state[0], v0=graze.state[1])
        _, counts = sections(model, STRIBECK_LAW, o.state[0], o.state[1], 2)
        assert (counts[tangent.C_STICK] > 0) == sticks == o.has_stick


def test_stroboscopic_sweep_periods():
    s = stroboscopic_sweep(SUB3, SUB3_LAW, "omega", [1.0, 1.05], transient_periods=600, keep=12)
    assert [s.multiple(0), s.multiple(1)] == [3, 3]
    o = find_forced_orbit(SUB3, SUB3_LAW, m=3)
    assert np.min(np.abs(s.x[0] - o.state[0])) < 1e-8


def test_fold_of_the_locked_orbit_against_brute_force():
    """A self-excited cubic-law oscillator (pure slip) locked to a weak forcing: lowering F_ex, the locked
    orbit meets its saddle partner in a fold at the edge of the 1:1 tongue.  Brute force settles on the
    locked orbit above the fold and never repeats below it."""
    from frictionflow import Cubic, analyze, simulate
    from frictionflow.solvers import RK4

    law = Cubic(fs=0.3, k1=0.3, k3=10.0)  # 2 zeta + F'(V_b) < 0 at V_b = 0.08: a limit cycle that never sticks
    model = BeltOscillator(zeta=0.05, vb=0.08, fex=5e-4, omega=1.001)
    start = find_forced_orbit(model, law, m=1, transient_periods=600)
    branch = continue_forced(model, law, "fex", 5e-4, 1e-5, m=1, orbit=start)
    folds = [e.lam for e in branch.events if e.type == "fold"]
    assert folds, [e.type for e in branch.events]
    fold = folds[0]
    assert 1e-4 < fold < 1.3e-4
    for fex, locked in ((1.2 * fold, True), (0.87 * fold, False)):
        near = min(branch.points, key=lambda q: abs(q.lam - fex))  # start 1e-3 off the branch: the run must find it
        forced = replace(model, fex=fex)
        tr = simulate(forced, law, RK4(dt=2e-3), t_end=1500 * forced.forcing_period, x0=near.state[0] + 1e-3,
                      v0=near.state[1])
        ss = analyze(tr).steady_state
        assert (ss.kind == "periodic" and ss.forcing_multiple == 1) is locked, (fex, ss.kind)
        if locked:  # the run's section state is the continued orbit's
            orbit = find_forced_orbit(forced, law, m=1, x0=near.state[0], v0=near.state[1], transient_periods=0)
            assert tr.x[-1] == pytest.approx(orbit.state[0], abs=1e-6)
