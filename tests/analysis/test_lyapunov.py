"""Lyapunov exponents of the stick-slip flow against independent references.

References: the closed-form linear oscillator; Floquet multipliers of
unforced orbits (:func:`frictionflow.orbits.find_orbit`); for forced runs a
reference integrator written here (scipy's DOP853 phase by phase, switches
by its events and brentq: none of the package's kernels), whose stroboscopic
map gives finite-difference monodromy matrices and the divergence of nearby
sequences.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from frictionflow import BeltOscillator, Coulomb, Karnopp, Stribeck
from frictionflow.analysis.lyapunov import lyapunov_exponents
from frictionflow.orbits import find_orbit

# (zeta, vb, fd, fs, fex, omega) of forced Coulomb systems (F_e = X + 2 zeta V_b)
CHAOTIC = (0.01, 0.1, 0.5, 1.0, 0.5, 1.0)  # stick-slip, about one stick per period, lambda_1 ~ 0.08
PERIODIC_SLIP = (0.05, 0.01, 0.02, 0.04, 0.3, 1.2)  # period 1, two slip reversals, no stick
PERIODIC_STICK = (0.05, 0.1, 0.5, 1.0, 0.5, 1.0)  # period 3, one stick phase per orbit


def system(zeta, vb, fd, fs, fex, omega):
    return BeltOscillator(zeta=zeta, vb=vb, fex=fex, omega=omega), Coulomb(fd, fs)


# -- the reference integrator --------------------------------------------------------------------
def reference_strobe(case, x0, v0, n_periods, rtol=1e-12):
    """(X, X') at tau_k = k 2 pi / Omega, k = 1..n_periods: Coulomb stick-slip by DOP853 phase by phase."""
    zeta, vb, fd, fs, fex, omega = case
    period = 2 * math.pi / omega

    def f(t):
        return fex * math.cos(omega * t)

    def q(x, t):  # the force the interface must hold while sticking
        return x + 2 * zeta * vb - f(t)

    t, x, v = 0.0, float(x0), float(v0)
    mode = 1 if vb > v else -1
    if v == vb:
        mode = 0 if abs(q(x, 0.0)) <= fs else (1 if q(x, 0.0) > 0 else -1)
    out = np.empty((n_periods, 2))
    k = 0
    while k < n_periods:
        t_next = (k + 1) * period
        if mode == 0:
            def gap(s, x=x, t=t):
                return abs(q(x + vb * (s - t), s)) - fs

            grid = np.linspace(t, t_next, 65)
            exit_at = None
            for a, b in zip(grid[:-1], grid[1:]):
                if gap(b) >= 0.0:
                    exit_at = brentq(gap, a, b, xtol=1e-15, rtol=1e-15) if gap(a) < 0.0 else a
                    break
            if exit_at is None:
                x, t = x + vb * (t_next - t), t_next
                out[k] = x, vb
                k += 1
                continue
            x, t = x + vb * (exit_at - t), exit_at
            mode = 1 if q(x, t) > 0 else -1
            continue
        d = mode

        def rhs(s, y, d=d):
            return [y[1], d * fd + f(s) - y[0] - 2 * zeta * y[1]]

        def hit(s, y, d=d):
            return d * (vb - y[1])

        hit.terminal, hit.direction = True, -1
        sol = solve_ivp(rhs, (t, t_next), [x, v], method="DOP853", rtol=rtol, atol=1e-14, events=hit)
        if sol.status == 1:
            t, x, v = float(sol.t_events[0][0]), float(sol.y_events[0][0][0]), vb
            mode = 0 if abs(q(x, t)) <= fs else (1 if q(x, t) > 0 else -1)
        else:
            t, x, v = t_next, float(sol.y[0, -1]), float(sol.y[1, -1])
            out[k] = x, v
            k += 1
    return out


def reference_monodromy(case, y, periods, eps=1e-6):
    """d(strobe after ``periods``)/d(start) by central differences of the reference."""
    J = np.empty((2, 2))
    for i in range(2):
        e = np.zeros(2)
        e[i] = eps
        plus = reference_strobe(case, *(y + e), periods)[-1]
        minus = reference_strobe(case, *(y - e), periods)[-1]
        J[:, i] = (plus - minus) / (2 * eps)
    return J


def divergence_rate(case, starts, periods, d0=1e-9, saturation=1e-4):
    """Growth rate of log |separation| of stroboscopic sequences started d0 apart, before saturation.

    One least-squares slope through the points (tau_k, log d_k / d_0) of all
    pairs, each up to its first d_k above ``saturation``.
    """
    period = 2 * math.pi / case[5]
    ts, logs = [0.0], [0.0]
    for y in starts:
        a = reference_strobe(case, *y, periods)
        b = reference_strobe(case, y[0] + d0, y[1], periods)
        d = np.hypot(*(a - b).T)
        for k, dk in enumerate(d, start=1):
            if dk > saturation or dk == 0.0:
                break
            ts.append(k * period)
            logs.append(math.log(dk / d0))
    ts, logs = np.array(ts), np.array(logs)
    return float(np.polyfit(ts, logs, 1)[0]), len(ts)


# -- tests -----------------------------------------------------------------------------------------
def test_linear_forced_oscillator_has_both_exponents_minus_zeta():
    # V_b = 1 above the steady velocity amplitude Omega |X_p| ~ 0.79: slip+ for ever, F_c = F_d, linear
    zeta, omega, fex, fd = 0.05, 1.2, 0.3, 0.02
    model, law = BeltOscillator(zeta=zeta, vb=1.0, fex=fex, omega=omega), Coulomb(fd, 0.04)
    xp = fex / (1 - omega**2 + 2j * zeta * omega)  # start on the steady state: no transient, no switch
    r = lyapunov_exponents(model, law, x0=fd + xp.real, v0=(1j * omega * xp).real, t_transient=0.0,
                           t_end=5000 * model.forcing_period, steps_per_block=256)
    assert not any(r.switches.values())
    elapsed = r.times[-1]
    # e^{At} = V diag(e^{lambda t}) V^-1: |e^{At} u| / e^{-zeta t} stays within [1/kappa, kappa], kappa = cond V
    lam = np.linalg.eigvals(np.array([[0.0, 1.0], [-1.0, -2 * zeta]]))
    kappa = np.linalg.cond(np.array([[1.0, 1.0], lam]))
    bound = math.log(kappa) / elapsed
    assert bound < 2e-6
    h = model.forcing_period / 256
    for e in r.exponents:
        assert abs(e + zeta) <= bound + h**4 / 60
    # the trace -2 zeta, up to RK4's own error: log|R(h lambda)| - Re(h lambda) = Re((h lambda)^5) / 120 + ...
    # per step, about -h^4 / 240 per unit time and eigenvalue here (7e-10 in all at h = 0.02)
    assert sum(r.exponents) == pytest.approx(-2 * zeta, abs=h**4 / 60)


def test_unforced_coulomb_stick_slip_cycle_matches_its_floquet_multipliers():
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04)
    orbit = find_orbit(model, law)
    mu = sorted(np.abs(orbit.multipliers), reverse=True)
    assert orbit.has_stick and mu[0] == pytest.approx(1.0, abs=1e-9) and mu[1] < 1e-12
    # blocks of one period: the flow-direction exponent telescopes to |f(end)| / |f(start)| = 1
    r = lyapunov_exponents(model, law, x0=orbit.state[0], v0=0.0, t_transient=20 * orbit.period,
                           t_end=520 * orbit.period, block=orbit.period)
    assert r.exponents[0] == pytest.approx(math.log(mu[0]) / orbit.period, abs=1e-9)
    # multiplier 0: a stick onset every period, the tangent map loses rank: -inf, not a number
    assert r.exponents[1] == -math.inf and r.collapsed
    assert r.switches["stick_onsets"] == r.switches["slip_onsets"] == 520


def test_unforced_pure_slip_cycle_matches_its_floquet_multipliers():
    model, law = BeltOscillator(zeta=0.34, vb=0.016), Stribeck(0.02, 0.04, 0.01)
    orbit = find_orbit(model, law, x0=0.047, v0=0.0, transient=0.0)
    assert not orbit.has_stick
    mu = sorted(np.abs(orbit.multipliers), reverse=True)  # 1 and ~0.75
    # a transient of 100 periods turns the frame onto the flow direction (0.75^100 ~ 3e-13); then, in blocks
    # of one period, log r11 telescopes to log |f(end)| / |f(start)| and log r11 r22 is log mu_2 per block
    r = lyapunov_exponents(model, law, x0=orbit.state[0], v0=0.0, t_transient=100 * orbit.period,
                           t_end=2100 * orbit.period, block=orbit.period)
    assert not any(r.switches.values())
    assert r.exponents[0] == pytest.approx(math.log(mu[0]) / orbit.period, abs=1e-8)
    assert r.exponents[1] == pytest.approx(math.log(mu[1]) / orbit.period, abs=1e-8)


def test_forced_periodic_slip_exponents_match_the_reference_monodromy():
    model, law = system(*PERIODIC_SLIP)
    y = reference_strobe(PERIODIC_SLIP, 0.0, 0.0, 200)[-1]
    assert np.allclose(reference_strobe(PERIODIC_SLIP, *y, 1)[-1], y, atol=1e-10)  # a period-1 orbit
    mu = np.linalg.eigvals(reference_monodromy(PERIODIC_SLIP, y, 1))
    expected = sorted(np.log(np.abs(mu)) / model.forcing_period, reverse=True)
    r = lyapunov_exponents(model, law, x0=y[0], v0=y[1], t_transient=0.0, t_end=3000 * model.forcing_period,
                           steps_per_block=256)
    assert r.switches["slip_reversals"] == 2 * 3000 and r.switches["stick_onsets"] == 0
    # a complex pair: both exponents log|mu| / T; the finite-time split decays like 1 / t
    assert r.exponents[0] == pytest.approx(expected[0], abs=3e-6)
    assert r.exponents[1] == pytest.approx(expected[1], abs=3e-6)
    assert sum(r.exponents) == pytest.approx(sum(expected), abs=1e-7)  # log|det| per time: no finite-time split


def test_forced_periodic_stick_orbit_negative_exponent_matches_reference_and_divergence():
    model, law = system(*PERIODIC_STICK)
    T = model.forcing_period
    seq = reference_strobe(PERIODIC_STICK, 0.0, 0.0, 400)
    y = seq[-1]
    assert np.allclose(seq[-4], y, atol=1e-9) and not np.allclose(seq[-2], y, atol=1e-3)  # period 3
    J = reference_monodromy(PERIODIC_STICK, y, 3)
    assert abs(np.linalg.det(J)) < 1e-6 * np.abs(J).max() ** 2  # sticking: rank 1
    lam1 = math.log(abs(np.trace(J))) / (3 * T)  # the nonzero multiplier of a rank-1 matrix is its trace
    r = lyapunov_exponents(model, law, x0=y[0], v0=y[1], t_transient=0.0, t_end=3000 * T, steps_per_block=256)
    assert lam1 < 0.0
    assert r.exponents[0] == pytest.approx(lam1, rel=1e-5)
    assert r.exponents[1] == -math.inf
    # the distance of two sequences shrinks at that rate: compare at whole orbit periods
    a = reference_strobe(PERIODIC_STICK, *y, 60)
    b = reference_strobe(PERIODIC_STICK, y[0] + 1e-9, y[1], 60)
    d = np.hypot(*(a - b).T)[2::3]
    rate = np.polyfit(3 * T * np.arange(1, len(d) + 1), np.log(d), 1)[0]
    assert rate < 0.0
    assert rate == pytest.approx(r.exponents[0], rel=0.05)


def test_kernel_strobes_follow_the_reference_integrator():
    for case in (PERIODIC_STICK, PERIODIC_SLIP):
        model, law = system(*case)
        ref = reference_strobe(case, 0.0, 0.0, 40)
        r = lyapunov_exponents(model, law, 0.0, 0.0, t_transient=0.0, t_end=40 * model.forcing_period,
                               steps_per_block=512)
        assert np.abs(r.sections[:, :2] - ref).max() < 1e-7


def test_forced_chaotic_stick_slip_has_a_positive_exponent_confirmed_by_divergence():
    model, law = system(*CHAOTIC)
    T = model.forcing_period
    r = lyapunov_exponents(model, law, 0.0, 0.0, t_transient=200 * T, t_end=2200 * T, steps_per_block=256)
    assert r.chaotic and r.exponents[0] > 0.05
    assert r.exponents[1] == -math.inf  # it sticks about once a period
    assert r.switches["stick_onsets"] > 1500
    seq = reference_strobe(CHAOTIC, 0.0, 0.0, 220)
    rate, n = divergence_rate(CHAOTIC, seq[100::12][:10], periods=30)
    assert n > 100
    assert rate > 0.0
    assert rate == pytest.approx(r.exponents[0], rel=0.3)


@pytest.mark.parametrize("case", [PERIODIC_SLIP, PERIODIC_STICK], ids=["slip", "stick"])
def test_halving_the_step_changes_periodic_exponents_by_less_than_1e8(case):
    model, law = system(*case)
    runs = [lyapunov_exponents(model, law, t_transient=100 * model.forcing_period, t_end=600 * model.forcing_period,
                               steps_per_block=n) for n in (128, 256)]
    for a, b in zip(runs[0].exponents, runs[1].exponents):
        assert a == b or abs(a - b) < 1e-8


def test_halving_the_step_changes_the_chaotic_exponent_within_its_statistics():
    # a chaotic trajectory is not reproduced by another step: only the average is; 10% is ~3 spreads
    model, law = system(*CHAOTIC)
    T = model.forcing_period
    runs = [lyapunov_exponents(model, law, t_transient=200 * T, t_end=2200 * T, steps_per_block=n) for n in (256, 512)]
    assert runs[0].exponents[0] == pytest.approx(runs[1].exponents[0], rel=0.1)


def test_band_and_user_laws_are_refused():
    model = BeltOscillator(zeta=0.05, vb=0.01)
    with pytest.raises(ValueError, match="stick rule"):
        lyapunov_exponents(model, Karnopp(0.02, 0.04))
    from frictionflow.friction.user import SlipLaw

    with pytest.raises(ValueError, match="user-defined"):
        lyapunov_exponents(model, SlipLaw(lambda s: 0.02 + 0.0 * s))


@pytest.mark.parametrize("kw", [dict(t_end=10.0, t_transient=20.0), dict(t_transient=-1.0), dict(steps_per_block=2),
                                dict(steps_per_block=10.5), dict(x0=math.nan), dict(block=0.0)])
def test_bad_settings_are_refused(kw):
    with pytest.raises(ValueError):
        lyapunov_exponents(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04), **kw)


def test_forced_runs_renormalise_once_per_forcing_period():
    with pytest.raises(ValueError, match="forcing period"):
        lyapunov_exponents(BeltOscillator(zeta=0.05, vb=0.01, fex=0.1), Coulomb(0.02, 0.04), block=1.0)


def test_report_is_json_with_minus_infinity_marked():
    model, law = system(*PERIODIC_STICK)
    r = lyapunov_exponents(model, law, t_transient=50.0, t_end=300.0)
    d = json.loads(json.dumps(r.as_dict(), allow_nan=False))
    assert d["exponents"][0] == r.exponents[0] and d["exponents"][1] is None
    assert d["minus_infinity"] == [False, True] and d["collapsed"] is True
    assert d["settings"]["block"] == pytest.approx(model.forcing_period)
    assert "lambda_1" in r.summary() and "-inf" in repr(r)
    assert r.running.shape == (d["settings"]["blocks"], 2)


def test_cli_prints_the_exponents(capsys):
    from frictionflow.cli import main
    import frictionflow.cli.lyapunov  # noqa: F401  (registers the command)

    zeta, vb, fd, fs, fex, omega = PERIODIC_STICK
    args = ["lyapunov", "--zeta", str(zeta), "--vb", str(vb), "--fd", str(fd), "--fs", str(fs), "--fex", str(fex),
            "--omega", str(omega), "--t-transient", "100", "--t-end", "600", "--steps", "128", "--json"]
    assert main(args) == 0
    d = json.loads(capsys.readouterr().out)
    model, law = system(*PERIODIC_STICK)
    # the CLI starts where every command does, at (F_d, V_b)
    r = lyapunov_exponents(model, law, x0=fd, v0=vb, t_transient=100.0, t_end=600.0, steps_per_block=128)
    assert d["exponents"][0] == r.exponents[0] and d["params"]["friction"] == "coulomb"
    assert main(["lyapunov", "--friction", "karnopp"]) == 2
    assert "band" in capsys.readouterr().err
