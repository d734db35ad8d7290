"""The forced steady state on the stroboscopic section, P_ex, TR_B by Eq. 6, and forced reports."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.analysis.forced import repeat_multiple, revisits, section_indices
from frictionflow.friction import Coulomb, Karnopp
from frictionflow.orbits import find_forced_orbit
from frictionflow.solvers import RK4, Exact

# a linear oscillator (no friction): its steady response is known in closed form
ZETA, OMEGA, FEX = 0.1, 0.8, 0.5
LINEAR = BeltOscillator(zeta=ZETA, vb=0.0, fex=FEX, omega=OMEGA)
NO_FRICTION = Karnopp(fd=0.0, fs=0.0, vd=1e-3)


def _linear_amplitude(zeta: float, omega: float, fex: float) -> float:
    return fex / math.hypot(1.0 - omega * omega, 2.0 * zeta * omega)


@pytest.fixture(scope="module")
def linear_run():
    with pytest.warns(UserWarning):  # the step is coarse for a band no motion reaches
        return simulate(LINEAR, NO_FRICTION, RK4(dt=1e-2), t_end=300.0, x0=0.0, v0=0.0)


# -- the section's sequence --------------------------------------------------------------------

def test_repeat_multiple_finds_the_smallest_period():
    base = np.array([0.3, -0.1, 0.7])
    for m in (1, 2, 3):
        x = np.tile(base[:m], 20)
        assert repeat_multiple(x, -x, 1e-12, 3)[0] == m


def test_repeat_multiple_rejects_an_incommensurate_rotation():
    k = np.arange(200)
    theta = 2 * math.pi * k * (math.sqrt(5) - 1) / 2  # golden rotation: never repeats
    assert repeat_multiple(np.cos(theta), np.sin(theta), 1e-6, 3) == (0, 0)
    assert revisits(np.cos(theta), np.sin(theta), 0.05)


def _spiral(mu: complex, n: int, end: float, cycle: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Section points P_k = P* + c mu^k (a focus with multiplier ``mu``), |c mu^(n-1)| = ``end``, around a fixed
    point or, with ``cycle``, around the points of an m-cycle (one multiplier per point, as a cycle's m-th map has)."""
    k = np.arange(n)
    z = end * mu ** (k - (n - 1))
    base = np.zeros(n, dtype=complex) if cycle is None else cycle[k % len(cycle)]
    return (base + z).real.copy(), (base + z).imag.copy()


def test_a_harmonic_still_converging_is_no_subharmonic():
    """A focus with mu = 0.94i: P_{k+4} - P_k shrinks as |mu^4 - 1| = 0.22, P_{k+1} - P_k as |mu - 1| = 1.37.  With the
    last points 1.2 tolerances from the fixed point the 4-step differences pass the tolerance and the 1-step ones do
    not: the run was reported a 4-cycle (the QA case: Coulomb at Omega 2.3, a 2-cycle reported as 4 at t_end 600)."""
    tol = 1e-9
    x, v = _spiral(0.94j, 60, 1.2 * tol)
    assert np.all(np.maximum(np.abs(x[-16:] - x[-20:-4]), np.abs(v[-16:] - v[-20:-4])) <= tol)  # as the old test saw
    assert np.max(np.abs(x[-2:] - x[-3:-1])) > tol
    assert repeat_multiple(x, v, tol, 3) == (0, 0)
    # the same approach to a true 4-cycle (points 0.1 apart) is one
    x4, v4 = _spiral(0.94j, 60, 1.2 * tol, np.array([0.1, 0.2 + 0.1j, -0.1, 0.05j]))
    assert repeat_multiple(x4, v4, tol, 3)[0] == 4


def test_a_drift_does_not_revisit():
    x = np.linspace(0.0, 1.0, 200)
    assert not revisits(x, x, 0.05)


def test_repetitions_count_back_from_the_end():
    x = np.concatenate([np.linspace(5, 1, 10), np.tile([0.2, 0.4], 10)])
    m, reps = repeat_multiple(x, x, 1e-12, 3)
    assert m == 2 and reps == 9  # 20 repeating points: 18 differences, 9 whole repetitions


def test_forced_runs_sample_the_section(linear_run):
    idx = section_indices(linear_run)
    period = 2 * math.pi / OMEGA
    assert np.allclose(linear_run.t[idx], np.arange(len(idx)) * period, rtol=1e-12, atol=1e-9)
    assert linear_run.t[idx[-1]] > 300.0 - period


# -- the linear oscillator against its closed form ---------------------------------------------

def test_linear_response_is_harmonic_with_closed_form_power_and_tr_b(linear_run):
    an = analyze(linear_run)
    ss = an.steady_state
    assert ss.kind == "periodic" and ss.forcing_multiple == 1
    assert ss.period == pytest.approx(2 * math.pi / OMEGA, rel=1e-12)
    a = _linear_amplitude(ZETA, OMEGA, FEX)
    # P_dv = mean of 2 zeta X'^2 = zeta Omega^2 A^2; P_ex equals it over whole periods
    assert an.power.P_dv == pytest.approx(ZETA * OMEGA**2 * a * a, rel=1e-6)
    assert an.power.P_ex == pytest.approx(an.power.P_dv, rel=1e-6)
    # Eq. 6 with the forcing amplitude: max|X + 2 zeta X'| = A sqrt(1 + (2 zeta Omega)^2)
    assert an.TR_B == pytest.approx(a * math.hypot(1.0, 2 * ZETA * OMEGA) / FEX, rel=1e-4)
    assert an.energy_residual < 1e-8


def test_forced_report_names_the_forcing(linear_run):
    d = analyze(linear_run).to_dict()
    assert d["params"]["fex"] == FEX and d["params"]["omega"] == OMEGA and d["params"]["phi"] == 0.0
    assert "P_ex" in d["averages"]
    assert d["steady_state"]["forcing_multiple"] == 1


def test_unforced_report_keeps_its_keys():
    tr = simulate(BeltOscillator(zeta=0.05, vb=0.01), Karnopp(fd=0.02, fs=0.04), t_end=200.0)
    d = analyze(tr).to_dict()
    assert not {"fex", "omega", "phi"} & set(d["params"])
    assert "P_ex" not in d["averages"]
    assert "forcing_multiple" not in d["steady_state"]


def test_a_short_run_is_not_settled():
    # after 6 forcing periods the transient e^(-zeta tau) is still ~1e-2 of the response
    with pytest.warns(UserWarning):
        tr = simulate(LINEAR, NO_FRICTION, RK4(dt=1e-2), t_end=6 * 2 * math.pi / OMEGA, x0=0.0, v0=0.0)
    assert analyze(tr).steady_state.kind == "not_settled"


def test_phase_shifts_the_forcing_not_the_steady_amplitude():
    shifted = BeltOscillator(zeta=ZETA, vb=0.0, fex=FEX, omega=OMEGA, phi=1.0)
    with pytest.warns(UserWarning):
        tr = simulate(shifted, NO_FRICTION, RK4(dt=1e-2), t_end=300.0, x0=0.0, v0=0.0)
    an = analyze(tr)
    a = _linear_amplitude(ZETA, OMEGA, FEX)
    assert 0.5 * (an.amplitude["X_max"] - an.amplitude["X_min"]) == pytest.approx(a, rel=1e-5)
    # the state on the section follows the phase: X(tau_k) = A cos(phi - delta)
    delta = math.atan2(2 * ZETA * OMEGA, 1 - OMEGA**2)
    assert tr.x[section_indices(tr)[-1]] == pytest.approx(a * math.cos(1.0 - delta), abs=1e-6)


# -- beyond periodic: told by the largest Lyapunov exponent --------------------------------------

def _coulomb_run(model, law, x0, v0, periods):
    return simulate(model, law, RK4(dt=1e-3), t_end=periods * model.forcing_period, x0=x0, v0=v0)


def test_a_chaotic_run_is_chaotic_with_its_exponent():
    # stick-slip once per forcing period with little damping: lambda_1 ~ 0.08 (tests/analysis/test_lyapunov.py
    # checks it against the divergence of nearby sequences)
    tr = _coulomb_run(BeltOscillator(zeta=0.01, vb=0.1, fex=0.5, omega=1.0), Coulomb(0.5, 1.0), 0.0, 0.0, 300)
    ss = analyze(tr).steady_state
    assert ss.kind == "chaotic" and ss.forcing_multiple is None and ss.period is None
    assert 0.05 < ss.lyapunov < 0.11


def test_a_weakly_forced_stick_slip_cycle_is_quasi_periodic():
    # the autonomous stick-slip cycle (period 7.63) forced weakly at an unrelated frequency: a torus, lambda_1 ~ 0
    tr = _coulomb_run(BeltOscillator(zeta=0.05, vb=0.01, fex=0.003, omega=2.1), Coulomb(0.02, 0.04), 0.02, 0.01, 400)
    ss = analyze(tr).steady_state
    assert ss.kind == "quasi_periodic"
    assert abs(ss.lyapunov) < 1e-3
    # the section never repeats, even at long multiples: its points fill a closed curve
    idx = section_indices(tr)[200:]
    assert repeat_multiple(tr.x[idx], tr.v[idx], 1e-6, 3, max_multiple=60) == (0, 0)


def test_karnopp_runs_that_do_not_repeat_stay_not_settled():
    # no tangent kernel for a band law: no exponent, so no claim beyond "not settled"
    model = BeltOscillator(zeta=0.01, vb=0.1, fex=0.5, omega=1.0)
    tr = simulate(model, Karnopp(fd=0.5, fs=1.0, vd=1e-4), RK4(dt=1e-3), t_end=60 * model.forcing_period, x0=0.0, v0=0.0)
    ss = analyze(tr).steady_state
    assert ss.kind == "not_settled" and ss.lyapunov is None


def test_a_two_cycle_still_converging_is_not_reported_as_a_four_cycle():
    """The QA case: Coulomb stick-slip at Omega = 2.3 locks onto a 2-cycle (shooting: stable, multiplier -0.821).
    At t_end 600 its section passed the 4-period test before the 2-period one and the run was 'periodic, multiple 4';
    it is not settled there, and from t_end 640 on it is the 2-cycle, the shot orbit's points."""
    model, law = BeltOscillator(zeta=0.05, vb=0.1, fex=0.45, omega=2.3), Coulomb(0.5, 1.0)
    early = analyze(simulate(model, law, Exact(), t_end=600.0)).steady_state
    assert early.kind == "not_settled"
    tr = simulate(model, law, Exact(), t_end=640.0)
    ss = analyze(tr).steady_state
    assert ss.kind == "periodic" and ss.forcing_multiple == 2
    orbit = find_forced_orbit(model, law, m=2)
    assert orbit.stability == "stable"
    idx = section_indices(tr)[-2:]
    assert min(abs(tr.x[i] - orbit.state[0]) + abs(tr.v[i] - orbit.state[1]) for i in idx) < 1e-7


def test_a_subharmonic_is_periodic_with_its_multiple_and_matches_the_shot_orbit():
    """Coulomb stick-slip locked at three forcing periods (exact solver), against Newton shooting on the
    tangent integrator's map (an independent integration) and its Floquet multiplier."""
    from frictionflow.orbits import find_forced_orbit
    from frictionflow.solvers import Exact

    model, law = BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.0), Coulomb(0.5, 1.0)
    tr = simulate(model, law, Exact(), t_end=400 * model.forcing_period, x0=0.0, v0=0.0)
    an = analyze(tr)
    ss = an.steady_state
    assert ss.kind == "periodic" and ss.forcing_multiple == 3
    assert ss.period == pytest.approx(3 * model.forcing_period, rel=1e-12)
    assert an.energy_residual < 1e-10
    orbit = find_forced_orbit(model, law, m=3)
    # the run's last three section states are the orbit's three points, one of them its shooting state
    idx = section_indices(tr)[-3:]
    assert min(abs(tr.x[i] - orbit.state[0]) + abs(tr.v[i] - orbit.state[1]) for i in idx) < 1e-7
    assert an.power.P_ex == pytest.approx(orbit.averages["P_ex"], rel=1e-6)


def test_a_fixed_steps_own_cycle_is_not_reported_as_a_subharmonic():
    """RK4 through Coulomb's stick band: its discrete run repeats exactly after 9 forcing periods (the step grid's
    own cycle), while the period-to-period spread of the section is within a few steps' travel.  The motion is
    the harmonic orbit every event-located solver finds (m = 1); RK4 reported m = 9 (QA)."""
    model, law = BeltOscillator(zeta=0.03, vb=0.05, fex=0.02, omega=0.9), Coulomb(0.02, 0.04)
    with pytest.warns(UserWarning):  # (dt = 1e-3 crosses the band in one step: warned, as any such run)
        traj = simulate(model, law, RK4(), t_end=3000.0)
    idx = section_indices(traj)
    tail = idx[len(idx) // 2:]
    xs, vs = traj.x[tail], traj.v[tail]
    scale = max(np.ptp(traj.x[tail[0]:]), 1e-300)
    assert repeat_multiple(xs, vs, 1e-12 * scale, 3)[0] == 9  # the discrete run's exact cycle
    rk4 = analyze(traj).steady_state
    exact = analyze(simulate(model, law, Exact(), t_end=3000.0)).steady_state
    assert exact.kind == rk4.kind == "periodic"
    assert exact.forcing_multiple == rk4.forcing_multiple == 1
    assert rk4.period == exact.period == pytest.approx(2 * math.pi / 0.9, rel=1e-12)
    assert rk4.jitter is not None and rk4.jitter < 0.01  # within the tolerance a fixed step is given
