"""The adaptive solver for structures against the exact engine, the single mass's adaptive solver, energy
balances and an independent event-driven integrator (scipy's solve_ivp with its own events, written here)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import frictionflow as ff
from frictionflow.core.structure.combo import N_SLOTS
from frictionflow.solvers.structure import simulate_system, structure_solvers, supported_laws
from frictionflow.system import System, load_system

from ..cli.processes import in_process, one_line

RTOL, ATOL = 1e-10, 1e-12
EXAMPLES = "examples/models"


def _model(path):
    return load_system(Path(__file__).parents[2] / EXAMPLES / path)


def _chain(law_table, n=2, belt=0.1, q0=None, v0=None, coupling=1.0, damping=0.05, forces=()):
    """n masses in a chain (wall-k-m1-kc-m2-...-k-wall), each rubbing on the belt with the law ``law_table``
    (``forces``: the model file's force tables)."""
    dof = [f"x{i}" for i in range(n)]
    springs = [{"on": {dof[0]: 1.0}, "k": 1.0}, {"on": {dof[-1]: 1.0}, "k": 1.0}]
    springs += [{"on": {dof[i]: 1.0, dof[i + 1]: -1.0}, "k": coupling} for i in range(n - 1)]
    data = {"dof": dof, "mass": [1.0] * n, "spring": springs,
            "damper": [{"on": {d: 1.0}, "c": damping} for d in dof],
            "contact": [{"on": {d: 1.0}, "belt": belt, **law_table} for d in dof],
            "initial": {"q": dict(zip(dof, q0 or [0.0] * n)), "v": dict(zip(dof, v0 or [0.0] * n))}}
    if forces:
        data["force"] = list(forces)
    return System.from_dict(data)


STRIBECK = {"friction": "stribeck", "fd": 0.3, "fs": 0.5, "vs": 0.2}


# -- (1) Coulomb: the same motion as the exact engine --------------------------------------------------------

COULOMB = {"friction": "coulomb", "fd": 0.3, "fs": 0.5}
FORCE = {"on": {"x0": 1.0}, "amplitude": 0.6, "omega": 0.8, "phi": 0.3}


@pytest.mark.parametrize("model", ["two_mass_chain.toml", "chain3", "forced_chain2"])
def test_coulomb_chain_switches_as_the_exact_engine(model):
    system = (_model(model) if model.endswith(".toml")
              else _chain(COULOMB, n=3, q0=[0.2, -0.1, 0.0], v0=[0.0, 0.3, 0.0]) if model == "chain3"
              else _chain(COULOMB, n=2, q0=[0.1, 0.0], forces=[FORCE]))
    exact = simulate_system(system, 40.0)
    adaptive = simulate_system(system, 40.0, solver="adaptive", rtol=RTOL, atol=ATOL)
    assert len(exact.switches) >= 4
    np.testing.assert_array_equal(adaptive.switch_contact, exact.switch_contact)
    np.testing.assert_array_equal(adaptive.switch_mode, exact.switch_mode)
    np.testing.assert_allclose(adaptive.switches, exact.switches, rtol=0, atol=1e-7)
    grid = np.linspace(0.0, 40.0, 97)
    np.testing.assert_allclose(adaptive.states(grid), exact.states(grid), rtol=0, atol=1e-7)
    np.testing.assert_allclose(adaptive.work[:, -1], exact.work[:, -1], rtol=1e-7, atol=1e-9)


# -- (2), (3) the single mass's adaptive solver -------------------------------------------------------------

def _single(law, x0, v0, t_end, zeta=0.05, vb=0.3):
    model = ff.BeltOscillator(zeta=zeta, vb=vb)
    return ff.simulate(model, law, ff.solvers.Adaptive(rtol=RTOL, atol=ATOL), t_end=t_end, x0=x0, v0=v0)


def test_one_dof_stribeck_equals_the_single_mass():
    law = ff.Stribeck(fd=0.3, fs=0.5, vs=0.2)
    single = _single(law, 0.1, 0.0, 60.0)
    system = System.single_mass(ff.BeltOscillator(zeta=0.05, vb=0.3), law, x0=0.1, v0=0.0)
    motion = simulate_system(system, 60.0, solver="adaptive", rtol=RTOL, atol=ATOL)
    assert len(single.events["t"]) >= 6
    np.testing.assert_allclose(motion.switches, single.events["t"], rtol=0, atol=1e-7)
    grid = np.linspace(0.0, 60.0, 121)
    x, v = single.at(grid)
    np.testing.assert_allclose(motion.states(grid), np.vstack((x, v)), rtol=0, atol=1e-7)


def test_uncoupled_stribeck_masses_each_equal_the_single_mass():
    starts = [(0.1, 0.0), (-0.4, 0.2), (0.6, -0.1)]
    dof = [f"x{i}" for i in range(len(starts))]
    data = {"dof": dof, "mass": [1.0] * len(dof),
            "spring": [{"on": {d: 1.0}, "k": 1.0} for d in dof], "damper": [{"on": {d: 1.0}, "c": 0.1} for d in dof],
            "contact": [{"on": {d: 1.0}, "belt": 0.3, **STRIBECK} for d in dof],
            "initial": {"q": {d: s[0] for d, s in zip(dof, starts)}, "v": {d: s[1] for d, s in zip(dof, starts)}}}
    motion = simulate_system(System.from_dict(data), 40.0, solver="adaptive", rtol=RTOL, atol=ATOL)
    grid = np.linspace(0.0, 40.0, 81)
    states = motion.states(grid)
    law = ff.Stribeck(fd=0.3, fs=0.5, vs=0.2)
    for i, (x0, v0) in enumerate(starts):
        single = _single(law, x0, v0, 40.0)
        x, v = single.at(grid)
        np.testing.assert_allclose(states[[i, len(dof) + i]], np.vstack((x, v)), rtol=0, atol=1e-7)
        mine = motion.switches[motion.switch_contact == i]
        np.testing.assert_allclose(mine, single.events["t"], rtol=0, atol=1e-7)


# -- (4) energy balance per element ---------------------------------------------------------------------------

def test_energy_balance_per_element_closes_to_the_tolerance():
    system = _chain(STRIBECK, n=3, q0=[0.3, 0.0, -0.2], v0=[0.0, 0.1, 0.0])
    motion = simulate_system(system, 60.0, solver="adaptive", rtol=RTOL, atol=ATOL)
    assert motion.energy_residual < 1e-8
    a, n = motion.assembly, motion.n
    q, v = motion.state[:n], motion.state[n:]
    for s, name in enumerate(motion.elements["spring"]):  # a spring's work is minus its potential's change
        pe = 0.5 * a.spring_k[s] * (a.spring_dir[s] @ q) ** 2
        np.testing.assert_allclose(motion.work[motion.channels.index(name)], -(pe - pe[0]), rtol=0, atol=1e-8)
    for d, name in enumerate(motion.elements["damper"]):  # -c (e.q')^2 by Simpson on the step samples
        grid = np.linspace(0.0, 60.0, 6001)
        w = a.damper_dir[d] @ motion.states(grid)[n:]
        p = -a.damper_c[d] * w * w
        simpson = (grid[1] - grid[0]) / 3.0 * (p[0] + p[-1] + 4.0 * p[1:-1:2].sum() + 2.0 * p[2:-1:2].sum())
        assert abs(motion.work[motion.channels.index(name), -1] - simpson) < 1e-6 * (1.0 + abs(simpson))
    heat = np.array([motion.work[motion.channels.index(f"{c}.heat")] for c in motion.contacts])
    assert (np.diff(heat, axis=1) >= -1e-12).all()  # the interfaces only dissipate


# -- (5) contact loss ------------------------------------------------------------------------------------------

def test_contact_loss_is_reported_with_a_state_dependent_normal_load():
    system = _model("hoffmann_2dof.toml")
    exact = simulate_system(system, 200.0)
    adaptive = simulate_system(system, 200.0, solver="adaptive", rtol=RTOL, atol=ATOL)
    assert exact.status == adaptive.status == "contact_lost"
    assert adaptive.lost[0] == exact.lost[0]
    assert abs(adaptive.lost[1] - exact.lost[1]) < 1e-6
    a = adaptive.assembly
    q = adaptive.state[:adaptive.n, -1]
    assert abs(a.normal[0, 0] + a.normal[0, 1:] @ q) < 1e-9  # N = 0 where the run ends
    data = system.to_dict()
    data["contact"][0].update({"friction": "stribeck", "fd": 0.7, "fs": 0.9, "vs": 0.5})
    lost = simulate_system(System.from_dict(data), 200.0, solver="adaptive", rtol=RTOL, atol=ATOL)
    assert lost.status == "contact_lost" and lost.lost[0] == "contact.0"
    q = lost.state[:lost.n, -1]
    assert abs(a.normal[0, 0] + a.normal[0, 1:] @ q) < 1e-9


# -- (6) a 2-mass Stribeck chain against an independent integrator ---------------------------------------------

def _stribeck(law, speed):
    return law["fd"] + (law["fs"] - law["fd"]) * math.exp(-(speed / law["vs"]) ** 2)


def _reference(system, law, t_end):
    """Two masses, each on its own contact along its own coordinate (M = I): modes per mass, solve_ivp
    with an event per mass (V_r = 0 slipping; |held force| = F_s stuck), the stick rule by hand."""
    K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    C = 0.05 * np.eye(2)
    b = 0.1

    def held(i, y, modes):
        acc = -(K @ y[:2]) - C @ y[2:]
        for j in range(2):
            if modes[j] != 0:
                acc[j] += modes[j] * _stribeck(law, abs(b - y[2 + j]))
        return -acc[i]  # what the contact must hold so that mass i does not accelerate

    def rhs(t, y, modes):
        acc = -(K @ y[:2]) - C @ y[2:]
        for j in range(2):
            acc[j] = 0.0 if modes[j] == 0 else acc[j] + modes[j] * _stribeck(law, abs(b - y[2 + j]))
        return np.concatenate((y[2:], acc))

    y, t, modes, switches = np.concatenate((system.q0, system.v0)), 0.0, [1, 1], []
    while t < t_end:
        evs = []
        for i in range(2):
            def ev(t, y, modes=tuple(modes), i=i):
                return (b - y[2 + i]) * modes[i] if modes[i] != 0 else law["fs"] - abs(held(i, y, modes))
            ev.terminal, ev.direction = True, -1
            evs.append(ev)
        sol = solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=1e-13, atol=1e-14, events=evs, args=(tuple(modes),),
                        dense_output=False)
        hit = [i for i in range(2) if len(sol.t_events[i])]
        if not hit:
            return switches, sol.y[:, -1]
        i = min(hit, key=lambda i: sol.t_events[i][0])
        t, y = sol.t_events[i][0], sol.y_events[i][0].copy()
        if modes[i] != 0:  # V_r = 0: stick if the held force is within F_s (the slip level at 0 is F_s)
            trial = list(modes)
            trial[i] = 0
            modes[i] = 0 if abs(held(i, y, trial)) < law["fs"] else -modes[i]
            if modes[i] == 0:
                y[2 + i] = b
        else:
            modes[i] = 1 if held(i, y, modes) > 0 else -1
        switches.append((t, i, modes[i]))
    return switches, y


def test_two_mass_stribeck_chain_equals_an_independent_integrator():
    law = {"fd": 0.3, "fs": 0.5, "vs": 0.2}
    system = _chain({"friction": "stribeck", **law}, n=2, belt=0.1, q0=[0.4, -0.3])
    motion = simulate_system(system, 30.0, solver="adaptive", rtol=RTOL, atol=ATOL)
    switches, y_end = _reference(system, law, 30.0)
    assert len(switches) >= 4
    stuck_alone = [m for m in range(motion.modes.shape[1]) if sorted(motion.modes[:, m].tolist()) in ([0, 1], [-1, 0])]
    assert stuck_alone, "a stretch with one mass stuck while the other slips"
    np.testing.assert_array_equal(motion.switch_contact, [s[1] for s in switches])
    np.testing.assert_array_equal(motion.switch_mode, [s[2] for s in switches])
    np.testing.assert_allclose(motion.switches, [s[0] for s in switches], rtol=0, atol=1e-7)
    np.testing.assert_allclose(motion.state[:, -1], y_end, rtol=0, atol=1e-7)


# -- the solvers' declarations and refusals ---------------------------------------------------------------------

def test_the_solvers_declare_the_laws_they_run_in_structures():
    assert set(structure_solvers()) == {"exact", "adaptive"}
    assert set(supported_laws("adaptive").values()) == {"coulomb", "stribeck", "cubic"}
    system = _chain(STRIBECK)
    with pytest.raises(ValueError, match=r"^solver=exact runs structures whose contacts' laws are coulomb; "
                                         r"contact\.0 has friction=stribeck; use solver=adaptive$"):
        simulate_system(system, 10.0)
    with pytest.raises(ValueError, match="solver must be one of exact, adaptive for a structure, got 'rk4'"):
        simulate_system(system, 10.0, solver="rk4")
    with pytest.raises(ValueError, match="rtol"):
        simulate_system(system, 10.0, solver="adaptive", rtol=0.5)
    with pytest.raises(ValueError, match=r"karnopp has a velocity band, which no structure solver runs"):
        _chain({"friction": "karnopp", "fd": 0.3, "fs": 0.5})  # refused with the model: no solver could run it


# -- the command line ---------------------------------------------------------------------------------------------

ONE_DOF_STRIBECK = """
dof = ["x"]
mass = [1.0]
[[spring]]
on = { x = 1.0 }
k = 1.0
[[damper]]
on = { x = 1.0 }
c = 0.1
[[contact]]
on = { x = 1.0 }
belt = 0.01
friction = "stribeck"
fd = 0.02
fs = 0.04
vs = 0.05
[initial]
q = { x = 0.02 }
v = { x = 0.01 }
"""


def test_cli_model_with_a_stribeck_law_runs_adaptive_and_agrees_with_the_single_mass(tmp_path):
    path = tmp_path / "one.toml"
    path.write_text(ONE_DOF_STRIBECK)
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "300", "--json")
    assert code == 0, err
    model = json.loads(out)
    code, out, err, _ = in_process("simulate", "--friction", "stribeck", "--fd", "0.02", "--fs", "0.04", "--vs", "0.05",
                            "--vb", "0.01", "--zeta", "0.05", "--x0", "0.02", "--v0", "0.01", "--t-end", "300",
                            "--solver", "adaptive", "--json")
    assert code == 0, err
    single = json.loads(out)
    assert model["steady_state"]["kind"] == single["steady_state"]["kind"] == "periodic"
    assert model["steady_state"]["period"] == pytest.approx(single["steady_state"]["period"], rel=1e-7)
    av, contact = single["averages"], model["elements"]["contact.0"]
    assert contact["P_belt"] == pytest.approx(av["P_belt"], rel=1e-6)
    assert contact["P_heat"] == pytest.approx(av["P_heat"], rel=1e-6)
    assert -model["elements"]["damper.0"]["P"] == pytest.approx(av["P_dv"], rel=1e-6)
    assert model["energy_residual"] < 1e-8
    code, out, err, _ = in_process("simulate", "--model", str(path), "--solver", "exact", "--t-end", "30", "--json")
    assert code == 2 and out == ""
    one_line(err, "solver=exact", "contact.0", "friction=stribeck", "solver=adaptive")
    coulomb = tmp_path / "coulomb.toml"
    coulomb.write_text(ONE_DOF_STRIBECK.replace('"stribeck"', '"coulomb"').replace("vs = 0.05\n", ""))
    code, out, err, _ = in_process("simulate", "--model", str(coulomb), "--ode-rtol", "1e-8", "--t-end", "30", "--json")
    assert code == 2 and out == ""  # auto runs Coulomb contacts exactly: the adaptive tolerance would go unused
    one_line(err, "--ode-rtol", "solver=exact")
    code, out, err, _ = in_process("orbit", "--model", str(coulomb), "--solver", "adaptive", "--json")
    assert code == 2 and out == ""
    one_line(err, "--solver", "--model")


def test_dense_grid_samples_equal_the_exact_motion_and_the_step_cap_is_one_line():
    system = _chain(COULOMB, n=2, q0=[0.1, 0.0], forces=[FORCE])
    exact = simulate_system(system, 20.0)
    motion = simulate_system(system, 20.0, solver="adaptive", dense_dt=0.5, rtol=RTOL, atol=ATOL)
    grid = np.arange(1, 40) * 0.5
    on_grid = np.isin(grid, motion.t)
    assert on_grid.all()
    columns = np.searchsorted(motion.t, grid)
    np.testing.assert_allclose(motion.state[:, columns], exact.states(grid), rtol=0, atol=1e-7)
    np.testing.assert_allclose(motion.work[:, columns], np.array([exact.work_at(t) for t in grid]).T, rtol=0, atol=1e-8)
    with pytest.raises(RuntimeError, match=r"^solver=adaptive: the run stopped at t=[0-9.e-]+ with status 'step cap' "
                                           r"\(max_steps=10\)$"):
        simulate_system(system, 20.0, solver="adaptive", max_steps=10)


def test_a_stick_reached_at_a_graze_within_one_step_is_found_at_any_tolerance():
    """An undamped mass whose normal load follows x (N = 1 + 1.78 x), F_s barely above F_d: each slip ends with
    V_r crossing 0 shallowly, and on the step's dense output V_r dips below 0 and back within one step.  The
    adaptive solver watched the signs at the step ends only: at rtol 1e-6 to 1e-10 it found 3 of the exact
    engine's 15 switches over t = 60 (no stick after t = 1.9), at 1e-12 it found 7.  A slipping contact's V_r
    (and a normal load) now also has its Hermite cubic from the ends' values and slopes looked at, and a dip's
    bottom searched on the dense output."""
    system = System.from_dict(
        {"dof": ["x"], "mass": [2.54], "spring": [{"on": {"x": 1.0}, "k": 1.39}],
         "contact": [{"on": {"x": 1.0}, "belt": 0.19, "friction": "coulomb", "fd": 0.1005, "fs": 0.1011,
                      "normal": {"preload": 1.0, "x": 1.78}}],
         "initial": {"q": {"x": -0.25}, "v": {"x": 0.1}}}, source=None)
    exact = simulate_system(system, 60.0, solver="exact")
    assert len(exact.switches) == 15
    for rtol, close in ((1e-6, 1e-3), (1e-10, 1e-7)):
        run = simulate_system(system, 60.0, solver="adaptive", rtol=rtol, atol=1e-2 * rtol)
        assert np.array_equal(run.switch_mode, exact.switch_mode), rtol
        np.testing.assert_allclose(run.switches, exact.switches, rtol=0, atol=close)
        assert np.abs(run.at(60.0) - exact.at(60.0)).max() < close


@pytest.mark.parametrize("excess", [1e-7, 1e-10])
def test_a_held_force_touching_its_limit_within_one_step_breaks_the_stick_at_any_tolerance(excess):
    """A mass stuck on a belt at 1e-9, a harmonic force whose peak at t = pi - 3 exceeds F_s by ``excess``: the
    held force passes its limit and back within a fraction of a step.  The adaptive solver (end signs only)
    kept the mass stuck to t = 20 (no switch) where the exact engine breaks away at 0.14 and then switches 12
    times more.  A held-force slot's dip is now looked for on the parabola through the step's ends and its
    middle (its rate is not among the step's), then on the dense output."""
    system = System.from_dict(
        {"dof": ["x"], "mass": [1.0], "spring": [{"on": {"x": 1.0}, "k": 1.0}],
         "damper": [{"on": {"x": 1.0}, "c": 0.1}],
         "contact": [{"on": {"x": 1.0}, "belt": 1e-9, "friction": "coulomb", "fd": 0.4, "fs": 0.5}],
         "force": [{"on": {"x": 1.0}, "amplitude": 0.5 + excess, "omega": 1.0, "phi": 3.0}],
         "initial": {"v": {"x": 1e-9}}}, source=None)
    exact = simulate_system(system, 20.0, solver="exact")
    assert len(exact.switches) == 13 and abs(exact.switches[0] - (math.pi - 3.0)) < 1e-3
    for rtol, close in ((1e-6, 1e-3), (1e-10, 1e-6)):
        run = simulate_system(system, 20.0, solver="adaptive", rtol=rtol, atol=1e-2 * rtol)
        assert np.array_equal(run.switch_mode, exact.switch_mode), rtol
        np.testing.assert_allclose(run.switches, exact.switches, rtol=0, atol=close)
