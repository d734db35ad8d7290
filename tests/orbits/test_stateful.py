"""Orbits, multipliers, steady sliding and Hopf points of laws with internal state (orbits/stateful*.py),
against scipy's Radau on the equations written in the tests, finite differences of it, and the closed-form
Hopf condition of LuGre's 3 x 3 linearisation derived here."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from frictionflow import BeltOscillator, simulate
from frictionflow.cli import main
from frictionflow.friction import Coulomb, Dahl, ElastoPlastic, LuGre, RateState
from frictionflow.orbits import ShootingError, continuation, find_orbit
from frictionflow.orbits.flow_stiff import StiffFlow
from frictionflow.orbits.stateful import (ShootingMap, StatefulOrbit, fd_state_monodromy, find_stateful_orbit, newton,
                                          orbit_of)
from frictionflow.orbits.stateful_cycles import StateCycleProblem, branch_from_hopf, branch_from_orbit
from frictionflow.orbits.stateful_equilibria import state_equilibrium, state_hopf_points
from frictionflow.orbits.tracing import StepControl
from frictionflow.solvers import Stiff

from ..friction.test_lugre import lugre_rhs

# stiff bristles (sigma0 = 1e4 k): a stick-slip cycle
STICK = dict(fd=0.02, fs=0.04, vs=0.01, delta=2.0, sigma0=1e4, sigma1=100.0, sigma2=0.0)
STICK_MODEL = BeltOscillator(zeta=0.05, vb=0.01)
# soft bristles: steady sliding loses stability at a Hopf point in zeta, and slip-only cycles are born there
SOFT = dict(fd=0.3, fs=0.5, vs=0.05, delta=2.0, sigma0=10.0, sigma1=0.5, sigma2=0.0)
SOFT_MODEL = BeltOscillator(zeta=1.0, vb=0.05)


def radau_end(p, model, y0, period):
    """The state after ``period`` from y0 by scipy's Radau on LuGre's equations (test_lugre.lugre_rhs)."""
    sol = solve_ivp(lugre_rhs(p, model.zeta, model.vb), (0.0, period), y0, method="Radau", rtol=1e-12,
                    atol=[1e-14, 1e-14, 1e-14 * p["fs"] / p["sigma0"]])
    assert sol.success
    return sol.y[:, -1]


def radau_monodromy(p, model, y0, period):
    """dy(T)/dy(0) by central differences of Radau runs (step 1e-6 of each state's scale)."""
    scale = np.array([max(p["fs"], model.vb)] * 2 + [p["fs"] / p["sigma0"]])
    cols = []
    for j in range(3):
        e = np.zeros(3)
        e[j] = 1e-6 * scale[j]
        cols.append((radau_end(p, model, y0 + e, period) - radau_end(p, model, y0 - e, period)) / (2 * e[j]))
    return np.column_stack(cols)


def g(p, v):
    return p["fd"] + (p["fs"] - p["fd"]) * math.exp(-(abs(v) / p["vs"]) ** p["delta"])


def dg(p, v):
    u = v / p["vs"]
    return -(p["fs"] - p["fd"]) * math.exp(-u ** p["delta"]) * p["delta"] * u ** (p["delta"] - 1) / p["vs"]


def hopf_coefficients(p, vb):
    """LuGre linearised about steady sliding at V_r = V_b > 0, in (x, v, z) deviations:

    z' = -c v - a z          (a = sigma0 V_b / g, c = V_b g' / g: dr/dz and -dr/dv)
    v' = -x - D v + K z      (D = 2 zeta + sigma1 c + sigma2, K = sigma0 - sigma1 a)

    det(l I - A) = l^3 + (D + a) l^2 + (D a + K c + 1) l + a, and a Hopf point is where the Hurwitz
    determinant a2 a1 - a0 vanishes: a D^2 + (a^2 + K c + 1) D + a K c = 0.  Returns (a, c, K)."""
    a = p["sigma0"] * vb / g(p, vb)
    c = vb * dg(p, vb) / g(p, vb)
    return a, c, p["sigma0"] - p["sigma1"] * a


def hopf_zeta(p, vb):
    """The zeta of the Hopf points in closed form: the roots D of the quadratic, zeta = (D - sigma1 c - sigma2) / 2."""
    a, c, k = hopf_coefficients(p, vb)
    disc = (a * a + k * c + 1.0) ** 2 - 4.0 * a * a * k * c
    roots = [(-(a * a + k * c + 1.0) + s * math.sqrt(disc)) / (2.0 * a) for s in (1.0, -1.0)]
    return sorted((d - p["sigma1"] * c - p["sigma2"]) / 2.0 for d in roots)


# -- the flow's monodromy ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("p, model, y0, period", [
    (SOFT, SOFT_MODEL, np.array([0.4, 0.0, 0.04]), 7.0),
    (STICK, STICK_MODEL, np.array([0.01, 0.0, 0.0]), 7.0),  # breakaway, stick (V_r crosses 0), slip
])
def test_variational_monodromy_matches_differences_of_radau(p, model, y0, period):
    law = LuGre(**p)
    end = StiffFlow(model, law).run(y0, period)
    assert np.allclose(end.y, radau_end(p, model, y0, period), rtol=0, atol=1e-8 * np.array([1, 1, 1e-4]))
    m_fd = radau_monodromy(p, model, y0, period)
    col = np.max(np.abs(m_fd), axis=0)  # each column's scale (z's column is ~ sigma0 larger)
    assert np.max(np.abs(end.jacobian - m_fd) / col) < 1e-5


def test_two_returns_of_the_stick_slip_cycle_at_the_default_stiff_tolerance():
    """Stiff()'s rtol 1e-8: the second period's stick onset (V_r -> 0) ended the variational flow at a vanishing
    step (every step onto the kink was rejected: its last stages took J at V_r = 0, neither side's)."""
    law = LuGre(**STICK)
    one = find_stateful_orbit(STICK_MODEL, law, x0=0.02, v0=0.01, transient=500.0, solver=Stiff())
    two = find_stateful_orbit(STICK_MODEL, law, x0=0.02, v0=0.01, transient=500.0, returns=2, solver=Stiff())
    assert two.period == pytest.approx(2.0 * one.period, rel=1e-9)
    assert two.state == pytest.approx(one.state, rel=1e-9, abs=1e-14)
    mu = two.multipliers  # the superstable cycle twice: 1 and ~0, as once
    assert abs(mu[0] - 1.0) < 1e-6 and np.all(np.abs(mu[1:]) < 1e-6)
    # the monodromy through the second stick onset (tau ~ 12.25) at rtol 1e-8, against differences of Radau
    y0 = radau_end(STICK, STICK_MODEL, two.state, 11.7)
    end = StiffFlow(STICK_MODEL, law, rtol=1e-8).run(y0, 1.0)
    m_fd = radau_monodromy(STICK, STICK_MODEL, y0, 1.0)
    assert np.max(np.abs(end.jacobian - m_fd) / np.max(np.abs(m_fd), axis=0)) < 1e-6


# -- shooting -----------------------------------------------------------------------------------------------------
def test_shooting_converges_onto_the_lugre_stick_slip_cycle():
    law = LuGre(**STICK)
    found = find_orbit(STICK_MODEL, law, transient=12.0)
    assert isinstance(found, StatefulOrbit)
    # the cycle is superstable (a stick phase), so the transient lands on it: Newton from a guess well off it
    smap = ShootingMap(StiffFlow(STICK_MODEL, law))
    guess = np.array([found.state[0] * 1.1, found.state[2] * 0.5, found.period * 1.05])
    orbit = orbit_of(smap, newton(smap, guess, 1e-10), Stiff(rtol=1e-10, atol=1e-12))
    assert orbit.iterations >= 2
    assert orbit.state == pytest.approx(found.state, rel=1e-7, abs=1e-12) and orbit.period == pytest.approx(found.period, rel=1e-8)
    assert 0.2 < orbit.stick_fraction < 0.8 and orbit.amplitude > 0.01
    # one period of Radau from the orbit's whole state comes back to it
    back = radau_end(STICK, STICK_MODEL, orbit.state, orbit.period)
    assert np.max(np.abs(back - orbit.state) / np.array([0.04, 0.04, 4e-6])) < 1e-7
    # an independent simulation from rest settles onto it: its last downward section crossings
    traj = simulate(STICK_MODEL, law, Stiff(rtol=1e-11, atol=1e-13), t_end=200.0, x0=0.0, v0=0.0)
    down = np.flatnonzero((traj.v[:-1] > 0) & (traj.v[1:] == 0.0)) + 1
    assert traj.t[down[-1]] - traj.t[down[-2]] == pytest.approx(orbit.period, rel=1e-8)
    assert traj.x[down[-1]] == pytest.approx(orbit.state[0], rel=1e-8)
    assert traj.internal[0, down[-1]] == pytest.approx(orbit.state[2], rel=1e-6)
    # a stick phase forgets perturbations: the multipliers are the trivial 1 and ~0
    mu = orbit.multipliers
    assert abs(mu[0] - 1.0) < 1e-6 and np.all(np.abs(mu[1:]) < 1e-6) and orbit.stable


def test_multipliers_of_a_slip_cycle_against_radau_differences():
    law = LuGre(**SOFT)
    orbit = find_stateful_orbit(SOFT_MODEL, law, transient=150.0)
    assert orbit.stick_fraction == 0.0  # a slip-only cycle: a nontrivial multiplier in (0, 1)
    m_fd = radau_monodromy(SOFT, SOFT_MODEL, orbit.state, orbit.period)
    mu_fd = np.linalg.eigvals(m_fd)
    mu_fd = mu_fd[np.argsort(-np.abs(mu_fd))]
    assert np.allclose(orbit.multipliers, mu_fd, atol=1e-6)
    assert abs(orbit.multipliers[0] - 1.0) < 1e-7  # the trivial one, from the variational equations
    assert 0.05 < abs(orbit.multiplier) < 0.5 and orbit.stable
    assert len(orbit.nontrivial) == 2


def test_forced_orbit_is_a_fixed_point_of_the_stroboscopic_map():
    p = dict(SOFT, sigma2=0.1)
    model = BeltOscillator(zeta=0.2, vb=0.5, fex=0.1, omega=0.9)  # sliding throughout, driven
    orbit = find_stateful_orbit(model, LuGre(**p), transient=5 * model.forcing_period)
    assert orbit.period == pytest.approx(2 * math.pi / 0.9, rel=1e-15)
    sol = solve_ivp(lugre_rhs(p, 0.2, 0.5, 0.1, 0.9, 0.0), (0.0, orbit.period), orbit.state, method="Radau",
                    rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(sol.y[:, -1] - orbit.state)) < 1e-8
    assert len(orbit.nontrivial) == 3 and orbit.stable  # no trivial multiplier of a forced orbit
    # the report carries the external force's power and the period's energy residual: P_ex against the mean
    # of F_ex cos(Omega tau) X' over Radau's period (Gauss-Legendre on its dense output)
    d = orbit.to_dict()
    nodes, weights = np.polynomial.legendre.leggauss(64)
    edges = np.linspace(0.0, orbit.period, 33)
    dense = solve_ivp(lugre_rhs(p, 0.2, 0.5, 0.1, 0.9, 0.0), (0.0, orbit.period), orbit.state, method="Radau",
                      rtol=1e-12, atol=1e-14, dense_output=True).sol
    work = sum(0.5 * (b - a) * np.sum(weights * 0.1 * np.cos(0.9 * t) * dense(t)[1])
               for a, b in zip(edges[:-1], edges[1:]) for t in [0.5 * (b - a) * nodes + 0.5 * (a + b)])
    assert d["averages"]["P_ex"] == pytest.approx(work / orbit.period, rel=1e-7)
    assert d["energy_residual"] < 1e-9


# -- steady sliding and Hopf points -----------------------------------------------------------------------------
@pytest.mark.parametrize("law", [LuGre(**SOFT), LuGre(**STICK), Dahl(fd=0.02, sigma0=1e3, alpha=1.0),
                                 ElastoPlastic(fd=0.02, fs=0.03, vs=0.01, sigma0=1e4, sigma1=10.0, z_ba=1e-6)])
def test_steady_sliding_rests_the_states_at_the_law_steady_force(law):
    model = BeltOscillator(zeta=0.1, vb=0.02)
    eq = state_equilibrium(model, law)
    assert eq.state[1] == 0.0
    assert eq.x == pytest.approx(law.slip_force(0.02), rel=1e-12)  # X* = F(V_b), the law's own steady force
    assert np.max(np.abs(law.rate(0.02, eq.state[2:]))) < 1e-14  # the states at rest (numpy formulas)
    assert len(eq.eigenvalues) == 2 + law.n_internal


@pytest.mark.parametrize("p, vb", [(SOFT, 0.05), (SOFT, 0.08), (dict(SOFT, sigma1=0.0, sigma2=0.05), 0.05),
                                   (dict(STICK, sigma2=0.001), 0.012)])
def test_hopf_point_in_zeta_matches_the_closed_form(p, vb):
    expected = [z for z in hopf_zeta(p, vb) if z > 0.0]
    assert expected
    top = 1.5 * max(expected)
    found = state_hopf_points(BeltOscillator(zeta=0.1, vb=vb), LuGre(**p), "zeta", np.linspace(1e-3, top, 25))
    assert found == pytest.approx(expected, rel=1e-9)
    # just below it steady sliding is unstable, just above stable
    for z, want in ((expected[-1] * 0.99, "unstable"), (expected[-1] * 1.01, "stable")):
        assert state_equilibrium(BeltOscillator(zeta=z, vb=vb), LuGre(**p)).stability == want


@pytest.mark.parametrize("param, grid", [("vb", np.linspace(0.01, 0.3, 30)), ("fs", np.linspace(0.31, 1.0, 24)),
                                         ("sigma0", np.linspace(1.0, 40.0, 40))])
def test_hopf_point_in_other_parameters_matches_the_closed_form(param, grid):
    zeta = 0.3

    def hurwitz(value):  # a2 a1 - a0 of the closed-form characteristic polynomial
        p, vb = (SOFT, value) if param == "vb" else (dict(SOFT, **{param: value}), 0.05)
        a, c, k = hopf_coefficients(p, vb)
        d = 2 * zeta + p["sigma1"] * c + p["sigma2"]
        return (d + a) * (d * a + k * c + 1.0) - a

    vals = [hurwitz(v) for v in grid]
    expected = [brentq(hurwitz, a, b, xtol=1e-15) for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:])
                if fa * fb < 0]
    found = state_hopf_points(BeltOscillator(zeta=zeta, vb=0.05), LuGre(**SOFT), param, grid)
    assert len(expected) >= 1 and found == pytest.approx(expected, rel=1e-9)


# -- cycles continued ----------------------------------------------------------------------------------------------
def test_the_cycle_branch_born_at_the_hopf_point_has_vanishing_amplitude_there():
    lam_h = max(hopf_zeta(SOFT, 0.05))
    problem = StateCycleProblem(SOFT_MODEL, LuGre(**SOFT), "zeta", 0.8, 1.5)
    trace = branch_from_hopf(problem, lam_h, 2e-3, StepControl(h0=0.004, h_max=0.004, max_points=6))
    pts = trace.solutions
    assert len(pts) == 6 and all(s.lam < lam_h for s in pts)  # supercritical: cycles where sliding is unstable
    assert all(s.stable for s in pts)
    lam, xi2 = np.array([s.lam for s in pts]), np.array([s.xi ** 2 for s in pts])
    assert np.all(np.diff(lam) < 0) and np.all(np.diff(xi2) > 0)
    # near a Hopf point xi^2 is smooth in lambda (xi ~ sqrt(lambda_H - lambda)): the curve through the points
    # meets xi = 0 at lambda_H, within a small part of the distance of the nearest point
    root = np.roots(np.polyfit(lam, xi2, 2))
    root = root[np.argmin(np.abs(root - lam_h))].real
    assert abs(root - lam_h) < 0.05 * (lam_h - lam[0])
    assert pts[0].period == pytest.approx(2 * math.pi / state_equilibrium(
        BeltOscillator(zeta=lam_h, vb=0.05), LuGre(**SOFT)).eigenvalues[0].imag, rel=1e-2)
    # traced back from the orbit a simulation finds at zeta = 1, the branch ends on steady sliding at lambda_H
    orbit = find_stateful_orbit(SOFT_MODEL, LuGre(**SOFT), transient=150.0)
    back = branch_from_orbit(problem, 1.0, orbit.state, orbit.period, toward=1.5, steps=StepControl(max_points=60))
    assert back.end == "hopf"
    assert back.solutions[-1].lam == pytest.approx(lam_h, abs=2e-3)
    assert back.solutions[0].xi == pytest.approx(orbit.state[0] - state_equilibrium(SOFT_MODEL, LuGre(**SOFT)).x,
                                                 rel=1e-8)


# -- the API and the CLI -------------------------------------------------------------------------------------------
def test_orbit_cli_with_lugre(capsys):
    args = ["orbit", "--friction", "lugre", *[f"--{k}={v}" for k, v in STICK.items()], "--zeta", "0.05",
            "--vb", "0.01", "--t-end", "30", "--json", "--fd-check"]
    assert main(args) == 0
    d = json.loads(capsys.readouterr().out)
    assert {"state", "period", "floquet_multipliers", "stability", "interface_balance"} <= d.keys()
    assert set(d["state"]) == {"X", "V", "z"} and d["state"]["V"] == 0.0
    assert d["floquet_multipliers"][0] == pytest.approx([1.0, 0.0], abs=1e-6)
    assert abs(d["interface_balance"]["residual"]) < 1e-8 * d["interface_balance"]["belt"]
    assert d["fd_deviation"] < 1e-3
    assert main(args[:-2]) == 0 and "Floquet multiplier 3" in capsys.readouterr().out


@pytest.mark.parametrize("args, message", [
    (["--returns", "0"], "returns"),
    (["--plot", "orbit.png"], "--plot"),
    (["--sigma0", "0"], "sigma0 must be"),
    (["--solver", "rk4"], "solver=rk4"),
])
def test_orbit_cli_refuses_bad_input_with_one_line(capsys, args, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["orbit", "--friction", "lugre", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err
    assert not list(tmp_path.iterdir())  # nothing written


def test_orbit_cli_without_a_cycle_fails_with_one_line(capsys):
    # overdamped: the run settles on steady sliding, nothing periodic to find (a run-time failure, exit 1)
    assert main(["orbit", "--friction", "lugre", "--zeta", "2", "--t-end", "30"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error:") and err.count("\n") == 1


def test_api_refuses_bad_input_with_one_line():
    law = LuGre(**STICK)
    cases = [
        (lambda: StiffFlow(STICK_MODEL, Coulomb()), r"^friction=coulomb has no internal state"),
        (lambda: find_stateful_orbit(BeltOscillator(vb=0.01, vb_amplitude=0.001, vb_omega=1.0), law), r"^vb_amplitude"),
        (lambda: find_stateful_orbit(STICK_MODEL, law, returns=0), r"^returns must be an integer in \[1, 64\]"),
        (lambda: find_stateful_orbit(STICK_MODEL, law, transient=-1.0), r"^transient must be finite"),
        (lambda: Stiff().solve_state(STICK_MODEL, law, np.array([0.0, 0.0]), 1.0), r"^y0 must be 3 finite numbers"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message) as e:
            call()
        assert "\n" not in str(e.value)
    with pytest.raises(ShootingError, match="settled"):  # overdamped: no cycle
        find_stateful_orbit(BeltOscillator(zeta=2.0, vb=0.01), law, transient=30.0)


def test_continuation_of_a_stateful_law_finds_the_hopf_point_and_its_branch(capsys):
    lam_h = max(hopf_zeta(SOFT, 0.05))
    result = continuation(SOFT_MODEL, LuGre(**SOFT), "zeta", 0.8, 1.5, n_equilibria=15, transient=150.0, max_points=40)
    hopf = [b for b in result.bifurcations if b.type == "hopf"]
    assert len(hopf) == 1 and hopf[0].value == pytest.approx(lam_h, rel=1e-9)
    eq, cycles = result.branches[0], [b for b in result.branches if b.kind == "periodic"]
    assert {p.stability for p in eq.points if p.value < lam_h - 1e-6} == {"unstable"}
    assert {p.stability for p in eq.points if p.value > lam_h + 1e-6} == {"stable"}
    assert "neutral" in {p.stability for p in eq.points}  # the Hopf point itself, in the branch
    assert len(cycles) == 1 and cycles[0].seed.startswith("hopf")  # the attractor at zeta = 0.8 is on it
    values = [p.value for p in cycles[0].points]
    assert min(values) == pytest.approx(0.8) and max(values) < lam_h
    assert all(p.stable and p.stick_fraction == 0.0 for p in cycles[0].points)
    # every point's power flow: the belt's input at the vibration's average over the period
    assert all(p.measures.averages()["P_belt"] > 0.0 for p in cycles[0].points)
    args = ["continue", "--friction", "lugre", *[f"--{k}={v}" for k, v in SOFT.items()], "--vb", "0.05",
            "--vary", "zeta=0.8:1.5:15", "--t-end", "150", "--max-points", "40", "--json"]
    assert main(args) == 0
    d = json.loads(capsys.readouterr().out)
    assert [b["type"] for b in d["bifurcations"]] == ["hopf"]
    assert main([*args[:-1], "--overlay", "3"]) == 2
    err = capsys.readouterr().err
    assert "sweep 0 for friction=lugre" in err and err.count("\n") == 1


def test_the_shooting_is_generic_over_stateful_laws_elastoplastic():
    law = ElastoPlastic(fd=0.02, fs=0.04, vs=0.01, sigma0=1e4, sigma1=100.0, z_ba=1e-6)
    orbit = find_orbit(STICK_MODEL, law, transient=60.0)
    assert isinstance(orbit, StatefulOrbit) and orbit.stick_fraction > 0.2
    # the variational monodromy against central differences of one-period runs from the perturbed whole state
    m_fd = fd_state_monodromy(orbit)
    assert np.max(np.abs(orbit.monodromy - m_fd) / np.max(np.abs(m_fd), axis=0)) < 1e-5
    # a run from the orbit's state for three periods comes back to it each period (Stiff.solve_state)
    traj = Stiff(rtol=1e-11, atol=1e-13).solve_state(STICK_MODEL, law, orbit.state, 3 * orbit.period)
    down = np.flatnonzero((traj.v[:-1] > 0) & (traj.v[1:] == 0.0)) + 1
    assert np.allclose(np.diff(traj.t[down]), orbit.period, rtol=1e-8)
    assert np.allclose(traj.x[down], orbit.state[0], rtol=1e-8)


def test_a_start_on_an_equilibrium_is_named_as_such_not_settled():
    """Rate-and-state at its defaults (V_b = V_0): the default start is steady sliding itself, unstable for
    D_c = 0.005 (k = 1 below Rice-Ruina's k_c = 3), so the run never moves.  It said "it settled"; a start off
    it finds the stable cycle (period 10.7442, a QA's own integration)."""
    law = RateState(dc=0.005)
    model = BeltOscillator()
    with pytest.raises(ShootingError, match=r"stayed where it started .* an equilibrium, stable or not"):
        find_stateful_orbit(model, law)
    orbit = find_stateful_orbit(model, law, x0=0.61)
    assert orbit.period == pytest.approx(10.7442197, rel=1e-6)
