"""The RK4 grid of flow maps and tangent runs under a forcing much slower than the oscillator (Omega < 1/8).

512 steps per forcing period were steps of 2 pi / (512 Omega): at Omega = 0.01, 1.2 time units against the
oscillator's own period 2 pi, and ``forced-orbit``'s multipliers came out four decades small, ``lyapunov``'s
exponent 49 % off with a spread that looked converged (QA).  Unless told, the grid is now doubled until no step
exceeds 2 pi / 64.  The checks are closed forms: the point slips for good (Coulomb, V_b above every velocity of
the response), so the flow is a linear damped oscillator, both multipliers have modulus exp(-zeta T) and both
exponents are -zeta; and RK4's fourth order, which the error must show when the grid is doubled again.
"""

from __future__ import annotations

import math

import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.analysis.lyapunov import lyapunov_exponents
from frictionflow.orbits.forced import continue_forced, find_forced_orbit
from frictionflow.solvers.base import RK4_STEPS, rk4_steps

ZETA, OMEGA = 0.03, 0.01
SLOW = BeltOscillator(zeta=ZETA, vb=0.05, fex=0.02, omega=OMEGA)
LAW = Coulomb(0.02, 0.04)
EXACT_MU = math.exp(-ZETA * 2 * math.pi / OMEGA)  # 6.5e-9 (the 512-step grid gave 6.1e-13)


def test_the_default_grid_doubles_only_below_an_eighth():
    assert {rk4_steps(2 * math.pi / w) for w in (2.0, 1.0, 0.5, 0.125)} == {RK4_STEPS}  # as before
    assert rk4_steps(2 * math.pi / 0.1) == 2 * RK4_STEPS
    assert rk4_steps(2 * math.pi / OMEGA) == 16 * RK4_STEPS  # steps of 2 pi / 81.9
    assert rk4_steps(2 * math.pi / OMEGA, 64) == 64  # a given number is the caller's


def test_slow_forcing_orbit_multipliers_converge_to_the_linear_flows():
    orbit = find_forced_orbit(SLOW, LAW, m=1)
    assert orbit.stick_fraction == 0.0  # slips for good: the closed form applies
    steps = orbit.settings["steps_per_period"]
    assert steps == rk4_steps(SLOW.forcing_period)
    error = max(abs(abs(mu) / EXACT_MU - 1.0) for mu in orbit.multipliers)
    finer = find_forced_orbit(SLOW, LAW, m=1, x0=orbit.state[0], v0=orbit.state[1], steps=2 * steps)
    error_finer = max(abs(abs(mu) / EXACT_MU - 1.0) for mu in finer.multipliers)
    assert error < 1e-4  # (|mu| 1e4 times too small before)
    assert 10.0 < error / error_finer < 24.0  # fourth order: 16 for halved steps


def test_slow_forcing_exponents_are_minus_zeta():
    r = lyapunov_exponents(SLOW, LAW, t_transient=2 * SLOW.forcing_period, t_end=6 * SLOW.forcing_period)
    assert r.settings["steps_per_block"] == rk4_steps(SLOW.forcing_period)
    assert r.exponents == pytest.approx((-ZETA, -ZETA), abs=1e-4)  # (-0.0448 with the 512-step grid)


def test_a_branch_takes_the_grid_of_its_slowest_forcing():
    model = BeltOscillator(zeta=ZETA, vb=0.05, fex=0.02, omega=0.2)
    branch = continue_forced(model, LAW, "omega", 0.2, 0.09, max_points=6)
    assert branch.settings["steps_per_period"] == rk4_steps(2 * math.pi / 0.09) == 2 * RK4_STEPS
    told = continue_forced(model, LAW, "omega", 0.2, 0.09, max_points=6, steps=300)
    assert told.settings["steps_per_period"] == 300


def test_forced_continue_finds_its_first_orbit_on_the_branchs_grid(capsys):
    """The command's branch down to Omega = 0.09 runs on 1,024 steps a period (512 before), its first orbit too
    (at FROM, Omega = 0.2, where an orbit found alone takes 512); the branch's first point is the orbit
    find_forced_orbit finds there on that grid."""
    from frictionflow.cli import main
    import json

    args = ["forced-continue", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--zeta", str(ZETA), "--vb",
            "0.05", "--fex", "0.02", "--vary", "omega=0.2:0.09", "--max-points", "6", "--json"]
    assert main(args) == 0
    branch = json.loads(capsys.readouterr().out)["branches"][0]
    assert branch["settings"]["steps_per_period"] == 2 * RK4_STEPS
    first = find_forced_orbit(BeltOscillator(zeta=ZETA, vb=0.05, fex=0.02, omega=0.2), LAW, m=1,
                              steps=2 * RK4_STEPS, transient_periods=200)
    assert (branch["points"][0]["X"], branch["points"][0]["V"]) == pytest.approx(tuple(first.state), abs=1e-12)
